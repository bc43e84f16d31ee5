//! The true surface out of the octree: closed, manifold, feature-preserving triangle
//! meshes by dual contouring of Hermite data.
//!
//! - [`hermite`]: where the surface crosses each boundary face's segment, and its
//!   normal ([`HermiteData`], from a shape exactly, from nothing as the faces).
//! - `faces`: a solid's boundary faces, one a voxel face.
//! - `combine`: Hermite data through a set operation ([`HermiteData::combine`]: a
//!   CSG result's crossings from its operands').
//! - `transform`: Hermite data through the exact whole-voxel moves.

mod combine;
mod faces;
pub mod hermite;
mod transform;

pub(crate) use faces::is_boundary_face;
pub use hermite::{Crossing, Direction, FaceKey, HermiteData};
