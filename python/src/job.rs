//! A long call's set-up: its `memory_budget=` ([`crate::budget`]) and `progress=`
//! ([`crate::progress`]) made into the library's budget and a reporter, and its work run
//! without the GIL. Every call that takes both goes through [`Job::run`], so each does
//! them in the one order: the work with the GIL released, then the progress callable's
//! exception if it raised one (it comes first: the work may have failed because of
//! it), then the work's error as the Python exception of its kind.

use octsolid::MemoryBudget;
use pyo3::prelude::*;

use crate::budget::{Budget, budget_of};
use crate::errors::to_py;
use crate::progress::{Reporter, Want};

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
        let done = py.detach(|| work(budget, &reporter));
        reporter.check()?;
        done.map_err(raise)
    }
}
