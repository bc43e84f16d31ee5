//! The k-way merge: one set operation over any number of linear octrees in one pass,
//! in parallel over Morton ranges.
//!
//! A chain of binary merges re-reads the accumulated result once per operand (a plate
//! minus 400 holes reads the plate 400 times); the k-way merge reads every operand
//! once. It sweeps the run boundaries of all `k` operands in Morton order, keeping
//! how many operands hold the current position (and whether the first does); between
//! two boundaries membership is constant, and the segments where the operator holds
//! are the result's runs, cut into the canonical node list by [`ranges::cut_runs`]:
//!
//! - union: in at least one operand; intersection: in all `k`;
//! - difference: in the first and in none of the others (`a - b - c ...`);
//! - symmetric difference: in an odd number (what the pairwise fold `a ^ b ^ c` gives).
//!
//! The next boundary comes from a binary heap of the operands' next boundaries,
//! `O(log k)` a boundary. Two operands take specialized merges instead: a union or a
//! difference [`super::two_way`]'s stretches of keys (runs the other operand leaves
//! alone are copied as they are, only where the runs meet is a run cut), an
//! intersection the overlaps of two pointers, a symmetric difference [`super::pairwise`]'s
//! two-cursor sweep. Time `O(n log k + output)` for `n` input nodes.
//!
//! **Parallelism.** The Morton range `[0, 8^depth)` is cut into chunks at equal shares
//! of the largest operand's keys (several a thread), and at the start and the end of
//! any key that holds such a cut inside it. So in each chunk an operand either has its
//! keys inside the chunk, a slice of its list that the merge takes as it is (an
//! operand's keys up to a boundary are the canonical keys of its part there), or one
//! key that holds the whole chunk, whose part in the chunk is cut to stand for it. The
//! chunks merge on their own (rayon) into plans, which [`plan::assemble`] writes into
//! the result in place, cutting again each run of the result that crosses a boundary.
//! The canonical form of a voxel set is unique, so the result is bit-identical to the
//! pairwise fold and to one sequential sweep, on any number of threads.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::pairwise::{SetOp, sweep};
use super::plan::{self, Plan};
use super::two_way;
use crate::error::{Error, Result};
use crate::octree::linear::LinearOctree;
use crate::octree::node::NodeKey;
use crate::octree::ranges::{self, Emit, Runs};

/// Input nodes below which a merge runs as one sweep (threads would cost more).
const PARALLEL_MIN_NODES: usize = 1 << 15;

/// Chunks a thread, so that uneven chunks still balance.
const CHUNKS_PER_THREAD: usize = 8;

impl LinearOctree {
    /// `op` over all `operands` (see the module doc for what each operator keeps),
    /// canonical; fails for no operands or operands over different domains or depths.
    pub fn combine_all(operands: &[&LinearOctree], op: SetOp) -> Result<LinearOctree> {
        let (first, rest) =
            operands.split_first().ok_or_else(|| Error::invalid("operands", "a set operation needs a solid"))?;
        for other in rest {
            first.check_same_domain(other)?;
        }
        let domain = *first.domain();
        if rest.is_empty() {
            return Ok((*first).clone());
        }
        let keys: Vec<&[NodeKey]> = operands.iter().map(|t| t.keys()).collect();
        let bounds = chunk_bounds(&keys, domain.voxel_total());
        Ok(LinearOctree::from_canonical(domain, merge_chunks(&keys, op, &bounds)))
    }
}

/// `op` over the operands' keys, each chunk between consecutive `bounds` (see
/// [`chunk_bounds`]) on its own: one chunk straight into the result, more in parallel
/// as plans written in place by [`plan::assemble`].
fn merge_chunks(keys: &[&[NodeKey]], op: SetOp, bounds: &[u64]) -> Vec<NodeKey> {
    if let [lo, hi] = *bounds {
        // About as many nodes out as in: reserved once (pages are only touched as written).
        let mut out = Vec::with_capacity(keys.iter().map(|k| k.len()).sum());
        merge_range(keys, op, lo, hi, &mut out);
        return out;
    }
    let plans: Vec<Plan> = bounds.par_windows(2).map(|w| plan_chunk(keys, op, w[0], w[1])).collect();
    plan::assemble(&plans)
}

/// The plan of `op` in the chunk `[lo, hi)`. An operand's keys there are the slice of
/// its keys that start in it, unless one of its keys holds more than the chunk: then
/// the chunk's part of that key, cut, stands for it, and the chunk's keys go into the
/// plan's own list (a copy, for the chunks inside a large key).
fn plan_chunk<'a>(keys: &[&'a [NodeKey]], op: SetOp, lo: u64, hi: u64) -> Plan<'a> {
    let holds_more = |k: &[NodeKey]| holding(k, lo).is_some_and(|key| key.start() < lo || key.end() > hi);
    if keys.iter().any(|k| holds_more(k)) {
        let mut part = Vec::new();
        ranges::cut_run(lo, hi, &mut part);
        let parts: Vec<&[NodeKey]> =
            keys.iter().map(|&k| if holds_more(k) { &part[..] } else { starting_in(k, lo, hi) }).collect();
        let mut own = Vec::new();
        merge_range(&parts, op, lo, hi, &mut own);
        return Plan::owning(own);
    }
    let parts: Vec<&[NodeKey]> = keys.iter().map(|k| starting_in(k, lo, hi)).collect();
    let mut plan = Plan::default();
    merge_range(&parts, op, lo, hi, &mut plan);
    plan
}

