//! Exact orientation predicates (Shewchuk's adaptive arithmetic, `robust` crate).
//!
//! Crossing counts must agree between the two triangles of a shared edge; float
//! determinants near zero can give both the same sign and lose or double a crossing.
//! These return the exact sign (the magnitude is approximate).

use glam::{DVec2, DVec3};
use robust::{Coord, Coord3D};

/// Sign of `(b - a) x (c - a) . (d - a)`: positive when `d` is on the side the
/// counter-clockwise triangle `a, b, c` faces.
#[inline]
#[must_use]
pub fn orient3d(a: DVec3, b: DVec3, c: DVec3, d: DVec3) -> f64 {
    let k = |v: DVec3| Coord3D { x: v.x, y: v.y, z: v.z };
    -robust::orient3d(k(a), k(b), k(c), k(d))
}

/// Sign of `(b - a) x (c - a)` in 2-D: positive when `c` is left of `a -> b`.
#[inline]
#[must_use]
pub fn orient2d(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let k = |v: DVec2| Coord { x: v.x, y: v.y };
    robust::orient2d(k(a), k(b), k(c))
}

/// Sign of `(p - q) x (b - a)` in 2-D, exactly: the four differences and the two
/// products are split into exact float pairs (two-diff, two-product by a fused
/// multiply-add) and the sixteen terms summed into a non-overlapping expansion
/// (Shewchuk's grow-expansion), whose largest component has the sign of the sum.
/// Only the tie cases of the crossing predicates call it, so it is not filtered.
#[must_use]
pub fn cross_of_differences(p: DVec2, q: DVec2, b: DVec2, a: DVec2) -> f64 {
    let (u, w) = ([two_diff(p.x, q.x), two_diff(p.y, q.y)], [two_diff(b.x, a.x), two_diff(b.y, a.y)]);
    let mut sum = [0.0f64; 16];
    let mut len = 0;
    // u.x w.y - u.y w.x, each factor a pair (hi, lo).
    for (f, g, sign) in [(u[0], w[1], 1.0), (u[1], w[0], -1.0)] {
        for x in [f.0, f.1] {
            for y in [g.0, g.1] {
                let (hi, lo) = two_product(sign * x, y);
                for term in [hi, lo] {
                    len = grow_expansion(&mut sum, len, term);
                }
            }
        }
    }
    sum[..len].iter().rev().copied().find(|&c| c != 0.0).map_or(0.0, f64::signum)
}

/// `a - b` as `hi + lo` exactly (Knuth's two-sum on `a + (-b)`).
fn two_diff(a: f64, b: f64) -> (f64, f64) {
    two_sum(a, -b)
}

/// `a + b` as `hi + lo` exactly.
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let hi = a + b;
    let bv = hi - a;
    (hi, (a - (hi - bv)) + (b - bv))
}

/// `a b` as `hi + lo` exactly.
fn two_product(a: f64, b: f64) -> (f64, f64) {
    let hi = a * b;
    (hi, a.mul_add(b, -hi))
}

/// Adds `b` to the expansion `e[..len]` (non-overlapping, increasing magnitude) in
/// place; returns the new length (at most `e.len()`, zeros are dropped).
fn grow_expansion(e: &mut [f64; 16], len: usize, b: f64) -> usize {
    let mut q = b;
    let mut out = 0;
    for i in 0..len {
        let (s, h) = two_sum(q, e[i]);
        q = s;
        if h != 0.0 {
            e[out] = h;
            out += 1;
        }
    }
    if q != 0.0 {
        e[out] = q;
        out += 1;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signs_follow_the_right_hand_rule() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert!(orient3d(a, b, c, DVec3::Z) > 0.0 && orient3d(a, b, c, -DVec3::Z) < 0.0);
        assert_eq!(orient3d(a, b, c, DVec3::new(0.3, 0.3, 0.0)), 0.0);
        assert!(orient2d(DVec2::ZERO, DVec2::X, DVec2::Y) > 0.0);
    }

    #[test]
    fn cross_of_differences_is_exact_where_floats_cancel() {
        // Oracle: the same value in integers. Every coordinate stays in 1..2, so is a
        // multiple of 2^-52, and b - a is p - q plus a unit or so of 2^-52 on each
        // axis: the cross product is some 2^-55, the products some 2^-6.
        let mut rng = crate::test_util::Rng(17);
        let fixed = |x: f64| (x * 2f64.powi(52)) as i128;
        let (mut positive, mut negative) = (0, 0);
        for _ in 0..2000 {
            let mut near = || 1.5 + rng.range(-0.1, 0.1);
            let [px, qx, ax, py, qy, ay] = std::array::from_fn(|_| near());
            let mut ulps = || (rng.next() % 3) as f64 - 1.0;
            let (bx, by) = (ax + (px - qx) + ulps() * 2f64.powi(-52), ay + (py - qy) + ulps() * 2f64.powi(-52));
            let exact =
                (fixed(px) - fixed(qx)) * (fixed(by) - fixed(ay)) - (fixed(py) - fixed(qy)) * (fixed(bx) - fixed(ax));
            let got =
                cross_of_differences(DVec2::new(px, py), DVec2::new(qx, qy), DVec2::new(bx, by), DVec2::new(ax, ay));
            assert_eq!(got, exact.signum() as f64, "{px} {py} {qx} {qy} {bx} {by} {ax} {ay}");
            positive += usize::from(exact > 0);
            negative += usize::from(exact < 0);
        }
        assert!(positive > 200 && negative > 200, "{positive} positive, {negative} negative");
        // Parallel differences, not representable exactly: zero, not a rounding sign.
        let (q, p) = (DVec2::new(0.1, 0.7), DVec2::new(0.3, 1.3));
        assert_eq!(cross_of_differences(p, q, p, q), 0.0);
    }
}
