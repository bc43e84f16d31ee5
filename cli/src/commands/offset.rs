//! `octsolid offset IN --by D -o OUT` (or `--voxels N`), `octsolid shell IN --thickness T
//! -o OUT [--outward]` and `octsolid round IN --radius R -o OUT [--convex] [--concave]`:
//! a solid grown or shrunk by a ball, hollowed to a wall, or with its edges rounded, by
//! the library's exact band distance (`LinearOctree::offset`, `shell`, `round`).
//! Distances are world units unless `--voxels` says voxels; a file of several solids
//! works on their union. A solid that carries surface data (an `.oct` with a surface
//! section, a `.vdb` level set) is measured to its true surface
//! (`surface::offset_with_surface` and its kin) and its result written with its new
//! crossings, so `export` meshes a wall of the asked thickness.
//!
//! A sharded solid into a sharded solid (`IN.octs -o OUT.octs`) goes cell by cell
//! (`sharded::morph`: each cell from a window of it and a halo of the distance read
//! from its neighbours' shards), never whole in memory: `--memory-budget` is checked
//! on the largest window before any cell is written; `--shard-level` and `--cells` as
//! for `csg`. A sharded input to any other output is read whole within the budget.
//!
//! `--metric manhattan` or `chebyshev` measure the distance by the octahedron or the
//! cube instead of the ball (`OffsetOptions::metric`), over the voxels as cubes: the
//! true surface is measured by the Euclidean distance only, so such a result carries
//! no surface data (and a sharded solid is offset by the ball only).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use octsolid::octree::{LinearOctree, Metric, OffsetOptions};
use octsolid::sharded::{self, Morph, ShardedSolid};
use octsolid::surface::{HermiteData, offset_with_surface, round_with_surface, shell_with_surface};
use octsolid::{FileKind, MemoryBudget, human_bytes};

use super::{print_summary, warn_if_clipped};
use crate::output::{check_extension, check_not_an_input, write_solid_file};
use crate::progress_bar::Bar;
use crate::sharded_output::{ShardFlags, is_sharded};
use crate::solid_input::{ReadFlags, read_solid_file};

/// Arguments of `octsolid offset`.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct OffsetArgs {
    /// The solid file: .oct, .octs, .vox, .binvox or .vdb.
    pub input: PathBuf,
    /// Output file: .oct, or .vox, .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Grow (positive) or shrink (negative) by this world distance.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_finite, conflicts_with = "voxels", required_unless_present = "voxels")]
    pub by: Option<f64>,
    /// Grow (positive) or shrink (negative) by this many voxels.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_finite)]
    pub voxels: Option<f64>,
    #[command(flatten)]
    pub metric: MetricFlag,
    #[command(flatten)]
    pub read: ReadFlags,
    #[command(flatten)]
    pub shards: ShardFlags,
}

/// Arguments of `octsolid shell`.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct ShellArgs {
    /// The solid file: .oct, .octs, .vox, .binvox or .vdb.
    pub input: PathBuf,
    /// Output file: .oct, or .vox, .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The wall's thickness, a world distance.
    #[arg(long, value_parser = crate::values::parse_finite)]
    pub thickness: f64,
    /// The wall outside the surface instead of inside it.
    #[arg(long)]
    pub outward: bool,
    #[command(flatten)]
    pub metric: MetricFlag,
    #[command(flatten)]
    pub read: ReadFlags,
    #[command(flatten)]
    pub shards: ShardFlags,
}

/// Arguments of `octsolid round`.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct RoundArgs {
    /// The solid file: .oct, .octs, .vox, .binvox or .vdb.
    pub input: PathBuf,
    /// Output file: .oct, or .vox, .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
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
    pub metric: MetricFlag,
    #[command(flatten)]
    pub read: ReadFlags,
    #[command(flatten)]
    pub shards: ShardFlags,
}

/// The distance an offset, shell or round measures.
#[derive(clap::Args, Debug)]
pub struct MetricFlag {
    /// The distance measured: euclidean (a ball), manhattan (an octahedron) or chebyshev
    /// (a cube); other than euclidean, over the voxels, the result without surface data.
    #[arg(long, default_value_t = Metric::Euclidean)]
    pub metric: Metric,
}

/// `octsolid offset IN (--by D | --voxels N) -o OUT`
pub fn run_offset(a: &OffsetArgs, budget: MemoryBudget) -> Result<()> {
    let (by, voxels) = (a.by, a.voxels);
    let morph = |per_unit: f64| Morph::Offset(voxels.unwrap_or_else(|| by.unwrap_or(0.0) * per_unit));
    if cell_by_cell(&a.input, &a.output, &a.shards, a.metric.metric, budget, morph)? {
        return Ok(());
    }
    apply(&a.input, &a.output, &a.read, budget, a.metric.metric, "offset", |tree, surface, per_unit, options| {
        let d = voxels.unwrap_or_else(|| by.unwrap_or(0.0) * per_unit);
        Ok(match surface {
            Some(data) => {
                let (tree, data) = offset_with_surface(tree, data, d, options)?;
                (tree, Some(data))
            }
            None => (tree.offset(d, options)?, None),
        })
    })
}

