//! `octsolid transform IN -o OUT [--translate X,Y,Z] [--rotate AXIS,DEG]... [--scale S]
//! [--domain ...] [--depth D]`: a solid moved by the library's exact transforms where
//! the move maps voxels to voxels, resampled otherwise. A file of several solids (a
//! `.vox` file's colours) written to `.vox`, `.vdb` or `.glb` keeps them apart, each
//! moved into the domain of the moved union; other outputs get the union.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use glam::DVec3;
use octsolid::io::{ColouredSolid, Solids, WriteOptions};
use octsolid::octree::{Domain, Fit, Motion, Turn, VoxelizeOptions};
use octsolid::surface::{Moved, transform_with_surface};
use octsolid::{FileKind, MemoryBudget, NoProgress, Progress, human_bytes};

use super::print_summary;
use crate::output::{check_extension, check_not_an_input, write_solid_file};
use crate::progress_bar::Bar;
use crate::solid_input::{ReadFlags, read_solid_file};
use crate::values::{TargetFlags, parse_turn, parse_vec3};

/// Arguments of `octsolid transform`.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct TransformArgs {
    /// The solid file: .oct, .vox, .binvox or .vdb (a file of several solids moves
    /// as their union).
    pub input: PathBuf,
    /// Output file: .oct, or .vox, .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Move by X,Y,Z world units (applied last).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_vec3)]
    pub translate: Option<[f64; 3]>,
    /// Turn about an axis through the origin: AXIS,DEG (x, y or z; right-handed).
    /// Repeat for several turns, applied in order after the scale.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_turn)]
    pub rotate: Vec<Turn>,
    /// Uniform scale about the origin (applied first), positive.
    #[arg(long, default_value_t = 1.0, value_parser = crate::values::parse_finite)]
    pub scale: f64,
    // The target domain and depth (default: the moved domain when the move is exact,
    // else the cube around the moved solid, at the input's depth).
    #[command(flatten)]
    pub target: TargetFlags,
    #[command(flatten)]
    pub read: ReadFlags,
}

/// `octsolid transform IN -o OUT [...]`
pub fn run(a: &TransformArgs, budget: MemoryBudget) -> Result<()> {
    let output_kind = check_extension(&a.output, FileKind::SOLID_OUTPUTS)?;
    check_not_an_input(&a.output, &[&a.input])?;
    let mut file = read_solid_file(&a.input, &a.read, budget)?;
    let meta = file.meta;
    let surface = file.surface.take();
    let file_had_surface = surface.is_some();
    // Several solids going to a format that keeps them apart move one by one into the
    // domain their union moves into; else the union moves.
    let (tree, apart) = if file.solids.solids.len() > 1 && output_kind.holds_many_solids() {
        (file.solids.union(), Some(file.solids))
    } else {
        (file.into_union(), None)
    };
    let motion =
        Motion { scale: a.scale, turns: a.rotate.clone(), translate: a.translate.map_or(DVec3::ZERO, DVec3::from) };
    let map = motion.checked_affine()?;
    let target = |default: Domain| a.target.target(default);
    let started = Instant::now();
    let bar = Bar::new("resampling");
    // One solid keeps its surface data through an exact move, or is made again from
    // its moved smooth surface; several solids kept apart move by their voxels.
    let carried = if apart.is_none() { surface } else { None };
    let had_data = carried.is_some();
    let Moved { tree: moved, surface, fit } =
        transform_with_surface(&tree, carried.as_ref(), map, target, &VoxelizeOptions { budget, progress: &bar })
            .with_context(|| format!("{}: cannot transform", a.input.display()))?;
    out!("{}: {fit} into {} in {:.1} ms", a.input.display(), moved.domain(), started.elapsed().as_secs_f64() * 1e3);
    if let (Fit::Resampled, true, Some(data)) = (fit, had_data, &surface) {
        out!("surface    resampled from the moved smooth surface, {} crossings", data.len());
    }
    if moved.is_empty() && !tree.is_empty() {
        warn!("the result is empty: the moved solid lies outside the target domain");
    }
    let bytes = match apart {
        Some(solids) => {
            let domain = *moved.domain();
            let mut each = Vec::with_capacity(solids.solids.len());
            for solid in solids.solids {
                let (tree, _) = solid
                    .tree
                    .transformed(map, |_| Ok(domain), &VoxelizeOptions { budget, progress: &bar })
                    .with_context(|| {
                        format!("{}: {}: cannot transform", a.input.display(), octsolid::printable(&solid.name))
                    })?;
                each.push(ColouredSolid { tree, ..solid });
            }
            let moved = Solids { domain, solids: each };
            let options = WriteOptions { budget, meta, ..WriteOptions::default() };
            let meshing = output_kind.meshes_solid().then(|| Bar::new("meshing"));
            let progress: &dyn Progress = meshing.as_ref().map_or(&NoProgress, |b| b);
            octsolid::write_solid_file(&a.output, &moved.borrowed(), &options, progress)?
        }
        None => {
            // Exact moves carry the surface data, resampling makes it again; a
            // refinement leaves it out.
            if surface.is_none() && file_had_surface {
                out!("surface    the input's surface data is left out: {fit}");
            }
            write_solid_file(&a.output, &moved, &meta, surface, budget)?
        }
    };
    out!("wrote {} ({})", a.output.display(), human_bytes(bytes));
    print_summary(&moved, None);
    Ok(())
}
