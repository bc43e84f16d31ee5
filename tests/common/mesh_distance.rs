//! The distance from a point to a triangle mesh (a reference mesh, such as the source a
//! solid was voxelized from), for issue 38's "mean distance to the source mesh".
//!
//! The nearest point of one triangle is Ericson's (Real-Time Collision Detection, 2005,
//! section 5.1.5): the point's Voronoi region of the triangle (three vertex regions,
//! three edge regions, the face) from six dot products, then the projection on that
//! feature. Over a mesh: a bounding-box hierarchy (median split of the centroids along
//! the longest axis, leaves of at most [`LEAF`] triangles), searched depth first,
//! nearer child first, a node skipped when its box lies farther than the best found.
#![allow(dead_code)]

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
    triangles: Vec<[DVec3; 3]>,
    nodes: Vec<Node>,
}

impl MeshDistance {
    /// The hierarchy over `mesh`'s triangles.
    pub fn new(mesh: &TriangleMesh) -> Self {
        let mut triangles: Vec<[DVec3; 3]> = (0..mesh.triangles.len()).map(|t| mesh.corners(t)).collect();
        let mut nodes = Vec::new();
        build(&mut triangles, 0, &mut nodes);
        MeshDistance { triangles, nodes }
    }

    /// The distance from `p` to the nearest point of the mesh.
    pub fn distance(&self, p: DVec3) -> f64 {
        let mut best = f64::INFINITY;
        let mut stack = vec![0usize];
        while let Some(i) = stack.pop() {
            let node = self.nodes[i];
            if box_distance_squared(p, node.lo, node.hi) >= best {
                continue;
            }
            if node.count > 0 {
                for [a, b, c] in &self.triangles[node.first..node.first + node.count] {
                    best = best.min((closest_on_triangle(p, *a, *b, *c) - p).length_squared());
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
        best.sqrt()
    }
}

fn box_distance_squared(p: DVec3, lo: DVec3, hi: DVec3) -> f64 {
    (lo - p).max(p - hi).max(DVec3::ZERO).length_squared()
}

/// Builds the node for `tris` (which start at `offset` in the final order) and its
/// subtree, depth first; returns its index.
fn build(tris: &mut [[DVec3; 3]], offset: usize, nodes: &mut Vec<Node>) -> usize {
    let lo = tris.iter().flatten().fold(DVec3::INFINITY, |m, &v| m.min(v));
    let hi = tris.iter().flatten().fold(DVec3::NEG_INFINITY, |m, &v| m.max(v));
    let index = nodes.len();
    if tris.len() <= LEAF {
        nodes.push(Node { lo, hi, first: offset, count: tris.len() });
        return index;
    }
    nodes.push(Node { lo, hi, first: 0, count: 0 });
    let centroid = |t: &[DVec3; 3]| t[0] + t[1] + t[2];
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
