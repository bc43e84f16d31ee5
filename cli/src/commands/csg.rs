//! `octsolid csg OP A B [MORE...] -o OUT [--domain ...] [--depth D]`: solids combined
//! by a set operation, after bringing them into one domain, then merged in one pass
//! over all of them (`LinearOctree::combine_all`, parallel over Morton ranges). Into an
//! `.oct` file, the operands' surface data is carried through (`HermiteData::combine`).

use std::cell::Cell;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use octsolid::octree::{Fit, LinearOctree, SetOp, VoxelizeOptions, common_domain};
use octsolid::sharded::{self, ShardedSolid};
use octsolid::surface::{HermiteData, Moved, fit_with_surface};
use octsolid::{FileKind, MemoryBudget, human_bytes};

use super::{print_summary, uses_surface};
use crate::output::{check_extension, check_not_an_input, write_solid_file};
use crate::progress_bar::Bar;
use crate::sharded_output::{ShardFlags, is_sharded};
use crate::solid_input::{ReadFlags, read_solid_file};
use crate::values::{TargetFlags, names};

/// Arguments of `octsolid csg`.
#[derive(clap::Args, Debug)]
pub struct CsgArgs {
    /// The operation: union (voxels in any input), intersect (in every input),
    /// difference (in the first input and no other), xor (in an odd number of inputs).
    #[arg(value_parser = names::<SetOp>(SetOp::ALL.map(SetOp::name)))]
    pub op: SetOp,
    /// Input solid files, .oct, .vox, .binvox or .vdb (at least two; a file of several
    /// solids counts as their union). Inputs over other domains or depths are brought
    /// into one: exactly where their voxels nest, else resampled.
    #[arg(required = true, num_args = 2..)]
    pub inputs: Vec<PathBuf>,
    /// Output file: .oct, or .vox, .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
    #[arg(short, long)]
    pub output: PathBuf,
    // The common domain and depth (default: the smallest cube holding every input's
    // domain, at the deepest depth, or deeper where an input's voxels nest only at a
    // finer level).
    #[command(flatten)]
    pub target: TargetFlags,
    #[command(flatten)]
    pub read: ReadFlags,
    #[command(flatten)]
    pub shards: ShardFlags,
}

