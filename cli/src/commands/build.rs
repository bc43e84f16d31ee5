//! `octsolid build SCENE.toml -o OUT.oct [--solid NAME]`: a scene's solid voxelized to
//! a file without rendering, so scene files are also a modeling language.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use octsolid::io::oct::Metadata;
use octsolid::octree::{Domain, VoxelizeOptions};
use octsolid::scene_file::{build_shape, build_solid};
use octsolid::shape::{Csg, has_morphed};
use octsolid::sharded;
use octsolid::surface::resolve_offsets;
use octsolid::{FileKind, MemoryBudget, human_bytes};

use super::{print_summary, surface_for, uses_surface, voxelize_with_bar};
use crate::output::{check_extension, check_not_an_input, write_solid_file};
use crate::progress_bar::Bar;
use crate::sharded_output::{ShardFlags, is_sharded};

/// Arguments of `octsolid build`.
#[derive(clap::Args, Debug)]
pub struct BuildArgs {
    /// The scene file (.toml).
    pub scene: PathBuf,
    /// Output file: .oct, a sharded solid (.octs, voxelized cell by cell: shape
    /// solids only), or .vox, .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
    #[arg(short, long)]
    pub output: PathBuf,
    /// The `[[solid]]` to build, by its name (default: the union of the scene's shape
    /// solids, voxelized in one pass into their shared domain).
    #[arg(long)]
    pub solid: Option<String>,
    /// Voxelize at this depth (1..=21) instead of the scene's `[domain]` depth, in the
    /// same cube (shape solids only).
    #[arg(long)]
    pub depth: Option<u8>,
    #[command(flatten)]
    pub shards: ShardFlags,
}

/// The offset, shell and round nodes of `shape` resolved on `domain`'s lattice, with a
/// bar when there are any.
fn resolve_with_bar(shape: &Csg, domain: Domain, budget: MemoryBudget) -> Result<Csg> {
    if !has_morphed(shape) {
        return Ok(shape.clone());
    }
    let bar = Bar::new("offsets");
    let started = Instant::now();
    let shape = resolve_offsets(shape, domain, &VoxelizeOptions { budget, progress: &bar })?;
    out!("offsets, shells and rounds at depth {} in {:.1} ms", domain.depth(), started.elapsed().as_secs_f64() * 1e3);
    Ok(shape)
}

/// `octsolid build SCENE.toml -o OUT.oct [--solid NAME]`
pub fn run(a: &BuildArgs, budget: MemoryBudget) -> Result<()> {
    check_extension(&a.output, FileKind::SOLID_OUTPUTS)?;
    check_not_an_input(&a.output, &[a.scene.as_path()])?;
    a.shards.check_for(&a.output)?;
    // A shape with offset nodes goes through its shape, once: resolving them is the work.
    let uses_surface_data = uses_surface(&a.output);
    let with_offsets = if uses_surface_data {
        build_shape(&a.scene, a.solid.as_deref(), budget).ok().filter(|(shape, _)| has_morphed(shape))
    } else {
        None
    };
    if is_sharded(&a.output) || a.depth.is_some() || with_offsets.is_some() {
        let (shape, domain) = match with_offsets {
            Some(built) => built,
            None => build_shape(&a.scene, a.solid.as_deref(), budget)?,
        };
        let domain = match a.depth {
            Some(depth) => domain.with_depth(depth)?,
            None => domain,
        };
        let shape = resolve_with_bar(&shape, domain, budget)?;
        if !is_sharded(&a.output) {
            let tree = voxelize_with_bar(&shape, domain, budget)?;
            let surface = surface_for(&a.output, &shape, &tree)?;
            let bytes = write_solid_file(&a.output, &tree, &Metadata::default(), surface, budget)?;
            out!("wrote {} ({})", a.output.display(), human_bytes(bytes));
            print_summary(&tree, None);
            return Ok(());
        }
        return a.shards.write(&a.output, budget, Instant::now(), |options| {
            Ok(sharded::voxelize_shape(&shape, domain, Metadata::default(), &a.output, options)?)
        });
    }
    let bar = Bar::new("voxelizing");
    let started = Instant::now();
    let options = VoxelizeOptions { budget, progress: &bar };
    // The library's errors name the scene file and the place in it.
    let tree = build_solid(&a.scene, a.solid.as_deref(), &options)?;
    let what = a.solid.as_deref().map_or_else(|| "the shape solids".to_owned(), |n| format!("solid '{n}'"));
    out!("built {what} at depth {} in {:.1} ms", tree.depth(), started.elapsed().as_secs_f64() * 1e3);
    if tree.is_empty() {
        warn!("the solid is empty: no voxel is in it");
    }
    // A shape solid's surface data, from the CSG tree it was voxelized from (a mesh or
    // oct solid has no shape here, and gets none).
    let shape = if uses_surface_data { build_shape(&a.scene, a.solid.as_deref(), budget).ok() } else { None };
    let surface = match shape {
        Some((shape, domain)) if domain == *tree.domain() => surface_for(&a.output, &shape, &tree)?,
        _ => None,
    };
    let bytes = write_solid_file(&a.output, &tree, &Metadata::default(), surface, budget)?;
    out!("wrote {} ({})", a.output.display(), human_bytes(bytes));
    print_summary(&tree, None);
    Ok(())
}
