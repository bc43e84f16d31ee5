//! `octsolid export FILE.oct -o OUT.(obj|stl|ply) [--unit-faces]`: the boundary of a
//! solid as a closed, manifold triangle mesh.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use octsolid::io::oct;
use octsolid::mesh::{BoundaryOptions, MeshFormat, save_mesh, try_boundary_mesh};
use octsolid::{MemoryBudget, human_bytes};

use crate::output::check_not_an_input;
use crate::progress_bar::Bar;

/// Arguments of `octsolid export`.
#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// The .oct file.
    pub file: PathBuf,
    /// Output mesh: .obj, .stl or .ply.
    #[arg(short, long)]
    pub output: PathBuf,
    /// One voxel face = two triangles (default: coplanar faces merged into rectangles).
    #[arg(long)]
    pub unit_faces: bool,
}

/// `octsolid export FILE.oct -o OUT.(obj|stl|ply) [--unit-faces]`
pub fn run(a: &ExportArgs, budget: MemoryBudget) -> Result<()> {
    let (file, output, unit_faces) = (&a.file, &a.output, a.unit_faces);
    MeshFormat::of(output)?;
    check_not_an_input(output, &[file])?;
    let tree = oct::load(file, budget)?;
    if tree.is_empty() {
        bail!("{}: the solid is empty; there is no boundary to export", file.display());
    }
    let started = Instant::now();
    let bar = Bar::new("meshing");
    let mesh = try_boundary_mesh(&tree, &BoundaryOptions { unit_faces }, budget, &bar)
        .with_context(|| format!("{}: cannot export", file.display()))?;
    let elapsed = started.elapsed().as_secs_f64();
    let bytes = save_mesh(&mesh, output)?;
    let faces = if unit_faces { "unit faces" } else { "merged faces" };
    out!("read       {} ({} nodes, depth {})", file.display(), tree.node_count(), tree.depth());
    out!("mesh       {} triangles, {} vertices ({faces})", mesh.triangles.len(), mesh.vertices.len());
    let (enclosed, volume) = (mesh.volume(), tree.volume());
    out!("volume     {enclosed:.6} enclosed, {volume:.6} octree ({:+.1e} relative)", enclosed / volume - 1.0);
    out!("time       {:.1} ms (boundary mesh)", elapsed * 1e3);
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    Ok(())
}
