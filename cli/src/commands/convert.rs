//! `octsolid convert IN OUT [--depth D] [--domain MINX,MINY,MINZ,EDGE] [--threshold T]
//! [--grid NAME] [--voxel-size S]`: a solid file in another format, each chosen by its
//! extension.
//!
//! Reads `.oct`, MagicaVoxel `.vox`, `.binvox` and OpenVDB `.vdb`
//! ([`crate::solid_input`]); writes those, or the true surface as a mesh (`.obj`,
//! `.stl`, `.ply`, `.3mf`, `.glb`); `-o OUT` names the output as in the other commands.
//! A file's solids go over as they are: `.vox` and `.vdb` keep one solid a colour or
//! grid and `.glb` one mesh a solid with its colour; `.oct`, `.binvox` and
//! the meshes hold one solid, so several are written as their union (said on stdout).
//! With `--domain` or `--depth` every solid is first brought into that domain (exactly
//! where the voxels nest, resampled at the target's voxel centres otherwise, as `csg`
//! and `transform` do); without them the solids keep their domain, so `.oct -> X ->
//! .oct` gives back the same file for what X can hold (`docs/FORMAT.md`).
//!
//! The summary is `info`'s: the file read (format, solids, colours), the domain, nodes,
//! voxels, volume, bounds, then the file written with its size and the times.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use octsolid::io::{ColouredSolid, Solids, WriteOptions};
use octsolid::octree::{Fit, VoxelizeOptions};
use octsolid::sharded;
use octsolid::{FileKind, MemoryBudget, NoProgress, Progress, human_bytes};

use super::info::{print_solids, solid_infos};
use super::{print_summary, uses_surface};
use crate::output::{check_extension, check_not_an_input, write_solid_file};
use crate::progress_bar::{Bar, Spinner};
use crate::sharded_output::ShardFlags;
use crate::solid_input::{ReadFlags, read_solid_file};
use crate::values::TargetFlags;

/// Arguments of `octsolid convert`.
#[derive(clap::Args, Debug)]
pub struct ConvertArgs {
    /// The solid file read: .oct, .vox, .binvox or .vdb.
    pub input: PathBuf,
    /// The file written: .oct, .vox, .binvox, .vdb, or the true surface as .obj, .stl,
    /// .ply, .3mf or .glb.
    #[arg(required_unless_present = "output_flag", conflicts_with = "output_flag")]
    pub output: Option<PathBuf>,
    /// The file written, as the positional OUTPUT (the other commands' `-o`).
    #[arg(short = 'o', long = "output", id = "output_flag", value_name = "OUTPUT")]
    pub output_flag: Option<PathBuf>,
    // Bring the solids into this domain and depth first (default: the input's).
    #[command(flatten)]
    pub target: TargetFlags,
    #[command(flatten)]
    pub read: ReadFlags,
    #[command(flatten)]
    pub shards: ShardFlags,
}

/// `octsolid convert IN OUT [...]`
pub fn run(a: &ConvertArgs, budget: MemoryBudget) -> Result<()> {
    let Some(output) = a.output.as_ref().or(a.output_flag.as_ref()) else {
        bail!("convert: no output file (give OUTPUT or -o OUTPUT)")
    };
    let input = &a.input;
    let output_kind = check_extension(output, FileKind::SOLID_OUTPUTS)?;
    check_not_an_input(output, &[input])?;
    a.shards.check_for(output)?;
    let started = Instant::now();
    let file = read_solid_file(input, &a.read, budget)?;
    let read_ms = started.elapsed().as_secs_f64() * 1e3;
    let bytes_in = std::fs::metadata(input).with_context(|| format!("{}", input.display()))?.len();
    let (kind, meta) = (file.kind, file.meta);
    let mut surface = file.surface;
    let mut solids = file.solids;
    out!("read       {} (.{}, {}) in {read_ms:.1} ms", input.display(), kind.extension(), human_bytes(bytes_in));
    print_solids(&solid_infos(&solids));

    if a.target.given() {
        solids = fitted(a, solids, budget)?;
        if surface.take().is_some() {
            out!("surface    the input's surface data is left out: the solid moved into another domain");
        }
    }
    let d = solids.domain;
    out!(
        "depth      {} ({} voxels a side, voxel edge {})",
        d.depth(),
        d.resolution(),
        crate::human::num(d.voxel_size())
    );
    out!("domain     min {} edge {}", crate::human::point(d.min()), crate::human::num(d.edge()));
    let union = solids.union();
    print_summary(&union, None);

    if surface.is_some() && !uses_surface(output) {
        out!(
            "surface    .{} keeps no surface data: the input's crossings are left out (read back, the surface \
             is estimated from the voxels; keep the .oct for export)",
            output_kind.extension()
        );
    }
    let started = Instant::now();
    // A mesh shows its own bar while it is meshed.
    let spinner = (!output_kind.meshes_solid()).then(|| Spinner::new("writing"));
    let bytes_out = if output_kind == FileKind::Octs {
        drop(spinner);
        return a.shards.write(output, budget, started, |options| Ok(sharded::write(&union, meta, output, options)?));
    } else if output_kind.holds_many_solids() {
        let up = meta.up.unwrap_or(kind.default_up());
        let surface = surface.filter(|_| solids.solids.len() == 1).map(Arc::new);
        let options = WriteOptions { budget, up, meta, surface, ..WriteOptions::default() };
        let bar = output_kind.meshes_solid().then(|| Bar::new("meshing"));
        let progress: &dyn Progress = bar.as_ref().map_or(&NoProgress, |b| b);
        octsolid::write_solid_file(output, &solids.borrowed(), &options, progress)
            .with_context(|| format!("{}: cannot write", output.display()))?
    } else {
        if solids.solids.len() > 1 {
            let n = solids.solids.len();
            out!("joined     {n} solids into one: {} holds one solid and no colour", output.display());
        }
        write_solid_file(output, &union, &meta, surface, budget)?
    };
    drop(spinner);
    let write_ms = started.elapsed().as_secs_f64() * 1e3;
    let ratio = bytes_out as f64 / bytes_in.max(1) as f64;
    out!("wrote      {} ({}, {ratio:.2}x the input) in {write_ms:.1} ms", output.display(), human_bytes(bytes_out));
    Ok(())
}

/// Every solid brought into the `--domain` and `--depth` target, each fit said.
fn fitted(a: &ConvertArgs, solids: Solids, budget: MemoryBudget) -> Result<Solids> {
    let target = a.target.target(solids.domain)?;
    let bar = Bar::new("fitting");
    let options = VoxelizeOptions { budget, progress: &bar };
    let mut out = Vec::with_capacity(solids.solids.len());
    for solid in solids.solids {
        let started = Instant::now();
        let (tree, fit) = solid.tree.fit_to(target, &options).with_context(|| {
            format!("{}: {}: cannot bring into {target}", a.input.display(), octsolid::printable(&solid.name))
        })?;
        if fit != Fit::Same {
            let ms = started.elapsed().as_secs_f64() * 1e3;
            out!("fitted     {}: {fit} into {target} in {ms:.1} ms", octsolid::printable(&solid.name));
        }
        out.push(ColouredSolid { tree, ..solid });
    }
    Ok(Solids { domain: target, solids: out })
}
