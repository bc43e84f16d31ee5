//! The true surface out of the octree: closed, manifold, feature-preserving triangle
//! meshes by dual contouring of Hermite data.
//!
//! - [`hermite`]: where the surface crosses each boundary face's segment, and its
//!   normal ([`HermiteData`], from a shape exactly, from nothing as the faces).
//! - `faces`: a solid's boundary faces, one a voxel face.

mod faces;
pub mod hermite;
mod simplify;

pub use hermite::{Crossing, Direction, FaceKey, HermiteData};
pub use simplify::{SimplifyOptions, SimplifyReport, simplify};
