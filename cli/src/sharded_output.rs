//! Sharded solids (`-o NAME.octs`, a folder of shards and an index) on the command
//! line: the flags that steer writing one, the summary of one written, and the peak
//! memory of the process (what a memory budget is about).

use std::ops::Range;
use std::path::Path;
use std::time::Instant;

use anyhow::{Result, bail};
use octsolid::sharded::{ShardIndex, StreamOptions};
use octsolid::{FileKind, MemoryBudget, Progress, human_bytes};

use crate::progress_bar::Bar;

/// Flags of a sharded output.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ShardFlags {
    /// Sharded output (.octs): cut the domain into the 8^L cells L levels below the
    /// root, one shard a cell the surface crosses (default: cells of 2^11 voxels a
    /// side, one cell up to depth 11).
    #[arg(long, value_name = "L")]
    pub shard_level: Option<u8>,
    /// Sharded output: make only the cells FIRST..END (numbers in Morton order, of
    /// 8^L): one task of a job spread over workers, which leaves a part file;
    /// `octsolid join OUT.octs` makes the solid once every cell is made.
    #[arg(long, value_name = "FIRST..END", value_parser = parse_cells)]
    pub cells: Option<Range<u64>>,
}

impl ShardFlags {
    /// The library's options for these flags.
    pub fn options<'a>(&'a self, budget: MemoryBudget, progress: &'a dyn Progress) -> StreamOptions<'a> {
        StreamOptions { level: self.shard_level, cells: self.cells.as_ref(), budget, progress, source: job_source() }
    }

    /// Runs the sharded job `job` writing `output` with these flags' options and a
    /// progress bar of cells, then prints what it wrote (from `started`: the job's
    /// reading counts too).
    pub fn write(
        &self,
        output: &Path,
        budget: MemoryBudget,
        started: Instant,
        job: impl FnOnce(&StreamOptions) -> Result<Option<ShardIndex>>,
    ) -> Result<()> {
        let bar = Bar::new("cells");
        let written = job(&self.options(budget, &bar))?;
        drop(bar);
        print_written(output, written.as_ref(), started);
        Ok(())
    }

    /// Refuses the flags for an output that is not sharded.
    pub fn check_for(&self, output: &Path) -> Result<()> {
        if (self.shard_level.is_some() || self.cells.is_some()) && !is_sharded(output) {
            bail!("{}: --shard-level and --cells are for a sharded output (.octs)", output.display());
        }
        Ok(())
    }
}

/// What a sharded job makes, for its identity: this command line's arguments without
/// `--cells` (what the tasks of a job differ in) and the output (where, not what),
/// NUL-separated.
fn job_source() -> &'static [u8] {
    static SOURCE: std::sync::OnceLock<Vec<u8>> = std::sync::OnceLock::new();
    SOURCE.get_or_init(|| {
        let mut out = Vec::new();
        let mut args = std::env::args_os().skip(1);
        while let Some(arg) = args.next() {
            let bytes = arg.as_encoded_bytes();
            if ["--cells", "-o", "--output"].iter().any(|flag| bytes == flag.as_bytes()) {
                args.next();
            } else if !["--cells=", "--output=", "-o"].iter().any(|flag| bytes.starts_with(flag.as_bytes())) {
                out.extend_from_slice(arg.as_encoded_bytes());
                out.push(0);
            }
        }
        out
    })
}

/// `FIRST..END` with `FIRST <= END`.
fn parse_cells(s: &str) -> Result<Range<u64>, String> {
    let (a, b) = s.split_once("..").ok_or_else(|| format!("{s:?} is not FIRST..END"))?;
    let parse = |v: &str| v.trim().parse::<u64>().map_err(|e| format!("{v:?} in {s:?}: {e}"));
    let (a, b) = (parse(a)?, parse(b)?);
    if a > b {
        return Err(format!("{s:?}: FIRST is after END"));
    }
    Ok(a..b)
}

/// Whether `path` names a sharded solid (`.octs`, [`FileKind::Octs`]).
pub fn is_sharded(path: &Path) -> bool {
    FileKind::of(path, &[FileKind::Octs]).is_ok()
}

/// Prints what a sharded job wrote: the solid (with the index) or a task's part.
pub fn print_written(out: &Path, written: Option<&ShardIndex>, started: Instant) {
    let seconds = started.elapsed().as_secs_f64();
    match written {
        Some(index) => {
            let on_disk: u64 = index.shards.iter().map(|s| s.bytes).sum();
            out!(
                "wrote {} in {seconds:.2} s: {} shard{} ({}) and {} full nodes at cell level {}",
                out.display(),
                index.shards.len(),
                if index.shards.len() == 1 { "" } else { "s" },
                human_bytes(on_disk),
                index.full.len(),
                index.level
            );
            print_index_summary(index);
        }
        None => out!(
            "wrote a part of {} in {seconds:.2} s (`octsolid join {}` once every cell is made)",
            out.display(),
            out.display()
        ),
    }
    if let Some(peak) = peak_memory() {
        out!("peak mem.  {}", human_bytes(peak));
    }
}

/// Nodes, voxels, volume and bounds, from the index alone.
pub fn print_index_summary(index: &ShardIndex) {
    let d = index.domain;
    out!("nodes      {}", index.nodes);
    out!("voxels     {}", index.voxels);
    out!("volume     {:.6}", index.voxels as f64 * d.voxel_size().powi(3));
    match index.voxel_bounds() {
        Some((lo, hi)) => {
            let world = |c: [u32; 3]| d.lattice_point(c).to_array();
            out!("bounds     {} .. {}", crate::human::point(world(lo)), crate::human::point(world(hi)));
        }
        None => out!("bounds     (empty)"),
    }
}

/// The process's peak resident memory (Linux's `VmHWM`), when the system says.
pub fn peak_memory() -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kib * 1024)
}
