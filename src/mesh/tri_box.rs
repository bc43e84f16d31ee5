//! Triangle / axis-aligned box overlap by the separating axis theorem.
//!
//! Akenine-Moller, "Fast 3D Triangle-Box Overlap Testing" (2001): a triangle and a box
//! are disjoint iff one of 13 axes separates them: the 3 box normals, the triangle's
//! normal, and the 9 cross products of box and triangle edges. The box is grown by a
//! relative hair so that rounding can only report an overlap that is not there, never
//! miss one (the voxelizers need conservative answers).

use glam::DVec3;

/// Whether triangle `t` meets the closed box with centre `center` and half extents `half`.
#[must_use]
pub(crate) fn triangle_box_overlap(t: &[DVec3; 3], center: DVec3, half: DVec3) -> bool {
    let h = half * (1.0 + 1e-9) + DVec3::splat(1e-300);
    // Step 1: move the box to the origin.
    let v = [t[0] - center, t[1] - center, t[2] - center];
    // Step 2: the box normals (the triangle's bounding box against the box).
    for a in 0..3 {
        let (lo, hi) = min_max([v[0][a], v[1][a], v[2][a]]);
        if lo > h[a] || hi < -h[a] {
            return false;
        }
    }
    // Step 3: the triangle's plane: n . x = n . v0 against the box's projection radius
    // (cheap, and it rejects most near misses).
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let n = e[0].cross(e[1]);
    if n.dot(v[0]).abs() > h.dot(n.abs()) {
        return false;
    }
    // Step 4: the nine axes u_i x e_k (box axis u_i, triangle edge e_k). Edge k's two
    // ends project alike, to u_i . (e_k x v_k); the third corner adds
    // u_i . (e_k x (v_opposite - v_k)) = n_i, the same for every edge. So the
    // triangle's projection is [w_i, w_i + n_i] with w = e_k x v_k, against the box's
    // radius h_j |e_k,l| + h_l |e_k,j| ({i, j, l} = {x, y, z}).
    let (n_lo, n_hi) = (n.min(DVec3::ZERO), n.max(DVec3::ZERO));
    for k in 0..3 {
        let w = e[k].cross(v[k]);
        let a = e[k].abs();
        let r = DVec3::new(h.y * a.z + h.z * a.y, h.x * a.z + h.z * a.x, h.x * a.y + h.y * a.x);
        // Separated on some axis i: w_i + min(0, n_i) > r_i or w_i + max(0, n_i) < -r_i.
        if (w + n_lo).cmpgt(r).any() || (w + n_hi).cmplt(-r).any() {
            return false;
        }
    }
    true
}

/// Least and greatest of three finite values, by plain comparisons (`f64::min` also
/// orders NaNs, which costs a few instructions a call on this hot path).
#[inline]
fn min_max(p: [f64; 3]) -> (f64, f64) {
    let (lo, hi) = if p[0] < p[1] { (p[0], p[1]) } else { (p[1], p[0]) };
    (if p[2] < lo { p[2] } else { lo }, if p[2] > hi { p[2] } else { hi })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    #[test]
    fn plain_cases() {
        let t = [DVec3::new(-1.0, -1.0, 0.0), DVec3::new(1.0, -1.0, 0.0), DVec3::new(0.0, 1.0, 0.0)];
        assert!(triangle_box_overlap(&t, DVec3::ZERO, DVec3::splat(0.1)));
        assert!(!triangle_box_overlap(&t, DVec3::new(0.0, 0.0, 0.2), DVec3::splat(0.1)));
        // Beside the hypotenuse: the box-normal tests pass, an edge axis separates.
        assert!(!triangle_box_overlap(&t, DVec3::new(0.9, 0.9, 0.0), DVec3::splat(0.1)));
    }

    #[test]
    fn triangle_box_overlap_matches_sampling() {
        let mut rng = Rng(99);
        let (mut overlaps, mut separate) = (0, 0);
        for _ in 0..3000 {
            let t = [rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0)];
            let center = rng.vec(-1.0, 1.0);
            let half = rng.vec(0.02, 0.5);
            let got = triangle_box_overlap(&t, center, half);
            // Sample the triangle on a barycentric grid: distance from the box.
            const N: usize = 60;
            let mut nearest = f64::INFINITY;
            for i in 0..=N {
                for j in 0..=N - i {
                    let (u, v) = (i as f64 / N as f64, j as f64 / N as f64);
                    let p = t[0] + (t[1] - t[0]) * u + (t[2] - t[0]) * v;
                    nearest = nearest.min(((p - center).abs() - half).max(DVec3::ZERO).length());
                }
            }
            let spacing =
                [t[1] - t[0], t[2] - t[0], t[2] - t[1]].iter().map(|e| e.length()).fold(0.0, f64::max) / N as f64;
            if nearest == 0.0 {
                assert!(got, "a sampled point lies in the box: {t:?} {center} {half}");
            }
            if got {
                assert!(
                    nearest <= spacing,
                    "reported overlap, but the triangle is {nearest} away: {t:?} {center} {half}"
                );
                overlaps += 1;
            } else {
                separate += 1;
            }
        }
        assert!(overlaps > 300 && separate > 300, "{overlaps} overlaps, {separate} separate");
    }
}
