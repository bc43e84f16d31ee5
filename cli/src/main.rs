//! The `octsolid` command line: a thin layer over the library.
//!
//! Raw arguments -> validated values -> one library call a subcommand. Every error is
//! printed as one line and exits with status 1 (2 for a command line clap refuses).

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
mod drawn;
mod http;
mod human;
mod interrupt;
mod output;
mod progress_bar;
mod sharded_output;
mod solid_input;
mod stages;
mod values;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let args = match args::Args::try_parse() {
        Ok(args) => args,
        Err(e) => return usage_error(&e),
    };
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
        Err(e) if e.chain().any(|c| matches!(c.downcast_ref(), Some(octsolid::Error::Cancelled))) => {
            eprintln!("octsolid: interrupted; nothing written");
            ExitCode::from(130)
        }
        Err(e) => {
            eprintln!("octsolid: error: {}", one_line(&e));
            ExitCode::FAILURE
        }
    }
}

/// An error as one line: the context chain, each cause once (a library error already
/// names its source).
pub(crate) fn one_line(e: &anyhow::Error) -> String {
    let mut line = String::new();
    for cause in e.chain().map(ToString::to_string) {
        if !line.contains(&cause) {
            if !line.is_empty() {
                line.push_str(": ");
            }
            line.push_str(&cause);
        }
    }
    line
}

/// A command line clap refuses, as one line with status 2 (help and the version are
/// printed as clap prints them): clap's first paragraph, its lines joined, and where
/// the usage is.
fn usage_error(e: &clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(
        e.kind(),
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    ) {
        // Printed and checked here (clap's own exit ignores a failed write: `--help >
        // /dev/full` exited 0).
        use std::io::Write as _;
        return match e.print().and_then(|()| std::io::stdout().flush()) {
            Ok(()) => ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(1)),
            Err(w) => {
                eprintln!("octsolid: error: cannot write the help to stdout: {w}");
                ExitCode::FAILURE
            }
        };
    }
    let text = e.render().to_string();
    let paragraph: Vec<&str> = text.lines().take_while(|l| !l.trim().is_empty()).map(str::trim).collect();
    let message = paragraph.join(" ");
    let message = message.strip_prefix("error: ").unwrap_or(&message);
    eprintln!("octsolid: error: {message} (--help shows the usage)");
    ExitCode::from(2)
}
