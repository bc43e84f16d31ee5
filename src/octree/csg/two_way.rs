//! The union and the difference of two canonical key lists, by stretches of keys.
//!
//! The canonical list of a voxel set is the greedy cut of its maximal runs
//! ([`crate::octree::ranges`]), and the greedy cut of a maximal run restricted to a prefix that
//! ends on one of its keys' boundaries is the run's keys up to there (a node whose
//! parent fits in the prefix would fit in the whole run). So a maximal run of one
//! operand that the other operand does not change comes out as the same keys, and
//! whole stretches of such runs are copied with one slice copy; only where the runs of
//! the two lists meet is a run cut again:
//!
//! - **union**: the runs of the list whose next key starts first are its own up to the
//!   last run that ends before the other list's next key with a gap (a run that touches
//!   or overlaps it joins it); then, if the first list's next key starts no later than
//!   the other's, a group of overlapping or touching runs of both lists, cut as one;
//! - **difference** `a - b`: the runs of `a` that end at or before `b`'s next key are
//!   kept whole (touching takes nothing away), keys of `b` in the gaps of `a` are
//!   skipped, and a run of `a` that a key of `b` overlaps is cut in the pieces between
//!   `b`'s keys.
//!
//! Finding a stretch reads each key once (its end, compared with one bound), so the
//! time is linear in the input with a slice copy for most of the output, where a sweep
//! over runs pays a decision a run and a cut a node. Either operand may be a Morton
//! range of a larger list that no key of either list crosses (see [`super::merge`]).

use crate::octree::node::NodeKey;
use crate::octree::ranges::Emit;

/// How many keys at the front of `keys` make whole runs that end at or before `bound`:
/// the keys that end by then, less the run that goes on past it.
#[inline]
fn runs_ending_by(keys: &[NodeKey], bound: u64) -> usize {
    let Some(mut n) = keys.iter().position(|k| k.last() >= bound) else {
        return keys.len();
    };
    while n > 0 && keys[n - 1].end() == keys[n].start() {
        n -= 1;
    }
    n
}

/// The union of two canonical key lists (see the module doc).
pub(super) fn union<'a>(mut a: &'a [NodeKey], mut b: &'a [NodeKey], out: &mut impl Emit<'a>) {
    loop {
        let (Some(x), Some(y)) = (a.first(), b.first()) else {
            out.keys(a);
            out.keys(b);
            return;
        };
        // `a` is the list whose next key starts first.
        if y.start() < x.start() {
            std::mem::swap(&mut a, &mut b);
        }
        let limit = b[0].start();
        // Runs that end before `limit` with a gap (none when `limit` is 0).
        let n = if limit == 0 { 0 } else { runs_ending_by(a, limit - 1) };
        out.keys(&a[..n]);
        a = &a[n..];
        if a.first().is_some_and(|k| k.start() <= limit) {
            // `a`'s next run meets `b`'s next key: the group of runs that overlap or touch.
            let (start, mut end) = (a[0].start(), a[0].end());
            a = &a[1..];
            loop {
                if let Some(k) = a.first().filter(|k| k.start() <= end) {
                    end = end.max(k.end());
                    a = &a[1..];
                } else if let Some(k) = b.first().filter(|k| k.start() <= end) {
                    end = end.max(k.end());
                    b = &b[1..];
                } else {
                    break;
                }
            }
            out.run(start, end);
        }
    }
}

/// `a - b` of two canonical key lists (see the module doc).
pub(super) fn difference<'a>(mut a: &'a [NodeKey], mut b: &'a [NodeKey], out: &mut impl Emit<'a>) {
    while let Some(x) = a.first() {
        let Some(y) = b.first() else {
            out.keys(a);
            return;
        };
        if y.end() <= x.start() {
            // `b`'s keys in a gap of `a` take nothing away.
            b = &b[b.iter().position(|k| k.end() > x.start()).unwrap_or(b.len())..];
            continue;
        }
        let n = runs_ending_by(a, y.start());
        out.keys(&a[..n]);
        a = &a[n..];
        let Some(first) = a.first() else {
            return;
        };
        if first.start() >= y.end() {
            continue; // `y` lies in a gap of `a`.
        }
        // The run of `a` from `first` overlaps `y`: the pieces between `b`'s keys.
        let (start, mut end) = (first.start(), first.end());
        a = &a[1..];
        while let Some(k) = a.first().filter(|k| k.start() == end) {
            end = k.end();
            a = &a[1..];
        }
        let mut pos = start;
        while let Some(c) = b.first().filter(|c| c.start() < end) {
            if c.start() > pos {
                out.run(pos, c.start());
            }
            pos = pos.max(c.end());
            if c.end() > end {
                break; // It reaches into the next run of `a` too.
            }
            b = &b[1..];
        }
        if pos < end {
            out.run(pos, end);
        }
    }
}
