//! Dual contouring on the voxel faces: one vertex a sheet at each voxel corner of the
//! boundary, placed by its QEF, and each boundary face a quad of the four vertices
//! around it (Ju, Losasso, Schaefer and Warren, *Dual Contouring of Hermite Data*,
//! 2002).
//!
//! Voxels are decided by their centres, so the grid DC contours is the lattice of voxel
//! centres: its sign changes are the segments between a full voxel's centre and an
//! empty neighbour's, each crossing one boundary face, and its cells are the cubes
//! between eight voxel centres, one around each voxel corner. The quad DC makes for a
//! sign-changing edge is the boundary face itself, its corners moved to their cells'
//! vertices, so the dual mesh has exactly the staircase's connectivity
//! ([`crate::mesh::boundary_mesh`] with unit faces), which is closed, oriented and
//! manifold: where voxels touch only along an edge or at a corner the staircase keeps one
//! vertex a sheet, and so does this mesh. That is the guarantee Manifold Dual
//! Contouring (Schaefer, Ju and Warren 2007) builds its vertex clustering on: a cell
//! holds one vertex for each component of the surface inside it.
//!
//! A vertex's planes are the crossings of its sheet's faces (the edges of its cell
//! that the sheet crosses); it goes to the QEF's minimiser ([`super::qef`]) within its
//! cell (the cube of one voxel centred on the corner; a minimiser outside slides along
//! the cell's faces), so every vertex stays within its cell as the paper asks. A cell
//! whose edges cross only two of the three faces at a corner of the solid sees a
//! crease, and its vertex lands on the crease's line, up to a third of a voxel past the
//! corner (the Manifold DC shares this; a vertex of the two-ring's planes
//! would find the corner, not tried yet). A vertex none of whose faces carries a crossing
//! (occupancy only: a `.vox`, an old `.oct`) starts at the mean of its faces' centres
//! and is relaxed towards the mean of its neighbours within its cell, a few rounds, as
//! Surface Nets do (Gibson 1998): an estimate, reported as such.
//!
//! Each quad is cut along the diagonal whose two triangles pass nearer the face's
//! crossing, so a crease runs along the triangles' edges rather than across them.

use glam::DVec3;
use rayon::prelude::*;

use super::faces::face_key;
use super::hermite::{Crossing, FaceKey, HermiteData};
use super::qef::Qef;
use crate::error::Result;
use crate::mesh::{BoundarySize, UnitFaceQuads, unit_face_quads};
use crate::octree::LinearOctree;

/// Rounds of Surface-Nets relaxation for vertices without crossings.
const RELAX_ROUNDS: usize = 8;
/// Vertices handled a parallel task.
const CHUNK: usize = 4096;

/// What a vertex's planes say about the surface in its cell.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) enum VertexKind {
    /// No crossing: placed by relaxation (an estimate).
    #[default]
    Estimated,
    /// A smooth surface (planes of rank 1).
    Smooth,
    /// A crease (rank 2).
    Crease,
    /// A corner (rank 3).
    Corner,
}

/// The dual mesh before triangles: positions in lattice units, the quads, what each
/// vertex is, and each face's key.
pub(crate) struct DualMesh {
    /// Vertex positions, lattice units.
    pub positions: Vec<DVec3>,
    /// Each vertex's voxel corner (the centre of its cell).
    pub corners: Vec<[u32; 3]>,
    /// Each vertex's kind.
    pub kinds: Vec<VertexKind>,
    /// Whether the QEF's point left the cell and was clamped back.
    pub clamped: Vec<bool>,
    /// The largest distance from a vertex to one of its planes, lattice units.
    pub vertex_distance: f64,
    /// Each boundary face's key.
    pub faces: Vec<FaceKey>,
    /// Each face's crossing, `None` where the data has none.
    pub crossings: Vec<Option<Crossing>>,
    /// Each face's four vertices, counter-clockwise seen from outside.
    pub quads: Vec<[u32; 4]>,
    /// The faces around each vertex, ascending.
    pub fans: Fans,
}

