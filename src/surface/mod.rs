//! The true surface out of the octree: closed, manifold, feature-preserving triangle
//! meshes by dual contouring of Hermite data.
//!
//! - [`hermite`]: where the surface crosses each boundary face's segment, and its
//!   normal ([`HermiteData`], from a shape exactly, from nothing as the faces).
//! - `hermite_mesh`: [`HermiteData::from_mesh`], a mesh solid's crossings from its
//!   triangles under the voxelizer's inside rule.
//! - `hermite_patch`: [`HermiteData::from_patches`], a patch set's: its tessellation's
//!   crossings moved onto the patches by Newton's method.
//! - `faces`: a solid's boundary faces, one a voxel face, each named by its [`FaceKey`].
//! - `combine`: Hermite data through a set operation ([`HermiteData::combine`]: a
//!   CSG result's crossings from its operands').
//! - `transform`: Hermite data through the exact whole-voxel moves.
//! - `offset`: [`offset_with_surface`], [`shell_with_surface`],
//!   [`round_with_surface`]: offsets measured to the true surface, with the results'
//!   crossings from the distance field.
//! - `resample`: [`resample_with_surface`], a solid moved where its voxels do not
//!   follow, voxelized again from its moved smooth surface, with new crossings;
//!   [`fit_with_surface`] and [`transform_with_surface`], a solid and its data
//!   brought into a domain or moved, each the cheapest faithful way.
//! - `resolve`: [`resolve_offsets`], a CSG tree's offset, shell and round nodes
//!   replaced by their solids on a lattice ([`SurfacedOctree`]: an octree with its
//!   crossings as a shape).
//! - `qef`: the point nearest a cell's tangent planes, and their rank.
//! - `dual`: a vertex a sheet at each boundary voxel corner, the faces as quads.
//! - `untangle`: crossing triangles' vertices moved back towards the staircase.
//! - `cluster`: flat blocks of cells merged into one vertex each, before simplifying.
//! - `fan_cone`: the merge's normal bound, from its distance limit and a block's fan.
//! - `simplify`: edge collapses under a distance bound, kept manifold and uncrossed.
//! - `extract`: [`extract`], the surface as an indexed mesh.
//! - `window`: [`extract_cell`], the part of the surface one cell of a larger solid
//!   owns, from a window of its neighbours, named to weld with the other cells'.

mod cluster;
mod combine;
mod dual;
mod extract;
mod faces;
mod fan_cone;
pub mod hermite;
mod hermite_mesh;
mod hermite_patch;
mod offset;
mod qef;
mod resample;
mod resolve;
mod simplify;
mod transform;
mod untangle;
mod window;

pub(crate) use dual::Fans;
pub(crate) use extract::peak_bytes;
pub use extract::{CellMerge, DEFAULT_TOLERANCE, ExtractOptions, Style, SurfaceMesh, extract};
pub(crate) use faces::boundary_faces;
pub use hermite::{Crossing, Direction, FaceKey, HermiteData};
pub use offset::{offset_with_surface, round_with_surface, shell_with_surface};
pub use resample::{Moved, fit_with_surface, resample_with_surface, transform_with_surface};
pub use resolve::{SurfacedOctree, resolve_offsets};
pub use simplify::{SimplifyOptions, SimplifyReport, simplify, simplify_with_progress};
pub use window::{CELL_BORDER, CellSurface, CellVertexKind, VertexKey, extract_cell};
