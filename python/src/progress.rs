//! `progress=`: what a long call reports its progress to, as the library's
//! [`Progress`]. `True` draws a bar on the standard error as `label: 42% (3.1 s)`,
//! redrawn at most ten times a second, and only when the standard error is a terminal
//! (a notebook, a pipe or a log gets nothing), as the `octsolid` command's bars. A
//! callable `f(done, total)` is called instead (tqdm's `update`, a notebook widget): at
//! the start with `(0, total)`, then at most twenty times a second while `done` grows
//! (never backwards, even when the library's threads report out of order), and at the
//! end with `(total, total)`. A call made of stages (a mesh's voxelizing, then its
//! writing) starts again at `(0, total)` for each.
//!
//! The library calls [`Progress`] from its worker threads with the GIL released; a
//! callable is called with the GIL taken back for the call. If it raises, it is not
//! called again, the work is asked to stop ([`Progress::cancelled`]) and the callable's
//! exception is raised when the work returns ([`Reporter::check`]).
//!
//! Ctrl-C stops the work: the reporter answers the library's
//! [`Progress::cancelled`] from [`Reporter::stop`], which `crate::job` sets when
//! Python's signal handler raised while the work ran (whatever `progress=` is).

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use octsolid::{NoProgress, Progress};
use pyo3::prelude::*;
use pyo3::types::PyBool;

use crate::errors::invalid;

/// Least time between two redraws of a bar.
const REDRAW: Duration = Duration::from_millis(100);

/// Least time between two calls of a callable (besides the first and the last).
const RECALL: Duration = Duration::from_millis(50);

/// The `progress=` argument: `None`/`False` (nothing), `True` (a bar on the terminal)
/// or a callable `f(done, total)`.
pub enum Want {
    /// Report nothing.
    Nothing,
    /// A bar on the standard error when it is a terminal.
    Bar,
    /// Call this with `(done, total)`.
    Call(Py<PyAny>),
}

impl<'a, 'py> FromPyObject<'a, 'py> for Want {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        if obj.is_none() {
            return Ok(Want::Nothing);
        }
        if let Ok(wanted) = obj.cast::<PyBool>() {
            return Ok(if wanted.is_true() { Want::Bar } else { Want::Nothing });
        }
        if obj.is_callable() {
            return Ok(Want::Call(obj.to_owned().unbind()));
        }
        let given = obj.get_type().name().map(|n| n.to_string()).unwrap_or_else(|_| "?".into());
        Err(invalid("progress", format!("need True, False, None or a callable f(done, total), not a {given}")))
    }
}

impl Want {
    /// What reports this call's progress, a bar labelled `label` for `True`.
    pub fn reporter(self, label: &'static str) -> Reporter {
        match self {
            Want::Nothing => Sink::Nothing(NoProgress),
            Want::Bar => Sink::Bar(Bar::new(label)),
            Want::Call(f) => Sink::Call(Callback::new(f)),
        }
        .into()
    }
}

/// Where one call's progress goes, and whether the call was interrupted: the
/// library's [`Progress`].
pub struct Reporter {
    sink: Sink,
    /// Set when the call is to stop (Ctrl-C, `crate::job`): the library's
    /// [`Progress::cancelled`].
    stop: AtomicBool,
}

/// Where one call's progress goes.
enum Sink {
    /// Nowhere.
    Nothing(NoProgress),
    /// A bar on the terminal.
    Bar(Bar),
    /// A Python callable.
    Call(Callback),
}

impl From<Sink> for Reporter {
    fn from(sink: Sink) -> Self {
        Reporter { sink, stop: AtomicBool::new(false) }
    }
}

impl Reporter {
    /// Asks the library's work to stop at its next poll.
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    /// The callable's exception, if it raised one while the work ran.
    pub fn check(self) -> PyResult<()> {
        match self.sink {
            Sink::Call(c) => c.raised.into_inner().map_or(Ok(()), |raised| raised.map_or(Ok(()), Err)),
            _ => Ok(()),
        }
    }

    /// Reports a step the library did not report as one whole step (`start(1)`,
    /// `finish()`), so a callable always ends at `(total, total)`: a file written at
    /// once. Nothing when the library reported steps.
    pub fn end_in_one_step(&self) {
        let silent = match &self.sink {
            Sink::Nothing(_) => false,
            Sink::Bar(b) => b.drawn.lock().is_ok_and(|d| d.is_none()) && b.total.load(Ordering::Relaxed) == 0,
            Sink::Call(c) => c.last.lock().is_ok_and(|l| l.is_none()),
        };
        if silent {
            self.start(1);
            self.finish();
        }
    }

    fn inner(&self) -> &dyn Progress {
        match &self.sink {
            Sink::Nothing(n) => n,
            Sink::Bar(b) => b,
            Sink::Call(c) => c,
        }
    }
}

