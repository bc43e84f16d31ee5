//! Moving and fitting octrees, the whole family in one place: exact whole-voxel moves,
//! any affine map, resampling into any domain, a change of depth, and bringing several
//! solids into one domain.
//!
//! Each operation is exact where the map keeps the voxel lattice (voxels go to voxels
//! by an integer map, no sampling) and samples the source at the target's voxel
//! centres otherwise. The operations, all on [`LinearOctree`](crate::octree::LinearOctree)
//! unless said:
//!
//! - exact whole-voxel moves ([`exact`]): `translate`, `mirror`, `rotate90`;
//! - any affine map, exact for the cube's symmetries with a scale ([`affine`]):
//!   `transformed`, and [`Motion`] / [`Turn`], the similarity a user gives it;
//! - sampling at voxel centres ([`resample`]): `resample`, `resample_to`,
//!   `classify_voxel_box`, and [`OctreeShape`], an octree seen as a
//!   [`Shape`](crate::shape::Shape) through an affine map;
//! - change of depth ([`depth`]): `refine` exactly, `coarsen` by a [`CoarsenRule`];
//! - one domain for several solids ([`fit`]): [`common_domain`], and `fit_to`, which
//!   says how it moved the solid ([`Fit`]).

mod affine;
mod depth;
mod exact;
mod fit;
mod motion;
mod resample;

pub(crate) use affine::{CubeSymmetry, MovePlan};
pub use depth::CoarsenRule;
pub use fit::{Fit, common_domain};
pub use motion::{Motion, Turn};
pub use resample::OctreeShape;
pub(in crate::octree) use resample::enclosing_node;
