//! One bicubic Bezier patch.

use glam::{DAffine3, DVec3};

use crate::aabb::Aabb;

/// A bicubic Bezier patch: control points `p[i][j]`, `i` along `u`, `j` along `v`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BezierPatch {
    /// The 4x4 control net.
    pub p: [[DVec3; 4]; 4],
}

/// De Casteljau on four points: the curve point at `t`, and the two halves' nets when
/// `t = 1/2` is asked through [`split_curve`].
#[inline]
fn casteljau(c: [DVec3; 4], t: f64) -> DVec3 {
    let a = [c[0].lerp(c[1], t), c[1].lerp(c[2], t), c[2].lerp(c[3], t)];
    let b = [a[0].lerp(a[1], t), a[1].lerp(a[2], t)];
    b[0].lerp(b[1], t)
}

/// Derivative of the cubic at `t`: `3 sum B2_i(t) (c[i+1] - c[i])`.
#[inline]
fn derivative(c: [DVec3; 4], t: f64) -> DVec3 {
    let d = [c[1] - c[0], c[2] - c[1], c[3] - c[2]];
    let a = [d[0].lerp(d[1], t), d[1].lerp(d[2], t)];
    a[0].lerp(a[1], t) * 3.0
}

/// The two halves of a cubic at `t = 1/2` (de Casteljau's triangle).
#[inline]
fn split_curve(c: [DVec3; 4]) -> ([DVec3; 4], [DVec3; 4]) {
    let a = [c[0].lerp(c[1], 0.5), c[1].lerp(c[2], 0.5), c[2].lerp(c[3], 0.5)];
    let b = [a[0].lerp(a[1], 0.5), a[1].lerp(a[2], 0.5)];
    let m = b[0].lerp(b[1], 0.5);
    ([c[0], a[0], b[0], m], [m, b[1], a[2], c[3]])
}

impl BezierPatch {
    /// The patch moved by the affine map `map`: Bezier patches are affine invariant,
    /// so the control points are mapped. A map that reverses orientation (`det < 0`)
    /// also swaps `u` and `v` (the net transposed), so the normal `du x dv` keeps its side.
    #[must_use]
    pub fn transformed(&self, map: DAffine3) -> BezierPatch {
        let mirrored = map.matrix3.determinant() < 0.0;
        BezierPatch {
            p: std::array::from_fn(|i| {
                std::array::from_fn(|j| map.transform_point3(if mirrored { self.p[j][i] } else { self.p[i][j] }))
            }),
        }
    }

    /// The surface point `p(u, v)`.
    #[must_use]
    pub fn eval(&self, u: f64, v: f64) -> DVec3 {
        let rows = self.p.map(|row| casteljau(row, v));
        casteljau(rows, u)
    }

    /// The partial derivatives `(p_u, p_v)` at `(u, v)`.
    #[must_use]
    pub fn tangents(&self, u: f64, v: f64) -> (DVec3, DVec3) {
        let rows = self.p.map(|row| casteljau(row, v));
        let pu = derivative(rows, u);
        let cols: [DVec3; 4] =
            std::array::from_fn(|j| casteljau([self.p[0][j], self.p[1][j], self.p[2][j], self.p[3][j]], u));
        (pu, derivative(cols, v))
    }

    /// The unit normal `p_u x p_v / |p_u x p_v|` (zero where the patch degenerates).
    #[must_use]
    pub fn normal(&self, u: f64, v: f64) -> DVec3 {
        let (pu, pv) = self.tangents(u, v);
        pu.cross(pv).normalize_or_zero()
    }

    /// Bounding box of the control points; it holds the whole patch (convex hull).
    #[must_use]
    pub fn bounds(&self) -> Aabb {
        Aabb::from_points(self.p.iter().flatten().copied()).expect("16 points")
    }

    /// The halves `u in [0, 1/2]` and `[1/2, 1]`.
    #[must_use]
    pub fn split_u(&self) -> (BezierPatch, BezierPatch) {
        let mut a = self.p;
        let mut b = self.p;
        for j in 0..4 {
            let (l, r) = split_curve([self.p[0][j], self.p[1][j], self.p[2][j], self.p[3][j]]);
            for i in 0..4 {
                a[i][j] = l[i];
                b[i][j] = r[i];
            }
        }
        (BezierPatch { p: a }, BezierPatch { p: b })
    }

    /// The halves `v in [0, 1/2]` and `[1/2, 1]`.
    #[must_use]
    pub fn split_v(&self) -> (BezierPatch, BezierPatch) {
        let mut a = self.p;
        let mut b = self.p;
        for i in 0..4 {
            let (l, r) = split_curve(self.p[i]);
            a[i] = l;
            b[i] = r;
        }
        (BezierPatch { p: a }, BezierPatch { p: b })
    }

    /// The four quarters (split at `u = v = 1/2`).
    #[must_use]
    pub fn split4(&self) -> [BezierPatch; 4] {
        let (a, b) = self.split_u();
        let (a0, a1) = a.split_v();
        let (b0, b1) = b.split_v();
        [a0, a1, b0, b1]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bilinear-like patch on the plane z = u + 2v, whose exact values are known.
    fn plane() -> BezierPatch {
        BezierPatch {
            p: std::array::from_fn(|i| {
                std::array::from_fn(|j| {
                    let (u, v) = (i as f64 / 3.0, j as f64 / 3.0);
                    DVec3::new(u, v, u + 2.0 * v)
                })
            }),
        }
    }

    #[test]
    fn evaluation_tangents_and_splits() {
        let p = plane();
        for (u, v) in [(0.0, 0.0), (0.3, 0.7), (1.0, 0.5)] {
            assert!(p.eval(u, v).distance(DVec3::new(u, v, u + 2.0 * v)) < 1e-12);
            let (pu, pv) = p.tangents(u, v);
            assert!(pu.distance(DVec3::new(1.0, 0.0, 1.0)) < 1e-12 && pv.distance(DVec3::new(0.0, 1.0, 2.0)) < 1e-12);
        }
        let n = p.normal(0.5, 0.5);
        assert!(n.distance(DVec3::new(-1.0, -2.0, 1.0).normalize()) < 1e-12);
        let [a, _, _, d] = p.split4();
        assert!(a.eval(1.0, 1.0).distance(p.eval(0.5, 0.5)) < 1e-12);
        assert!(d.eval(0.5, 0.5).distance(p.eval(0.75, 0.75)) < 1e-12);
    }
}
