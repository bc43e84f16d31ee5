//! `octsolid export FILE -o OUT.(obj|stl|ply|3mf|glb) [--unit-faces]`: the boundary of a
//! solid (`.oct`, `.vox`, `.binvox`, `.vdb`) as a closed, manifold triangle mesh.
//!
//! OBJ, STL, PLY and 3MF (the printers' package, in the solid's units, upright) hold one
//! mesh: a file of several solids (a `.vox` palette colour each) is written as their
//! union. Binary glTF (`.glb`, [`octsolid::io::gltf`]) keeps them apart: one mesh a
//! solid (its true surface, or with `--surface voxels` its staircase) with its vertex
//! normals and its colour as the material's base colour, for web viewers and Blender.
//!
//! A sharded solid (`.octs`) is exported cell by cell to STL or OBJ, streamed: memory
//! follows one cell and a border of its neighbours, and the cells' seams are welded
//! ([`octsolid::sharded::export_surface`]).
//!
//! STL has no vertex indices, so the vertices the mesh keeps apart where voxels touch
//! only along an edge or at a corner are written moved apart
//! ([`octsolid::mesh::separate_sheets`]); the printed volume is the moved mesh's.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use octsolid::io::WriteOptions;
use octsolid::mesh::separate_sheets;
use octsolid::shape::Axis;
use octsolid::sharded::{ShardedSolid, SurfaceExportOptions, export_surface};
use octsolid::surface::{DEFAULT_TOLERANCE, ExtractOptions, HermiteData, Style, SurfaceMesh, extract};
use octsolid::{
    FileKind, GlbSurfaces, MemoryBudget, NoProgress, SolidFile, human_bytes, write_glb_surfaces, write_mesh_file,
};

use crate::human::count;
use crate::output::{check_folder, check_not_an_input};
use crate::progress_bar::Bar;
use crate::sharded_output::{is_sharded, peak_memory};
use crate::solid_input::{ReadFlags, read_solid_file};

/// Arguments of `octsolid export`.
#[derive(clap::Args, Debug)]
pub struct ExportArgs {
    /// The solid file: .oct, .octs (sharded: exported cell by cell to .stl or .obj),
    /// .vox, .binvox or .vdb.
    pub file: PathBuf,
    /// Output mesh: .obj, .stl, .ply or .3mf (STL: vertices where voxels touch moved
    /// apart; 3MF: one object in the solid's units, millimetres when it records none,
    /// standing on +z, for printers), or .glb (binary glTF: a mesh a solid with its
    /// colour and smooth normals).
    #[arg(short, long)]
    pub output: PathBuf,
    /// Which surface: `smooth`, the true surface by dual contouring of the file's
    /// crossings (estimated from the voxels where the file carries none), or `voxels`,
    /// the voxels' exact staircase.
    #[arg(long, default_value_t = Style::Smooth)]
    pub surface: Style,
    /// How far, in voxels, simplification may move the smooth surface (0: a vertex every
    /// boundary voxel corner): flat blocks of cells merged within a quarter of it, then
    /// edge collapses within the rest (a true bound).
    #[arg(long, allow_hyphen_values = true, default_value_t = DEFAULT_TOLERANCE, value_parser = parse_tolerance)]
    pub tolerance: f64,
    /// With `--tolerance`: the largest angle, in degrees, a simplified face's normal may
    /// turn from the normals of the merged mesh under it (a true bound; default: none,
    /// only the distance bounds the normals).
    #[arg(long, allow_hyphen_values = true, value_name = "DEGREES", value_parser = parse_angle)]
    pub normal_tolerance: Option<f64>,
    /// With `--surface voxels`: one voxel face = two triangles (default: coplanar faces
    /// merged into rectangles; .glb always merges).
    #[arg(long)]
    pub unit_faces: bool,
    #[command(flatten)]
    pub read: ReadFlags,
}

/// A tolerance: a finite number of voxels, 0 or more.
fn parse_tolerance(s: &str) -> std::result::Result<f64, String> {
    match s.parse::<f64>() {
        Ok(t) if t.is_finite() && t >= 0.0 => Ok(t),
        _ => Err(format!("{s:?} is not a tolerance in voxels (a number, 0 or more)")),
    }
}

