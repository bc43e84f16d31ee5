//! `octsolid voxelize IN --depth D [--fill F] [--inside R] [--domain ... | --voxel-size S] -o OUT`: a
//! mesh or patch set voxelized into a solid file (`.oct`, `.vox`, `.binvox`, `.vdb`, `.glb`
//! or a mesh, by the extension of `-o`).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use glam::DVec3;
use octsolid::import::{self, Fill, ImportOptions};
use octsolid::io::oct::{Metadata, Units};
use octsolid::mesh::{InsideRule, MeshVoxelizeOptions};
use octsolid::octree::Domain;
use octsolid::shape::Axis;
use octsolid::sharded;
use octsolid::{FileKind, MemoryBudget, human_bytes};

use super::{print_summary, read_input, uses_surface};
use crate::output::{check_extension, check_not_an_input, write_solid_file};
use crate::progress_bar::Bar;
use crate::sharded_output::{ShardFlags, is_sharded};
use crate::values::parse_domain;

/// Arguments of `octsolid voxelize`.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct VoxelizeArgs {
    /// Input file: .obj, .stl, .ply or .patches.
    pub input: PathBuf,
    /// Octree depth (1..=21; default 8; with --voxel-size the least that holds the input).
    #[arg(long)]
    pub depth: Option<u8>,
    /// What to keep: the enclosed solid, every voxel the surface touches, or a thin shell.
    #[arg(long, default_value = "solid")]
    pub fill: Fill,
    /// Inside rule for solids: parity (watertight meshes), winding (robust), or auto.
    #[arg(long, default_value = "auto")]
    pub inside: InsideRule,
    /// Domain cube MINX,MINY,MINZ,EDGE (default: the input's bounding cube with a 2% margin).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_domain)]
    pub domain: Option<[f64; 4]>,
    /// A voxel's edge S instead of a domain: voxel planes on the multiples of S, so a
    /// model whose faces lie on them keeps its dimensions exactly.
    #[arg(long, conflicts_with = "domain", value_parser = crate::values::parse_finite)]
    pub voxel_size: Option<f64>,
    /// The source's up axis, recorded in the .oct file so `render` shows it upright
    /// (default by extension: y for .obj and .ply, z otherwise).
    #[arg(long)]
    pub up: Option<Axis>,
    /// The source's length unit, recorded in the .oct file: um, mm, cm, m, in or ft.
    #[arg(long)]
    pub units: Option<Units>,
    /// Output file: .oct, or .vox, .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub shards: ShardFlags,
}

