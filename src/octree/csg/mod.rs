//! Set operations on linear octrees, the whole family in one place.
//!
//! Every operation here is a merge of sorted Morton runs: a canonical key list is the
//! greedy cut of its maximal runs of voxel Morton codes ([`crate::octree::ranges`]), so
//! a set operation sweeps the run boundaries of its operands and cuts the runs where
//! the operator holds back into canonical keys. No tree is built and nothing is sorted.
//!
//! The operations, all on [`LinearOctree`](crate::octree::LinearOctree):
//!
//! - [`SetOp`]: union, intersection, difference, symmetric difference;
//! - two operands, one sweep ([`pairwise`]): `combine`, `union`, `intersection`,
//!   `difference`, `symmetric_difference`, `complement`, and the operators `|`, `&`,
//!   `-`, `^`, `!` on references (which panic where the methods return an error);
//! - any number of operands in one pass, in parallel over Morton ranges ([`merge`]):
//!   `combine_all`; its chunks run the two-operand stretches of keys of [`two_way`] and
//!   write their results in place through the plans of [`plan`].
//!
//! Operands must share one domain and depth; [`crate::octree::transform`] brings
//! solids into one first.

mod merge;
mod pairwise;
mod plan;
mod two_way;

pub use pairwise::SetOp;
