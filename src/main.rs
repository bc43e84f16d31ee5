//! The `octsolid` command line: a thin layer over the library.
//!
//! Raw arguments -> validated values -> one library call a subcommand. Every error is
//! printed as one line and exits with status 1 (2 for bad usage, from clap).

mod cli;

use std::process::ExitCode;

use clap::Parser;

fn main() -> ExitCode {
    let args = cli::Args::parse();
    match cli::run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("octsolid: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