/// `octsolid voxelize IN --depth D [--fill F] [--inside R] [--domain ...] -o OUT`
pub fn run(a: &VoxelizeArgs, budget: MemoryBudget) -> Result<()> {
    let (input, depth, fill, inside, output) = (&a.input, a.depth.unwrap_or(8), a.fill, a.inside, &a.output);
    check_extension(output, FileKind::SOLID_OUTPUTS)?;
    check_not_an_input(output, &[input])?;
    a.shards.check_for(output)?;
    let up = a.up.unwrap_or(FileKind::of(input, FileKind::SURFACES)?.default_up());
    let started = Instant::now();
    let loaded = read_input(input)?;
    let cannot = || format!("{}: cannot voxelize", input.display());
    let domain = match (a.domain, a.voxel_size) {
        (Some([x, y, z, edge]), _) => Domain::new(DVec3::new(x, y, z), edge, depth)?,
        (None, Some(voxel)) => Domain::on_grid(&loaded.bounds(), voxel, a.depth).with_context(cannot)?,
        (None, None) => import::default_domain(&loaded, depth).with_context(cannot)?,
    };
    let meta = Metadata { up: Some(up), units: a.units };
    if is_sharded(output) {
        return sharded_solid(a, &loaded, domain, meta, budget, started);
    }
    let bar = Bar::new("voxelizing");
    let (tree, summary) =
        import::voxelize_input(&loaded, domain, &ImportOptions { fill, inside, budget, progress: &bar })
            .with_context(|| format!("{}: cannot voxelize", input.display()))?;
    let elapsed = started.elapsed().as_secs_f64();
    let surface = surface_of(a, &loaded, &tree, &summary, budget)?;
    let bytes = write_solid_file(output, &tree, &meta, surface, budget)?;
    out!(
        "read       {} ({} triangle{})",
        input.display(),
        summary.triangles,
        if summary.triangles == 1 { "" } else { "s" }
    );
    if let Some(rule) = summary.rule {
        out!("inside     {} rule{}", rule.name(), if inside == InsideRule::Auto { " (auto)" } else { "" });
    }
    print_summary(&tree, None);
    match summary.mesh_volume {
        Some(v) if v.abs() > 0.0 => {
            out!("mesh vol.  {v:.6} ({:+.3}% voxelized vs mesh)", 100.0 * (tree.volume() / v - 1.0))
        }
        Some(_) => out!("mesh vol.  0 (the mesh encloses no volume)"),
        None if fill == Fill::Solid => out!("mesh vol.  none: the mesh is open (its solid is its winding number's)"),
        None => {}
    }
    if summary.void_triangles > 0 {
        out!(
            "left out   {} triangles that bound nothing (a repeated corner, or a copy facing the other way)",
            summary.void_triangles
        );
    }
    if fill == Fill::Solid && tree.is_empty() {
        warn!(
            "{}: the solid is empty: the mesh encloses nothing at depth {} (--fill surface keeps the voxels its \
             surface touches)",
            input.display(),
            domain.depth()
        );
    }
    out!("time       {:.1} ms (load and voxelize)", elapsed * 1e3);
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    Ok(())
}

/// The surface data of the solid `tree` made of `loaded` when the output is an `.oct`
/// file (the one format that stores it): the crossings of its triangles
/// ([`import::surface_of_input`]), with the time it took printed; `None` for other
/// outputs, surfaces and thin shells.
fn surface_of(
    a: &VoxelizeArgs,
    loaded: &import::Input,
    tree: &octsolid::octree::LinearOctree,
    summary: &import::VoxelizeSummary,
    budget: MemoryBudget,
) -> Result<Option<octsolid::surface::HermiteData>> {
    if !uses_surface(&a.output) {
        return Ok(None);
    }
    let started = Instant::now();
    let surface = import::surface_of_input(loaded, tree, summary, budget)
        .with_context(|| format!("{}: cannot find its surface's crossings", a.input.display()))?;
    if let Some(surface) = &surface {
        let ms = started.elapsed().as_secs_f64() * 1e3;
        let from = if matches!(loaded, import::Input::Patches(_)) { "patches" } else { "triangles" };
        out!("surface    {} boundary faces' crossings and normals from the {from} in {ms:.1} ms", surface.len());
    }
    Ok(surface)
}

/// A sharded output: a solid voxelized cell by cell (patch sets tessellated first, as
/// in memory); surfaces voxelized whole, then cut into shards.
fn sharded_solid(
    a: &VoxelizeArgs,
    loaded: &import::Input,
    domain: Domain,
    meta: Metadata,
    budget: MemoryBudget,
    started: Instant,
) -> Result<()> {
    let cannot = || format!("{}: cannot voxelize", a.input.display());
    a.shards.write(&a.output, budget, started, |options| {
        Ok(match a.fill {
            Fill::Solid => {
                let mesh = loaded.triangles(domain.voxel_size(), budget).with_context(cannot)?;
                let mesh_options = MeshVoxelizeOptions { inside: a.inside, budget, progress: options.progress };
                sharded::voxelize_mesh(&mesh, domain, meta, &mesh_options, &a.output, options).with_context(cannot)?
            }
            _ => {
                let import = ImportOptions { fill: a.fill, inside: a.inside, budget, progress: options.progress };
                let (tree, _) = import::voxelize_input(loaded, domain, &import).with_context(cannot)?;
                sharded::write(&tree, meta, &a.output, options)?
            }
        })
    })
}
