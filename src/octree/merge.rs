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
//! `O(log k)` a boundary. Two operands take the textbook interval merges instead: a
//! union is the runs of both merged by start (overlapping or touching runs cut as one),
//! an intersection the overlaps of two pointers, a difference each run with the
//! other's runs cut out; a symmetric difference [`super::csg`]'s two-cursor sweep. A
//! union's or difference's run that comes out as it went in (no run of the other
//! operand meets it) is copied key for key instead of cut again: the greedy cut of a
//! maximal run is the canonical list's own keys for it. Time
//! `O(n log k + output)` for `n` input nodes.
//!
//! **Parallelism.** The Morton range `[0, 8^depth)` is cut into chunks at key starts of
//! the largest operand (equal shares of its keys, several a thread), each chunk is
//! swept and cut on its own (rayon), and the chunks' node lists are joined in order.
//! A run of the result that crosses a chunk boundary comes out cut in two, which may
//! not be canonical (two halves of a node), so at each join the maximal run across
//! the boundary (the contiguous keys before and after it) is cut again. The canonical
//! form of a voxel set is unique, so the result is bit-identical to the pairwise fold
//! and to one sequential sweep, on any number of threads.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use rayon::prelude::*;

use super::csg::{SetOp, sweep};
use super::linear::LinearOctree;
use super::node::NodeKey;
use super::ranges::{self, Runs};
use crate::error::{Error, Result};

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
        let max_k = u32::from(domain.depth());
        let chunks = chunk_bounds(&keys, domain.voxel_total());
        let parts: Vec<Vec<NodeKey>> = chunks
            .par_windows(2)
            .map(|w| {
                let (lo, hi) = (w[0], w[1]);
                let clipped: Vec<&[NodeKey]> = keys.iter().map(|k| overlapping(k, lo, hi)).collect();
                cut_chunk(&clipped, op, lo, hi, max_k)
            })
            .collect();
        Ok(LinearOctree::from_canonical(domain, join(parts, max_k)))
    }
}

/// Chunk boundaries `0 = b0 < b1 < ... = total`: equal shares of the largest operand's
/// keys, one chunk when the inputs are small or there is one thread.
fn chunk_bounds(keys: &[&[NodeKey]], total: u64) -> Vec<u64> {
    let inputs: usize = keys.iter().map(|k| k.len()).sum();
    let threads = rayon::current_num_threads();
    let largest = keys.iter().max_by_key(|k| k.len()).expect("at least one operand");
    let mut bounds = vec![0];
    if inputs >= PARALLEL_MIN_NODES && threads > 1 {
        let chunks = threads * CHUNKS_PER_THREAD;
        bounds.extend((1..chunks).map(|c| largest[c * largest.len() / chunks].start()));
        bounds.dedup();
    }
    if bounds.last() != Some(&total) {
        bounds.push(total);
    }
    bounds
}

/// The keys of a sorted disjoint list that meet `[lo, hi)`.
fn overlapping(keys: &[NodeKey], lo: u64, hi: u64) -> &[NodeKey] {
    let from = keys.partition_point(|k| k.end() <= lo);
    let to = keys.partition_point(|k| k.start() < hi);
    &keys[from..to.max(from)]
}

/// The canonical keys of `op` over the operands (keys meeting `[lo, hi)`) in `[lo, hi)`.
fn cut_chunk(operands: &[&[NodeKey]], op: SetOp, lo: u64, hi: u64, max_k: u32) -> Vec<NodeKey> {
    // About as many nodes out as in: reserved once (pages are only touched as written).
    let out = Vec::with_capacity(operands.iter().map(|k| k.len()).sum());
    let clipped = |keys| Runs::new(keys).map(move |(s, e): (u64, u64)| (s.max(lo), e.min(hi)));
    match (operands, op) {
        ([a, b], SetOp::Union) => {
            let mut out = out;
            union_into(a, b, lo, hi, max_k, &mut out);
            out
        }
        ([a, b], SetOp::Intersection) => {
            ranges::cut_runs_into(IntersectionRuns::new(clipped(a), clipped(b)), max_k, out)
        }
        ([a, b], SetOp::Difference) => {
            let mut out = out;
            difference_into(a, b, lo, hi, max_k, &mut out);
            out
        }
        ([a, b], SetOp::SymmetricDifference) => {
            ranges::cut_runs_into(sweep(Runs::new(a), Runs::new(b), op, lo, hi), max_k, out)
        }
        _ => ranges::cut_runs_into(HeapSweep::new(operands, op, lo, hi), max_k, out),
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

/// A maximal run of a canonical key list with the keys that make it, clipped to a
/// chunk: `verbatim` when the clip left it whole, so that its keys are its greedy cut.
#[derive(Clone, Copy)]
struct KeyRun<'a> {
    start: u64,
    end: u64,
    keys: &'a [NodeKey],
    verbatim: bool,
}

/// The maximal runs of a sorted disjoint key list, clipped to `[lo, hi)`.
struct KeyRuns<'a> {
    keys: &'a [NodeKey],
    lo: u64,
    hi: u64,
}

