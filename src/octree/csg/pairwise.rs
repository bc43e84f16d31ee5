//! Set operations on linear octrees: one linear merge of Morton runs.
//!
//! Both operands are sorted disjoint runs of voxel Morton codes. A sweep over the
//! union of their run boundaries sees, between two consecutive boundaries, a segment
//! where membership in each operand is constant; the segments where the boolean
//! operator holds are the result's runs, which [`ranges::cut_runs`] turns into the
//! canonical node list. Time and memory O(n + m + output); no sort, no tree.
//!
//! Many operands, and two large ones in parallel: [`super::merge`], which this
//! sweep serves for two operands.
//!
//! The methods return an error for operands over different domains or depths; the
//! operators (`|`, `&`, `-`, `^`, `!` on references) panic in that case instead.

use std::ops::{BitAnd, BitOr, BitXor, Not, Sub};

use crate::error::Result;
use crate::octree::linear::LinearOctree;
use crate::octree::ranges::{self, Runs};

/// A boolean set operation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetOp {
    /// In either operand.
    Union,
    /// In both operands.
    Intersection,
    /// In the first and not the second.
    Difference,
    /// In exactly one operand.
    SymmetricDifference,
}

impl SetOp {
    /// Every operation, in the order `octsolid csg --help` lists them.
    pub const ALL: [SetOp; 4] = [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference];

    /// The operation's one spelling (`octsolid csg`'s, `Display`'s): `union`,
    /// `intersect`, `difference`, `xor`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            SetOp::Union => "union",
            SetOp::Intersection => "intersect",
            SetOp::Difference => "difference",
            SetOp::SymmetricDifference => "xor",
        }
    }

    /// The operator on memberships.
    #[inline]
    #[must_use]
    pub fn apply(self, a: bool, b: bool) -> bool {
        match self {
            SetOp::Union => a | b,
            SetOp::Intersection => a & b,
            SetOp::Difference => a & !b,
            SetOp::SymmetricDifference => a ^ b,
        }
    }
}

crate::spelling::spelled!(SetOp);

/// The cursor of one operand in the sweep: its current run, if any is left.
struct Cursor<'a> {
    runs: Runs<'a>,
    run: Option<(u64, u64)>,
}

impl<'a> Cursor<'a> {
    fn new(mut runs: Runs<'a>) -> Self {
        let run = runs.next();
        Cursor { runs, run }
    }

    /// Drops runs that end at or before `pos`; returns membership at `pos` and the
    /// next boundary after `pos` (`limit` when none is left).
    #[inline]
    fn at(&mut self, pos: u64, limit: u64) -> (bool, u64) {
        while let Some((_, e)) = self.run {
            if e > pos {
                break;
            }
            self.run = self.runs.next();
        }
        match self.run {
            Some((s, e)) if s <= pos => (true, e),
            Some((s, _)) => (false, s),
            None => (false, limit),
        }
    }
}

/// The sweep: segments of `[lo, hi)` where `op(a, b)` holds (touching segments are
/// not coalesced; [`ranges::cut_runs`] does that). The runs may start before `lo` and
/// end after `hi`; only their parts in the range count.
pub(super) fn sweep<'a>(
    a: Runs<'a>,
    b: Runs<'a>,
    op: SetOp,
    lo: u64,
    hi: u64,
) -> impl Iterator<Item = (u64, u64)> + 'a {
    let (mut ca, mut cb) = (Cursor::new(a), Cursor::new(b));
    let mut pos = lo;
    std::iter::from_fn(move || {
        while pos < hi {
            let (in_a, next_a) = ca.at(pos, hi);
            let (in_b, next_b) = cb.at(pos, hi);
            let next = next_a.min(next_b).min(hi);
            let segment = (pos, next);
            pos = next;
            if op.apply(in_a, in_b) {
                return Some(segment);
            }
        }
        None
    })
}

impl LinearOctree {
    /// `self op other`, canonical; fails when the domains or depths differ.
    ///
    /// Runs as [`LinearOctree::combine_all`] of the two: in parallel over Morton
    /// ranges when the operands are large.
    pub fn combine(&self, other: &LinearOctree, op: SetOp) -> Result<LinearOctree> {
        LinearOctree::combine_all(&[self, other], op)
    }

    /// Voxels in either solid.
    pub fn union(&self, other: &LinearOctree) -> Result<LinearOctree> {
        self.combine(other, SetOp::Union)
    }

    /// Voxels in both solids.
    pub fn intersection(&self, other: &LinearOctree) -> Result<LinearOctree> {
        self.combine(other, SetOp::Intersection)
    }

    /// Voxels in `self` and not in `other`.
    pub fn difference(&self, other: &LinearOctree) -> Result<LinearOctree> {
        self.combine(other, SetOp::Difference)
    }

    /// Voxels in exactly one of the solids.
    pub fn symmetric_difference(&self, other: &LinearOctree) -> Result<LinearOctree> {
        self.combine(other, SetOp::SymmetricDifference)
    }

    /// Voxels of the domain not in `self`.
    #[must_use]
    pub fn complement(&self) -> LinearOctree {
        let domain = *self.domain();
        let full = LinearOctree::full(domain);
        let runs = sweep(full.runs(), self.runs(), SetOp::Difference, 0, domain.voxel_total());
        LinearOctree::from_canonical(domain, ranges::cut_runs(runs))
    }
}

macro_rules! binary_operator {
    ($trait:ident, $method:ident, $op:expr) => {
        impl $trait<&LinearOctree> for &LinearOctree {
            type Output = LinearOctree;

            /// # Panics
            /// When the operands' domains or depths differ (use the method for a `Result`).
            fn $method(self, rhs: &LinearOctree) -> LinearOctree {
                self.combine(rhs, $op).unwrap_or_else(|e| panic!("{e}"))
            }
        }
    };
}

binary_operator!(BitOr, bitor, SetOp::Union);
binary_operator!(BitAnd, bitand, SetOp::Intersection);
binary_operator!(Sub, sub, SetOp::Difference);
binary_operator!(BitXor, bitxor, SetOp::SymmetricDifference);

impl Not for &LinearOctree {
    type Output = LinearOctree;

    fn not(self) -> LinearOctree {
        self.complement()
    }
}

#[cfg(test)]
mod tests {
    use super::SetOp;

    #[test]
    fn every_set_op_reads_back_its_own_spelling_and_a_wrong_one_lists_them() {
        for op in SetOp::ALL {
            assert_eq!(op.to_string().parse::<SetOp>(), Ok(op));
        }
        assert_eq!(SetOp::ALL.map(SetOp::name), ["union", "intersect", "difference", "xor"]);
        assert_eq!("Union".parse::<SetOp>(), Err("\"Union\" is not union, intersect, difference or xor".to_owned()));
    }
}
