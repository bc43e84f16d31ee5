//! A long call's set-up: its `memory_budget=` ([`crate::budget`]) and `progress=`
//! ([`crate::progress`]) made into the library's budget and a reporter, and its work run
//! without the GIL. Every call that takes both goes through [`Job::run`], so each does
//! them in the one order: the work with the GIL released, then `KeyboardInterrupt` if
//! Ctrl-C stopped it, then the progress callable's exception if it raised one (it comes
//! first: the work may have failed because of it), then the work's error as the Python
//! exception of its kind.
//!
//! Ctrl-C: Python runs its signal handlers only on the main thread, holding the GIL,
//! which the work does not hold. So the work runs on a thread of its own while the
//! calling thread waits for it, taking the GIL back every [`SIGNAL_POLL`] to run the
//! handlers (`PyErr_CheckSignals`). When one raises (`KeyboardInterrupt`, or what a
//! handler the user installed raises), the reporter asks the library to stop
//! ([`octsolid::Progress::cancelled`]), the call waits for the work to return (at the
//! library's next poll: a row, a shot, a cell, a stage) and raises that exception. The
//! work's own result, if it finished first, is dropped, as Python drops a statement's
//! when the interrupt comes in it.

use std::sync::mpsc::{RecvTimeoutError, channel};
use std::time::Duration;

use octsolid::MemoryBudget;
use pyo3::prelude::*;

use crate::budget::{Budget, budget_of};
use crate::errors::to_py;
use crate::progress::{Reporter, Want};

/// How often a waiting call runs Python's signal handlers: the longest Ctrl-C waits
/// before the library is asked to stop.
const SIGNAL_POLL: Duration = Duration::from_millis(100);

/// A call's budget and where its progress goes.
pub struct Job {
    /// The budget given, or the library's default.
    pub budget: MemoryBudget,
    /// What reports the progress: a bar labelled as the call's step, a callable or nothing.
    reporter: Reporter,
}

impl Job {
    /// The job of a call given `memory_budget` and `progress` (a bar labelled `label`
    /// for `True`).
    pub fn new(memory_budget: Option<Budget>, progress: Option<Want>, label: &'static str) -> Job {
        Job { budget: budget_of(memory_budget), reporter: progress.unwrap_or(Want::Nothing).reporter(label) }
    }

    /// Runs `work` with the budget and the reporter, without the GIL (module doc).
    pub fn run<T: Send>(
        self,
        py: Python<'_>,
        work: impl FnOnce(MemoryBudget, &Reporter) -> octsolid::Result<T> + Send,
    ) -> PyResult<T> {
        self.run_or(py, work, to_py)
    }

    /// [`Job::run`] with the work's error made into a Python exception by `raise`.
    pub fn run_or<T: Send>(
        self,
        py: Python<'_>,
        work: impl FnOnce(MemoryBudget, &Reporter) -> octsolid::Result<T> + Send,
        raise: impl FnOnce(octsolid::Error) -> PyErr,
    ) -> PyResult<T> {
        let Job { budget, reporter } = self;
        let (done, interrupt) = interruptible(py, &reporter, || work(budget, &reporter));
        if let Some(interrupt) = interrupt {
            return Err(interrupt);
        }
        reporter.check()?;
        done.map_err(raise)
    }
}

/// Runs `work` on a thread of its own while this one runs Python's signal handlers
/// (module doc); the work's result and the exception a handler raised, if one did.
fn interruptible<T: Send>(py: Python<'_>, reporter: &Reporter, work: impl FnOnce() -> T + Send) -> (T, Option<PyErr>) {
    std::thread::scope(|scope| {
        let (finished, wait) = channel::<()>();
        let worker = scope.spawn(move || {
            let done = work();
            // Dropped unsent when `work` panics: the wait ends either way.
            let _ = finished.send(());
            done
        });
        let (mut wait, mut interrupt) = (wait, None);
        loop {
            // The receiver goes into the wait and comes back (it is not `Sync`).
            let waited;
            (wait, waited) = py.detach(move || {
                let waited = wait.recv_timeout(SIGNAL_POLL);
                (wait, waited)
            });
            if !matches!(waited, Err(RecvTimeoutError::Timeout)) {
                break;
            }
            if interrupt.is_none()
                && let Err(e) = py.check_signals()
            {
                reporter.stop();
                interrupt = Some(e);
            }
        }
        match worker.join() {
            Ok(done) => (done, interrupt),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    })
}