impl<'a> Iterator for KeyRuns<'a> {
    type Item = KeyRun<'a>;

    #[inline]
    fn next(&mut self) -> Option<KeyRun<'a>> {
        let first = self.keys.first()?;
        let (start, mut end, mut n) = (first.start(), first.end(), 1);
        while let Some(k) = self.keys.get(n).filter(|k| k.start() == end) {
            end = k.end();
            n += 1;
        }
        let (keys, rest) = self.keys.split_at(n);
        self.keys = rest;
        let verbatim = start >= self.lo && end <= self.hi;
        Some(KeyRun { start: start.max(self.lo), end: end.min(self.hi), keys, verbatim })
    }
}

/// Appends the union of two canonical key lists (meeting `[lo, hi)`) in `[lo, hi)`: the
/// runs by start, each group of overlapping or touching runs cut as one run, except a
/// run that meets no other, whose keys are copied as they are (the greedy cut of a
/// maximal run is the canonical list's own keys for it).
fn union_into(a: &[NodeKey], b: &[NodeKey], lo: u64, hi: u64, max_k: u32, out: &mut Vec<NodeKey>) {
    let mut a = KeyRuns { keys: a, lo, hi }.peekable();
    let mut b = KeyRuns { keys: b, lo, hi }.peekable();
    // The run that starts first of the two lists' next runs.
    let mut earliest = move || match (a.peek(), b.peek()) {
        (Some(x), Some(y)) if y.start < x.start => b.next(),
        (Some(_), _) => a.next(),
        (None, _) => b.next(),
    };
    let mut next = earliest();
    while let Some(run) = next {
        let (start, mut end, mut alone) = (run.start, run.end, true);
        next = earliest();
        while let Some(other) = next.filter(|o| o.start <= end) {
            end = end.max(other.end);
            alone = false;
            next = earliest();
        }
        if alone && run.verbatim {
            out.extend_from_slice(run.keys);
        } else {
            ranges::cut_run(start, end, max_k, out);
        }
    }
}

/// Appends `a - b` of two canonical key lists (meeting `[lo, hi)`) in `[lo, hi)`: each
/// run of `a` with `b`'s runs cut out, a run that no run of `b` overlaps copied as it is.
fn difference_into(a: &[NodeKey], b: &[NodeKey], lo: u64, hi: u64, max_k: u32, out: &mut Vec<NodeKey>) {
    let mut cuts = KeyRuns { keys: b, lo, hi }.peekable();
    for run in (KeyRuns { keys: a, lo, hi }) {
        let (mut pos, mut cut) = (run.start, false);
        while let Some(c) = cuts.peek().copied() {
            if c.end <= pos {
                cuts.next();
                continue;
            }
            if c.start >= run.end {
                break;
            }
            // The cut overlaps what is left of the run: keep the part before it.
            cut = true;
            if pos < c.start {
                ranges::cut_run(pos, c.start, max_k, out);
            }
            pos = c.end;
            if c.end > run.end {
                break; // It reaches into the next run too.
            }
            cuts.next();
        }
        if !cut && run.verbatim {
            out.extend_from_slice(run.keys);
        } else if pos < run.end {
            ranges::cut_run(pos, run.end, max_k, out);
        }
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

/// The chunks' node lists in order, each maximal run across a join cut again.
fn join(parts: Vec<Vec<NodeKey>>, max_k: u32) -> Vec<NodeKey> {
    let total: usize = parts.iter().map(Vec::len).sum();
    let mut parts = parts.into_iter();
    // The first part is the start of the output: no copy.
    let mut out = parts.next().unwrap_or_default();
    out.reserve_exact(total - out.len());
    for part in parts {
        let touching = matches!((out.last(), part.first()), (Some(l), Some(f)) if l.end() == f.start());
        if !touching {
            out.extend(part);
            continue;
        }
        // The run ending at the join: contiguous keys back from the end of `out` ...
        let mut from = out.len() - 1;
        while from > 0 && out[from - 1].end() == out[from].start() {
            from -= 1;
        }
        // ... and on into `part`.
        let mut to = 0;
        while to + 1 < part.len() && part[to].end() == part[to + 1].start() {
            to += 1;
        }
        let (start, end) = (out[from].start(), part[to].end());
        out.truncate(from);
        ranges::cut_run(start, end, max_k, &mut out);
        out.extend_from_slice(&part[to + 1..]);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_cut_at_a_join_is_cut_again() {
        // [0, 64) at depth 2 cut in two chunks at 8: one node, not eight.
        let mut left = Vec::new();
        ranges::cut_run(0, 8, 2, &mut left);
        let mut right = Vec::new();
        ranges::cut_run(8, 64, 2, &mut right);
        assert_eq!(join(vec![left, right], 2), vec![NodeKey::new(0, 2)]);
    }
}
