//! `octsolid bench [--report] [--quick] [--out FILE] [--threads N] [--models DIR]`: the
//! octree against BVH crates (the harness's matrix).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use octsolid::MemoryBudget;
use octsolid_harness::markdown::render_section;
use octsolid_harness::report::IMAGES;
use octsolid_harness::{MatrixOptions, run_matrix, write_report};

use crate::progress_bar::Bar;

/// Arguments of `octsolid bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// Write the report: the section of --out between its bvh-report markers (the whole page for a new file), and plots in docs/images/.
    #[arg(long)]
    pub report: bool,
    /// A smaller matrix (depths 8 and 10, fewer rays, fewer runs).
    #[arg(long)]
    pub quick: bool,
    /// The Markdown file of the report.
    #[arg(long, default_value = "docs/bvh-report.md")]
    pub out: PathBuf,
    /// Threads of the "all threads" runs (default: all hardware threads).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Folder holding stanford-bunny.obj.
    #[arg(long, default_value = "models")]
    pub models: PathBuf,
}

/// `octsolid bench [--report] [--quick] [--out FILE] [--threads N] [--models DIR]`
pub fn run(a: &BenchArgs, budget: MemoryBudget) -> Result<()> {
    let mut options = if a.quick { MatrixOptions::quick() } else { MatrixOptions::full() };
    if let Some(n) = a.threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        options.threads = n;
    }
    options.models = a.models.clone();
    options.budget = budget;
    let started = Instant::now();
    let bar = Bar::new("benchmarking");
    let results = run_matrix(&options, &bar)?;
    out!("ran the matrix in {:.0} s", started.elapsed().as_secs_f64());
    if a.report {
        for path in write_report(&results, &a.out)? {
            out!("wrote {}", path.display());
        }
    } else {
        out!("{}", render_section(&results, IMAGES, &[]));
    }
    Ok(())
}
