//! Triangle meshes: loading (OBJ, STL, PLY), polygon tables and diagnostics,
//! voxelization into solid or surface octrees, and the boundary mesh of an octree.
//!
//! A [`TriangleMesh`] is a vertex table and a triangle table. Loaders weld vertices with
//! identical coordinates (STL stores every corner separately), so the edge table sees
//! the mesh's real connectivity.

mod boundary;
mod crossing;
pub mod generate;
mod mtl;
mod obj;
mod parity;
mod ply;
pub(crate) mod predicates;
mod read;
mod separate;
mod shape;
mod solid;
mod stl;
mod surface;
mod tables;
mod three_mf;
mod tri_box;
mod triangle_tree;
mod triangulate;
mod winding;
mod write;

use std::collections::HashMap;

use glam::{DAffine3, DVec3};

use crate::aabb::Aabb;
use crate::error::{Error, Result};

pub use boundary::{BoundaryOptions, boundary_mesh, try_boundary_mesh};
pub(crate) use boundary::{
    BoundarySize, Rect as BoundaryRect, UnitFaceQuads, boundary_mesh_of_size, boundary_rects, exposed_squares,
    unit_face_quads,
};
pub(crate) use crossing::{Plane, signed_crossing};
pub use parity::ParityGrid;
pub use read::{mesh_from_bytes, read_mesh, read_mesh_and_warnings};
pub use separate::{SEPARATION_LIMIT, SEPARATION_STEP, separate_sheets};
pub(crate) use separate::{separate, separated_vertices};
pub use shape::MeshShape;
pub(crate) use solid::solid_triangles;
pub use solid::{InsideRule, MeshVoxelizeOptions, MeshVoxelizeStats, voxelize_mesh, voxelize_mesh_cells};
pub use surface::{SurfaceKind, estimate_surface_bytes, voxelize_surface};
pub use tables::{Edge, MeshReport, PolygonTables};
pub use three_mf::{ThreeMfOptions, ThreeMfUnit, write_3mf};
pub(crate) use triangle_tree::TriangleTree;
pub use winding::WindingNumber;
pub use write::{write_mesh, write_mesh_with, write_obj, write_ply, write_stl};

/// A named run of triangles (an OBJ group or object).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Group {
    /// The group's name.
    pub name: String,
    /// Index of its first triangle.
    pub first: usize,
    /// Number of its triangles.
    pub count: usize,
}

/// A triangle mesh: positions and triangles as index triples, with optional groups.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// The vertex table.
    pub vertices: Vec<DVec3>,
    /// Triangles as indices into `vertices`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Named runs of triangles; may be empty.
    pub groups: Vec<Group>,
}

impl TriangleMesh {
    /// A mesh from tables, checked: non-empty, finite coordinates, indices in range.
    pub fn new(vertices: Vec<DVec3>, triangles: Vec<[u32; 3]>) -> Result<Self> {
        let mesh = TriangleMesh { vertices, triangles, groups: Vec::new() };
        mesh.validate()?;
        Ok(mesh)
    }

