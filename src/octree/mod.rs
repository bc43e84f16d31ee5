//! Linear octrees: domain, node keys, the canonical node list, and what works on it.
//!
//! Every voxelizer of the library (shapes here, mesh solids and surfaces in
//! [`crate::mesh`], patch surfaces in [`crate::patch`]) runs one top-down walk: its job
//! is refused before any work when its estimated memory exceeds the budget; children
//! are visited in Morton order and eight full children become their parent, so the
//! keys come out sorted and canonical; the top [`PARALLEL_LEVELS`] levels run as
//! parallel tasks joined in child order, so the result does not depend on the number
//! of threads; progress comes in units of level-3 subtrees ([`VoxelizeOptions`]).
//!
//! Measurements work on the key list too ([`LinearOctree::measure`], [`Measures`]):
//! exact mass properties, an estimate of the boundary's area that converges to a
//! smooth surface's, and the face-connected components.
//!
//! Two families live in sub-folders, each declaring its operations together in its
//! `mod.rs`: `csg/`, the set operations (two operands or any number, one merge of
//! Morton runs), and `transform/`, moving and fitting (exact whole-voxel moves, affine
//! maps, resampling, change of depth, one domain for several solids).

mod clipping;
mod csg;
mod domain;
mod driver;
mod hull;
mod linear;
mod measure;
mod neighbourhood;
mod node;
mod offset;
mod ranges;
mod section;
mod transform;
mod voxelize;
mod window;

pub use clipping::{Clipping, clipping};
pub use csg::SetOp;
pub use domain::{Domain, EDGE_RANGE, LATTICE_BITS, MAX_COORDINATE, MAX_DEPTH};
pub use driver::{CellNodes, CellSink, Cells, PARALLEL_LEVELS, VoxelizeOptions};
pub(crate) use driver::{Counters, Decision, Plan, Voxelizer};
pub use linear::LinearOctree;
pub use measure::{MassProperties, Measures, SurfaceArea};
pub use node::{Node, NodeKey};
pub use offset::{FaceCrossings, Metric, NewCrossing, OffsetOptions, Staircase};
pub use transform::{CoarsenRule, Fit, Motion, OctreeShape, Turn, common_domain};
pub(crate) use transform::{CubeSymmetry, MovePlan};
pub(crate) use voxelize::check_level;
pub use voxelize::{estimate_bytes, estimate_cell_bytes, voxelize, voxelize_cells};
pub(crate) use window::keys_meeting_near;