impl Progress for Reporter {
    fn start(&self, total: u64) {
        self.inner().start(total);
    }
    fn advance(&self, n: u64) {
        self.inner().advance(n);
    }
    fn finish(&self) {
        if self.cancelled() {
            // Stopped short: no `(total, total)`, no 100%; a bar's line is ended.
            if let Sink::Bar(b) = &self.sink {
                b.end_line();
            }
            return;
        }
        self.inner().finish();
    }
    fn cancelled(&self) -> bool {
        self.stop.load(Ordering::Relaxed) || matches!(&self.sink, Sink::Call(c) if c.failed.load(Ordering::Relaxed))
    }
}

/// A bar on the terminal, or nothing.
pub struct Bar {
    label: &'static str,
    /// Whether anything is drawn: the standard error is a terminal.
    on: bool,
    started: Instant,
    total: AtomicU64,
    done: AtomicU64,
    /// When the bar was last drawn.
    drawn: Mutex<Option<Instant>>,
}

impl Bar {
    /// A bar labelled `label`, drawn when the standard error is a terminal.
    pub fn new(label: &'static str) -> Self {
        Bar {
            label,
            on: std::io::stderr().is_terminal(),
            started: Instant::now(),
            total: AtomicU64::new(0),
            done: AtomicU64::new(0),
            drawn: Mutex::new(None),
        }
    }

    /// Ends the bar's line where it stands (a job stopped short), if one was drawn.
    fn end_line(&self) {
        if self.on && self.drawn.lock().is_ok_and(|d| d.is_some()) {
            let _ = writeln!(std::io::stderr());
        }
    }

    fn draw(&self, force: bool) {
        if !self.on {
            return;
        }
        let Ok(mut drawn) = self.drawn.lock() else { return };
        let now = Instant::now();
        if !force && drawn.is_some_and(|t| now - t < REDRAW) {
            return;
        }
        *drawn = Some(now);
        let (done, total) = (self.done.load(Ordering::Relaxed), self.total.load(Ordering::Relaxed));
        let percent = (100 * done.min(total)).checked_div(total).unwrap_or(0);
        let seconds = (now - self.started).as_secs_f64();
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r{}: {percent:>3}% ({seconds:.1} s)", self.label);
        let _ = err.flush();
    }
}

impl Progress for Bar {
    fn start(&self, total: u64) {
        self.total.store(total, Ordering::Relaxed);
        self.done.store(0, Ordering::Relaxed);
        self.draw(true);
    }

    fn advance(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
        self.draw(false);
    }

    fn finish(&self) {
        if self.on {
            self.done.store(self.total.load(Ordering::Relaxed), Ordering::Relaxed);
            self.draw(true);
            let _ = writeln!(std::io::stderr());
        }
    }
}

/// A Python callable `f(done, total)` as a [`Progress`] (module doc).
pub struct Callback {
    f: Py<PyAny>,
    total: AtomicU64,
    done: AtomicU64,
    /// The last `done` reported and when; held while calling, so calls never overlap.
    last: Mutex<Option<(u64, Instant)>>,
    /// The callable's exception; once set, the callable is not called again.
    raised: Mutex<Option<PyErr>>,
    /// Whether it raised: the work is asked to stop ([`Reporter`]'s `cancelled`).
    failed: AtomicBool,
}

impl Callback {
    fn new(f: Py<PyAny>) -> Self {
        Callback {
            f,
            total: AtomicU64::new(0),
            done: AtomicU64::new(0),
            last: Mutex::new(None),
            raised: Mutex::new(None),
            failed: AtomicBool::new(false),
        }
    }

    /// Calls `f(done, total)` unless it raised before or `done` did not grow since the
    /// last call; `force` skips the rate limit, `fresh` (a stage's start) both rules.
    fn report(&self, force: bool, fresh: bool) {
        let Ok(mut last) = self.last.lock() else { return };
        let total = self.total.load(Ordering::Relaxed);
        let done = self.done.load(Ordering::Relaxed).min(total);
        let now = Instant::now();
        if let Some((before, at)) = *last
            && !fresh
            && (done <= before || (!force && now - at < RECALL))
        {
            return;
        }
        if self.raised.lock().map_or(true, |r| r.is_some()) {
            return;
        }
        *last = Some((done, now));
        if let Err(e) = Python::attach(|py| self.f.call1(py, (done, total)).map(drop))
            && let Ok(mut raised) = self.raised.lock()
        {
            raised.get_or_insert(e);
            self.failed.store(true, Ordering::Relaxed);
        }
    }
}

impl Progress for Callback {
    fn start(&self, total: u64) {
        self.total.store(total, Ordering::Relaxed);
        self.done.store(0, Ordering::Relaxed);
        self.report(true, true);
    }

    fn advance(&self, n: u64) {
        self.done.fetch_add(n, Ordering::Relaxed);
        self.report(false, false);
    }

    fn finish(&self) {
        self.done.store(self.total.load(Ordering::Relaxed), Ordering::Relaxed);
        self.report(true, false);
    }
}
