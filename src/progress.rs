//! Progress reporting for long jobs, without printing from the library.
//!
//! Long jobs take a `&dyn Progress` and call it from any thread; the CLI implements it
//! with a terminal progress bar, tests and library users pass [`NoProgress`].

/// Receives the progress of a long job. Calls may come from several threads at once.
pub trait Progress: Sync {
    /// The job starts with `total` units of work.
    fn start(&self, _total: u64) {}
    /// `n` more units are done.
    fn advance(&self, _n: u64) {}
    /// The job ended.
    fn finish(&self) {}
}

/// Ignores all progress.
#[derive(Clone, Copy, Debug, Default)]
pub struct NoProgress;

impl Progress for NoProgress {}