    /// Checks the invariants [`TriangleMesh::new`] promises.
    pub fn validate(&self) -> Result<()> {
        if self.triangles.is_empty() {
            return Err(Error::invalid("mesh", "it has no triangles"));
        }
        if let Some(i) = self.vertices.iter().position(|v| !v.is_finite()) {
            return Err(Error::invalid("mesh", format!("vertex {i} is not finite: {}", self.vertices[i])));
        }
        let n = self.vertices.len();
        if let Some((t, tri)) = self.triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as usize >= n)) {
            return Err(Error::invalid("mesh", format!("triangle {t} has indices {tri:?} but there are {n} vertices")));
        }
        Ok(())
    }

    /// The three corners of triangle `t`.
    #[inline]
    #[must_use]
    pub fn corners(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|i| self.vertices[i as usize])
    }

    /// Bounding box of the vertices used by triangles.
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.triangles.iter().flatten().map(|&i| self.vertices[i as usize]))
            .unwrap_or(Aabb { min: DVec3::ZERO, max: DVec3::ZERO })
    }

    /// The surface area: the sum of the triangles' areas.
    #[must_use]
    pub fn area(&self) -> f64 {
        let s = self.coordinate_scale();
        (0..self.triangles.len()).map(|t| self.twice_area_scaled(t, s)).sum::<f64>() / 2.0 * s * s
    }

    /// Twice triangle `t`'s area, its corners divided by `s` (a [`coordinate_scale`]).
    ///
    /// [`coordinate_scale`]: TriangleMesh::coordinate_scale
    pub(crate) fn twice_area_scaled(&self, t: usize, s: f64) -> f64 {
        let [a, b, c] = self.corners(t).map(|p| p / s);
        (b - a).cross(c - a).length()
    }

    /// The power of two at or above the largest coordinate a triangle uses (1 for no
    /// triangles): coordinates divided by it lie in `[-1, 1]` (`[-2, 2]` past 2^1023), so
    /// the products of areas and volumes cannot overflow, and dividing by it and
    /// multiplying back are exact (a mesh with corners at 1e200 has area `inf`, not
    /// degenerate faces and a volume of `NaN`; any other mesh the same bits as unscaled).
    pub(crate) fn coordinate_scale(&self) -> f64 {
        let b = self.bounds();
        let largest = b.min.abs().max(b.max.abs()).max_element();
        if largest == 0.0 { 1.0 } else { 2f64.powi(largest.log2().ceil().clamp(-1022.0, 1023.0) as i32) }
    }

    /// Enclosed volume by the signed-tetrahedron sum `V = sum (p1 . (p2 x p3)) / 6`,
    /// exact for a closed, consistently oriented mesh (positive when it faces out).
    #[must_use]
    pub fn volume(&self) -> f64 {
        let s = self.coordinate_scale();
        (0..self.triangles.len())
            .map(|t| {
                let [a, b, c] = self.corners(t).map(|p| p / s);
                a.dot(b.cross(c))
            })
            .sum::<f64>()
            / 6.0
            * s
            * s
            * s
    }

    /// Whether every edge is used exactly twice, once in each direction (closed,
    /// manifold, consistently oriented): each directed edge `a -> b` occurs once and
    /// `b -> a` occurs too. The directed edges are bucketed by their first vertex (a
    /// counting sort, O(n)) and each bucket sorted (a few edges), so both checks look
    /// at one vertex's edges only: O(n log d) for vertex degree d, no tables.
    #[must_use]
    pub fn is_watertight(&self) -> bool {
        // Step 1: bucket starts by first vertex (counts, then prefix sums); indices
        // past the vertex table are counted too, so an unchecked mesh cannot panic.
        let n = self.triangles.iter().flatten().max().map_or(0, |&i| i as usize + 1);
        let mut start = vec![0u32; n + 1];
        for &a in self.triangles.iter().flatten() {
            start[a as usize + 1] += 1;
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        // Step 2: each edge's second vertex into its first vertex's bucket, sorted.
        let mut next = start.clone();
        let mut ends = vec![0u32; self.triangles.len() * 3];
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k] as usize, t[(k + 1) % 3]);
                ends[next[a] as usize] = b;
                next[a] += 1;
            }
        }
        let bucket = |a: usize| start[a] as usize..start[a + 1] as usize;
        for a in 0..n {
            ends[bucket(a)].sort_unstable();
        }
        // Step 3: no edge twice, and every edge's reverse present.
        (0..n).all(|a| {
            let out = &ends[bucket(a)];
            out.windows(2).all(|w| w[0] != w[1])
                && out.iter().all(|&b| ends[bucket(b as usize)].binary_search(&(a as u32)).is_ok())
        })
    }

    /// The triangles that bound a solid, under either inside rule: the mesh without
    /// the triangles that bound nothing, those with a repeated corner (no area) and
    /// pairs on the same three corners facing opposite ways (a ray crosses both or
    /// neither, so they cancel in a parity count and in the winding number alike);
    /// borrowed when there are none, and the number left out. Such triangles come from
    /// polygons that revisit their corners, fanned: a 1,000-corner face over 5
    /// vertices made 998 triangles, half with a repeated corner, every one on every
    /// node of its box and each a string of exact predicates on ties, 13 s at depth 8.
    #[must_use]
    pub fn solid_boundary(&self) -> (std::borrow::Cow<'_, TriangleMesh>, usize) {
        use std::borrow::Cow;
        let void = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
        // Each triangle's corners sorted, its index, and whether sorting took an odd
        // permutation; sorted, so the triangles of one set of corners are adjacent.
        let mut sets = corner_sets(&self.triangles);
        if !self.triangles.iter().any(void) && all_distinct(&sets) {
            return (Cow::Borrowed(self), 0);
        }
        // Keep the first |net| triangles of each set that face its way.
        let mut keep = vec![false; self.triangles.len()];
        sets.retain(|&(k, _, _)| !void(&k));
        for group in sets.chunk_by(|a, b| a.0 == b.0) {
            let net: i64 = group.iter().map(|&(_, _, odd)| if odd { -1 } else { 1 }).sum();
            let mut left = net.unsigned_abs();
            let mut members: Vec<u32> =
                group.iter().filter(|&&(_, _, odd)| odd == (net < 0)).map(|&(_, t, _)| t).collect();
            members.sort_unstable();
            for t in members {
                if left == 0 {
                    break;
                }
                keep[t as usize] = true;
                left -= 1;
            }
        }
        let triangles: Vec<[u32; 3]> = self.triangles.iter().zip(&keep).filter(|(_, k)| **k).map(|(t, _)| *t).collect();
        if triangles.len() == self.triangles.len() {
            return (Cow::Borrowed(self), 0);
        }
        let left_out = self.triangles.len() - triangles.len();
        (Cow::Owned(TriangleMesh { vertices: self.vertices.clone(), triangles, groups: Vec::new() }), left_out)
    }

    /// Merges vertices with bit-identical coordinates and drops unused ones.
    pub fn weld(&mut self) {
        let mut index: HashMap<[u64; 3], u32> = HashMap::with_capacity(self.vertices.len());
        let mut vertices = Vec::with_capacity(self.vertices.len());
        let mut remap = vec![u32::MAX; self.vertices.len()];
        for tri in &mut self.triangles {
            for i in tri.iter_mut() {
                if remap[*i as usize] == u32::MAX {
                    let v = self.vertices[*i as usize];
                    // +0.0 and -0.0 weld together.
                    let bits = (v + DVec3::ZERO).to_array().map(f64::to_bits);
                    remap[*i as usize] = *index.entry(bits).or_insert_with(|| {
                        vertices.push(v);
                        (vertices.len() - 1) as u32
                    });
                }
                *i = remap[*i as usize];
            }
        }
        self.vertices = vertices;
    }

    /// Moves the mesh by the affine map `map`: every vertex to `map * v`. A map that
    /// reverses orientation (`det < 0`, a mirror) would turn the triangles inward, so
    /// their winding is reversed too and the mesh still faces out.
    pub fn transform(&mut self, map: DAffine3) {
        for v in &mut self.vertices {
            *v = map.transform_point3(*v);
        }
        if map.matrix3.determinant() < 0.0 {
            for t in &mut self.triangles {
                t.swap(1, 2);
            }
        }
    }

    /// Keeps only the triangles for which `keep(t)` is true (e.g. to open a mesh).
    pub fn retain_triangles(&mut self, mut keep: impl FnMut(usize) -> bool) {
        let mut t = 0;
        self.triangles.retain(|_| {
            t += 1;
            keep(t - 1)
        });
        self.groups.clear();
    }
}

/// Whether no two triangles of `sets` ([`corner_sets`]) are on the same corners.
pub(crate) fn all_distinct(sets: &[([u32; 3], u32, bool)]) -> bool {
    sets.windows(2).all(|w| w[0].0 != w[1].0)
}

/// Each triangle's corners sorted, its index, and whether sorting its corners took an
/// odd permutation, sorted by corners (so the triangles on one set of corners are
/// adjacent, in file order).
pub(crate) fn corner_sets(triangles: &[[u32; 3]]) -> Vec<([u32; 3], u32, bool)> {
    use rayon::slice::ParallelSliceMut;
    let mut sets: Vec<([u32; 3], u32, bool)> = triangles
        .iter()
        .enumerate()
        .map(|(t, &[a, b, c])| {
            let odd = (a > b) ^ (b > c) ^ (a > c);
            let mut k = [a, b, c];
            k.sort_unstable();
            (k, t as u32, odd)
        })
        .collect();
    sets.par_sort_unstable();
    sets
}
