//! Subcommands of the `octsolid` binary.

mod args;
mod commands;
mod progress_bar;

pub use args::Args;
pub use commands::run;