/// An angle in degrees: finite, 0 or more.
fn parse_angle(s: &str) -> std::result::Result<f64, String> {
    match s.parse::<f64>() {
        Ok(t) if t.is_finite() && t >= 0.0 => Ok(t),
        _ => Err(format!("{s:?} is not an angle in degrees (a number, 0 or more)")),
    }
}

/// `octsolid export FILE -o OUT.(obj|stl|ply|3mf|glb) [--surface smooth|voxels] [--tolerance T] [--normal-tolerance DEGREES] [--unit-faces]`
pub fn run(a: &ExportArgs, budget: MemoryBudget) -> Result<()> {
    let (file, output, unit_faces) = (&a.file, &a.output, a.unit_faces);
    let format =
        match FileKind::of(output, &[FileKind::Obj, FileKind::Stl, FileKind::Ply, FileKind::ThreeMf, FileKind::Glb]) {
            Ok(FileKind::Glb) => None,
            Ok(mesh) => Some(mesh),
            Err(octsolid::Error::UnknownExtension { found, .. }) => {
                let found =
                    if found.is_empty() { "has no extension".into() } else { format!("has extension .{found}") };
                bail!("{}: {found}, which names no mesh format; accepted: obj, stl, ply, 3mf, glb", output.display())
            }
            Err(e) => return Err(e.into()),
        };
    check_folder(output)?;
    check_not_an_input(output, &[file])?;
    if a.normal_tolerance.is_some() && (a.tolerance == 0.0 || a.surface == Style::Voxels) {
        warn!("--normal-tolerance bounds simplification's normals: it is for the smooth surface with --tolerance");
    }
    if is_sharded(file) {
        return export_sharded(a, budget);
    }
    let mut read = read_solid_file(file, &a.read, budget)?;
    if read.solids.solids.iter().all(|s| s.tree.is_empty()) {
        bail!("{}: the solid is empty; there is no boundary to export", file.display());
    }
    let Some(format) = format else {
        let up = read.meta.up.unwrap_or(read.kind.default_up());
        if a.surface == Style::Smooth {
            return export_glb_smooth(a, read, up, budget);
        }
        return export_glb(a, &read.solids, up, budget);
    };
    if unit_faces && a.surface == Style::Smooth {
        warn!("--unit-faces is for --surface voxels; the smooth surface has its own vertices");
    }
    let hermite = read.surface.take().unwrap_or_else(HermiteData::none);
    let carries_crossings = !hermite.is_empty();
    let meta = read.meta;
    let tree = read.into_union();
    let started = Instant::now();
    let bar = Bar::new("meshing");
    let options = ExtractOptions {
        style: a.surface,
        tolerance: a.tolerance,
        normal_tolerance: a.normal_tolerance,
        unit_faces,
        budget,
    };
    let surface =
        extract(&tree, &hermite, &options, &bar).with_context(|| format!("{}: cannot export", file.display()))?;
    let mesh = &surface.mesh;
    let elapsed = started.elapsed().as_secs_f64();
    let separated = if format == FileKind::Stl {
        Some(
            separate_sheets(mesh)
                .with_context(|| format!("{}: cannot write STL; write .obj or .ply", output.display()))?,
        )
    } else {
        None
    };
    let written = separated.as_ref().unwrap_or(mesh);
    let bytes = write_mesh_file(written, output, &meta)?;
    out!("read       {} ({} nodes, depth {})", file.display(), tree.node_count(), tree.depth());
    print_surface(&surface, carries_crossings, unit_faces, a.tolerance, tree.domain().voxel_size());
    if separated.is_some() {
        let moved = written.vertices.iter().zip(&mesh.vertices).filter(|(a, b)| a != b).count();
        out!("stl        {moved} vertices where voxels touch moved apart");
    }
    if format == FileKind::ThreeMf {
        match meta.units {
            Some(units) => out!("3mf        in the solid's units ({}), standing on +z", units.name()),
            None => out!("3mf        in millimetres: the solid records no units (voxelize --units sets them)"),
        }
    }
    let (enclosed, volume) = (written.volume(), tree.volume());
    out!("volume     {enclosed:.6} enclosed, {volume:.6} octree ({:+.1e} relative)", enclosed / volume - 1.0);
    out!("time       {:.1} ms ({} surface)", elapsed * 1e3, surface.style);
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    Ok(())
}