/// Chunk boundaries `0 = b0 < b1 < ... = total`, one chunk when the inputs are small
/// or there is one thread: equal shares of the largest operand's keys, refined so
/// that no key crosses a boundary without holding the chunks on both sides whole
/// ([`refined`]).
fn chunk_bounds(keys: &[&[NodeKey]], total: u64) -> Vec<u64> {
    let inputs: usize = keys.iter().map(|k| k.len()).sum();
    let threads = rayon::current_num_threads();
    let largest = keys.iter().max_by_key(|k| k.len()).expect("at least one operand");
    if inputs < PARALLEL_MIN_NODES || threads < 2 {
        return vec![0, total];
    }
    let chunks = threads * CHUNKS_PER_THREAD;
    refined(keys, (1..chunks).map(|c| largest[c * largest.len() / chunks].start()), total)
}

/// The boundaries `0`, `cuts` and `total`, and the start and the end of every key that
/// holds a cut inside it, sorted. In each chunk between them an operand then has
/// either all its keys that meet the chunk inside it, or one key that holds the chunk:
/// aligned keys nest or are disjoint, so a key that crosses a boundary holds the cut
/// that the boundary came from, and its own start and end are boundaries.
fn refined(keys: &[&[NodeKey]], cuts: impl IntoIterator<Item = u64>, total: u64) -> Vec<u64> {
    let mut bounds = vec![0, total];
    for at in cuts {
        bounds.push(at);
        for key in keys.iter().filter_map(|k| holding(k, at)).filter(|key| key.start() < at) {
            bounds.extend([key.start(), key.end()]);
        }
    }
    bounds.sort_unstable();
    bounds.dedup();
    bounds
}

/// The key of a sorted disjoint list that holds voxel `code`, if any.
fn holding(keys: &[NodeKey], code: u64) -> Option<NodeKey> {
    let i = keys.partition_point(|k| k.start() <= code).checked_sub(1)?;
    Some(keys[i]).filter(|k| k.end() > code)
}

/// The keys of a sorted disjoint list that start in `[lo, hi)`.
fn starting_in(keys: &[NodeKey], lo: u64, hi: u64) -> &[NodeKey] {
    &keys[keys.partition_point(|k| k.start() < lo)..keys.partition_point(|k| k.start() < hi)]
}

/// Emits `op` over the operands' keys that lie in `[lo, hi)`.
fn merge_range<'a>(operands: &[&'a [NodeKey]], op: SetOp, lo: u64, hi: u64, out: &mut impl Emit<'a>) {
    match (operands, op) {
        ([a, b], SetOp::Union) => two_way::union(a, b, out),
        ([a, b], SetOp::Difference) => two_way::difference(a, b, out),
        ([a, b], SetOp::Intersection) => ranges::emit_runs(IntersectionRuns::new(Runs::new(a), Runs::new(b)), out),
        ([a, b], SetOp::SymmetricDifference) => ranges::emit_runs(sweep(Runs::new(a), Runs::new(b), op, lo, hi), out),
        _ => ranges::emit_runs(HeapSweep::new(operands, op, lo, hi), out),
    }
}

/// The overlaps of two sorted run lists: the later start to the earlier end, then
/// the run that ends first is done.
struct IntersectionRuns<A, B> {
    a: A,
    b: B,
    x: Option<(u64, u64)>,
    y: Option<(u64, u64)>,
}

impl<A: Iterator<Item = (u64, u64)>, B: Iterator<Item = (u64, u64)>> IntersectionRuns<A, B> {
    fn new(mut a: A, mut b: B) -> Self {
        let (x, y) = (a.next(), b.next());
        IntersectionRuns { a, b, x, y }
    }
}

impl<A: Iterator<Item = (u64, u64)>, B: Iterator<Item = (u64, u64)>> Iterator for IntersectionRuns<A, B> {
    type Item = (u64, u64);

    #[inline]
    fn next(&mut self) -> Option<(u64, u64)> {
        while let (Some(x), Some(y)) = (self.x, self.y) {
            let overlap = (x.0.max(y.0), x.1.min(y.1));
            if x.1 <= y.1 {
                self.x = self.a.next();
            } else {
                self.y = self.b.next();
            }
            if overlap.0 < overlap.1 {
                return Some(overlap);
            }
        }
        None
    }
}

/// One operand's runs and where it stands in the sweep.
struct Operand<'a> {
    runs: Runs<'a>,
    /// The current run (the one holding or after the sweep's position).
    run: Option<(u64, u64)>,
    inside: bool,
}

