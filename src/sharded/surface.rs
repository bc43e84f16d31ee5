//! A sharded solid's surface written cell by cell ([`export_surface`]): memory follows
//! one cell and its border, never the solid, and the mesh is closed across the seams.
//!
//! Each cell that owns a boundary face (a shard, or a full cell beside one that is not
//! full or at the domain's edge) is meshed on its own by [`extract_cell`] from a
//! **window**: its nodes and [`CELL_BORDER`] voxels of its neighbours' (each
//! neighbour's shard read, cropped to the window and dropped; full cells cropped from
//! the index), with the crossings the shards carry for those voxels. The cell emits
//! the triangles of the faces it owns (those of its full voxels), so every face is
//! emitted once.
//!
//! Welding: a vertex is named in the whole solid's frame ([`VertexKey`]); vertices on
//! a cell's box are kept in a table of the seams (a curve's worth of vertices a seam
//! plane, far fewer than the surface's), so that the second cell to reach one uses the
//! first cell's placement and index: the mesh's triangles share their seam vertices
//! exactly, whatever the windows. How far the second placement was from the first is
//! reported (0 when the border held everything that places them, see
//! `crate::surface`'s window module).
//!
//! Crossings come from the shards' surface sections. A full cell has no shard (the
//! index holds it as a node), so the faces of its voxels beside an empty voxel of the
//! next cell carry none: they are read as the faces themselves, and a vertex there is
//! placed by the other faces around it (estimated if none has a crossing). The export
//! counts them ([`SurfaceExport::full_cell_faces`]); a sphere at cells of 8 voxels has
//! a few, at 16 voxels none. Carrying them needs a place in the format (a section of
//! the index, or a file beside the shards), not made yet.
//!
//! Output, streamed as cells are done: binary STL (the triangles as they come, the
//! count written into the header at the end) and OBJ (each cell's new vertices, then
//! its faces by global index: OBJ allows vertices anywhere before their use, so the
//! file is welded). Formats whose head counts the vertices (PLY) or that hold the mesh
//! in one document (3MF, glTF) are not streamed; export a sharded solid to one of the two.
//! The staircase ([`Style::Voxels`]) comes in unit faces (merged rectangles would cross
//! the seams); for STL its sheets that share a position are moved apart, in each window,
//! as [`crate::mesh::separate_sheets`] moves them in a whole mesh.

use std::io::{Seek, SeekFrom, Write};
use std::path::Path;

use glam::DVec3;
use rustc_hash::FxHashMap;

use super::solid::ShardedSolid;
use super::window::{Window, is_full};
use crate::atomic::write_atomic_seekable;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::file_kind::FileKind;
use crate::mesh::BoundarySize;
use crate::morton;
use crate::progress::{Progress, stop_if_cancelled};
use crate::surface::{CELL_BORDER, CellSurface, CellVertexKind, Style, VertexKey, extract_cell};

/// Estimated peak bytes a boundary face of a window takes while its cell is meshed
/// (the staircase's quads and sheets, the fans, the QEF's results, the triangles: as
/// [`crate::surface::extract`] counts them).
const BYTES_PER_FACE: u64 = 256;

/// How [`export_surface`] works.
#[derive(Clone, Copy)]
pub struct SurfaceExportOptions<'a> {
    /// The smooth surface or the staircase (in unit faces).
    pub style: Style,
    /// Memory for one cell's window (its shards read, its mesh made).
    pub budget: MemoryBudget,
    /// Receives progress in cells.
    pub progress: &'a dyn Progress,
}

/// What [`export_surface`] wrote.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SurfaceExport {
    /// Triangles written.
    pub triangles: u64,
    /// Distinct vertices (seam vertices once).
    pub vertices: u64,
    /// Cells meshed.
    pub cells: u64,
    /// The most nodes one window held.
    pub largest_window: u64,
    /// Vertices on the seams between cells.
    pub seam_vertices: u64,
    /// The largest distance, world units, between the two placements of a seam vertex
    /// by the cells either side (the first is written).
    pub seam_gap: f64,
    /// Smooth vertices estimated from occupancy (no crossing on their faces).
    pub estimated: u64,
    /// Smooth vertices on smooth parts (planes of rank 1).
    pub smooth: u64,
    /// Smooth vertices on creases.
    pub creases: u64,
    /// Smooth vertices at corners.
    pub corners: u64,
    /// Vertices whose QEF point left its cell and was clamped back.
    pub clamped: u64,
    /// Boundary faces of full cells: the index holds a full cell as a node, with no
    /// file to carry its faces' crossings, so they are read as the faces themselves
    /// (their vertices placed by the other faces around them, or estimated).
    pub full_cell_faces: u64,
    /// The largest distance, in voxels, from a vertex to its crossings' tangent planes.
    pub vertex_distance: f64,
    /// The signed volume the written triangles enclose (as written: `f32` for STL).
    pub volume: f64,
    /// Their area.
    pub area: f64,
    /// Bytes of the file.
    pub bytes: u64,
}

