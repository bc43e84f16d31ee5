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
}
