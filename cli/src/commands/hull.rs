//! `octsolid hull IN -o OUT`: the convex hull of a solid, the hull of its voxels'
//! corners voxelized into the same domain, exactly (the library's
//! `LinearOctree::hull`). A file of several solids gives the hull of their union.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use octsolid::octree::VoxelizeOptions;
use octsolid::{FileKind, MemoryBudget, human_bytes};

use super::print_summary;
use crate::output::{check_extension, check_not_an_input, write_solid_file};
use crate::progress_bar::Bar;
use crate::solid_input::{ReadFlags, read_solid_file};

/// Arguments of `octsolid hull`.
#[derive(clap::Args, Debug)]
pub struct HullArgs {
    /// The solid file: .oct, .octs, .vox, .binvox or .vdb.
    pub input: PathBuf,
    /// Output file: .oct, or .vox, .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub read: ReadFlags,
}

/// `octsolid hull IN -o OUT`
pub fn run(a: &HullArgs, budget: MemoryBudget) -> Result<()> {
    check_extension(&a.output, FileKind::SOLID_OUTPUTS)?;
    check_not_an_input(&a.output, &[&a.input])?;
    let file = read_solid_file(&a.input, &a.read, budget)?;
    let meta = file.meta;
    let tree = file.into_union();
    let started = Instant::now();
    let bar = Bar::new("hull");
    let hull = tree
        .hull(&VoxelizeOptions { budget, progress: &bar })
        .with_context(|| format!("{}: cannot take the hull", a.input.display()))?;
    out!("{}: hull in {:.1} ms", a.input.display(), started.elapsed().as_secs_f64() * 1e3);
    let bytes = write_solid_file(&a.output, &hull, &meta, None, budget)?;
    out!("wrote {} ({})", a.output.display(), human_bytes(bytes));
    print_summary(&hull, None);
    Ok(())
}
