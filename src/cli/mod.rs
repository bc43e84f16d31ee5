//! Subcommands of the `octsolid` binary.

/// Prints a line to stdout, ignoring a closed pipe (`octsolid info x.oct | head -1`
/// must not panic).
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod args;
mod commands;
mod progress_bar;

pub use args::Args;
pub use commands::run;
