//! Polygon tables (vertex, edge and polygon tables with plane equations) and the mesh
//! diagnostics read off them.
//!
//! Plane of a triangle through `p1, p2, p3`: `A x + B y + C z + D = 0` with
//! `(A, B, C) = (p2 - p1) x (p3 - p1)` and `D = -(A, B, C) . p1`; this is the seed's
//! expansion `A = y1 (z2 - z3) + y2 (z3 - z1) + y3 (z1 - z2)`, ... in vector form.
//! Enclosed volume by the signed-tetrahedron sum `V = sum (p1 . (p2 x p3)) / 6`,
//! exact for a closed, consistently oriented mesh.

use std::collections::HashMap;

use glam::DVec3;
use serde::Serialize;

use super::TriangleMesh;

/// An edge of the edge table: its two vertices (lower index first) and its faces.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Edge {
    /// The endpoints, `v[0] < v[1]`.
    pub v: [u32; 2],
    /// Triangles using this edge (one for a boundary edge, two for a manifold one).
    pub faces: Vec<u32>,
    /// How many of those triangles run the edge from `v[0]` to `v[1]`.
    pub forward: u32,
}

/// The vertex, edge and polygon tables of a mesh.
#[derive(Clone, Debug)]
pub struct PolygonTables<'a> {
    /// The mesh (its vertex and polygon tables).
    pub mesh: &'a TriangleMesh,
    /// Each edge once, with its faces.
    pub edges: Vec<Edge>,
    /// Each triangle's plane `[A, B, C, D]`, `(A, B, C)` of length twice its area.
    pub planes: Vec<[f64; 4]>,
}

/// What `octsolid mesh-info` prints.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct MeshReport {
    /// Vertices in the vertex table.
    pub vertices: usize,
    /// Triangles.
    pub triangles: usize,
    /// Edges in the edge table.
    pub edges: usize,
    /// Triangles with zero area.
    pub degenerate_faces: usize,
    /// Edges with one face (holes).
    pub boundary_edges: usize,
    /// Edges with three or more faces.
    pub non_manifold_edges: usize,
    /// Edges whose two faces run them the same way (inconsistent orientation).
    pub misoriented_edges: usize,
    /// Closed, manifold and consistently oriented.
    pub watertight: bool,
    /// Signed-tetrahedron volume (exact when watertight).
    pub volume: f64,
    /// Total triangle area.
    pub area: f64,
    /// Bounding box min corner.
    pub bounds_min: [f64; 3],
    /// Bounding box max corner.
    pub bounds_max: [f64; 3],
    /// Group names and triangle counts.
    pub groups: Vec<(String, usize)>,
}

impl<'a> PolygonTables<'a> {
    /// Builds the edge table and plane equations in one pass over the triangles.
    #[must_use]
    pub fn new(mesh: &'a TriangleMesh) -> Self {
        let mut index: HashMap<[u32; 2], usize> = HashMap::with_capacity(mesh.triangles.len() * 3 / 2);
        let mut edges: Vec<Edge> = Vec::with_capacity(mesh.triangles.len() * 3 / 2);
        let mut planes = Vec::with_capacity(mesh.triangles.len());
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                let key = [a.min(b), a.max(b)];
                let e = *index.entry(key).or_insert_with(|| {
                    edges.push(Edge { v: key, faces: Vec::with_capacity(2), forward: 0 });
                    edges.len() - 1
                });
                edges[e].faces.push(t as u32);
                edges[e].forward += u32::from(a < b);
            }
            let [p1, p2, p3] = mesh.corners(t);
            let n = (p2 - p1).cross(p3 - p1);
            planes.push([n.x, n.y, n.z, -n.dot(p1)]);
        }
        PolygonTables { mesh, edges, planes }
    }

    /// Unit normal of triangle `t` (zero for a degenerate one).
    #[must_use]
    pub fn normal(&self, t: usize) -> DVec3 {
        let [a, b, c, _] = self.planes[t];
        DVec3::new(a, b, c).normalize_or_zero()
    }

    /// The diagnostics.
    #[must_use]
    pub fn report(&self) -> MeshReport {
        let mesh = self.mesh;
        // Areas with the corners scaled into [-1, 1] (exactly, by a power of two), so
        // that corners far out do not overflow them.
        let s = mesh.coordinate_scale();
        let area2: Vec<f64> = (0..mesh.triangles.len()).map(|t| mesh.twice_area_scaled(t, s)).collect();
        let b = mesh.bounds();
        let size = (b.max / s - b.min / s).max_element().max(f64::MIN_POSITIVE);
        let degenerate_faces = area2.iter().filter(|&&a| a <= 1e-14 * size * size).count();
        let boundary_edges = self.edges.iter().filter(|e| e.faces.len() == 1).count();
        let non_manifold_edges = self.edges.iter().filter(|e| e.faces.len() > 2).count();
        let misoriented_edges = self.edges.iter().filter(|e| e.faces.len() == 2 && e.forward != 1).count();
        let volume = mesh.volume();
        MeshReport {
            vertices: mesh.vertices.len(),
            triangles: mesh.triangles.len(),
            edges: self.edges.len(),
            degenerate_faces,
            boundary_edges,
            non_manifold_edges,
            misoriented_edges,
            watertight: boundary_edges == 0 && non_manifold_edges == 0 && misoriented_edges == 0,
            volume,
            area: area2.iter().sum::<f64>() / 2.0 * s * s,
            bounds_min: b.min.to_array(),
            bounds_max: b.max.to_array(),
            groups: mesh.groups.iter().map(|g| (g.name.clone(), g.count)).collect(),
        }
    }
}
