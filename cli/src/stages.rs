//! Wall-clock time of each stage of a command (`render`'s loading, voxelizing,
//! rendering, writing), printed at the end with the total.

use std::time::Instant;

/// The stages finished so far and when.
pub(crate) struct Stages {
    started: Instant,
    last: Instant,
    done: Vec<(String, f64)>,
}

impl Stages {
    pub(crate) fn new() -> Self {
        let now = Instant::now();
        Stages { started: now, last: now, done: Vec::new() }
    }

    /// Marks `stage` finished now: its time is since the last one.
    pub(crate) fn done(&mut self, stage: impl Into<String>) {
        let now = Instant::now();
        self.done.push((stage.into(), (now - self.last).as_secs_f64()));
        self.last = now;
    }

    /// Prints `time  TOTAL s: stage s, ...`.
    pub(crate) fn report(&self) {
        let parts: Vec<String> = self.done.iter().map(|(stage, s)| format!("{stage} {s:.2} s")).collect();
        out!("time       {:.2} s: {}", self.started.elapsed().as_secs_f64(), parts.join(", "));
    }
}
