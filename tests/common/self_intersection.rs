//! An exact check that a triangle mesh does not cross itself: every pair of triangles
//! whose boxes meet is tested with Shewchuk's exact orientation predicates (the
//! `robust` crate), independently of the library's own tests.
//!
//! Two triangles sharing no vertex must not meet at all. Sharing one vertex, they may
//! meet only there: when they are not coplanar, their planes meet in a line through
//! the shared vertex, and they overlap beyond it exactly when the edge opposite the
//! shared vertex of one meets the other. Sharing an edge, they must not fold onto each
//! other (coplanar, the other vertices on one side). Coplanar pairs sharing one vertex
//! are tested by their edges in the plane.

use glam::{DVec2, DVec3};
use octsolid::mesh::TriangleMesh;
use robust::{Coord, Coord3D, orient2d, orient3d};

fn o3(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    let p = |v: DVec3| Coord3D { x: v.x, y: v.y, z: v.z };
    -orient3d(p(a), p(b), p(c), p(d))
}

fn o2(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let p = |v: DVec2| Coord { x: v.x, y: v.y };
    orient2d(p(a), p(b), p(c))
}

/// The projection dropping the axis along which `n` is largest (exact: coordinates
/// are copied, not computed).
fn project(n: DVec3) -> impl Fn(DVec3) -> DVec2 {
    let a = n.abs().max_position();
    move |v: DVec3| match a {
        0 => DVec2::new(v.y, v.z),
        1 => DVec2::new(v.z, v.x),
        _ => DVec2::new(v.x, v.y),
    }
}

/// Whether the closed segments `pq` and `ab` of a plane meet.
fn segments_meet_2d(p: DVec2, q: DVec2, a: DVec2, b: DVec2) -> bool {
    let (d1, d2) = (o2(p, q, a), o2(p, q, b));
    let (d3, d4) = (o2(a, b, p), o2(a, b, q));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return true;
    }
    let on = |x: DVec2, y: DVec2, z: DVec2| {
        o2(x, y, z) == 0.0 && z.x >= x.x.min(y.x) && z.x <= x.x.max(y.x) && z.y >= x.y.min(y.y) && z.y <= x.y.max(y.y)
    };
    on(p, q, a) || on(p, q, b) || on(a, b, p) || on(a, b, q)
}

/// Whether `p` lies in the closed triangle `t` of a plane.
fn in_triangle_2d(p: DVec2, t: [DVec2; 3]) -> bool {
    let s = [o2(t[0], t[1], p), o2(t[1], t[2], p), o2(t[2], t[0], p)];
    s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
}

/// Whether the closed segment `pq` meets the closed triangle `t`.
pub fn segment_meets_triangle(p: DVec3, q: DVec3, t: [DVec3; 3]) -> bool {
    let [a, b, c] = t;
    let (sp, sq) = (o3(a, b, c, p), o3(a, b, c, q));
    if sp * sq > 0.0 {
        return false;
    }
    if sp == 0.0 && sq == 0.0 {
        let n = (b - a).cross(c - a);
        if n == DVec3::ZERO {
            return false;
        }
        let f = project(n);
        let t2 = [f(a), f(b), f(c)];
        return in_triangle_2d(f(p), t2)
            || in_triangle_2d(f(q), t2)
            || (0..3).any(|i| segments_meet_2d(f(p), f(q), t2[i], t2[(i + 1) % 3]));
    }
    let s = [o3(p, q, a, b), o3(p, q, b, c), o3(p, q, c, a)];
    s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
}

