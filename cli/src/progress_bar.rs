//! The library's [`Progress`] shown to the user: a progress bar on a terminal, plain
//! lines on stderr otherwise (a log, CI, a pipe), one every few seconds, so that long
//! work never looks like a hang. `OCTSOLID_PROGRESS_SECONDS` sets the interval of the
//! plain lines (default 5; 0 prints every update, for tests).

use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};
use octsolid::Progress;

/// Progress with a message, e.g. "voxelizing".
pub enum Bar {
    /// A terminal: an indicatif bar.
    Terminal(ProgressBar),
    /// Not a terminal: a line every `every`.
    Lines(Lines),
}

/// Plain progress lines.
pub struct Lines {
    message: &'static str,
    total: AtomicU64,
    done: AtomicU64,
    started: Instant,
    last: Mutex<Instant>,
    every: Duration,
}

impl Bar {
    pub fn new(message: &'static str) -> Self {
        if std::io::stderr().is_terminal() {
            let bar = ProgressBar::new(0);
            bar.set_style(
                ProgressStyle::with_template("{msg:>12} [{bar:40}] {percent:>3}% {elapsed_precise} eta {eta}")
                    .expect("valid template")
                    .progress_chars("=> "),
            );
            bar.set_message(message);
            return Bar::Terminal(bar);
        }
        let seconds = std::env::var("OCTSOLID_PROGRESS_SECONDS").ok().and_then(|s| s.parse::<f64>().ok());
        let every = Duration::from_secs_f64(seconds.filter(|s| s.is_finite() && *s >= 0.0).unwrap_or(5.0));
        let now = Instant::now();
        Bar::Lines(Lines {
            message,
            total: AtomicU64::new(0),
            done: AtomicU64::new(0),
            started: now,
            last: Mutex::new(now),
            every,
        })
    }
}

impl Lines {
    fn report(&self, force: bool) {
        let mut last = self.last.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if !force && last.elapsed() < self.every {
            return;
        }
        *last = Instant::now();
        let (done, total) = (self.done.load(Ordering::Relaxed), self.total.load(Ordering::Relaxed));
        let percent = if total == 0 { 100.0 } else { 100.0 * done as f64 / total as f64 };
        eprintln!("{}: {percent:.0}% ({:.1} s)", self.message, self.started.elapsed().as_secs_f64());
    }
}

impl Progress for Bar {
    fn start(&self, total: u64) {
        match self {
            Bar::Terminal(bar) => {
                bar.set_length(total);
                bar.set_position(0);
            }
            Bar::Lines(lines) => {
                lines.total.store(total, Ordering::Relaxed);
                lines.done.store(0, Ordering::Relaxed);
            }
        }
    }
    fn advance(&self, n: u64) {
        match self {
            Bar::Terminal(bar) => bar.inc(n),
            Bar::Lines(lines) => {
                lines.done.fetch_add(n, Ordering::Relaxed);
                lines.report(false);
            }
        }
    }
    fn finish(&self) {
        match self {
            Bar::Terminal(bar) => bar.finish_and_clear(),
            // Short work says nothing; long work ends its lines with 100%.
            Bar::Lines(lines) if lines.started.elapsed() >= lines.every && !lines.every.is_zero() => {
                lines.done.store(lines.total.load(Ordering::Relaxed), Ordering::Relaxed);
                lines.report(true);
            }
            Bar::Lines(_) => {}
        }
    }
    fn cancelled(&self) -> bool {
        crate::interrupt::interrupted()
    }
}

/// A spinner with the elapsed time, for work whose library call reports no progress
/// (reading or writing a whole file): on a terminal it ticks by itself until dropped
/// and then clears; elsewhere it shows nothing (the command's summary gives the time).
pub struct Spinner(Option<ProgressBar>);

impl Spinner {
    pub fn new(message: &'static str) -> Self {
        if !std::io::stderr().is_terminal() {
            return Spinner(None);
        }
        let bar = ProgressBar::new_spinner();
        bar.set_style(ProgressStyle::with_template("{msg:>12} {spinner} {elapsed_precise}").expect("valid template"));
        bar.set_message(message);
        bar.enable_steady_tick(Duration::from_millis(120));
        Spinner(Some(bar))
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        if let Some(bar) = &self.0 {
            bar.finish_and_clear();
        }
    }
}
