//! Interval helpers shared by the quadrics' box classifications.
//!
//! Every shape classifies a box by bounding a distance-like quantity `q` over the box
//! from below and above and comparing with the threshold `t` where `q = t` is the
//! surface: `max q < t` is Inside, `min q > t` is Outside, anything else Boundary.
//! A relative margin [`EPS`] keeps float rounding from turning a Boundary into a
//! wrong Inside or Outside (the point test at voxel centres has no margin).

use super::Class;

/// Relative safety margin on thresholds.
pub const EPS: f64 = 1e-9;

/// Classifies `q in [lo, hi]` against the solid `q <= t`.
#[inline]
#[must_use]
pub fn classify_below(lo: f64, hi: f64, t: f64) -> Class {
    let m = EPS * t.abs().max(1e-300);
    if hi < t - m {
        Class::Inside
    } else if lo > t + m {
        Class::Outside
    } else {
        Class::Boundary
    }
}

/// The range of `x^2` over `x in [a, b]`.
#[inline]
#[must_use]
pub fn square_range(a: f64, b: f64) -> (f64, f64) {
    let lo = if a > 0.0 {
        a * a
    } else if b < 0.0 {
        b * b
    } else {
        0.0
    };
    (lo, (a * a).max(b * b))
}

/// The range of `u^2 + v^2` over a rectangle `[u0, u1] x [v0, v1]`.
#[inline]
#[must_use]
pub fn radial_range(u: (f64, f64), v: (f64, f64)) -> (f64, f64) {
    let (ul, uh) = square_range(u.0, u.1);
    let (vl, vh) = square_range(v.0, v.1);
    (ul + vl, uh + vh)
}

/// Combines the classes of two conditions that must both hold.
#[inline]
#[must_use]
pub fn both(a: Class, b: Class) -> Class {
    match (a, b) {
        (Class::Outside, _) | (_, Class::Outside) => Class::Outside,
        (Class::Inside, Class::Inside) => Class::Inside,
        _ => Class::Boundary,
    }
}

/// Fails unless `v` is finite and positive.
pub(crate) fn positive(what: &'static str, v: f64) -> crate::Result<f64> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(crate::Error::invalid(what, format!("{} must be a finite positive number", crate::error::Number(v))))
    }
}

/// Fails unless every coordinate is finite.
pub(crate) fn finite(what: &'static str, v: glam::DVec3) -> crate::Result<glam::DVec3> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(crate::Error::invalid(what, format!("{} must be finite", crate::error::Vector(v))))
    }
}