/// Whether triangles `s` and `t` (vertex indices `si`, `ti` into one mesh) meet
/// anywhere but where they share vertices (module doc).
pub fn triangles_cross(s: [DVec3; 3], si: [u32; 3], t: [DVec3; 3], ti: [u32; 3]) -> bool {
    let shared: Vec<(usize, usize)> =
        (0..3).flat_map(|i| (0..3).map(move |j| (i, j))).filter(|&(i, j)| si[i] == ti[j]).collect();
    let edges_meet = |x: [DVec3; 3], y: [DVec3; 3], skip: Option<usize>| {
        (0..3).filter(|&i| Some(i) != skip).any(|i| segment_meets_triangle(x[(i + 1) % 3], x[(i + 2) % 3], y))
    };
    match shared.len() {
        0 => edges_meet(s, t, None) || edges_meet(t, s, None),
        1 => {
            let (i, j) = shared[0];
            // Only the edges opposite the shared vertex, and in the coplanar case the
            // edges at it too, except at the shared vertex itself.
            let coplanar = (0..3).all(|k| o3(t[0], t[1], t[2], s[k]) == 0.0);
            if coplanar {
                let n = (t[1] - t[0]).cross(t[2] - t[0]);
                let f = project(n);
                let (s2, t2) = (s.map(&f), t.map(&f));
                // A vertex of one strictly inside the other's angle at the shared vertex.
                let inside = |x: [DVec2; 3], k: usize, y: [DVec2; 3], l: usize| {
                    let (v, a, b) = (y[l], y[(l + 1) % 3], y[(l + 2) % 3]);
                    let w = x[(k + 1) % 3];
                    let w2 = x[(k + 2) % 3];
                    let strictly = |w: DVec2| {
                        let (d1, d2) = (o2(v, a, w), o2(v, w, b));
                        let turn = o2(v, a, b);
                        d1 * turn > 0.0 && d2 * turn > 0.0
                    };
                    strictly(w) || strictly(w2)
                };
                return inside(s2, i, t2, j)
                    || inside(t2, j, s2, i)
                    || segment_meets_triangle(s[(i + 1) % 3], s[(i + 2) % 3], t)
                    || segment_meets_triangle(t[(j + 1) % 3], t[(j + 2) % 3], s);
            }
            segment_meets_triangle(s[(i + 1) % 3], s[(i + 2) % 3], t)
                || segment_meets_triangle(t[(j + 1) % 3], t[(j + 2) % 3], s)
        }
        2 => {
            // The vertices not on the shared edge.
            let k = (0..3).find(|&k| !shared.iter().any(|&(i, _)| i == k)).unwrap();
            let l = (0..3).find(|&l| !shared.iter().any(|&(_, j)| j == l)).unwrap();
            let (a, b) = (s[shared[0].0], s[shared[1].0]);
            if o3(a, b, s[k], t[l]) != 0.0 {
                return false;
            }
            let f = project((b - a).cross(s[k] - a));
            o2(f(a), f(b), f(s[k])) * o2(f(a), f(b), f(t[l])) > 0.0
        }
        _ => false,
    }
}

/// The pairs of triangles of `mesh` that cross (at most `limit` of them), found by a
/// grid of cells of side `cell` over the triangles' boxes.
pub fn self_crossings(mesh: &TriangleMesh, cell: f64, limit: usize) -> Vec<(usize, usize)> {
    use std::collections::HashMap;
    let tri = |i: usize| mesh.triangles[i].map(|v| mesh.vertices[v as usize]);
    let key = |p: DVec3| (p / cell).floor().as_ivec3();
    let mut grid: HashMap<glam::IVec3, Vec<usize>> = HashMap::new();
    let mut boxes = Vec::with_capacity(mesh.triangles.len());
    for i in 0..mesh.triangles.len() {
        let t = tri(i);
        let (lo, hi) = (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]));
        boxes.push((lo, hi));
        let (a, b) = (key(lo), key(hi));
        for x in a.x..=b.x {
            for y in a.y..=b.y {
                for z in a.z..=b.z {
                    grid.entry(glam::IVec3::new(x, y, z)).or_default().push(i);
                }
            }
        }
    }
    let mut found = std::collections::BTreeSet::new();
    let mut cells: Vec<_> = grid.into_iter().collect();
    cells.sort_by_key(|(k, _)| (k.x, k.y, k.z));
    for (_, list) in cells {
        for (n, &i) in list.iter().enumerate() {
            for &j in &list[n + 1..] {
                let (a, b) = (boxes[i], boxes[j]);
                if a.0.cmpgt(b.1).any() || b.0.cmpgt(a.1).any() || found.contains(&(i.min(j), i.max(j))) {
                    continue;
                }
                if triangles_cross(tri(i), mesh.triangles[i], tri(j), mesh.triangles[j]) {
                    found.insert((i.min(j), i.max(j)));
                    if found.len() >= limit {
                        return found.into_iter().collect();
                    }
                }
            }
        }
    }
    found.into_iter().collect()
}
