//! The chunks of a parallel merge written once, in place, into the result.
//!
//! Each chunk of a merge over Morton ranges ([`super::merge`]) first makes a [`Plan`]:
//! its canonical keys as pieces, slices of the operands that go out as they are
//! ([`Emit::keys`]) and the cuts of its runs, kept in the plan ([`Emit::run`]). A
//! union's plan is nearly all slices; a difference keeps the cuts of the runs that the
//! other operand breaks, the sweeps of the other operators all their keys. Then the
//! chunks' node counts give each chunk its place in the result, allocated once, and
//! the chunks copy their pieces into their places in parallel: no list is joined
//! after another, and each page of the result is first touched by the thread that
//! writes it.
//!
//! **Seams.** A run of the result that crosses a chunk boundary comes out cut in two,
//! which may not be canonical (two halves of a node). Where the last run of a chunk's
//! keys ends at the start of the next chunk's first run, the run across the seam
//! (which may cross several chunks) is cut as one and written by the chunk where it
//! starts, in place of its last run; the chunks it goes on into leave their first run
//! out. The canonical form of a voxel set is unique, so the result is the keys of one
//! sequential sweep, on any number of threads.

use std::mem::MaybeUninit;

use rayon::prelude::*;

use crate::octree::node::NodeKey;
use crate::octree::ranges::{self, Emit};

/// One piece of a chunk's keys.
enum Piece<'a> {
    /// Keys of an operand, as they are.
    Keys(&'a [NodeKey]),
    /// Keys in the plan's own list, `own[from..to]`.
    Own(usize, usize),
}

/// A chunk's canonical keys, as pieces in Morton order.
#[derive(Default)]
pub(super) struct Plan<'a> {
    pieces: Vec<Piece<'a>>,
    /// Keys the plan holds itself: the cuts of runs, or all its keys ([`Plan::owning`]).
    own: Vec<NodeKey>,
}

impl<'a> Emit<'a> for Plan<'a> {
    #[inline]
    fn keys(&mut self, keys: &'a [NodeKey]) {
        if !keys.is_empty() {
            self.pieces.push(Piece::Keys(keys));
        }
    }

    #[inline]
    fn run(&mut self, start: u64, end: u64) {
        let from = self.own.len();
        ranges::cut_run(start, end, &mut self.own);
        let to = self.own.len();
        match self.pieces.last_mut() {
            Some(Piece::Own(_, last)) if *last == from => *last = to,
            _ => self.pieces.push(Piece::Own(from, to)),
        }
    }
}

/// A maximal run of a chunk's keys and how many keys it has.
#[derive(Clone, Copy)]
struct Run {
    start: u64,
    end: u64,
    nodes: usize,
}

impl Plan<'_> {
    /// The plan of keys of its own.
    pub(super) fn owning(own: Vec<NodeKey>) -> Self {
        let pieces = if own.is_empty() { Vec::new() } else { vec![Piece::Own(0, own.len())] };
        Plan { pieces, own }
    }

    /// The pieces as slices of keys (none is empty).
    fn slices(&self) -> impl DoubleEndedIterator<Item = &[NodeKey]> {
        self.pieces.iter().map(|p| match *p {
            Piece::Keys(keys) => keys,
            Piece::Own(from, to) => &self.own[from..to],
        })
    }

    /// How many keys the plan holds.
    fn len(&self) -> usize {
        self.slices().map(<[NodeKey]>::len).sum()
    }

    /// The first run: the contiguous keys at the front of the first piece (no run goes
    /// on into the next piece: each holds whole runs).
    fn head(&self) -> Option<Run> {
        let keys = self.slices().next()?;
        let nodes = 1 + keys.windows(2).take_while(|w| w[0].end() == w[1].start()).count();
        Some(Run { start: keys[0].start(), end: keys[nodes - 1].end(), nodes })
    }

    /// The last run: the contiguous keys at the back of the last piece.
    fn tail(&self) -> Option<Run> {
        let keys = self.slices().next_back()?;
        let nodes = 1 + keys.windows(2).rev().take_while(|w| w[0].end() == w[1].start()).count();
        Some(Run { start: keys[keys.len() - nodes].start(), end: keys[keys.len() - 1].end(), nodes })
    }
}