/// The crossing of each of `faces` (nearly sorted: the exposed squares come in key
/// order), each chunk searched from where its previous face was found.
fn crossings_of(faces: &[FaceKey], hermite: &HermiteData) -> Vec<Option<Crossing>> {
    let data = hermite.faces();
    if data.is_empty() {
        return vec![None; faces.len()];
    }
    faces
        .par_chunks(CHUNK)
        .flat_map_iter(|chunk| {
            let mut at = data.partition_point(|(k, _)| *k < chunk[0]);
            chunk.iter().map(move |&key| {
                // Gallop from the last place, forwards or backwards.
                let near = at.min(data.len() - 1);
                let found = if data[near].0 == key {
                    Some(near)
                } else if data[near].0 < key {
                    let mut step = 1;
                    let mut hi = near + 1;
                    while hi < data.len() && data[hi].0 < key {
                        hi = (near + step).min(data.len());
                        step *= 2;
                    }
                    let lo = near + 1;
                    let hi = hi.min(data.len());
                    let i = lo + data[lo..hi].partition_point(|(k, _)| *k < key);
                    (i < data.len() && data[i].0 == key).then_some(i)
                } else {
                    let i = data[..near].partition_point(|(k, _)| *k < key);
                    (data[i].0 == key).then_some(i)
                };
                if let Some(i) = found {
                    at = i;
                }
                found.map(|i| data[i].1)
            })
        })
        .collect()
}

impl DualMesh {
    /// Dual contouring of `tree`'s boundary with the crossings of `hermite`; `size` is
    /// [`BoundarySize::of`] `tree` (its caller's budget check counted it already).
    pub(crate) fn of(tree: &LinearOctree, size: BoundarySize, hermite: &HermiteData) -> Result<DualMesh> {
        let UnitFaceQuads { faces: rects, points, quads } = unit_face_quads(tree, size)?;
        let faces: Vec<FaceKey> = rects.par_iter().map(|r| face_key(r, 0, 0)).collect();
        let crossings = crossings_of(&faces, hermite);
        let fans = Fans::of(points.len(), &quads);
        let placed: Vec<Placed> = (0..points.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|v| place(points[v], fans.of_vertex(v), &faces, &crossings))
            .collect();
        let vertex_distance = placed.iter().map(|p| p.distance).fold(0.0, f64::max);
        let mut positions: Vec<DVec3> = placed.iter().map(|p| p.position).collect();
        let kinds: Vec<VertexKind> = placed.iter().map(|p| p.kind).collect();
        let clamped: Vec<bool> = placed.iter().map(|p| p.clamped).collect();
        if kinds.contains(&VertexKind::Estimated) {
            relax(&mut positions, &points, &kinds, &fans, &quads);
        }
        Ok(DualMesh { positions, corners: points, kinds, clamped, vertex_distance, faces, crossings, quads, fans })
    }
}

/// The faces around each vertex (compressed rows: `faces[offsets[v]..offsets[v + 1]]`),
/// of quads here and in [`super::untangle`], of triangles in [`super::cluster`].
pub(crate) struct Fans {
    offsets: Vec<u32>,
    faces: Vec<u32>,
}

impl Fans {
    /// The fans of `vertices` vertices over polygons of `N` corners, in polygon order.
    pub(crate) fn of<const N: usize>(vertices: usize, polygons: &[[u32; N]]) -> Fans {
        let mut offsets = vec![0u32; vertices + 1];
        for p in polygons {
            for &v in p {
                offsets[v as usize + 1] += 1;
            }
        }
        for v in 0..vertices {
            offsets[v + 1] += offsets[v];
        }
        let mut fill = offsets.clone();
        let mut faces = vec![0u32; N * polygons.len()];
        for (f, p) in polygons.iter().enumerate() {
            for &v in p {
                faces[fill[v as usize] as usize] = f as u32;
                fill[v as usize] += 1;
            }
        }
        Fans { offsets, faces }
    }

    /// The polygons around vertex `v`.
    pub(crate) fn of_vertex(&self, v: usize) -> &[u32] {
        &self.faces[self.offsets[v] as usize..self.offsets[v + 1] as usize]
    }
}

/// A vertex placed: where, what its planes say, whether clamped, and its largest
/// distance to one of its planes.
struct Placed {
    position: DVec3,
    kind: VertexKind,
    clamped: bool,
    distance: f64,
}

