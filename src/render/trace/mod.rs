//! Ray tracing through the octree itself: the traversal octree built from a linear
//! octree ([`Traversal`], 8 bytes an inner node), rays in the domain's lattice
//! ([`VoxelRay`]) and the exact first-hit walk (`walk`, after Revelles et al. 2000),
//! whose step reads the three mid-plane times in SIMD lanes (`lanes`: AVX2 chosen at
//! run time, SSE2, scalar; the same bits), after a division-free test that the ray can
//! come near the full voxels at all (`reach`); and the
//! beam pre-pass that walks an 8x8 tile of primary rays as one packet (`beam`, after
//! Reshetov et al. 2005), bit for bit the hits of the rays one by one; and a contender,
//! the 64-tree of 4x4x4 nodes and its walk ([`Tree64`]), with the same hits.

mod beam;
mod lanes;
mod reach;
mod traversal;
mod tree64;
mod voxel_ray;
mod walk;

pub use beam::{PACKET, TILE};
pub(crate) use traversal::Inner;
pub use traversal::Traversal;
pub use tree64::Tree64;
pub(crate) use voxel_ray::Entry;
pub use voxel_ray::{Hit, VoxelRay};
