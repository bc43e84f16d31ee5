//! Linear octrees: domain, node keys, the canonical node list, and what works on it.

mod csg;
mod depth;
mod domain;
mod linear;
mod neighbourhood;
mod node;
mod ranges;
mod resample;
mod transform;
mod voxelize;
mod window;

pub use csg::SetOp;
pub use depth::CoarsenRule;
pub use domain::{Domain, MAX_DEPTH};
pub use linear::LinearOctree;
pub use node::{Node, NodeKey};
pub use voxelize::{PARALLEL_LEVELS, VoxelizeOptions, estimate_bytes, voxelize};
pub(crate) use window::keys_meeting_near;
