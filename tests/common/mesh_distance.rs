//! The distance from a point to a triangle mesh (a reference mesh, such as the source a
//! solid was voxelized from), for issue 38's "mean distance to the source mesh".
//!
//! The nearest point of one triangle is Ericson's (Real-Time Collision Detection, 2005,
//! section 5.1.5): the point's Voronoi region of the triangle (three vertex regions,
//! three edge regions, the face) from six dot products, then the projection on that
//! feature. Over a mesh: a bounding-box hierarchy (median split of the centroids along
//! the longest axis, leaves of at most [`LEAF`] triangles), searched depth first,
//! nearer child first, a node skipped when its box lies farther than the best found.
//!
//! Where the reference is open (the Stanford bunny's holes in its base), a solid closes
//! it, and the closing surface has no counterpart to be near: a point whose nearest
//! point of the reference lies on an open edge (an edge of one triangle, corners welded
//! by position) or on a corner of one is said to lie over the reference's boundary
//! ([`Nearest::over_open_boundary`]), so a measure can leave the closing surface out.
#![allow(dead_code)]

use std::collections::HashMap;

use glam::DVec3;
use octsolid::mesh::TriangleMesh;

/// Most triangles a leaf.
const LEAF: usize = 4;

/// The point of triangle `abc` nearest to `p` (Ericson 2005, 5.1.5).
pub fn closest_on_triangle(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + d1 / (d1 - d3) * ab;
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + d2 / (d2 - d6) * ac;
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// A triangle of the hierarchy: its corners, and which of its edges and corners lie on
/// the mesh's open boundary (bit `k`: the edge from corner `k` to corner `k + 1`; bit
/// `3 + k`: corner `k`).
#[derive(Clone, Copy, Debug)]
struct Triangle {
    corners: [DVec3; 3],
    open: u8,
}

impl Triangle {
    /// Whether `q`, a point of the triangle, lies on one of its open edges or corners
    /// (within a billionth of the edge's length: the nearest point on an edge is computed
    /// on it).
    fn on_open_boundary(&self, q: DVec3) -> bool {
        (0..3).any(|k| {
            let (a, b) = (self.corners[k], self.corners[(k + 1) % 3]);
            let tolerance = 1e-9 * (b - a).length();
            (self.open >> (3 + k) & 1 == 1 && (q - a).length() <= tolerance)
                || (self.open >> k & 1 == 1 && segment_distance(q, a, b) <= tolerance)
        })
    }
}

/// The distance from `q` to the segment `ab`.
fn segment_distance(q: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 { ((q - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0) } else { 0.0 };
    (a + t * ab - q).length()
}

/// The nearest point of the mesh to a point: how far, and whether it lies over the
/// mesh's open boundary (see the module doc).
#[derive(Clone, Copy, Debug)]
pub struct Nearest {
    pub distance: f64,
    pub over_open_boundary: bool,
}

/// A node: its box; a leaf holds `count > 0` triangles from `first`, an inner node has
/// its first child next and its second at `first`.
#[derive(Clone, Copy, Debug)]
struct Node {
    lo: DVec3,
    hi: DVec3,
    first: usize,
    count: usize,
}

/// The hierarchy over a mesh's triangles (see the module doc).
pub struct MeshDistance {
    triangles: Vec<Triangle>,
    nodes: Vec<Node>,
}

impl MeshDistance {
    /// The hierarchy over `mesh`'s triangles.
    pub fn new(mesh: &TriangleMesh) -> Self {
        let open = open_boundary(mesh);
        let mut triangles: Vec<Triangle> =
            (0..mesh.triangles.len()).map(|t| Triangle { corners: mesh.corners(t), open: open[t] }).collect();
        let mut nodes = Vec::new();
        build(&mut triangles, 0, &mut nodes);
        MeshDistance { triangles, nodes }
    }

    /// The distance from `p` to the nearest point of the mesh.
    pub fn distance(&self, p: DVec3) -> f64 {
        self.nearest(p).distance
    }

    /// The nearest point of the mesh to `p`: how far, and whether over the mesh's open
    /// boundary.
    pub fn nearest(&self, p: DVec3) -> Nearest {
        let mut best = f64::INFINITY;
        let mut over_open_boundary = false;
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let node = self.nodes[i];
            if box_distance_squared(p, node.lo, node.hi) >= best {
                continue;
            }
            if node.count > 0 {
                for t in &self.triangles[node.first..node.first + node.count] {
                    let [a, b, c] = t.corners;
                    let q = closest_on_triangle(p, a, b, c);
                    let d = (q - p).length_squared();
                    // Of equally near points (a corner or an edge shared by triangles),
                    // any on the open boundary says so.
                    if d < best {
                        (best, over_open_boundary) = (d, t.on_open_boundary(q));
                    } else if d == best {
                        over_open_boundary |= t.on_open_boundary(q);
                    }
                }
                continue;
            }
            let (near, far) = (i + 1, node.first);
            let (dn, df) = (
                box_distance_squared(p, self.nodes[near].lo, self.nodes[near].hi),
                box_distance_squared(p, self.nodes[far].lo, self.nodes[far].hi),
            );
            // Pushed last, searched first: the nearer child.
            if dn <= df {
                stack.extend([far, near]);
            } else {
                stack.extend([near, far]);
            }
        }
        Nearest { distance: best.sqrt(), over_open_boundary }
    }
}

/// Each triangle's open edges and corners (the bits of [`Triangle::open`]): an edge of
/// one triangle, with corners welded by position, and the corners of such edges.
fn open_boundary(mesh: &TriangleMesh) -> Vec<u8> {
    let mut ids: HashMap<[u64; 3], usize> = HashMap::new();
    let welded: Vec<[usize; 3]> = (0..mesh.triangles.len())
        .map(|t| {
            mesh.corners(t).map(|v| {
                let next = ids.len();
                *ids.entry(v.to_array().map(f64::to_bits)).or_insert(next)
            })
        })
        .collect();
    let edge = |a: usize, b: usize| (a.min(b), a.max(b));
    let mut uses: HashMap<(usize, usize), u32> = HashMap::new();
    for t in &welded {
        for k in 0..3 {
            *uses.entry(edge(t[k], t[(k + 1) % 3])).or_default() += 1;
        }
    }
    let mut open_corner = vec![false; ids.len()];
    for (&(a, b), &n) in &uses {
        if n == 1 {
            (open_corner[a], open_corner[b]) = (true, true);
        }
    }
    welded
        .iter()
        .map(|t| {
            (0..3).fold(0u8, |bits, k| {
                let edge_open = uses[&edge(t[k], t[(k + 1) % 3])] == 1;
                bits | u8::from(edge_open) << k | u8::from(open_corner[t[k]]) << (3 + k)
            })
        })
        .collect()
}

fn box_distance_squared(p: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    (lo - p).max(p - hi).max(DVec3::ZERO).length_squared()
}

/// Builds the node for `tris` (which start at `offset` in the final order) and its
/// subtree, depth first; returns its index.
fn build(tris: &mut [Triangle], offset: usize, nodes: &mut Vec<Node>) -> usize {
    let lo = tris.iter().flat_map(|t| t.corners).fold(DVec3::INFINITY, |m, v| m.min(v));
    let hi = tris.iter().flat_map(|t| t.corners).fold(DVec3::NEG_INFINITY, |m, v| m.max(v));
    let index = nodes.len();
    if tris.len() <= LEAF {
        nodes.push(Node { lo, hi, first: offset, count: tris.len() });
        return index;
    }
    nodes.push(Node { lo, hi, first: 0, count: 0 });
    let centroid = |t: &Triangle| t.corners[0] + t.corners[1] + t.corners[2];
    let clo = tris.iter().fold(DVec3::INFINITY, |m, t| m.min(centroid(t)));
    let chi = tris.iter().fold(DVec3::NEG_INFINITY, |m, t| m.max(centroid(t)));
    let extent = chi - clo;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mid = tris.len() / 2;
    tris.select_nth_unstable_by(mid, |a, b| centroid(a)[axis].total_cmp(&centroid(b)[axis]));
    let (left, right) = tris.split_at_mut(mid);
    build(left, offset, nodes);
    let second = build(right, offset + mid, nodes);
    nodes[index].first = second;
    index
}
