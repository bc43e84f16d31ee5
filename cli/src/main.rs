//! The `octsolid` command line: a thin layer over the library.
//!
//! Raw arguments -> validated values -> one library call a subcommand. Every error is
//! printed as one line and exits with status 1 (2 for bad usage, from clap).

/// Prints a line to stdout. A closed pipe (`octsolid info x.oct | head -1`) is
/// ignored; any other failure (`> /dev/full`) is remembered, and the command then
/// exits with an error instead of losing its output silently.
macro_rules! out {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if let Err(e) = writeln!(std::io::stdout(), $($arg)*) {
            crate::stdout_failed(e);
        }
    }};
}

/// The first error writing stdout, other than a closed pipe.
static STDOUT_ERROR: std::sync::Mutex<Option<String>> = std::sync::Mutex::new(None);

fn stdout_failed(e: std::io::Error) {
    if e.kind() != std::io::ErrorKind::BrokenPipe {
        STDOUT_ERROR.lock().unwrap_or_else(std::sync::PoisonError::into_inner).get_or_insert(e.to_string());
    }
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
mod sharded_output;
mod solid_input;
mod values;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let args = args::Args::parse();
    let result = args::run(args).and_then(|()| {
        use std::io::Write as _;
        if let Err(e) = std::io::stdout().flush() {
            stdout_failed(e);
        }
        match STDOUT_ERROR.lock().unwrap_or_else(std::sync::PoisonError::into_inner).take() {
            Some(e) => Err(anyhow::anyhow!("cannot write the output to stdout: {e}")),
            None => Ok(()),
        }
    });
    match result {
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
