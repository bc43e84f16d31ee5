//! The command line's integration suites (the cli package's: they run the `octsolid`
//! binary), one test binary, as `tests/library.rs` is the library's: each suite is a
//! file of its own beside this one and a module here, loaded with `#[path]` so its
//! `mod common;` resolves from `tests/`. Run one suite with its module's name as the
//! filter: `cargo test --release --test command_line readme_walkthrough::`.

// Every suite keeps its own `mod common;`, as when it was a crate of its own, so a
// file of tests/common/ is a module of each suite that uses it.
#![allow(clippy::duplicate_mod)]

#[path = "chapter.rs"]
mod chapter;
#[path = "cli.rs"]
mod cli;
#[path = "distributed.rs"]
mod distributed;
#[path = "first_hour.rs"]
mod first_hour;
#[path = "readme_walkthrough.rs"]
mod readme_walkthrough;
#[path = "sharded_processes.rs"]
mod sharded_processes;
#[path = "threads.rs"]
mod threads;
#[path = "view.rs"]
mod view;
#[path = "view_browser.rs"]
mod view_browser;
