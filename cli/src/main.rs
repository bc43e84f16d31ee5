//! The `octsolid` command line: a thin layer over the library.
//!
//! Raw arguments -> validated values -> one library call a subcommand. Every error is
//! printed as one line and exits with status 1 (2 for bad usage, from clap).

/// Prints a line to stdout, ignoring a closed pipe (`octsolid info x.oct | head -1`
/// must not panic).
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// Prints a warning to stderr: something was ignored or is probably not what the
/// user meant, but the command goes on.
macro_rules! warn {
    ($($arg:tt)*) => {{
        eprintln!("octsolid: warning: {}", format_args!($($arg)*));
    }};
}

mod args;
mod camera_flags;
mod commands;
mod output;
mod progress_bar;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let args = args::Args::parse();
    match commands::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the context chain, each cause once (a library error already
            // names its source).
            let mut line = String::new();
            for cause in e.chain().map(ToString::to_string) {
                if !line.contains(&cause) {
                    if !line.is_empty() {
                        line.push_str(": ");
                    }
                    line.push_str(&cause);
                }
            }
            eprintln!("octsolid: error: {line}");
            ExitCode::FAILURE
        }
    }
}
