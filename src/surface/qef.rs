//! The quadratic error function of dual contouring: the point nearest, in the least
//! squares sense, to the tangent planes of a cell's crossings (Ju et al. 2002, §2.3).
//!
//! `E(x) = sum_i (n_i . (x - p_i))^2 = x^T A x - 2 b^T x + c`, with
//! `A = sum n_i n_i^T`, `b = sum n_i (n_i . p_i)`. Its minimiser solves `A x = b`; where
//! the planes do not pin the point down (a flat region: rank 1; a crease: rank 2), the
//! least-norm solution around the **mass point** `m` (the crossings' mean) is taken:
//! `x = m + A^+ (b - A m)`, with the pseudo-inverse of `A` from its eigen-decomposition
//! (Jacobi rotations; `A` is symmetric 3 x 3), eigenvalues under `TRUNCATION` times the
//! largest counted as zero (Lindstrom's truncated SVD, as in the paper). The rank says
//! what the cell holds: 1 a smooth surface, 2 a crease, 3 a corner.
//!
//! Departure: the paper solves by QR of the stacked planes for numerical range; here the
//! points are in cell-local coordinates (within a voxel or two of the origin), where the
//! normal equations in `f64` lose nothing that matters.

use glam::{DMat3, DVec3};

/// Eigenvalues below this fraction of the largest are taken as zero (singular values
/// below a tenth).
const TRUNCATION: f64 = 0.01;
/// Jacobi sweeps at most (a 3 x 3 converges in four or five).
const SWEEPS: usize = 12;

/// The sums a QEF keeps: `A`, `b`, `c`, and the mass point's sum and count.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Qef {
    a: [f64; 6],
    b: DVec3,
    c: f64,
    mass: DVec3,
    count: u32,
}

/// A QEF's minimiser, its error there and the rank of its planes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct QefSolution {
    /// The point.
    pub point: DVec3,
    /// `E(point)`: the sum of squared distances to the planes.
    pub error: f64,
    /// How many independent directions the planes fix (0 to 3).
    pub rank: u8,
}

impl Qef {
    /// Adds the plane through `p` with unit normal `n`.
    pub fn add(&mut self, p: DVec3, n: DVec3) {
        let d = n.dot(p);
        self.a[0] += n.x * n.x;
        self.a[1] += n.x * n.y;
        self.a[2] += n.x * n.z;
        self.a[3] += n.y * n.y;
        self.a[4] += n.y * n.z;
        self.a[5] += n.z * n.z;
        self.b += n * d;
        self.c += d * d;
        self.mass += p;
        self.count += 1;
    }

    /// Whether no plane was added.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.count == 0
    }

    /// The matrix `A`.
    fn matrix(&self) -> DMat3 {
        let a = &self.a;
        DMat3::from_cols(DVec3::new(a[0], a[1], a[2]), DVec3::new(a[1], a[3], a[4]), DVec3::new(a[2], a[4], a[5]))
    }

    /// The crossings' mean (the origin without planes).
    #[must_use]
    pub fn mass_point(&self) -> DVec3 {
        if self.count == 0 { DVec3::ZERO } else { self.mass / f64::from(self.count) }
    }

    /// `E(x)`.
    #[must_use]
    pub fn error(&self, x: DVec3) -> f64 {
        (x.dot(self.matrix() * x) - 2.0 * self.b.dot(x) + self.c).max(0.0)
    }

    /// The minimiser nearest the mass point (module doc).
    #[must_use]
    pub fn solve(&self) -> QefSolution {
        let m = self.mass_point();
        if let Some(solution) = self.solve_flat(m) {
            return solution;
        }
        let a = self.matrix();
        let (values, vectors) = symmetric_eigen(a);
        let largest = values.max_element();
        let residual = self.b - a * m;
        let mut point = m;
        let mut rank = 0;
        if largest > 0.0 {
            for i in 0..3 {
                if values[i] > TRUNCATION * largest {
                    let v = vectors.col(i);
                    point += v * (v.dot(residual) / values[i]);
                    rank += 1;
                }
            }
        }
        QefSolution { point, error: self.error(point), rank }
    }
}