impl SurfaceExport {
    /// Whether any vertex was estimated from occupancy alone.
    #[must_use]
    pub fn is_estimate(&self) -> bool {
        self.estimated > 0
    }
}

/// Writes the surface of `solid` to `path` (`.stl` or `.obj`), cell by cell (module
/// doc), atomically.
///
/// # Errors
/// Another extension; a shard that fails its checks (named); a window over the
/// budget; more than `2^32` triangles for STL; writing fails.
pub fn export_surface(solid: &ShardedSolid, path: &Path, options: &SurfaceExportOptions) -> Result<SurfaceExport> {
    let format = match FileKind::of(path, &[FileKind::Stl, FileKind::Obj]) {
        Ok(format) => format,
        Err(Error::UnknownExtension { .. }) => {
            return Err(Error::invalid(
                "sharded export",
                format!(
                    "{}: a sharded solid's surface is written cell by cell to .stl or .obj only (PLY counts its vertices in its head; 3MF and glTF hold one document)",
                    path.display()
                ),
            ));
        }
        Err(e) => return Err(e),
    };
    let cells = cells_to_mesh(solid);
    let mut report = SurfaceExport::default();
    let mut failure = None;
    let bytes = write_atomic_seekable(path, |w| {
        let mut stream = Stream { w, format, seams: FxHashMap::default(), next: 0, report: &mut report };
        stream.begin()?;
        options.progress.start(cells.len() as u64);
        for &cell in &cells {
            let (piece, nodes) = match mesh_cell(solid, cell, format == FileKind::Stl, options) {
                Ok(done) => done,
                Err(e) => {
                    failure = Some(e);
                    return Err(std::io::Error::other("a cell could not be meshed"));
                }
            };
            stream.report.largest_window = stream.report.largest_window.max(nodes);
            if is_full(solid, cell) {
                stream.report.full_cell_faces += piece.triangles.len() as u64 / 2;
            }
            stream.cell(&piece)?;
            options.progress.advance(1);
            if let Err(e) = stop_if_cancelled(options.progress) {
                failure = Some(e);
                return Err(std::io::Error::other("cancelled"));
            }
        }
        options.progress.finish();
        stream.end()
    });
    if let Some(e) = failure {
        return Err(e);
    }
    report.bytes = bytes?;
    report.cells = cells.len() as u64;
    Ok(report)
}

/// The cells that own a boundary face, in Morton order: every shard's, and the full
/// cells with a face on the domain's edge or beside a cell that is not full.
fn cells_to_mesh(solid: &ShardedSolid) -> Vec<u64> {
    let index = solid.index();
    let layout = index.layout();
    let per_side = 1u64 << index.level;
    let mut cells: Vec<u64> = index.shards.iter().map(|s| s.cell).collect();
    for key in &index.full {
        // The node's cells on its box, each kept if a face neighbour is not full.
        let lo = morton::decode(key.start()).map(|c| u64::from(c >> layout.cell_k()));
        let hi = lo.map(|c| c + (1u64 << (key.k() - u32::from(layout.cell_k()))) - 1);
        for x in lo[0]..=hi[0] {
            for y in lo[1]..=hi[1] {
                let side = x == lo[0] || x == hi[0] || y == lo[1] || y == hi[1];
                let zs: Vec<u64> = if side { (lo[2]..=hi[2]).collect() } else { vec![lo[2], hi[2]] };
                for z in zs {
                    let c = [x, y, z];
                    let exposed = (0..3).any(|a| {
                        [c[a].checked_sub(1), Some(c[a] + 1).filter(|&n| n < per_side)].into_iter().any(|n| {
                            n.is_none_or(|n| {
                                let mut d = c;
                                d[a] = n;
                                !is_full(solid, cell_number(d))
                            })
                        })
                    });
                    if exposed {
                        cells.push(cell_number(c));
                    }
                }
            }
        }
    }
    cells.sort_unstable();
    cells.dedup();
    cells
}

/// The Morton number of the cell at cell coordinates `c`.
fn cell_number(c: [u64; 3]) -> u64 {
    morton::encode(c[0] as u32, c[1] as u32, c[2] as u32)
}

