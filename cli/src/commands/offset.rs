//! `octsolid offset IN --by D -o OUT` (or `--voxels N`), `octsolid shell IN --thickness T
//! -o OUT [--outward]` and `octsolid round IN --radius R -o OUT [--convex] [--concave]`:
//! a solid grown or shrunk by a ball, hollowed to a wall, or with its edges rounded, by
//! the library's exact band distance (`LinearOctree::offset`, `shell`, `round`).
//! Distances are world units unless `--voxels` says voxels; a file of several solids
//! works on their union.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use octsolid::octree::{LinearOctree, OffsetOptions};
use octsolid::{FileKind, MemoryBudget, human_bytes};

use super::print_summary;
use crate::output::{check_extension, check_not_an_input, write_solid_file};
use crate::progress_bar::Bar;
use crate::solid_input::{ReadFlags, read_solid_file};

/// Arguments of `octsolid offset`.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct OffsetArgs {
    /// The solid file: .oct, .octs, .vox, .binvox or .vdb.
    pub input: PathBuf,
    /// Output file: .oct, or .vox, .binvox, .vdb, .glb, or a mesh (.obj, .stl, .ply, .3mf).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Grow (positive) or shrink (negative) by this world distance.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_finite, conflicts_with = "voxels", required_unless_present = "voxels")]
    pub by: Option<f64>,
    /// Grow (positive) or shrink (negative) by this many voxels.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_finite)]
    pub voxels: Option<f64>,
    #[command(flatten)]
    pub read: ReadFlags,
}

/// Arguments of `octsolid shell`.
#[derive(clap::Args, Debug)]
pub struct ShellArgs {
    /// The solid file: .oct, .octs, .vox, .binvox or .vdb.
    pub input: PathBuf,
    /// Output file: .oct, or .vox, .binvox, .vdb, .glb, or a mesh (.obj, .stl, .ply, .3mf).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The wall's thickness, a world distance.
    #[arg(long, value_parser = crate::values::parse_finite)]
    pub thickness: f64,
    /// The wall outside the surface instead of inside it.
    #[arg(long)]
    pub outward: bool,
    #[command(flatten)]
    pub read: ReadFlags,
}

/// Arguments of `octsolid round`.
#[derive(clap::Args, Debug)]
pub struct RoundArgs {
    /// The solid file: .oct, .octs, .vox, .binvox or .vdb.
    pub input: PathBuf,
    /// Output file: .oct, or .vox, .binvox, .vdb, .glb, or a mesh (.obj, .stl, .ply, .3mf).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The rounding radius, a world distance.
    #[arg(long, value_parser = crate::values::parse_finite)]
    pub radius: f64,
    /// Round only the convex edges (an opening).
    #[arg(long)]
    pub convex: bool,
    /// Round only the concave edges (a closing).
    #[arg(long)]
    pub concave: bool,
    #[command(flatten)]
    pub read: ReadFlags,
}

/// `octsolid offset IN (--by D | --voxels N) -o OUT`
pub fn run_offset(a: &OffsetArgs, budget: MemoryBudget) -> Result<()> {
    let (by, voxels) = (a.by, a.voxels);
    apply(&a.input, &a.output, &a.read, budget, "offset", |tree, per_unit, options| {
        let d = voxels.unwrap_or_else(|| by.unwrap_or(0.0) * per_unit);
        Ok(tree.offset(d, options)?)
    })
}

/// `octsolid shell IN --thickness T -o OUT [--outward]`
pub fn run_shell(a: &ShellArgs, budget: MemoryBudget) -> Result<()> {
    if a.thickness <= 0.0 {
        bail!("--thickness must be positive, not {}", a.thickness);
    }
    apply(&a.input, &a.output, &a.read, budget, "shell", |tree, per_unit, options| {
        Ok(tree.shell(a.thickness * per_unit, a.outward, options)?)
    })
}

/// `octsolid round IN --radius R -o OUT [--convex] [--concave]`
pub fn run_round(a: &RoundArgs, budget: MemoryBudget) -> Result<()> {
    if a.radius <= 0.0 {
        bail!("--radius must be positive, not {}", a.radius);
    }
    // Neither flag: both kinds of edge.
    let (convex, concave) = if a.convex || a.concave { (a.convex, a.concave) } else { (true, true) };
    apply(&a.input, &a.output, &a.read, budget, "round", |tree, per_unit, options| {
        Ok(tree.round(a.radius * per_unit, convex, concave, options)?)
    })
}

/// Reads `input`'s union, runs `op` on it (given voxels a world unit) with a bar, and
/// writes the result to `output`.
fn apply(
    input: &std::path::Path,
    output: &std::path::Path,
    read: &ReadFlags,
    budget: MemoryBudget,
    name: &str,
    op: impl FnOnce(&LinearOctree, f64, &OffsetOptions) -> Result<LinearOctree>,
) -> Result<()> {
    check_extension(output, FileKind::SOLID_OUTPUTS)?;
    check_not_an_input(output, &[input])?;
    let file = read_solid_file(input, read, budget)?;
    let meta = file.meta;
    let tree = file.into_union();
    let started = Instant::now();
    let bar = Bar::new("band");
    let per_unit = tree.domain().voxels_per_unit();
    let result = op(&tree, per_unit, &OffsetOptions { budget, progress: &bar })
        .with_context(|| format!("{}: cannot {name}", input.display()))?;
    out!("{}: {name} in {:.1} ms", input.display(), started.elapsed().as_secs_f64() * 1e3);
    let bytes = write_solid_file(output, &result, &meta, None, budget)?;
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    print_summary(&result, None);
    Ok(())
}
