//! The surface of one cell of a solid too large to mesh whole: the part of the mesh
//! [`super::extract`] would make that a cell **owns**, extracted from a **window** of
//! the solid (the cell and a border of its neighbours' voxels), its vertices named in
//! the whole solid's frame so that cells extracted apart weld into one closed mesh.
//!
//! Ownership: a triangle belongs to the boundary face it was cut from, and a face to
//! the cell of its full voxel ([`FaceKey::voxel`]), so every face is owned by exactly
//! one cell. An owned face's four vertices sit at voxel corners on or inside the
//! cell's closed box; those on its box are shared with the neighbours (the seam).
//!
//! Why a border: in dual contouring (Ju et al. 2002) a vertex's place depends on the
//! crossings of the faces around its voxel corner, one voxel around it, and whether a
//! face is a boundary face on the voxels either side, so one voxel of border gives
//! every owned face's vertices as the whole solid's extraction places them. Two steps
//! reach further: Surface Nets' relaxation of vertices without crossings
//! (`super::dual`, eight rounds along the quads' edges: eight voxels) and the
//! untangling (`super::untangle`: a round moves the vertices of crossing triangles,
//! tested within two voxels of a risky vertex, and moved vertices are tested again
//! the next round). The window's own edge is a cut through the solid, a staircase of
//! faces without crossings that the real surface does not have; what it changes must
//! not reach the cell. [`CELL_BORDER`] voxels hold the relaxation with room to spare
//! and the untangling as far as its rounds go in practice (a round or two); that is
//! where this departs from a proof: two cells could place a seam vertex differently
//! after many untangling rounds near their seam, so a caller welding cells takes one
//! placement for each seam vertex (the first) and can report how far the other was.
//!
//! Naming: a vertex is one sheet of the surface at a voxel corner; a boundary face
//! touches one sheet at each of its corners, so the corner with the least face
//! around it ([`VertexKey`]) names the vertex in any window that holds its faces.

use glam::DVec3;
use rayon::prelude::*;

use super::dual::{DualMesh, VertexKind};
use super::extract::Style;
use super::faces::face_key;
use super::hermite::{FaceKey, HermiteData};
use super::untangle::untangle;
use crate::error::{Error, Result};
use crate::mesh::{BoundarySize, TriangleMesh, UnitFaceQuads, separate, unit_face_quads};
use crate::morton;
use crate::octree::{LinearOctree, NodeKey};

/// Voxels of the neighbours' solid a window must hold around its cell on every side
/// (within the domain): the eight rounds of relaxation and the untangling's reach,
/// with room to spare (module doc).
pub const CELL_BORDER: u32 = 16;

/// A vertex of the surface named in the whole solid's frame: its voxel corner (lattice
/// coordinates) and the least boundary face around it there, which names its sheet.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct VertexKey {
    /// The voxel corner.
    pub corner: [u32; 3],
    /// The least face (in [`FaceKey`] order) of the sheet at that corner.
    pub face: FaceKey,
}

/// The part of a solid's surface that one cell owns (module doc).
#[derive(Clone, Debug, Default)]
pub struct CellSurface {
    /// Vertex positions, world coordinates.
    pub vertices: Vec<DVec3>,
    /// Each vertex's name in the whole solid.
    pub keys: Vec<VertexKey>,
    /// Whether a vertex lies on the cell's box, shared with a neighbouring cell.
    pub seam: Vec<bool>,
    /// Each vertex's kind: what its planes say (`None` for the staircase).
    pub kinds: Vec<Option<CellVertexKind>>,
    /// Whether a vertex's QEF point left its cell and was clamped back.
    pub clamped: Vec<bool>,
    /// The owned triangles, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// The largest distance, in voxels, from a vertex of the window to the tangent
    /// planes of its crossings (0 for the staircase).
    pub vertex_distance: f64,
}

/// What a smooth vertex's planes say about the surface at it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CellVertexKind {
    /// No crossing on its faces: placed by relaxation, an estimate.
    Estimated,
    /// Planes of rank 1.
    Smooth,
    /// Rank 2: a crease.
    Crease,
    /// Rank 3: a corner.
    Corner,
}

impl From<VertexKind> for CellVertexKind {
    fn from(kind: VertexKind) -> Self {
        match kind {
            VertexKind::Estimated => CellVertexKind::Estimated,
            VertexKind::Smooth => CellVertexKind::Smooth,
            VertexKind::Crease => CellVertexKind::Crease,
            VertexKind::Corner => CellVertexKind::Corner,
        }
    }
}

