//! Mirror reflection and refraction directions (seed: transmission, Whitted model).
//!
//! With `d` the unit incident direction and `n` the unit normal facing the incident
//! side (`d . n < 0`), `cos i = -d . n`:
//! - reflection: `r = d + 2 cos(i) n` (the mirror image of `d` about the surface);
//! - refraction from index `eta1` into `eta2` (Snell: `eta1 sin i = eta2 sin t`), with
//!   `eta = eta1 / eta2` and `k = 1 - eta^2 (1 - cos^2 i)`: total internal reflection
//!   when `k < 0`, else `t = eta d + (eta cos i - sqrt(k)) n`.
//!
//! Both return unit vectors for unit inputs.

use glam::DVec3;

/// The mirror direction of unit `d` about the unit normal `n` (either orientation).
#[must_use]
pub fn reflect(d: DVec3, n: DVec3) -> DVec3 {
    d - n * (2.0 * d.dot(n))
}

/// The refracted direction of unit `d` entering the medium of index `eta2` from one of
/// index `eta1` through a surface of unit normal `n` (either orientation), or `None`
/// on total internal reflection (`sin t` would exceed 1).
#[must_use]
pub fn refract(d: DVec3, n: DVec3, eta1: f64, eta2: f64) -> Option<DVec3> {
    // Face the normal against the incident ray.
    let n = if d.dot(n) > 0.0 { -n } else { n };
    let cos_i = (-d.dot(n)).min(1.0);
    let eta = eta1 / eta2;
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    (k >= 0.0).then(|| d * eta + n * (eta * cos_i - k.sqrt()))
}