impl Qef {
    /// The minimiser within the box `[lo, hi]`: [`Qef::solve`]'s point when it lies
    /// inside, else the coordinates outside are clamped to the box's faces and the
    /// others solved again with those fixed (the QEF restricted to the face, then the
    /// edge), up to three times; the flag says whether the box stopped the point.
    #[must_use]
    pub fn solve_within(&self, lo: DVec3, hi: DVec3) -> (QefSolution, bool) {
        let free = self.solve();
        let inside = |x: DVec3| x.cmpge(lo).all() && x.cmple(hi).all();
        if inside(free.point) {
            return (free, false);
        }
        let a = self.matrix();
        let scale = a.x_axis.x.max(a.y_axis.y).max(a.z_axis.z).max(1.0);
        let mut x = free.point.clamp(lo, hi);
        let mut fixed = [false; 3];
        for _ in 0..3 {
            for i in 0..3 {
                fixed[i] |= x[i] <= lo[i] || x[i] >= hi[i];
            }
            // A' x = b' with the fixed coordinates' rows and columns replaced by
            // `scale` on the diagonal (block diagonal: they come out as fixed).
            let mut reduced = *self;
            let mut m = self.mass_point();
            let mut rhs = self.b;
            let mut cols = [a.x_axis, a.y_axis, a.z_axis];
            for i in 0..3 {
                if fixed[i] {
                    rhs -= cols[i] * x[i];
                }
            }
            for i in 0..3 {
                if fixed[i] {
                    cols[i] = DVec3::ZERO;
                    cols[i][i] = scale;
                    for (j, col) in cols.iter_mut().enumerate() {
                        if j != i {
                            col[i] = 0.0;
                        }
                    }
                    rhs[i] = scale * x[i];
                    m[i] = x[i];
                }
            }
            reduced.set_matrix(DMat3::from_cols(cols[0], cols[1], cols[2]));
            reduced.b = rhs;
            reduced.mass = m * f64::from(reduced.count.max(1));
            reduced.count = reduced.count.max(1);
            let point = reduced.solve_around(m).clamp(lo, hi);
            let done = inside(point) && (0..3).all(|i| fixed[i] || (point[i] > lo[i] && point[i] < hi[i]));
            x = point;
            if done {
                break;
            }
        }
        (QefSolution { point: x, error: self.error(x), rank: free.rank }, true)
    }

    fn set_matrix(&mut self, m: DMat3) {
        self.a = [m.x_axis.x, m.y_axis.x, m.z_axis.x, m.y_axis.y, m.z_axis.y, m.z_axis.z];
    }

    /// The truncated pseudo-inverse solution around `m`.
    fn solve_around(&self, m: DVec3) -> DVec3 {
        let a = self.matrix();
        let (values, vectors) = symmetric_eigen(a);
        let largest = values.max_element();
        let residual = self.b - a * m;
        let mut point = m;
        if largest > 0.0 {
            for i in 0..3 {
                if values[i] > TRUNCATION * largest {
                    let v = vectors.col(i);
                    point += v * (v.dot(residual) / values[i]);
                }
            }
        }
        point
    }

    /// The rank-1 case without an eigen-decomposition: when the planes' normals all lie
    /// within [`FLAT_SPREAD`] of their mean `n`, the second eigenvalue is under
    /// [`TRUNCATION`] times the first, and the solution is `m + s n` with `s` minimising
    /// `E` along `n`: `s = n . (b - A m) / (n . A n)`.
    fn solve_flat(&self, m: DVec3) -> Option<QefSolution> {
        let a = self.matrix();
        let (n, along) = flat_direction(a, FLAT_SPREAD)?;
        let point = m + n * (n.dot(self.b - a * m) / along);
        Some(QefSolution { point, error: self.error(point), rank: 1 })
    }
}

/// The share of `A`'s trace off its dominant direction under which the planes count as
/// one (well under [`TRUNCATION`], so the fast path never decides a rank the
/// decomposition would call 2).
pub(super) const FLAT_SPREAD: f64 = 0.001;

/// The dominant direction `n` of the symmetric positive semi-definite `a` and its
/// eigenvalue `n . A n`, when the other two eigenvalues together are at most `spread`
/// times it (a rank-1 matrix up to `spread`), without an eigen-decomposition: two
/// power iterations from `a`'s largest column (at least about a third of it along
/// `n`), after which `n` is within about `2 spread^3` radians of the eigenvector;
/// `None` otherwise.
pub(super) fn flat_direction(a: DMat3, spread: f64) -> Option<(DVec3, f64)> {
    let mut n =
        [a.x_axis, a.y_axis, a.z_axis].into_iter().max_by(|p, q| p.length_squared().total_cmp(&q.length_squared()))?;
    n = (a * n).try_normalize()?;
    n = (a * n).try_normalize()?;
    let along = n.dot(a * n);
    let trace = a.x_axis.x + a.y_axis.y + a.z_axis.z;
    // The other eigenvalues sum to trace - along; all of them small means rank 1.
    (along > 0.0 && trace - along <= spread * along).then_some((n, along))
}

