//! Progress reporting for long jobs, without printing from the library.
//!
//! Long jobs take a `&dyn Progress` and call it from any thread; the CLI implements it
//! with a terminal progress bar, tests and library users pass [`NoProgress`]. A job
//! made of several jobs in a row (a round's four offsets, a resample's extraction and
//! voxelization, an extraction's dual contouring, untangling, merge and
//! simplification, the last weighted by what each takes) reports through [`Stages`],
//! so its bar fills once.
//!
//! A job also asks its [`Progress`] whether to stop ([`Progress::cancelled`]): between
//! units of work (a row of pixels, a radiosity shot, a cell of a voxelization, a
//! stage) it polls, and once the answer is yes it returns [`crate::Error::Cancelled`]
//! without its result, having written nothing (outputs are written whole or not at
//! all, `atomic`). Python's Ctrl-C stops a long call this way; the CLI is stopped by
//! the signal itself.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

/// Receives the progress of a long job. Calls may come from several threads at once.
pub trait Progress: Sync {
    /// The job starts with `total` units of work.
    fn start(&self, _total: u64) {}
    /// `n` more units are done.
    fn advance(&self, _n: u64) {}
    /// The job ended.
    fn finish(&self) {}
    /// Whether the job should stop: once true, the job returns
    /// [`crate::Error::Cancelled`] at its next poll (module doc). Once true it must stay
    /// true (a job skips work at one poll and reports the stop at a later one). Polled
    /// from any thread, often: it must be cheap (an atomic load).
    fn cancelled(&self) -> bool {
        false
    }
}

/// A job's part that shows no progress of its own but stops with the job: reports
/// nothing to its inner [`Progress`], asks it whether to stop.
pub(crate) struct CancelOnly<'a>(pub &'a dyn Progress);

impl Progress for CancelOnly<'_> {
    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}

/// [`crate::Error::Cancelled`] when `progress` asks the job to stop.
pub(crate) fn stop_if_cancelled(progress: &dyn Progress) -> crate::Result<()> {
    if progress.cancelled() { Err(crate::Error::Cancelled) } else { Ok(()) }
}

/// Ignores all progress.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}

/// The bar's units a stage of weight 1: a stage's own units are scaled to its weight
/// times these.
const STAGE_UNITS: u64 = 1 << 20;

/// One job of `count` stages run one after another on one [`Progress`]: each stage
/// reports as a job of its own (its `start`, `advance`s and `finish`, as the library's
/// jobs do) and fills its share of the bar (equal shares, or as weighted), so the bar
/// goes once from 0 to 100% instead of once a stage. A stage's share is shown whole (unless the job was cancelled)
/// when the next one starts or it finishes; starts beyond `count` add nothing; the
/// last stage's `finish` (or the drop, when a stage failed or never started) finishes
/// the bar.
pub struct Stages<'a> {
    inner: &'a dyn Progress,
    /// Each stage's share of the bar, in bar units (all [`STAGE_UNITS`] when equal).
    shares: Vec<u64>,
    /// Stages started so far.
    started: AtomicU64,
    /// The current stage's total and units done, and how many bar units it has shown.
    total: AtomicU64,
    done: AtomicU64,
    shown: AtomicU64,
    finished: AtomicBool,
}

impl<'a> Stages<'a> {
    /// Starts `inner` for a job of `count` stages of equal shares.
    pub fn new(inner: &'a dyn Progress, count: u64) -> Self {
        let shares = vec![STAGE_UNITS; usize::try_from(count).unwrap_or(0)];
        Self::of_shares(inner, shares)
    }

    /// Starts `inner` for a job of one stage a weight, each filling a share of the bar
    /// in proportion to its weight (what it is expected to take of the job's time).
    pub fn weighted(inner: &'a dyn Progress, weights: &[u64]) -> Self {
        Self::of_shares(inner, weights.iter().map(|&w| w.saturating_mul(STAGE_UNITS)).collect())
    }

    fn of_shares(inner: &'a dyn Progress, shares: Vec<u64>) -> Self {
        inner.start(shares.iter().fold(0, |sum: u64, &s| sum.saturating_add(s)));
        Stages {
            inner,
            shares,
            started: AtomicU64::new(0),
            total: AtomicU64::new(0),
            done: AtomicU64::new(0),
            shown: AtomicU64::new(0),
            finished: AtomicBool::new(false),
        }
    }

    /// The bar units of stage `started` (from 1); 0 past the last.
    fn share(&self, started: u64) -> u64 {
        usize::try_from(started).ok().and_then(|i| self.shares.get(i.checked_sub(1)?)).copied().unwrap_or(0)
    }

    /// Shows the current stage as whole (what it has not shown yet).
    fn complete_stage(&self) {
        let share = self.share(self.started.load(Ordering::Relaxed));
        let shown = self.shown.swap(share, Ordering::Relaxed);
        if shown < share {
            self.inner.advance(share - shown);
        }
    }
}