/// The summary's lines on the mesh: triangles, what placed the vertices (from the
/// file's crossings when it `carries_crossings`), the distance bound.
fn print_surface(surface: &SurfaceMesh, carries_crossings: bool, unit_faces: bool, tolerance: f64, voxel: f64) {
    let mesh = &surface.mesh;
    let (triangles, vertices) = (mesh.triangles.len(), mesh.vertices.len());
    if surface.style == Style::Voxels {
        let faces = if unit_faces { "unit faces" } else { "merged faces" };
        out!("mesh       {triangles} triangles, {vertices} vertices (the voxels' staircase, {faces})");
        return;
    }
    out!(
        "mesh       {triangles} triangles, {vertices} vertices (smooth: dual contouring, tolerance {tolerance} voxel)"
    );
    if !carries_crossings && surface.is_estimate() {
        out!(
            "surface    estimated from the voxels (Surface Nets quality) at {} of {} vertices: the file carries no crossings",
            surface.estimated,
            vertices
        );
    } else if surface.is_estimate() {
        out!(
            "surface    exact crossings: {} smooth vertices, {} on creases, {} at corners; {} estimated from the \
             voxels (Surface Nets quality) where the file has no crossing (faces its source does not cross, as a \
             mesh's holes)",
            surface.smooth,
            surface.creases,
            surface.corners,
            surface.estimated
        );
    } else {
        out!(
            "surface    exact crossings: {} smooth vertices, {} on creases, {} at corners",
            surface.smooth,
            surface.creases,
            surface.corners
        );
    }
    if !surface.is_estimate() {
        out!("distance   vertices within {:.3} voxel of their crossings' tangent planes", surface.vertex_distance);
    }
    if let Some(merge) = &surface.merged {
        out!(
            "merged     {} flat blocks of cells ({} vertices) into one vertex each, within {:.3} voxel of their planes",
            merge.blocks,
            merge.vertices,
            merge.max_plane_distance
        );
    }
    if let Some(report) = &surface.simplified {
        out!(
            "simplified {} -> {} triangles, within {:.3} voxel of the merged mesh both ways (a true bound)",
            report.triangles_before,
            report.triangles_after,
            report.max_distance_bound / voxel
        );
        if let Some(angle) = report.max_normal_bound {
            out!("normals    within {:.3} degrees of the merged mesh's under them (a true bound)", angle.to_degrees());
        }
    }
}

/// `export BIG.octs -o OUT.(stl|obj)`: the surface cell by cell, streamed
/// ([`octsolid::sharded::export_surface`]): memory follows one cell and its border.
fn export_sharded(a: &ExportArgs, budget: MemoryBudget) -> Result<()> {
    let (file, output) = (&a.file, &a.output);
    if a.tolerance > 0.0 {
        bail!(
            "{}: --tolerance simplifies a whole mesh; a sharded solid is exported cell by cell without it (export at 0, or a .oct)",
            file.display()
        );
    }
    if a.surface == Style::Voxels && !a.unit_faces {
        warn!("a sharded solid's staircase is written in unit faces (merged faces would cross the cells' seams)");
    }
    let started = Instant::now();
    let solid = ShardedSolid::open(file)?;
    let bar = Bar::new("cells");
    let options = SurfaceExportOptions { style: a.surface, budget, progress: &bar };
    let report =
        export_surface(&solid, output, &options).with_context(|| format!("{}: cannot export", file.display()))?;
    drop(bar);
    let index = solid.index();
    let voxel = index.domain.voxel_size();
    out!(
        "read       {} (sharded: {} shards, cell level {}, depth {}), cell by cell",
        file.display(),
        index.shards.len(),
        index.level,
        index.domain.depth()
    );
    out!(
        "cells      {} meshed, at most {} nodes in a window (the cell and a border of its neighbours)",
        report.cells,
        report.largest_window
    );
    let what = if a.surface == Style::Voxels { "the voxels' staircase, unit faces" } else { "smooth: dual contouring" };
    out!("mesh       {} triangles, {} vertices ({what})", report.triangles, report.vertices);
    if a.surface == Style::Smooth {
        if report.is_estimate() {
            out!(
                "surface    estimated from the voxels (Surface Nets quality) at {} of {} vertices: the shards carry no crossings there",
                report.estimated,
                report.vertices
            );
        } else {
            out!(
                "surface    exact crossings: {} smooth vertices, {} on creases, {} at corners",
                report.smooth,
                report.creases,
                report.corners
            );
            out!("distance   vertices within {:.3} voxel of their crossings' tangent planes", report.vertex_distance);
        }
    }
    if report.full_cell_faces > 0 {
        out!(
            "full cells {} faces of cells full to their seams carry no crossings (the index holds those cells whole): read as the voxel faces there",
            report.full_cell_faces
        );
    }
    out!(
        "seams      {} vertices shared by cells, placed alike from both sides within {:.2e} voxel",
        report.seam_vertices,
        report.seam_gap / voxel
    );
    let volume = index.voxels as f64 * voxel.powi(3);
    out!(
        "volume     {:.6} enclosed, {volume:.6} octree ({:+.1e} relative)",
        report.volume,
        report.volume / volume - 1.0
    );
    out!("time       {:.1} ms ({} surface)", started.elapsed().as_secs_f64() * 1e3, a.surface);
    out!("wrote {} ({})", output.display(), human_bytes(report.bytes));
    if let Some(peak) = peak_memory() {
        out!("peak mem.  {}", human_bytes(peak));
    }
    Ok(())
}

