//! `octsolid export FILE.oct -o OUT.(obj|stl|ply) [--unit-faces]`: the boundary of a
//! solid as a closed, manifold triangle mesh.
//!
//! STL has no vertex indices, so the vertices the mesh keeps apart where voxels touch
//! only along an edge or at a corner are written moved apart
//! ([`octsolid::mesh::separate_sheets`]); the printed volume is the moved mesh's.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use octsolid::io::oct;
use octsolid::mesh::{BoundaryOptions, MeshFormat, save_mesh, separate_sheets, try_boundary_mesh};
use octsolid::{MemoryBudget, human_bytes};

use crate::output::check_not_an_input;
use crate::progress_bar::Bar;

/// Arguments of `octsolid export`.
#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// The .oct file.
    pub file: PathBuf,
    /// Output mesh: .obj, .stl or .ply (STL: vertices where voxels touch moved apart).
    #[arg(short, long)]
    pub output: PathBuf,
    /// One voxel face = two triangles (default: coplanar faces merged into rectangles).
    #[arg(long)]
    pub unit_faces: bool,
}

/// `octsolid export FILE.oct -o OUT.(obj|stl|ply) [--unit-faces]`
pub fn run(a: &ExportArgs, budget: MemoryBudget) -> Result<()> {
    let (file, output, unit_faces) = (&a.file, &a.output, a.unit_faces);
    let format = MeshFormat::of(output)?;
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
    let separated = if format == MeshFormat::Stl {
        Some(
            separate_sheets(&mesh)
                .with_context(|| format!("{}: cannot write STL; write .obj or .ply", output.display()))?,
        )
    } else {
        None
    };
    let written = separated.as_ref().unwrap_or(&mesh);
    let bytes = save_mesh(written, output)?;
    let faces = if unit_faces { "unit faces" } else { "merged faces" };
    out!("read       {} ({} nodes, depth {})", file.display(), tree.node_count(), tree.depth());
    out!("mesh       {} triangles, {} vertices ({faces})", mesh.triangles.len(), mesh.vertices.len());
    if separated.is_some() {
        let moved = written.vertices.iter().zip(&mesh.vertices).filter(|(a, b)| a != b).count();
        out!("stl        {moved} vertices where voxels touch moved apart");
    }
    let (enclosed, volume) = (written.volume(), tree.volume());
    out!("volume     {enclosed:.6} enclosed, {volume:.6} octree ({:+.1e} relative)", enclosed / volume - 1.0);
    out!("time       {:.1} ms (boundary mesh)", elapsed * 1e3);
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    Ok(())
}
