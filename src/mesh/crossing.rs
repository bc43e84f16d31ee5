//! Signed crossings of a segment with mesh triangles, counted once at shared edges.
//!
//! Segment `q -> p` crosses triangle `(a, b, c)` when `q` and `p` lie on opposite sides
//! of its plane and the line through them passes inside the triangle, i.e. the three
//! orientations `orient(q, p, a, b)`, `orient(q, p, b, c)`, `orient(q, p, c, a)` share
//! a sign (Plucker test). Ties are broken symbolically so that a segment through a
//! shared edge counts for exactly one of the two triangles: a zero edge orientation
//! takes the sign of the comparison of the edge's vertex indices, which flips between
//! the two triangles that run the edge in opposite directions; a point on a plane
//! counts as in front of it. The orientations are exact, so the two triangles of an
//! edge always see opposite signs.

use glam::DVec3;

use super::TriangleMesh;
use super::predicates::orient3d as orient;

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

    /// Whether `x` is in front of triangle `t` (whose plane this is), on the plane
    /// counting as in front: the float value when it clears its error bound (a
    /// generous `1e-12 |b - a| |c - a| |x - a|`), else the exact predicate.
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

/// Whether `x` is in front of triangle `t` (on its plane counts as in front).
#[inline]
#[must_use]
pub fn in_front(mesh: &TriangleMesh, t: u32, x: DVec3) -> bool {
    let v = mesh.triangles[t as usize].map(|i| mesh.vertices[i as usize]);
    orient(v[0], v[1], v[2], x) >= 0.0
}

/// [`signed_crossing`] with both sides known (many segments from one point share its side).
#[inline]
#[must_use]
pub fn signed_crossing_sides(mesh: &TriangleMesh, t: u32, q: DVec3, front_q: bool, p: DVec3, front_p: bool) -> i32 {
    let idx = mesh.triangles[t as usize];
    let v = idx.map(|i| mesh.vertices[i as usize]);
    if front_q == front_p {
        return 0;
    }
    let edge_sign = |k: usize| {
        let (i, j) = (k, (k + 1) % 3);
        let o = orient(q, p, v[i], v[j]);
        if o != 0.0 { o > 0.0 } else { idx[i] < idx[j] }
    };
    let s0 = edge_sign(0);
    if edge_sign(1) != s0 || edge_sign(2) != s0 {
        return 0;
    }
    if front_q { 1 } else { -1 }
}

#[cfg(test)]
mod tests {
    use rand::rngs::Xoshiro256PlusPlus;
    use rand::{RngExt, SeedableRng};

    use super::*;
    use crate::mesh::tri_box::triangle_box_overlap;

    #[test]
    fn plane_test_keeps_every_triangle_that_meets_the_cube() {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        let mut point =
            || DVec3::new(rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0), rng.random_range(-1.0..1.0));
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
