//! Signed crossings of a segment with mesh triangles, counted once at shared edges and
//! vertices.
//!
//! Segment `q -> p` crosses triangle `(a, b, c)` when `q` and `p` lie on opposite sides
//! of its plane and the line through them passes inside the triangle, i.e. the three
//! orientations `orient(q, p, a, b)`, `orient(q, p, b, c)`, `orient(q, p, c, a)` share
//! a sign (Plucker test). The orientations are exact.
//!
//! Ties (a point on a plane, a line through an edge or a vertex) are broken by
//! simulation of simplicity (Edelsbrunner and Mucke, 1990) with one perturbation for
//! every point: each query point `x` stands for `x + eps d`, `d = (1, delta, delta^2)`,
//! `0 < eps << delta << 1`, i.e. moved a hair toward `+x`, then `+y`, then `+z`.
//! - On the plane of `(a, b, c)`: `orient(a, b, c, x + eps d) = orient(a, b, c, x) +
//!   eps n . d`, `n = (b - a) x (c - a)`: the sign of the first non-zero of `n_x, n_y,
//!   n_z` (each an exact 2-D orientation). A degenerate triangle (`n = 0`) counts as
//!   in front, as before, so no segment crosses it.
//! - Through edge `a -> b`: `orient(q + eps d, p + eps d, a, b) = orient(q, p, a, b) +
//!   eps d . ((p - q) x (b - a))`: the sign of the first non-zero component of
//!   `(p - q) x (b - a)` (exact, [`cross_of_differences`]). It flips with the edge's
//!   direction, so of two triangles sharing an edge exactly one counts, and since it
//!   is one geometric perturbation of the segment, around a vertex the fan counts as
//!   a translated segment would: once.
//!
//! Departure from the paper: one translation for all points rather than a
//! perturbation per point, which is all the carried values need (every point of a
//! chain `q -> p -> ...` moves alike, so the sums telescope). The perturbed point is
//! the tie rule of the solid voxelizer: a voxel centre on the surface is inside when
//! the point just above it in `(x, y, z)` lexicographic order is; for a box, `lo <= c
//! < hi` on each axis.
//! An earlier version broke edge ties by vertex indices, which is consistent for an
//! edge but not around a vertex: a segment ending at a cube corner counted two or
//! none of its three faces.

use glam::{DVec2, DVec3};

use super::TriangleMesh;
use super::predicates::{cross_of_differences, orient2d, orient3d as orient};

/// A triangle's plane for fast side tests: normal `n = (b - a) x (c - a)`, a corner,
/// and `|b - a| |c - a|`, which bounds the rounding of `n . (x - a)`.
#[derive(Clone, Copy, Debug)]
pub struct Plane {
    n: DVec3,
    a: DVec3,
    scale: f64,
}

impl Plane {
    /// The plane of triangle `t`.
    #[must_use]
    pub fn new(mesh: &TriangleMesh, t: u32) -> Self {
        let [a, b, c] = mesh.corners(t as usize);
        let (e1, e2) = (b - a, c - a);
        Plane { n: e1.cross(e2), a, scale: e1.length() * e2.length() }
    }

    /// Whether `x` is in front of triangle `t` (whose plane this is), a point on the
    /// plane perturbed (module docs): the float value when it clears its error bound
    /// (a generous `1e-12 |b - a| |c - a| |x - a|`), else the exact predicate.
    #[inline]
    #[must_use]
    pub fn in_front(&self, mesh: &TriangleMesh, t: u32, x: DVec3) -> bool {
        let d = x - self.a;
        let s = self.n.dot(d);
        if s.abs() > 1e-12 * self.scale * d.length() {
            return s > 0.0;
        }
        in_front(mesh, t, x)
    }

    /// Whether `x` lies exactly on the plane of triangle `t` (whose plane this is).
    #[inline]
    #[must_use]
    pub fn contains(&self, mesh: &TriangleMesh, t: u32, x: DVec3) -> bool {
        let d = x - self.a;
        if self.n.dot(d).abs() > 1e-12 * self.scale * d.length() {
            return false;
        }
        let v = mesh.triangles[t as usize].map(|i| mesh.vertices[i as usize]);
        orient(v[0], v[1], v[2], x) == 0.0
    }
}

impl Plane {
    /// Whether the plane may meet the closed box of centre `c` and half side `h`
    /// (conservative): it misses when `|n . (c - a)| > |n|_1 h`, the box's projection
    /// radius on `n`. The bound is grown by `1e-12 |n|_1 |c - a|_inf`, more than the
    /// rounding of the dot product, and by a relative hair on `h`.
    #[inline]
    #[must_use]
    pub fn meets_cube(&self, c: DVec3, h: f64) -> bool {
        let d = c - self.a;
        self.n.dot(d).abs() <= self.n.abs().element_sum() * (h * (1.0 + 1e-9) + 1e-12 * d.abs().max_element())
    }
}

/// `+1` when the segment `q -> p` enters triangle `t` (plane `plane`) against its
/// normal (front to back), `-1` when it leaves, `0` when it misses. The plane's float
/// side tests settle most segments, which stay on one side.
#[inline]
#[must_use]
pub fn signed_crossing(mesh: &TriangleMesh, plane: &Plane, t: u32, q: DVec3, p: DVec3) -> i32 {
    let (front_q, front_p) = (plane.in_front(mesh, t, q), plane.in_front(mesh, t, p));
    signed_crossing_sides(mesh, t, q, front_q, p, front_p)
}

