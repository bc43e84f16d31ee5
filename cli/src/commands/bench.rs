//! `octsolid bench [--report] [--quick] [--out FILE] [--threads N] [--models DIR]
//! [--issue-rays | --matrix-only] [--no-perf]`: the octree against BVH crates (the
//! harness's matrix), then issue 41's incoherent rays (the harness's `secondary_bench`)
//! in their own section of the same file; `--issue-rays` runs only the latter,
//! `--matrix-only` only the former.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Result, bail};
use octsolid::MemoryBudget;
use octsolid_harness::markdown::render_section;
use octsolid_harness::report::IMAGES;
use octsolid_harness::secondary_markdown::render_secondary;
use octsolid_harness::{
    MatrixOptions, SecondaryOptions, run_matrix, run_secondary, write_report, write_secondary_report,
};

use crate::progress_bar::Bar;

/// Arguments of `octsolid bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// Write the report: the section of --out between its bvh-report markers (the whole page for a new file), and plots in docs/images/.
    #[arg(long)]
    pub report: bool,
    /// A smaller matrix (depths 8 and 10, fewer rays, fewer runs), and issue 41's rays from a 256x256 view, one run.
    #[arg(long)]
    pub quick: bool,
    /// The Markdown file of the report.
    #[arg(long, default_value = "docs/bvh-report.md")]
    pub out: PathBuf,
    /// Threads of the "all threads" runs (default: all hardware threads).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Folder holding stanford-bunny.obj (the matrix) and bunny-watertight.obj (issue 41's rays).
    #[arg(long, default_value = "models")]
    pub models: PathBuf,
    /// Only issue 41's incoherent rays (run after the matrix otherwise): primary, bounce and shadow rays of a 1024x1024 view of models/bunny-watertight.obj at depth 10, one thread, with embreex (target/peers-venv) and branch misses (perf stat) when available.
    #[arg(long, conflicts_with = "matrix_only")]
    pub issue_rays: bool,
    /// Only the matrix, not issue 41's rays.
    #[arg(long)]
    pub matrix_only: bool,
    /// Issue 41's rays without branch misses (no perf stat, no build of walk_one).
    #[arg(long)]
    pub no_perf: bool,
}

/// `octsolid bench [--report] [--quick] [--out FILE] [--threads N] [--models DIR] [--issue-rays | --matrix-only] [--no-perf]`
pub fn run(a: &BenchArgs, budget: MemoryBudget) -> Result<()> {
    if a.issue_rays {
        return issue_rays(a, budget);
    }
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
    if a.matrix_only { Ok(()) } else { issue_rays(a, budget) }
}

/// `octsolid bench --issue-rays [--report] [--quick] [--out FILE] [--models DIR] [--no-perf]`: `--quick`
/// is a 256x256 view and one run.
fn issue_rays(a: &BenchArgs, budget: MemoryBudget) -> Result<()> {
    let defaults = SecondaryOptions::default();
    let mut options = SecondaryOptions {
        model: a.models.join(defaults.model.file_name().unwrap_or_default()),
        branch_misses: !a.no_perf,
        budget,
        ..defaults
    };
    if a.quick {
        (options.size, options.repeats) = (256, 1);
    }
    let started = Instant::now();
    let bar = Bar::new("issue 41's rays");
    let results = run_secondary(&options, &bar)?;
    out!("measured issue 41's rays in {:.0} s", started.elapsed().as_secs_f64());
    if a.report {
        write_secondary_report(&results, &a.out)?;
        out!("wrote {}", a.out.display());
    } else {
        out!("{}", render_secondary(&results));
    }
    Ok(())
}