/// The k-way sweep over `[lo, hi)` with a heap of next boundaries.
struct HeapSweep<'a> {
    operands: Vec<Operand<'a>>,
    /// `(next boundary, operand)`, smallest first.
    heap: BinaryHeap<Reverse<(u64, usize)>>,
    op: SetOp,
    /// Operands holding the current position.
    count: usize,
    pos: u64,
    hi: u64,
}

impl<'a> HeapSweep<'a> {
    fn new(keys: &[&'a [NodeKey]], op: SetOp, lo: u64, hi: u64) -> Self {
        let mut sweep =
            HeapSweep { operands: Vec::with_capacity(keys.len()), heap: BinaryHeap::new(), op, count: 0, pos: lo, hi };
        for (i, k) in keys.iter().enumerate() {
            let mut runs = Runs::new(k);
            let run = runs.next();
            // A run that starts at or before `lo` holds it (the keys meet the range).
            let inside = run.is_some_and(|(s, _)| s <= lo);
            sweep.count += usize::from(inside);
            sweep.operands.push(Operand { runs, run, inside });
            sweep.schedule(i);
        }
        sweep
    }

    /// Pushes operand `i`'s next boundary: the end of its run when inside, else the
    /// start of its run.
    fn schedule(&mut self, i: usize) {
        let o = &self.operands[i];
        if let Some((s, e)) = o.run {
            let next = if o.inside { e } else { s };
            if next < self.hi {
                self.heap.push(Reverse((next, i)));
            }
        }
    }

    /// Whether the operator holds with the current memberships.
    fn holds(&self) -> bool {
        let k = self.operands.len();
        match self.op {
            SetOp::Union => self.count > 0,
            SetOp::Intersection => self.count == k,
            SetOp::Difference => self.operands[0].inside && self.count == 1,
            SetOp::SymmetricDifference => self.count % 2 == 1,
        }
    }
}

impl Iterator for HeapSweep<'_> {
    type Item = (u64, u64);

    fn next(&mut self) -> Option<(u64, u64)> {
        while self.pos < self.hi {
            // Step 1: membership is constant up to the next boundary.
            let next = self.heap.peek().map_or(self.hi, |Reverse((b, _))| *b);
            let segment = (self.pos, next);
            let holds = self.holds();
            self.pos = next;
            // Step 2: operands whose boundary this is step in or out.
            while let Some(&Reverse((b, i))) = self.heap.peek() {
                if b != next {
                    break;
                }
                self.heap.pop();
                let o = &mut self.operands[i];
                if o.inside {
                    o.inside = false;
                    self.count -= 1;
                    o.run = o.runs.next();
                } else {
                    o.inside = true;
                    self.count += 1;
                }
                self.schedule(i);
            }
            if holds && segment.0 < segment.1 {
                return Some(segment);
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    /// A canonical key list in `[0, total)`: random runs of 1 to 512 voxels (nodes of
    /// every size, ragged ends), some touching.
    fn random_keys(rng: &mut Rng, total: u64) -> Vec<NodeKey> {
        let mut runs: Vec<(u64, u64)> = (0..rng.below(30))
            .map(|_| {
                let start = rng.below(total);
                (start, (start + (1 << rng.below(10))).min(total))
            })
            .collect();
        runs.sort_unstable();
        ranges::cut_runs(runs)
    }

    #[test]
    fn chunked_merges_are_the_voxelwise_operation_wherever_the_chunks_fall() {
        let total = 8u64.pow(4);
        let mut rng = Rng(0x5eed_c0de);
        for case in 0..300 {
            let lists: Vec<Vec<NodeKey>> = (0..2 + rng.below(2)).map(|_| random_keys(&mut rng, total)).collect();
            let keys: Vec<&[NodeKey]> = lists.iter().map(Vec::as_slice).collect();
            let cuts: Vec<u64> = (0..rng.below(40)).map(|_| rng.below(total)).collect();
            let bounds = refined(&keys, cuts, total);
            // Oracle: voxel by voxel, how many operands hold it and whether the first does.
            let inside: Vec<Vec<bool>> = keys
                .iter()
                .map(|k| (0..total).map(|v| k.iter().any(|key| (key.start()..key.end()).contains(&v))).collect())
                .collect();
            for op in [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference] {
                let holds = |v: usize| {
                    let count = inside.iter().filter(|i| i[v]).count();
                    match op {
                        SetOp::Union => count > 0,
                        SetOp::Intersection => count == keys.len(),
                        SetOp::Difference => inside[0][v] && count == 1,
                        SetOp::SymmetricDifference => count % 2 == 1,
                    }
                };
                let want = ranges::cut_runs((0..total).filter(|&v| holds(v as usize)).map(|v| (v, v + 1)));
                assert_eq!(merge_chunks(&keys, op, &[0, total]), want, "case {case}: {op:?} of {}", keys.len());
                assert_eq!(merge_chunks(&keys, op, &bounds), want, "case {case}: {op:?} in chunks {bounds:?}");
            }
        }
    }
}