/// Vertex at voxel corner `corner` with faces `fan`: its QEF's point in its cell.
fn place(corner: [u32; 3], fan: &[u32], faces: &[FaceKey], crossings: &[Option<Crossing>]) -> Placed {
    let p = DVec3::new(f64::from(corner[0]), f64::from(corner[1]), f64::from(corner[2]));
    let mut qef = Qef::default();
    let mut centres = DVec3::ZERO;
    for &f in fan {
        let key = faces[f as usize];
        match crossings[f as usize] {
            Some(c) => qef.add(c.point(key) - p, c.normal.as_dvec3()),
            None => centres += Crossing::face(key).point(key) - p,
        }
    }
    if qef.is_empty() {
        let position = p + centres / fan.len() as f64;
        return Placed { position, kind: VertexKind::Estimated, clamped: false, distance: 0.0 };
    }
    let (solution, clamped) = qef.solve_within(DVec3::splat(-0.5), DVec3::splat(0.5));
    let kind = match solution.rank {
        0 | 1 => VertexKind::Smooth,
        2 => VertexKind::Crease,
        _ => VertexKind::Corner,
    };
    let x = solution.point;
    let distance = fan
        .iter()
        .filter_map(|&f| crossings[f as usize].map(|c| (faces[f as usize], c)))
        .map(|(key, c)| c.normal.as_dvec3().dot(x - (c.point(key) - p)).abs())
        .fold(0.0, f64::max);
    Placed { position: p + x, kind, clamped, distance }
}

/// Surface Nets' relaxation of the estimated vertices: each moves to the mean of its
/// neighbours along the quads' edges, kept in its cell, [`RELAX_ROUNDS`] times.
fn relax(positions: &mut [DVec3], corners: &[[u32; 3]], kinds: &[VertexKind], fans: &Fans, quads: &[[u32; 4]]) {
    for _ in 0..RELAX_ROUNDS {
        let next: Vec<DVec3> = (0..positions.len())
            .into_par_iter()
            .with_min_len(CHUNK)
            .map(|v| {
                if kinds[v] != VertexKind::Estimated {
                    return positions[v];
                }
                let mut sum = DVec3::ZERO;
                let mut count = 0.0;
                for &f in fans.of_vertex(v) {
                    let q = quads[f as usize];
                    let i = q.iter().position(|&u| u as usize == v).unwrap_or(0);
                    for n in [q[(i + 1) % 4], q[(i + 3) % 4]] {
                        sum += positions[n as usize];
                        count += 1.0;
                    }
                }
                let c = corners[v];
                let p = DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]));
                (sum / count).clamp(p - 0.5, p + 0.5)
            })
            .collect();
        positions.copy_from_slice(&next);
    }
}

/// The two triangles of quad `q` (counter-clockwise), cut along the diagonal whose
/// triangles pass nearer `crossing` (lattice units); ties keep the `0-2` diagonal.
pub(crate) fn split_quad(q: [u32; 4], positions: &[DVec3], crossing: DVec3) -> [[u32; 3]; 2] {
    let a = [[q[0], q[1], q[2]], [q[0], q[2], q[3]]];
    let b = [[q[1], q[2], q[3]], [q[1], q[3], q[0]]];
    let distance = |split: &[[u32; 3]; 2]| {
        split
            .iter()
            .map(|t| point_triangle_distance2(crossing, t.map(|i| positions[i as usize])))
            .fold(f64::INFINITY, f64::min)
    };
    if distance(&b) < distance(&a) { b } else { a }
}

/// Squared distance from `p` to the triangle `t` (Ericson, *Real-Time Collision
/// Detection*, 5.1.5: the closest point by Voronoi regions).
pub(crate) fn point_triangle_distance2(p: DVec3, t: [DVec3; 3]) -> f64 {
    let [a, b, c] = t;
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return ap.length_squared();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return bp.length_squared();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (p - (a + ab * v)).length_squared();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return cp.length_squared();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (p - (a + ac * w)).length_squared();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + (c - b) * w)).length_squared();
    }
    let denom = va + vb + vc;
    if denom.abs() < f64::MIN_POSITIVE {
        return ap.length_squared().min(bp.length_squared()).min(cp.length_squared());
    }
    let (v, w) = (vb / denom, vc / denom);
    (p - (a + ab * v + ac * w)).length_squared()
}
