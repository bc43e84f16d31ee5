//! Reading and writing solids and images: the native `.oct` format (see
//! `docs/FORMAT.md`), the voxel and volume formats other tools use (MagicaVoxel
//! `.vox`, binvox, OpenVDB `.vdb`; glTF `.glb` meshes out), pictures out (PNG, and
//! OpenEXR for linear radiance), and the atomic write they all use. [`read_solids`],
//! [`write_solids`] and [`save_picture`] pick the format by extension.

pub mod binvox;
mod bitgrid;
mod blosc;
pub mod exr;
pub mod gltf;
pub mod oct;
mod picture;
pub mod png;
mod solid_set;
mod solids;
pub mod vdb;
pub mod vox;

pub use crate::atomic::{same_file, write_atomic};
pub use picture::{PictureFormat, save_picture};
pub use solid_set::{ColouredSolid, ReadOptions, Solids};
pub use solids::{SolidFormat, WriteOptions, read_solids, write_solid, write_solids};