/// `octsolid csg OP A B [MORE...] -o OUT [--domain ...] [--depth D]`
pub fn run(a: &CsgArgs, budget: MemoryBudget) -> Result<()> {
    let (op, inputs, output) = (a.op, &a.inputs, &a.output);
    check_extension(output, FileKind::SOLID_OUTPUTS)?;
    check_not_an_input(output, &inputs.iter().map(PathBuf::as_path).collect::<Vec<_>>())?;
    a.shards.check_for(output)?;
    if is_sharded(output) && inputs.iter().all(|p| is_sharded(p)) && !a.target.given() {
        // Sharded into sharded: merged cell by cell, never whole in memory.
        let solids = inputs.iter().map(ShardedSolid::open).collect::<octsolid::Result<Vec<_>>>()?;
        return a
            .shards
            .write(output, budget, Instant::now(), |options| Ok(sharded::combine(&solids, op, output, options)?));
    }
    // The budget is the job's: every operand (its tree and its surface data) is held
    // while the next is read, and the result is made beside them all.
    let surface_bytes = Cell::new(0u64);
    let held = |trees: &[LinearOctree]| trees.iter().map(|t| t.bytes() as u64).sum::<u64>() + surface_bytes.get();
    let left = |trees: &[LinearOctree]| MemoryBudget(budget.0.saturating_sub(held(trees)));
    // A refusal for memory after the first operand says what the others hold.
    let whole_job = |e: anyhow::Error, trees: &[LinearOctree]| {
        let over = e.chain().any(|c| matches!(c.downcast_ref(), Some(octsolid::Error::OverBudget { .. })));
        if !over || trees.is_empty() {
            return e;
        }
        e.context(format!(
            "the memory budget of {} is the whole job's; the {} operands before hold {}",
            human_bytes(budget.0),
            trees.len(),
            human_bytes(held(trees))
        ))
    };
    let mut trees: Vec<LinearOctree> = Vec::with_capacity(inputs.len());
    // Each operand's surface data, where its file carries it.
    let mut surfaces: Vec<Option<HermiteData>> = Vec::with_capacity(inputs.len());
    let mut meta = None;
    for path in inputs {
        let mut file = read_solid_file(path, &a.read, left(&trees)).map_err(|e| whole_job(e, &trees))?;
        meta.get_or_insert(file.meta);
        surfaces.push(file.surface.take());
        surface_bytes.set(surfaces.iter().flatten().map(|s| s.bytes() as u64).sum());
        trees.push(file.into_union());
    }
    let common = common_domain(&trees.iter().map(|t| *t.domain()).collect::<Vec<_>>())?;
    let target = a.target.target(common)?;
    let bar = Bar::new("fitting");
    let mut resampled = false;
    for (i, path) in inputs.iter().enumerate() {
        if *trees[i].domain() == target {
            continue;
        }
        let started = Instant::now();
        let options = VoxelizeOptions { budget: left(&trees), progress: &bar };
        // A solid with surface data that its voxels cannot bring is made again from
        // its smooth surface; exact moves carry the data.
        let data = surfaces[i].take();
        let had_data = data.is_some();
        let Moved { tree: fitted, surface, fit } = fit_with_surface(&trees[i], data.as_ref(), target, &options)
            .with_context(|| format!("{}: cannot bring into {target}", path.display()))
            .map_err(|e| whole_job(e, &trees))?;
        let ms = started.elapsed().as_secs_f64() * 1e3;
        match (&surface, had_data, fit) {
            (Some(data), _, Fit::Resampled) => out!(
                "{}: {fit} into {target} from its smooth surface, {} crossings, in {ms:.1} ms",
                path.display(),
                data.len()
            ),
            (None, true, _) => {
                out!("{}: {fit} into {target} in {ms:.1} ms", path.display());
                out!(
                    "{}: its surface data is left out ({fit}): its faces take part as the voxels' own",
                    path.display()
                );
            }
            _ => out!("{}: {fit} into {target} in {ms:.1} ms", path.display()),
        }
        resampled |= fit == Fit::Resampled && !had_data;
        surfaces[i] = surface;
        surface_bytes.set(surfaces.iter().flatten().map(|s| s.bytes() as u64).sum());
        trees[i] = fitted;
    }
    if resampled {
        out!(
            "note       resampling moves a surface by up to half a voxel diagonal; inputs made in one domain \
             (or on one --voxel-size grid, or with domains whose voxels nest) combine exactly"
        );
    }
    // The result: at most as many nodes as the operands together (what the merge reserves).
    let nodes: u64 = trees.iter().map(|t| t.node_count() as u64).sum();
    let job = format!("the {op} of {} solids of {nodes} nodes beside them", trees.len());
    budget.check(job, held(&trees).saturating_add(nodes.saturating_mul(8)))?;
    let started = Instant::now();
    let result = LinearOctree::combine_all(&trees.iter().collect::<Vec<_>>(), op)?;
    let operands = trees.len();
    let budget = MemoryBudget(budget.0.saturating_sub(result.bytes() as u64));
    out!("{op} of {operands} solids in {:.2} ms", started.elapsed().as_secs_f64() * 1e3);
    let surface = combined_surface(op, &trees, &surfaces, &result, output)?;
    drop((trees, surfaces));
    if result.is_empty() {
        warn!("the {op} is empty: no voxel is in it");
    }
    if is_sharded(output) {
        return a.shards.write(output, budget, Instant::now(), |options| {
            Ok(sharded::write(&result, meta.unwrap_or_default(), output, options)?)
        });
    }
    let bytes = write_solid_file(output, &result, &meta.unwrap_or_default(), surface, budget)?;
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    print_summary(&result, None);
    Ok(())
}

/// The result's surface data from the operands' ([`HermiteData::combine`]) when some
/// operand carries data and `output` is an `.oct` file (the format that stores it);
/// operands without data take part as their voxels' faces.
fn combined_surface(
    op: SetOp,
    trees: &[LinearOctree],
    surfaces: &[Option<HermiteData>],
    result: &LinearOctree,
    output: &Path,
) -> Result<Option<HermiteData>> {
    if surfaces.iter().all(Option::is_none) || !uses_surface(output) {
        return Ok(None);
    }
    let started = Instant::now();
    let none = HermiteData::none();
    let operands: Vec<_> = trees.iter().zip(surfaces).map(|(t, s)| (t, s.as_ref().unwrap_or(&none))).collect();
    let surface = HermiteData::combine(op, &operands, result)?;
    let with = surfaces.iter().filter(|s| s.is_some()).count();
    out!(
        "surface    {} boundary faces' crossings and normals from {with} of {} operands' in {:.1} ms",
        surface.len(),
        trees.len(),
        started.elapsed().as_secs_f64() * 1e3
    );
    Ok(Some(surface))
}