/// The surface cell `cell` owns, from its window, and the window's node count;
/// `separate_sheets` for STL.
fn mesh_cell(
    solid: &ShardedSolid,
    cell: u64,
    separate_sheets: bool,
    options: &SurfaceExportOptions,
) -> Result<(CellSurface, u64)> {
    let index = solid.index();
    let layout = index.layout();
    let window = Window::around(layout, cell, CELL_BORDER, index.domain.resolution());
    let (window, hermite) = window.read(solid, true, None, options.budget)?;
    let size = BoundarySize::of(&window);
    let bytes = u64::try_from(size.unit_faces).unwrap_or(u64::MAX).saturating_mul(BYTES_PER_FACE);
    options.budget.check(format!("meshing cell {cell} of {} with its border", solid.dir().display()), bytes)?;
    let piece = extract_cell(&window, &hermite, layout.cell_key(cell), options.style, separate_sheets)?;
    Ok((piece, window.node_count() as u64))
}

/// The output as cells come: the seam table and the running counts.
struct Stream<'a, W: Write + Seek> {
    w: &'a mut W,
    format: FileKind,
    /// Seam vertices met so far: their index and position as first placed.
    seams: FxHashMap<VertexKey, (u64, DVec3)>,
    next: u64,
    report: &'a mut SurfaceExport,
}

impl<W: Write + Seek> Stream<'_, W> {
    fn begin(&mut self) -> std::io::Result<()> {
        match self.format {
            FileKind::Stl => {
                let mut header = [0u8; 80];
                header[..20].copy_from_slice(b"octsolid binary STL ");
                self.w.write_all(&header)?;
                self.w.write_all(&0u32.to_le_bytes())
            }
            _ => writeln!(self.w, "# written by octsolid, cell by cell"),
        }
    }

    /// Welds one cell's piece to the seams met so far and writes it.
    fn cell(&mut self, piece: &CellSurface) -> std::io::Result<()> {
        let report = &mut *self.report;
        let mut global = Vec::with_capacity(piece.vertices.len());
        let mut positions = Vec::with_capacity(piece.vertices.len());
        let mut fresh = Vec::new();
        for v in 0..piece.vertices.len() {
            let p = piece.vertices[v];
            let known = if piece.seam[v] { self.seams.get(&piece.keys[v]).copied() } else { None };
            let (g, p) = match known {
                Some((g, first)) => {
                    report.seam_gap = report.seam_gap.max(first.distance(p));
                    (g, first)
                }
                None => {
                    let g = self.next;
                    self.next += 1;
                    if piece.seam[v] {
                        self.seams.insert(piece.keys[v], (g, p));
                        report.seam_vertices += 1;
                    }
                    match piece.kinds[v] {
                        Some(CellVertexKind::Estimated) => report.estimated += 1,
                        Some(CellVertexKind::Smooth) => report.smooth += 1,
                        Some(CellVertexKind::Crease) => report.creases += 1,
                        Some(CellVertexKind::Corner) => report.corners += 1,
                        None => {}
                    }
                    report.clamped += u64::from(piece.clamped[v]);
                    fresh.push(p);
                    (g, p)
                }
            };
            global.push(g);
            positions.push(p);
        }
        report.vertices = self.next;
        report.vertex_distance = report.vertex_distance.max(piece.vertex_distance);
        if self.format == FileKind::Obj {
            for p in &fresh {
                writeln!(self.w, "v {} {} {}", p.x, p.y, p.z)?;
            }
        }
        for t in &piece.triangles {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            match self.format {
                FileKind::Stl => {
                    let n = (b - a).cross(c - a).normalize_or_zero();
                    for v in [n, a, b, c] {
                        for x in v.to_array() {
                            self.w.write_all(&(x as f32).to_le_bytes())?;
                        }
                    }
                    self.w.write_all(&[0, 0])?;
                    let [a, b, c] = [a, b, c].map(|v| v.as_vec3().as_dvec3());
                    report.volume += a.dot(b.cross(c)) / 6.0;
                    report.area += 0.5 * (b - a).cross(c - a).length();
                }
                _ => {
                    let [i, j, k] = t.map(|v| global[v as usize] + 1);
                    writeln!(self.w, "f {i} {j} {k}")?;
                    report.volume += a.dot(b.cross(c)) / 6.0;
                    report.area += 0.5 * (b - a).cross(c - a).length();
                }
            }
            report.triangles += 1;
        }
        Ok(())
    }

    fn end(&mut self) -> std::io::Result<()> {
        if self.format == FileKind::Stl {
            let count = u32::try_from(self.report.triangles).map_err(|_| {
                std::io::Error::other(format!("{} triangles do not fit STL's count; write .obj", self.report.triangles))
            })?;
            self.w.seek(SeekFrom::Start(80))?;
            self.w.write_all(&count.to_le_bytes())?;
            self.w.seek(SeekFrom::End(0))?;
        }
        Ok(())
    }
}
