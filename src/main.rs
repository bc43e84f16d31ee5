//! The `octsolid` command line.
fn main() {}
