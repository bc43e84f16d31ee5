//! Linear octrees: domain, node keys, the canonical node list, and what works on it.

mod csg;
mod depth;
mod domain;
mod driver;
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
pub(crate) use driver::{Counters, Decision, Plan, Voxelizer};
pub use driver::{PARALLEL_LEVELS, VoxelizeOptions};
pub use linear::LinearOctree;
pub use node::{Node, NodeKey};
pub use voxelize::{estimate_bytes, voxelize};
pub(crate) use window::keys_meeting_near;