/// `export FILE -o OUT.glb` (the smooth surface, the default): each solid's true surface
/// (on the file's crossings for a file of one solid, else estimated from the voxels),
/// simplified by `--tolerance`, one mesh a solid with its colour and smooth normals
/// ([`octsolid::write_glb_surfaces`]).
fn export_glb_smooth(a: &ExportArgs, read: SolidFile, up: Axis, budget: MemoryBudget) -> Result<()> {
    let (file, output) = (&a.file, &a.output);
    if a.unit_faces {
        warn!("--unit-faces is for --surface voxels; the smooth surface has its own vertices");
    }
    let started = Instant::now();
    let solids = &read.solids;
    let options = ExtractOptions {
        style: Style::Smooth,
        tolerance: a.tolerance,
        normal_tolerance: a.normal_tolerance,
        unit_faces: false,
        budget,
    };
    let bar = Bar::new("meshing");
    let written = write_glb_surfaces(output, &solids.borrowed(), read.surface.as_ref(), &options, up, &bar)
        .with_context(|| format!("{}: cannot export", file.display()))?;
    drop(bar);
    let GlbSurfaces { bytes, meshes, triangles, estimated } = written;
    let n = solids.solids.len();
    out!("read       {} ({}, depth {})", file.display(), count(n, "solid", "solids"), solids.domain.depth());
    let placed =
        if estimated { "estimated from the voxels where the file has no crossings" } else { "exact crossings" };
    out!(
        "glb        {}, {triangles} triangles (smooth: dual contouring, tolerance {} voxel; {placed}), \
         smooth normals and a base colour each",
        count(meshes, "mesh", "meshes"),
        a.tolerance
    );
    out!("time       {:.1} ms (surfaces and the file)", started.elapsed().as_secs_f64() * 1e3);
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    Ok(())
}

/// `export FILE -o OUT.glb --surface voxels`: one staircase mesh a solid, with its colour.
fn export_glb(a: &ExportArgs, solids: &octsolid::io::Solids, up: Axis, budget: MemoryBudget) -> Result<()> {
    let (file, output) = (&a.file, &a.output);
    if a.unit_faces {
        warn!("--unit-faces is for OBJ, STL, PLY and 3MF; .glb is written with merged faces");
    }
    let started = Instant::now();
    let options = WriteOptions { budget, up, mesh_style: Style::Voxels, ..WriteOptions::default() };
    let bytes = octsolid::write_solid_file(output, &solids.borrowed(), &options, &NoProgress)
        .with_context(|| format!("{}: cannot export", file.display()))?;
    let meshed = solids.solids.iter().filter(|s| !s.tree.is_empty()).count();
    let n = solids.solids.len();
    out!("read       {} ({}, depth {})", file.display(), count(n, "solid", "solids"), solids.domain.depth());
    out!("glb        {} with normals and a base colour each (merged faces)", count(meshed, "mesh", "meshes"));
    out!("time       {:.1} ms (boundary meshes and the file)", started.elapsed().as_secs_f64() * 1e3);
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    Ok(())
}
