//! Octree traversal against bounding volume hierarchies, measured on the same work.
//!
//! Contenders ([`Contender`]: built from their input, then asked for closest and any
//! hits): our traversal octree, and the BVH crates `obvhs` (CWBVH) and `bvh` (binary SAH
//! BVH), each built over the octree's boundary faces and, where the solid came from a
//! triangle mesh, over that mesh; with the `embree` feature also Embree 3 (the system
//! library, one ray a call and 8-ray packets) over the same meshes. [`run_matrix`]
//! traces the same [`RaySet`]s (primary, shadow, random) through each on one thread and
//! on all threads and returns build times, bytes and rays a second; [`write_report`]
//! turns the results into a Markdown section and plots.

pub mod bvh_contender;
pub mod contender;
#[cfg(feature = "embree")]
pub mod embree_contender;
pub mod machine;
pub mod markdown;
pub mod matrix;
pub mod obvhs_contender;
pub mod octree_contender;
pub mod plots;
pub mod rays;
pub mod report;
pub mod scenes;

pub use bvh_contender::BvhCrateBvh;
pub use contender::{Contender, SurfaceHit};
#[cfg(feature = "embree")]
pub use embree_contender::{EmbreeBvh, EmbreePackets};
pub use machine::Machine;
pub use matrix::{CaseResult, ContenderKind, ContenderResult, MatrixOptions, MatrixResults, Speed, run_matrix};
pub use obvhs_contender::ObvhsBvh;
pub use rays::{RayKind, RaySet};
pub use report::write_report;
pub use scenes::{BenchScene, SceneKind, build_scene};
