//! `octsolid join OUT.octs`: the last step of a sharded job spread over workers:
//! once every task (`--cells FIRST..END`) has left its part, the parts of the job are
//! checked to cover every cell once, every shard is checked against them, and the
//! solid (its index and shards) replaces `OUT.octs` in one step.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use octsolid::sharded;

use crate::sharded_output::{is_sharded, print_written};

/// Arguments of `octsolid join`.
#[derive(clap::Args, Debug)]
pub struct JoinArgs {
    /// The sharded solid (.octs) the tasks wrote parts of.
    pub output: PathBuf,
}

/// `octsolid join OUT.octs`
pub fn run(a: &JoinArgs) -> Result<()> {
    if !is_sharded(&a.output) {
        anyhow::bail!("{}: join makes a sharded solid (.octs)", a.output.display());
    }
    let started = Instant::now();
    let index = sharded::join(&a.output)?;
    print_written(&a.output, Some(&index), started);
    Ok(())
}
