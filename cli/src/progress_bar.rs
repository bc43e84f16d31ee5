//! The library's [`Progress`] drawn as a terminal progress bar (hidden when stderr is
//! not a terminal).

use indicatif::{ProgressBar, ProgressStyle};
use octsolid::Progress;

/// A progress bar with a message, e.g. "voxelizing".
pub struct Bar(ProgressBar);

impl Bar {
    pub fn new(message: &'static str) -> Self {
        let bar = ProgressBar::new(0);
        bar.set_style(
            ProgressStyle::with_template("{msg:>12} [{bar:40}] {percent:>3}% {elapsed_precise} eta {eta}")
                .expect("valid template")
                .progress_chars("=> "),
        );
        bar.set_message(message);
        Bar(bar)
    }
}

impl Progress for Bar {
    fn start(&self, total: u64) {
        self.0.set_length(total);
        self.0.set_position(0);
    }
    fn advance(&self, n: u64) {
        self.0.inc(n);
    }
    fn finish(&self) {
        self.0.finish_and_clear();
    }
}