/// The surface `cell` owns (module doc) from `window`, the solid's nodes in the cell
/// and at least [`CELL_BORDER`] voxels around it (as far as the domain goes), and
/// `hermite`, the crossings of the window's faces (faces without one are estimated).
/// `style` as [`super::extract`] takes it, the staircase always in unit faces (merged
/// rectangles would cross the seams). `separate_sheets`: vertices of sheets sharing a
/// position moved apart as [`crate::mesh::separate_sheets`] does, for STL, over the
/// faces within two voxels of the cell (a vertex's move depends on its own triangles
/// and the other copies at its position, all within one voxel of it).
///
/// # Errors
/// When the window's mesh would need more than `2^32` vertices, or `separate_sheets`
/// cannot keep two vertices apart in `f32`.
pub fn extract_cell(
    window: &LinearOctree,
    hermite: &HermiteData,
    cell: NodeKey,
    style: Style,
    separate_sheets: bool,
) -> Result<CellSurface> {
    if window.is_empty() {
        return Ok(CellSurface::default());
    }
    let domain = *window.domain();
    let piece = match style {
        Style::Smooth => {
            let mut dual = DualMesh::of(window, BoundarySize::of(window), hermite)?;
            let triangles = untangle(&mut dual);
            let (min, voxel) = (domain.min(), domain.voxel_size());
            Piece {
                vertices: dual.positions.par_iter().map(|&p| min + p * voxel).collect(),
                corners: dual.corners,
                kinds: dual.kinds.into_iter().map(|k| Some(k.into())).collect(),
                clamped: dual.clamped,
                faces: dual.faces,
                quads: dual.quads,
                triangles,
                vertex_distance: dual.vertex_distance,
            }
        }
        Style::Voxels => {
            let UnitFaceQuads { faces, points, quads } = unit_face_quads(window, BoundarySize::of(window))?;
            let n = points.len();
            Piece {
                vertices: points.par_iter().map(|&p| domain.lattice_point(p)).collect(),
                corners: points,
                kinds: vec![None; n],
                clamped: vec![false; n],
                faces: faces.par_iter().map(|r| face_key(r, 0, 0)).collect(),
                triangles: quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect(),
                quads,
                vertex_distance: 0.0,
            }
        }
    };
    piece.owned_by(cell, separate_sheets)
}

/// A window's whole mesh before the cell's part is taken.
struct Piece {
    vertices: Vec<DVec3>,
    corners: Vec<[u32; 3]>,
    kinds: Vec<Option<CellVertexKind>>,
    clamped: Vec<bool>,
    faces: Vec<FaceKey>,
    quads: Vec<[u32; 4]>,
    /// Face `f`'s two triangles at `2 f` and `2 f + 1`.
    triangles: Vec<[u32; 3]>,
    vertex_distance: f64,
}

impl Piece {
    /// The triangles of the faces whose voxel lies in `cell`, their vertices
    /// renumbered in order of first use and named.
    fn owned_by(self, cell: NodeKey, separate_sheets: bool) -> Result<CellSurface> {
        let Piece { vertices, corners, kinds, clamped, faces, quads, triangles, vertex_distance } = self;
        let (lo, size) = (morton::decode(cell.start()), 1u32 << cell.k());
        let vertices = if separate_sheets {
            // The faces within two voxels of the cell: every owned vertex with all its
            // triangles, and none of the window's cut edge, whose vertices may sit
            // where f32 cannot tell them from a real one.
            let near = |f: &FaceKey| {
                let v = f.voxel();
                (0..3).all(|a| v[a].saturating_add(2) >= lo[a] && v[a] < (lo[a] + size).saturating_add(2))
            };
            let around: Vec<[u32; 3]> = (0..faces.len())
                .filter(|&f| near(&faces[f]))
                .flat_map(|f| [triangles[2 * f], triangles[2 * f + 1]])
                .collect();
            let mesh = TriangleMesh { vertices, triangles: around, groups: Vec::new() };
            separate(&mesh).map_err(|reason| Error::invalid("mesh for STL", reason))?.vertices
        } else {
            vertices
        };
        // Each vertex's least face.
        let mut least = vec![FaceKey { voxel: u64::MAX, direction: u8::MAX }; vertices.len()];
        for (f, q) in quads.iter().enumerate() {
            for &v in q {
                least[v as usize] = least[v as usize].min(faces[f]);
            }
        }
        let (first, end) = (cell.start(), cell.end());
        let on_box = |c: [u32; 3]| (0..3).any(|a| c[a] == lo[a] || c[a] == lo[a] + size);
        let mut out = CellSurface { vertex_distance, ..CellSurface::default() };
        let mut renumber = vec![u32::MAX; vertices.len()];
        for (f, face) in faces.iter().enumerate() {
            if face.voxel < first || face.voxel >= end {
                continue;
            }
            for t in [triangles[2 * f], triangles[2 * f + 1]] {
                out.triangles.push(t.map(|v| {
                    let v = v as usize;
                    if renumber[v] == u32::MAX {
                        renumber[v] = out.vertices.len() as u32;
                        out.vertices.push(vertices[v]);
                        out.keys.push(VertexKey { corner: corners[v], face: least[v] });
                        out.seam.push(on_box(corners[v]));
                        out.kinds.push(kinds[v]);
                        out.clamped.push(clamped[v]);
                    }
                    renumber[v]
                }));
            }
        }
        Ok(out)
    }
}
