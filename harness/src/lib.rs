//! Octree traversal against bounding volume hierarchies, measured on the same work.
//!
//! Contenders ([`Contender`]: built from their input, then asked for closest and any
//! hits): our traversal octree and our 64-tree (4x4x4 nodes, the same hits), and the BVH crates `obvhs` (CWBVH) and `bvh` (binary SAH
//! BVH), each built over the octree's boundary faces and, where the solid came from a
//! triangle mesh, over that mesh; with the `embree` feature also Embree 3 (the system
//! library, one ray a call and 8-ray packets) over the same meshes. [`run_matrix`]
//! traces the same [`RaySet`]s (primary, shadow, random) through each on one thread and
//! on all threads and returns build times, bytes and rays a second; [`write_report`]
//! turns the results into a Markdown section and plots. Issue 41's incoherent rays
//! (bounce and shadow rays leaving the primary hits of one view, [`secondary_rays()`])
//! have their own section: [`run_secondary`] measures them on one thread with the peers
//! outside Rust (embreex, `perf stat`) and [`write_secondary_report`] splices it in.

pub mod any_contender;
pub mod bvh_contender;
pub mod contender;
#[cfg(feature = "embree")]
pub mod embree_contender;
pub mod machine;
pub mod markdown;
pub mod matrix;
pub mod obvhs_contender;
pub mod octree_contender;
pub mod perf_window;
pub mod plots;
pub mod ray_file;
pub mod rays;
pub mod report;
pub mod scenes;
pub mod secondary_bench;
pub mod secondary_markdown;
pub mod secondary_rays;
pub mod tree64_contender;

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
pub use secondary_bench::{SecondaryOptions, SecondaryResults, run_secondary};
pub use secondary_markdown::write_secondary_report;
pub use secondary_rays::{SecondaryRays, secondary_rays};