/// Eigenvalues and unit eigenvectors (the columns) of the symmetric `a`, by cyclic
/// Jacobi rotations.
pub(super) fn symmetric_eigen(a: DMat3) -> (DVec3, DMat3) {
    let mut m = a.to_cols_array_2d();
    let mut v = DMat3::IDENTITY.to_cols_array_2d();
    for _ in 0..SWEEPS {
        let off = m[0][1].powi(2) + m[0][2].powi(2) + m[1][2].powi(2);
        let scale = m[0][0].powi(2) + m[1][1].powi(2) + m[2][2].powi(2);
        if off <= 1e-30 * scale.max(f64::MIN_POSITIVE) {
            break;
        }
        for (p, q) in [(0, 1), (0, 2), (1, 2)] {
            if m[p][q] == 0.0 {
                continue;
            }
            let theta = (m[q][q] - m[p][p]) / (2.0 * m[p][q]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // m <- J^T m J, v <- v J, with J the rotation in the (p, q) plane.
            for row in &mut m {
                let (mkp, mkq) = (row[p], row[q]);
                row[p] = c * mkp - s * mkq;
                row[q] = s * mkp + c * mkq;
            }
            let (rp, rq) = (m[p], m[q]);
            m[p] = std::array::from_fn(|k| c * rp[k] - s * rq[k]);
            m[q] = std::array::from_fn(|k| s * rp[k] + c * rq[k]);
            for col in &mut v {
                let (vp, vq) = (col[p], col[q]);
                col[p] = c * vp - s * vq;
                col[q] = s * vp + c * vq;
            }
        }
    }
    // `v` is stored column-major as [col][row]; the rotation acted on its rows.
    let vectors = DMat3::from_cols_array_2d(&v).transpose();
    (DVec3::new(m[0][0], m[1][1], m[2][2]), vectors)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigen_decomposition_reconstructs_the_matrix() {
        let a = DMat3::from_cols(DVec3::new(4.0, 1.0, 0.5), DVec3::new(1.0, 3.0, -0.2), DVec3::new(0.5, -0.2, 2.0));
        let (values, vectors) = symmetric_eigen(a);
        for i in 0..3 {
            let v = vectors.col(i);
            assert!((v.length() - 1.0).abs() < 1e-12);
            assert!((a * v - v * values[i]).length() < 1e-10, "column {i} is not an eigenvector");
        }
    }

    #[test]
    fn three_planes_meet_at_their_corner() {
        let corner = DVec3::new(0.2, -0.1, 0.3);
        let mut q = Qef::default();
        for n in [DVec3::X, DVec3::Y, DVec3::Z] {
            q.add(corner + n.cross(DVec3::ONE) * 0.4, n);
        }
        let s = q.solve();
        assert_eq!(s.rank, 3);
        assert!((s.point - corner).length() < 1e-12);
        assert!(s.error < 1e-20);
    }

    #[test]
    fn a_point_outside_the_box_slides_along_its_face() {
        // Planes x = 0.8 and y = 0.1 (a crease along z); the box stops x at 0.5, and
        // along the face x = 0.5 the best point keeps y = 0.1.
        let mut q = Qef::default();
        q.add(DVec3::new(0.8, 0.0, 0.2), DVec3::X);
        q.add(DVec3::new(0.8, 0.3, -0.2), DVec3::X);
        q.add(DVec3::new(0.2, 0.1, 0.0), DVec3::Y);
        q.add(DVec3::new(0.4, 0.1, 0.0), DVec3::Y);
        let (s, clamped) = q.solve_within(DVec3::splat(-0.5), DVec3::splat(0.5));
        assert!(clamped);
        assert!((s.point - DVec3::new(0.5, 0.1, 0.0)).length() < 1e-12, "{:?}", s.point);
    }

    #[test]
    fn a_crease_keeps_the_mass_point_along_it() {
        // Two planes x = 0.1 and y = -0.2: the line along z; points along z average 0.25.
        let mut q = Qef::default();
        q.add(DVec3::new(0.1, 0.3, 0.0), DVec3::X);
        q.add(DVec3::new(0.1, -0.4, 0.5), DVec3::X);
        q.add(DVec3::new(-0.3, -0.2, 0.5), DVec3::Y);
        q.add(DVec3::new(0.4, -0.2, 0.0), DVec3::Y);
        let s = q.solve();
        assert_eq!(s.rank, 2);
        assert!((s.point - DVec3::new(0.1, -0.2, 0.25)).length() < 1e-12, "{:?}", s.point);
    }
}