/// The projections on the `yz`, `zx` and `xy` planes, whose 2-D cross products are
/// the `x`, `y` and `z` components of the 3-D one.
const PROJECTIONS: [fn(DVec3) -> DVec2; 3] =
    [|p| DVec2::new(p.y, p.z), |p| DVec2::new(p.z, p.x), |p| DVec2::new(p.x, p.y)];

/// Whether `x` is in front of triangle `t`, a point on its plane perturbed toward
/// `d = (1, delta, delta^2)` (module docs).
#[inline]
#[must_use]
pub fn in_front(mesh: &TriangleMesh, t: u32, x: DVec3) -> bool {
    let v = mesh.triangles[t as usize].map(|i| mesh.vertices[i as usize]);
    let o = orient(v[0], v[1], v[2], x);
    if o != 0.0 {
        return o > 0.0;
    }
    // n . d: n_x, then n_y, then n_z, each the orientation of a coordinate projection.
    let normal = PROJECTIONS.iter().map(|f| orient2d(f(v[0]), f(v[1]), f(v[2]))).find(|&n| n != 0.0);
    normal.is_none_or(|n| n > 0.0)
}

/// Whether the segment `q -> p`, moved by `eps d`, passes on the positive side of edge
/// `a -> b` when `orient(q, p, a, b)` is zero: the sign of the first non-zero
/// component of `(p - q) x (b - a)` (module docs). All zero only when the segment is
/// parallel to the edge, which a segment crossing the edge's plane is not.
fn tie_sign(q: DVec3, p: DVec3, a: DVec3, b: DVec3) -> bool {
    let c = PROJECTIONS.iter().map(|f| cross_of_differences(f(p), f(q), f(b), f(a))).find(|&c| c != 0.0);
    c.is_some_and(|c| c > 0.0)
}

/// [`signed_crossing`] with both sides known (many segments from one point share its side).
#[inline]
#[must_use]
pub fn signed_crossing_sides(mesh: &TriangleMesh, t: u32, q: DVec3, front_q: bool, p: DVec3, front_p: bool) -> i32 {
    if front_q == front_p {
        return 0;
    }
    let v = mesh.triangles[t as usize].map(|i| mesh.vertices[i as usize]);
    let edge_sign = |k: usize| {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        let o = orient(q, p, a, b);
        if o != 0.0 { o > 0.0 } else { tie_sign(q, p, a, b) }
    };
    let s0 = edge_sign(0);
    if edge_sign(1) != s0 || edge_sign(2) != s0 {
        return 0;
    }
    if front_q { 1 } else { -1 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::tri_box::triangle_box_overlap;
    use crate::test_util::Rng;

    /// Every segment between points of a grid that holds the unit cube's corners, edge
    /// midpoints and face centres (and points outside): the signed crossings with its
    /// twelve triangles are the change of the tie rule's indicator, `lo <= x < hi` on
    /// each axis (the point moved toward `+x`, then `+y`, then `+z`), so chains of
    /// carried values telescope even through vertices and along faces.
    #[test]
    fn crossings_through_cube_corners_edges_and_faces_follow_the_perturbation() {
        let mesh = crate::mesh::generate::cuboid(DVec3::splat(0.5), DVec3::ONE);
        let planes: Vec<Plane> = (0..12).map(|t| Plane::new(&mesh, t)).collect();
        let steps = [-0.5, 0.0, 0.5, 1.0, 1.5];
        let points: Vec<DVec3> = (0..125).map(|i| DVec3::new(steps[i % 5], steps[i / 5 % 5], steps[i / 25])).collect();
        let inside = |x: DVec3| i32::from(x.cmpge(DVec3::ZERO).all() && x.cmplt(DVec3::ONE).all());
        for &q in &points {
            for &p in &points {
                let sum: i32 = (0..12).map(|t| signed_crossing(&mesh, &planes[t as usize], t, q, p)).sum();
                assert_eq!(sum, inside(p) - inside(q), "{q} -> {p}");
            }
        }
    }

    #[test]
    fn plane_test_keeps_every_triangle_that_meets_the_cube() {
        let mut rng = Rng(5);
        let mut point = || rng.vec(-1.0, 1.0);
        let (mut met, mut missed) = (0, 0);
        for _ in 0..3000 {
            let mesh = TriangleMesh::new(vec![point(), point(), point()], vec![[0, 1, 2]]).unwrap();
            let (c, h) = (point(), 0.3 * (point().x + 1.0) + 0.01);
            let plane = Plane::new(&mesh, 0);
            // The oracle: the exact separating-axis test on the same cube.
            if triangle_box_overlap(&mesh.corners(0), c, DVec3::splat(h)) {
                assert!(plane.meets_cube(c, h), "{:?} {c} {h}", mesh.corners(0));
                met += 1;
            } else {
                missed += usize::from(!plane.meets_cube(c, h));
            }
        }
        assert!(met > 300 && missed > 300, "{met} met, {missed} missed by the plane too");
    }
}