/// What a chunk writes: its keys `[from, to)` and then the run across the seam that
/// starts in it, cut.
struct Share {
    from: usize,
    to: usize,
    seam: Vec<NodeKey>,
}

impl Share {
    fn len(&self) -> usize {
        self.to - self.from + self.seam.len()
    }

    /// Writes the share of `plan` into `slot`, which it fills.
    fn write(&self, plan: &Plan, slot: &mut [MaybeUninit<NodeKey>]) {
        let (mut at, mut written) = (0, 0);
        for keys in plan.slices() {
            let (from, to) = (self.from.clamp(at, at + keys.len()), self.to.clamp(at, at + keys.len()));
            if from < to {
                let n = to - from;
                slot[written..written + n].write_copy_of_slice(&keys[from - at..to - at]);
                written += n;
            }
            at += keys.len();
        }
        slot[written..].write_copy_of_slice(&self.seam);
    }
}

/// The chunks' keys, from their plans in Morton order, as one canonical list.
pub(super) fn assemble(plans: &[Plan]) -> Vec<NodeKey> {
    let mut shares: Vec<Share> = plans.iter().map(|p| Share { from: 0, to: p.len(), seam: Vec::new() }).collect();
    // The chunk whose last run the next chunk may continue, and that run so far.
    let mut open: Option<(usize, u64, u64)> = None;
    for (c, plan) in plans.iter().enumerate() {
        let (Some(head), Some(tail)) = (plan.head(), plan.tail()) else {
            continue;
        };
        if let Some((owner, start, end)) = open
            && end == head.start
        {
            if shares[owner].seam.is_empty() {
                shares[owner].to -= plans[owner].tail().map_or(0, |t| t.nodes);
            }
            shares[owner].seam.clear();
            ranges::cut_run(start, head.end, &mut shares[owner].seam);
            shares[c].from = head.nodes;
            if head.nodes == shares[c].to {
                // The chunk is one run: the next chunk may continue it too.
                open = Some((owner, start, head.end));
                continue;
            }
        }
        open = Some((c, tail.start, tail.end));
    }
    let total = shares.iter().map(Share::len).sum();
    let mut keys = Vec::with_capacity(total);
    let mut slots = Vec::with_capacity(shares.len());
    let mut rest = &mut keys.spare_capacity_mut()[..total];
    for share in &shares {
        let (slot, after) = rest.split_at_mut(share.len());
        slots.push(slot);
        rest = after;
    }
    plans.par_iter().zip(&shares).zip(slots).for_each(|((plan, share), slot)| share.write(plan, slot));
    // SAFETY: the slots are `keys[..total]` cut in consecutive pieces, and each chunk
    // has filled its slot (`Share::write` copies the share's length, or panics).
    unsafe { keys.set_len(total) };
    keys
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan_of(keys: &[NodeKey]) -> Plan<'_> {
        let mut plan = Plan::default();
        plan.keys(keys);
        plan
    }

    fn cut(start: u64, end: u64) -> Vec<NodeKey> {
        let mut keys = Vec::new();
        ranges::cut_run(start, end, &mut keys);
        keys
    }

    #[test]
    fn runs_cut_at_seams_are_cut_again() {
        // [0, 64) at depth 2 cut at 8 and at 16: one node, not eight.
        let (a, b, c) = (cut(0, 8), cut(8, 16), cut(16, 64));
        assert_eq!(assemble(&[plan_of(&a), plan_of(&b), plan_of(&c)]), vec![NodeKey::new(0, 2)]);
        // Runs on both sides of the seams stay as they are; an empty chunk between.
        let mut left = cut(0, 3);
        left.extend(cut(5, 8));
        let mut right = cut(8, 16);
        right.extend(cut(20, 21));
        let mut run_pieces = Plan::default();
        run_pieces.run(64, 65);
        run_pieces.run(66, 72);
        let plans = [plan_of(&left), plan_of(&right), Plan::default(), run_pieces, plan_of(&[])];
        let mut want = cut(0, 3);
        want.extend(cut(5, 16));
        want.extend(cut(20, 21));
        want.extend(cut(64, 65));
        want.extend(cut(66, 72));
        assert_eq!(assemble(&plans), want);
    }
}
