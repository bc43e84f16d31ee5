//! Reading and writing solids and images: the native `.oct` format (see
//! `docs/FORMAT.md`), the voxel and volume formats other tools use (MagicaVoxel
//! `.vox`, binvox, OpenVDB `.vdb`; glTF `.glb` meshes out), pictures out (PNG, and
//! OpenEXR for linear radiance). [`write_picture`] picks the picture format by
//! extension ([`crate::FileKind`]); solid files are read and written through the door
//! above `io` and `sharded`, [`crate::SolidFile::read`] and [`crate::write_solid_file`].
//! Every file is written through [`write_atomic`] (the bottom floor's, re-exported
//! here).
//!
//! `io` sits above `render`: it writes `render`'s [`crate::render::Picture`] and builds
//! a [`crate::render::Scene`] of the solids a file holds; `render` never imports `io`.

pub mod binvox;
mod bitgrid;
mod blosc;
mod boundary_walk;
pub mod exr;
pub mod gltf;
pub mod oct;
mod oct_surface;
mod picture;
pub mod png;
mod solid_set;
mod solids;
mod varint;
pub mod vdb;
mod vdb_level_set;
pub mod vox;

pub use crate::atomic::{same_file, write_atomic};
pub use picture::write_picture;
pub(crate) use solid_set::file_stem;
pub use solid_set::{ColouredSolid, ReadOptions, SolidRef, Solids, SolidsRef};
pub use solids::WriteOptions;
pub(crate) use solids::{one_solid, write_voxel_solids};
