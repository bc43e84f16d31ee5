//! Morton ranges: the bridge between node lists and set operations.
//!
//! A canonical linear octree is exactly the greedy cut of its maximal runs of
//! consecutive voxel Morton codes into the largest aligned nodes: a node is in the
//! canonical list iff it is full and its parent is not, and the greedy cut of a run
//! `[a, b)` emits at each step the largest `8^k`-aligned block starting at `a` that
//! fits before `b`. So set operations only need to combine runs and cut the result.

use super::node::NodeKey;

/// Iterator over the maximal runs `[start, end)` of a sorted, disjoint key list:
/// touching nodes are coalesced into one run.
pub(crate) struct Runs<'a> {
    keys: std::slice::Iter<'a, NodeKey>,
    pending: Option<(u64, u64)>,
}

impl<'a> Runs<'a> {
    pub(crate) fn new(keys: &'a [NodeKey]) -> Self {
        let mut keys = keys.iter();
        let pending = keys.next().map(|k| (k.start(), k.end()));
        Runs { keys, pending }
    }
}

impl Iterator for Runs<'_> {
    type Item = (u64, u64);

    #[inline]
    fn next(&mut self) -> Option<(u64, u64)> {
        let (start, mut end) = self.pending?;
        for k in self.keys.by_ref() {
            if k.start() == end {
                end = k.end();
            } else {
                self.pending = Some((k.start(), k.end()));
                return Some((start, end));
            }
        }
        self.pending = None;
        Some((start, end))
    }
}

/// Appends the greedy cut of `[a, b)` into maximal aligned nodes to `out`. The
/// alignment of `a = 0` counts as the largest node, so a run inside a domain of depth
/// `d` (`b <= 8^d`) gives nodes of at most `8^d` voxels.
#[inline]
pub(crate) fn cut_run(mut a: u64, b: u64, out: &mut Vec<NodeKey>) {
    while a < b {
        // The largest k with a aligned to 8^k and 8^k <= b - a.
        let align_k = a.trailing_zeros() / 3;
        let fit_k = (63 - (b - a).leading_zeros()) / 3;
        let k = align_k.min(fit_k);
        out.push(NodeKey::new(a, k));
        a += 1u64 << (3 * k);
    }
}

/// Where canonical keys go, in Morton order: keys that are canonical already, and runs
/// to be cut into canonical nodes. Each call holds whole maximal runs of the result,
/// apart from the first and the last call of a merge over a Morton range, whose runs
/// may go on in the ranges before and after it.
pub(crate) trait Emit<'a> {
    /// Keys that go out as they are.
    fn keys(&mut self, keys: &'a [NodeKey]);
    /// The run `[start, end)`, to be cut.
    fn run(&mut self, start: u64, end: u64);
}

impl<'a> Emit<'a> for Vec<NodeKey> {
    #[inline]
    fn keys(&mut self, keys: &'a [NodeKey]) {
        self.extend_from_slice(keys);
    }

    #[inline]
    fn run(&mut self, start: u64, end: u64) {
        cut_run(start, end, self);
    }
}

/// Canonical keys from sorted runs that may touch but not overlap.
pub(crate) fn cut_runs(runs: impl IntoIterator<Item = (u64, u64)>) -> Vec<NodeKey> {
    let mut out = Vec::new();
    emit_runs(runs, &mut out);
    out
}

/// Emits sorted runs that may touch but not overlap, touching runs as one.
pub(crate) fn emit_runs<'a>(runs: impl IntoIterator<Item = (u64, u64)>, out: &mut impl Emit<'a>) {
    let mut current: Option<(u64, u64)> = None;
    for (a, b) in runs {
        if a >= b {
            continue;
        }
        match current {
            Some((s, e)) if a <= e => current = Some((s, e.max(b))),
            Some((s, e)) => {
                out.run(s, e);
                current = Some((a, b));
            }
            None => current = Some((a, b)),
        }
    }
    if let Some((s, e)) = current {
        out.run(s, e);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cut_is_maximal_and_covers_exactly() {
        for (a, b) in [(0u64, 512u64), (1, 100), (7, 9), (63, 65), (8, 72), (0, 1)] {
            let mut out = Vec::new();
            cut_run(a, b, &mut out);
            assert_eq!(out.first().unwrap().start(), a);
            assert_eq!(out.last().unwrap().end(), b);
            for w in out.windows(2) {
                assert_eq!(w[0].end(), w[1].start());
            }
            // Maximal: no node's parent lies wholly inside [a, b).
            for key in &out {
                if key.k() < 3 {
                    let p = key.parent();
                    assert!(p.start() < a || p.end() > b, "{key:?} could merge in {a}..{b}");
                }
            }
        }
    }
}
