//! A progress bar for long calls given `progress=True`: the library's [`Progress`]
//! drawn on the standard error as `label: 42% (3.1 s)`, redrawn at most ten times a
//! second, and only when the standard error is a terminal (a notebook, a pipe or a
//! log gets nothing), as the `octsolid` command's bars.

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use octsolid::Progress;

/// Least time between two redraws.
const REDRAW: Duration = Duration::from_millis(100);

/// A bar on the terminal, or nothing.
pub struct Bar {
    label: &'static str,
    /// Whether anything is drawn: asked for, and the standard error a terminal.
    on: bool,
    started: Instant,
    total: AtomicU64,
    done: AtomicU64,
    /// When the bar was last drawn.
    drawn: Mutex<Option<Instant>>,
}

impl Bar {
    /// A bar labelled `label`, drawn when `wanted` and the standard error is a terminal.
    pub fn new(label: &'static str, wanted: bool) -> Self {
        Bar {
            label,
            on: wanted && std::io::stderr().is_terminal(),
            started: Instant::now(),
            total: AtomicU64::new(0),
            done: AtomicU64::new(0),
            drawn: Mutex::new(None),
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
