//! Quadric error of a point against a set of planes (Garland and Heckbert 1997).
//!
//! A plane `n . x + d = 0` (`|n| = 1`) weighted by `w` contributes
//! `w (n . x + d)^2 = x^T (w n n^T) x + 2 (w d n) . x + w d^2`; a vertex's quadric is
//! the sum over its faces' planes, each weighted by the face's area, and a collapsed
//! vertex's is the sum of its two ends'. `Q(x)` is then the area-weighted sum of
//! squared distances to those planes.
//!
//! The minimiser solves `A x = -b`. Departure from the paper, as in dual contouring's
//! QEF (Lindstrom 2000; Ju et al. 2002): instead of inverting `A` when its determinant
//! allows, `A`'s eigenvectors are found (Jacobi rotations) and only directions whose
//! eigenvalue exceeds [`RANK_CUTOFF`] times the largest are solved for, starting from a
//! point the caller gives (the edge's midpoint): on a plane the point moves only
//! across it, on a crease only towards the crease, at a corner onto it. Where the
//! planes nearly agree (the other eigenvalues together under a thousandth of the
//! largest, far under the cutoff) the one direction is found by power iteration
//! instead, as dual contouring's QEF does (`qef::flat_direction`).

use crate::surface::qef::{FLAT_SPREAD, flat_direction, symmetric_eigen};
use glam::{DMat3, DVec3};

/// Eigenvalues below this fraction of the largest count as zero in the minimiser.
pub(crate) const RANK_CUTOFF: f64 = 0.02;

/// `x^T A x + 2 b . x + c` with `A` symmetric.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Quadric {
    /// `A`'s upper triangle: xx, xy, xz, yy, yz, zz.
    a: [f64; 6],
    b: DVec3,
    c: f64,
}

impl Quadric {
    /// The plane through `point` with unit normal `normal`, weighted by `weight`.
    #[must_use]
    pub(crate) fn plane(point: DVec3, normal: DVec3, weight: f64) -> Self {
        let n = normal;
        let d = -n.dot(point);
        Quadric {
            a: [n.x * n.x, n.x * n.y, n.x * n.z, n.y * n.y, n.y * n.z, n.z * n.z].map(|v| v * weight),
            b: n * (d * weight),
            c: d * d * weight,
        }
    }

    /// `Q(x)`, never negative.
    #[must_use]
    pub(crate) fn eval(&self, x: DVec3) -> f64 {
        let ax = self.matrix() * x;
        (x.dot(ax) + 2.0 * self.b.dot(x) + self.c).max(0.0)
    }

    /// The minimiser nearest `start` along `A`'s near-null directions (see the module
    /// doc).
    #[must_use]
    pub(crate) fn minimizer(&self, start: DVec3) -> DVec3 {
        // Most edges lie where their faces' planes nearly agree (rank 1): one direction
        // to solve, found without the decomposition.
        let a = self.matrix();
        if let Some((n, along)) = flat_direction(a, FLAT_SPREAD) {
            return start - n * (n.dot(a * start + self.b) / along);
        }
        self.minimizer_by_decomposition(start)
    }

    /// [`Quadric::minimizer`] from `A`'s eigen-decomposition, whatever its rank.
    fn minimizer_by_decomposition(&self, start: DVec3) -> DVec3 {
        let a = self.matrix();
        let (values, vectors) = symmetric_eigen(a);
        let largest = values.max_element();
        if largest <= 0.0 {
            return start;
        }
        let residual = a * start + self.b;
        let mut x = start;
        for k in 0..3 {
            if values[k] > RANK_CUTOFF * largest {
                let e = vectors.col(k);
                x -= e * (e.dot(residual) / values[k]);
            }
        }
        x
    }

    fn matrix(&self) -> DMat3 {
        let a = &self.a;
        DMat3::from_cols_array(&[a[0], a[1], a[2], a[1], a[3], a[4], a[2], a[4], a[5]])
    }
}

impl std::ops::Add for Quadric {
    type Output = Quadric;
    fn add(self, o: Quadric) -> Quadric {
        Quadric { a: std::array::from_fn(|i| self.a[i] + o.a[i]), b: self.b + o.b, c: self.c + o.c }
    }
}

impl std::ops::AddAssign for Quadric {
    fn add_assign(&mut self, o: Quadric) {
        *self = *self + o;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    #[test]
    fn jacobi_diagonalises_random_symmetric_matrices() {
        let mut rng = Rng(5);
        for _ in 0..200 {
            let b = DMat3::from_cols(rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0));
            let m = b.transpose() * b;
            let (values, vectors) = symmetric_eigen(m);
            for k in 0..3 {
                let e = vectors.col(k);
                assert!((e.length() - 1.0).abs() < 1e-12);
                assert!((m * e - e * values[k]).length() < 1e-10 * (1.0 + values.max_element()), "{m:?}");
            }
        }
    }

    #[test]
    fn nearly_agreeing_planes_give_the_decompositions_minimiser() {
        // Planes whose normals lie within a small cone (a curved patch a few voxels
        // wide), the case the power iteration takes: its answer is the decomposition's.
        let mut rng = Rng(11);
        let mut taken = 0;
        for _ in 0..500 {
            let axis = rng.vec(-1.0, 1.0).normalize();
            let spread = rng.range(0.0, 0.03);
            let mut q = Quadric::default();
            for _ in 0..8 {
                let normal = (axis + rng.vec(-spread, spread)).normalize();
                q += Quadric::plane(rng.vec(-1.0, 1.0), normal, rng.range(0.1, 2.0));
            }
            let start = rng.vec(-1.0, 1.0);
            let decomposed = q.minimizer_by_decomposition(start);
            let x = q.minimizer(start);
            if flat_direction(q.matrix(), FLAT_SPREAD).is_some() {
                taken += 1;
            }
            assert!((x - decomposed).length() < 1e-9 * (1.0 + decomposed.length()), "{x} against {decomposed}");
            assert!((q.eval(x) - q.eval(decomposed)).abs() <= 1e-9 * (1.0 + q.eval(decomposed)));
        }
        // Both paths were exercised.
        assert!(taken > 100 && taken < 500, "{taken} of 500 took the power iteration");
    }

    #[test]
    fn minimiser_finds_the_corner_the_crease_and_the_plane() {
        let corner = DVec3::new(0.3, -0.2, 0.7);
        let planes = [DVec3::X, DVec3::Y, DVec3::Z].map(|n| Quadric::plane(corner, n, 2.0));
        let start = DVec3::new(1.0, 1.0, 1.0);
        // Three planes: the corner.
        let q = planes[0] + planes[1] + planes[2];
        assert!((q.minimizer(start) - corner).length() < 1e-12);
        assert!(q.eval(corner) < 1e-12 && (q.eval(start) - 2.0 * (start - corner).length_squared()).abs() < 1e-9);
        // Two: the point of the crease x = 0.3, y = -0.2 nearest the start.
        let crease = (planes[0] + planes[1]).minimizer(start);
        assert!((crease - DVec3::new(0.3, -0.2, 1.0)).length() < 1e-12);
        // One: the start moved onto the plane along its normal.
        assert!(((planes[2]).minimizer(start) - DVec3::new(1.0, 1.0, 0.7)).length() < 1e-12);
    }
}