/// `octsolid shell IN --thickness T -o OUT [--outward]`
pub fn run_shell(a: &ShellArgs, budget: MemoryBudget) -> Result<()> {
    if a.thickness <= 0.0 {
        bail!("--thickness must be positive, not {}", a.thickness);
    }
    let morph = |per_unit: f64| Morph::Shell { thickness: a.thickness * per_unit, outward: a.outward };
    if cell_by_cell(&a.input, &a.output, &a.shards, a.metric.metric, budget, morph)? {
        return Ok(());
    }
    apply(&a.input, &a.output, &a.read, budget, a.metric.metric, "shell", |tree, surface, per_unit, options| {
        let t = a.thickness * per_unit;
        Ok(match surface {
            Some(data) => {
                let (tree, data) = shell_with_surface(tree, data, t, a.outward, options)?;
                (tree, Some(data))
            }
            None => (tree.shell(t, a.outward, options)?, None),
        })
    })
}

/// `octsolid round IN --radius R -o OUT [--convex] [--concave]`
pub fn run_round(a: &RoundArgs, budget: MemoryBudget) -> Result<()> {
    if a.radius <= 0.0 {
        bail!("--radius must be positive, not {}", a.radius);
    }
    // Neither flag: both kinds of edge.
    let (convex, concave) = if a.convex || a.concave { (a.convex, a.concave) } else { (true, true) };
    let morph = |per_unit: f64| Morph::Round { radius: a.radius * per_unit, convex, concave };
    if cell_by_cell(&a.input, &a.output, &a.shards, a.metric.metric, budget, morph)? {
        return Ok(());
    }
    apply(&a.input, &a.output, &a.read, budget, a.metric.metric, "round", |tree, surface, per_unit, options| {
        let r = a.radius * per_unit;
        Ok(match surface {
            Some(data) => {
                let (tree, data) = round_with_surface(tree, data, r, convex, concave, options)?;
                (tree, Some(data))
            }
            None => (tree.round(r, convex, concave, options)?, None),
        })
    })
}

/// A sharded `input` into a sharded `output`: `morph` (given voxels a world unit) cell
/// by cell with a bar of cells; false (nothing done) for any other pair of files.
fn cell_by_cell(
    input: &std::path::Path,
    output: &std::path::Path,
    shards: &ShardFlags,
    metric: Metric,
    budget: MemoryBudget,
    morph: impl FnOnce(f64) -> Morph,
) -> Result<bool> {
    shards.check_for(output)?;
    if !(is_sharded(input) && is_sharded(output)) {
        return Ok(false);
    }
    if metric != Metric::Euclidean {
        bail!(
            "{}: a sharded solid is offset cell by cell by the euclidean distance only, not {metric}",
            input.display()
        );
    }
    check_not_an_input(output, &[input])?;
    let solid = ShardedSolid::open(input)?;
    let morph = morph(solid.index().domain.voxels_per_unit());
    shards.write(output, budget, Instant::now(), |options| {
        sharded::morph(&solid, morph, output, options)
            .with_context(|| format!("{}: cannot make the {morph}", input.display()))
    })?;
    Ok(true)
}

/// Reads `input`'s union (and its surface data, for a file of one solid), runs `op`
/// on it (given voxels a world unit) with a bar, and writes the result (with its
/// surface data) to `output`.
fn apply(
    input: &std::path::Path,
    output: &std::path::Path,
    read: &ReadFlags,
    budget: MemoryBudget,
    metric: Metric,
    name: &str,
    op: impl FnOnce(&LinearOctree, Option<&HermiteData>, f64, &OffsetOptions) -> Result<(LinearOctree, Option<HermiteData>)>,
) -> Result<()> {
    check_extension(output, FileKind::SOLID_OUTPUTS)?;
    check_not_an_input(output, &[input])?;
    let mut file = read_solid_file(input, read, budget)?;
    let meta = file.meta;
    let mut surface = if file.solids.solids.len() == 1 { file.surface.take() } else { None };
    if metric != Metric::Euclidean && surface.take().is_some() {
        out!(
            "{}: the {metric} distance is measured over the voxels; the result carries no surface data",
            input.display()
        );
    }
    let tree = file.into_union();
    let started = Instant::now();
    let bar = Bar::new("band");
    let per_unit = tree.domain().voxels_per_unit();
    let (result, surface) = op(&tree, surface.as_ref(), per_unit, &OffsetOptions { budget, progress: &bar, metric })
        .with_context(|| format!("{}: cannot {name}", input.display()))?;
    out!("{}: {name} in {:.1} ms", input.display(), started.elapsed().as_secs_f64() * 1e3);
    warn_if_clipped(&tree, &result, name);
    let bytes = write_solid_file(output, &result, &meta, surface, budget)?;
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    print_summary(&result, None);
    Ok(())
}