impl Progress for Stages<'_> {
    fn start(&self, total: u64) {
        self.complete_stage();
        self.started.fetch_add(1, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
        self.done.store(0, Ordering::Relaxed);
        // Past `count` a stage shows nothing: its share is none.
        self.shown.store(0, Ordering::Relaxed);
    }

    fn advance(&self, n: u64) {
        let total = self.total.load(Ordering::Relaxed);
        let share = self.share(self.started.load(Ordering::Relaxed));
        let done = self.done.fetch_add(n, Ordering::Relaxed).saturating_add(n);
        let units = match total {
            0 => share,
            _ => (u128::from(done.min(total)) * u128::from(share) / u128::from(total)) as u64,
        };
        let shown = self.shown.fetch_max(units, Ordering::Relaxed);
        if units > shown {
            self.inner.advance(units - shown);
        }
    }

    fn cancelled(&self) -> bool {
        self.inner.cancelled()
    }

    fn finish(&self) {
        // A cancelled job's stage is not shown whole: it stopped short.
        if !self.cancelled() {
            self.complete_stage();
        }
        if self.started.load(Ordering::Relaxed) >= self.shares.len() as u64
            && !self.finished.swap(true, Ordering::Relaxed)
        {
            self.inner.finish();
        }
    }
}

impl Drop for Stages<'_> {
    fn drop(&mut self) {
        if !self.finished.load(Ordering::Relaxed) {
            self.inner.finish();
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Mutex;

    use rayon::prelude::*;

    use super::*;

    /// Every call.
    #[derive(Default)]
    struct Recorded {
        starts: Mutex<Vec<u64>>,
        advances: Mutex<Vec<u64>>,
        done: AtomicU64,
        finishes: AtomicU64,
    }

    impl Progress for Recorded {
        fn start(&self, total: u64) {
            self.starts.lock().unwrap().push(total);
        }
        fn advance(&self, n: u64) {
            self.done.fetch_add(n, Ordering::Relaxed);
            self.advances.lock().unwrap().push(n);
        }
        fn finish(&self) {
            self.finishes.fetch_add(1, Ordering::Relaxed);
        }
    }

    /// A stage as the library's jobs report: start, advances from several threads,
    /// finish (or not).
    fn stage(progress: &dyn Progress, total: u64, finish: bool) {
        progress.start(total);
        (0..total).into_par_iter().for_each(|_| progress.advance(1));
        if finish {
            progress.finish();
        }
    }

    #[test]
    fn stages_fill_one_bar_once() {
        let bar = Recorded::default();
        {
            let stages = Stages::new(&bar, 3);
            stage(&stages, 1000, true);
            assert_eq!(bar.done.load(Ordering::Relaxed), STAGE_UNITS);
            // A stage's steps move the bar as they come: each advance that raises the
            // stage's scaled units shows (one that another thread's overtook folds
            // into it), so the bar moved many times, not once at the stage's end.
            assert!(bar.advances.lock().unwrap().len() > 100);
            // A stage that does not finish is shown whole when the next starts.
            stage(&stages, 7, false);
            stage(&stages, 12_345, true);
            assert_eq!(bar.finishes.load(Ordering::Relaxed), 1, "the last stage finishes the bar");
        }
        assert_eq!(*bar.starts.lock().unwrap(), vec![3 * STAGE_UNITS]);
        assert_eq!(bar.done.load(Ordering::Relaxed), 3 * STAGE_UNITS);
        assert_eq!(bar.finishes.load(Ordering::Relaxed), 1, "and the drop does not again");
        // The bar only moves on (its starts: one).
        assert!(bar.advances.lock().unwrap().iter().all(|&n| n > 0));
    }

    #[test]
    fn weighted_stages_fill_their_shares() {
        let bar = Recorded::default();
        {
            let stages = Stages::weighted(&bar, &[1, 3, 0]);
            assert_eq!(*bar.starts.lock().unwrap(), vec![4 * STAGE_UNITS]);
            stage(&stages, 10, true);
            assert_eq!(bar.done.load(Ordering::Relaxed), STAGE_UNITS);
            // Half the second stage's work is half its three shares.
            stages.start(100);
            (0..50).into_par_iter().for_each(|_| stages.advance(1));
            assert_eq!(bar.done.load(Ordering::Relaxed), STAGE_UNITS + 3 * STAGE_UNITS / 2);
            stages.finish();
            assert_eq!(bar.done.load(Ordering::Relaxed), 4 * STAGE_UNITS);
            assert_eq!(bar.finishes.load(Ordering::Relaxed), 0, "a stage is left");
            stage(&stages, 5, true);
        }
        assert_eq!(bar.done.load(Ordering::Relaxed), 4 * STAGE_UNITS);
        assert_eq!(bar.finishes.load(Ordering::Relaxed), 1);
    }

    #[test]
    fn stages_past_their_count_and_missing_ones_stay_within_the_bar() {
        let bar = Recorded::default();
        {
            let stages = Stages::new(&bar, 2);
            stage(&stages, 10, true);
            stage(&stages, 10, true);
            stage(&stages, 10, true);
            stage(&stages, 0, true);
        }
        assert_eq!(bar.done.load(Ordering::Relaxed), 2 * STAGE_UNITS);
        assert_eq!(bar.finishes.load(Ordering::Relaxed), 1);
        // A job that fails after its first stage: the drop finishes the bar.
        let bar = Recorded::default();
        {
            let stages = Stages::new(&bar, 4);
            stage(&stages, 10, true);
            assert_eq!(bar.finishes.load(Ordering::Relaxed), 0);
        }
        assert_eq!(bar.done.load(Ordering::Relaxed), STAGE_UNITS);
        assert_eq!(bar.finishes.load(Ordering::Relaxed), 1);
    }
}
