//! From linear radiance to pixels and back: the box-filter average of a pixel's
//! samples scaled by the exposure, and the sRGB transfer function (IEC 61966-2-1),
//! each written once.
//!
//! Exposure: `stops` scale the radiance by `2^stops` before anything encodes it (as a
//! camera's exposure does; pbrt's film scales the same way before writing an EXR), so
//! `+1` doubles every value and `0` leaves the mean's bits as they are.
//!
//! Encode: `s = 12.92 c` for `c <= 0.0031308`, else `1.055 c^(1/2.4) - 0.055`, then
//! rounded to 8 bits; decode is its inverse with the threshold `0.04045`.

use glam::DVec3;

use crate::error::{Error, Result};

/// Largest exposure in stops either way: `2^64` is far past any radiance a scene can
/// hold, and keeps the scale a normal finite number.
pub const MAX_EXPOSURE_STOPS: f64 = 64.0;

/// sRGB encoding of a linear value in `[0, 1]` (clamped), to 8 bits.
#[must_use]
pub fn to_srgb8(linear: f64) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// Linear value of an 8-bit sRGB channel.
#[must_use]
pub fn from_srgb8(c: u8) -> f64 {
    let s = f64::from(c) / 255.0;
    if s <= 0.040_45 { s / 12.92 } else { ((s + 0.055) / 1.055).powf(2.4) }
}

/// The factor `2^stops` an exposure of `stops` scales radiance by; refused unless
/// `stops` is finite and within [`MAX_EXPOSURE_STOPS`] of 0.
pub fn exposure_scale(stops: f64) -> Result<f64> {
    if !(stops.is_finite() && stops.abs() <= MAX_EXPOSURE_STOPS) {
        return Err(Error::invalid(
            "exposure",
            format!("{stops} stops is not a finite number within -{MAX_EXPOSURE_STOPS}..={MAX_EXPOSURE_STOPS}"),
        ));
    }
    Ok(stops.exp2())
}

/// The pixel of `count` samples whose linear colours add up to `sum`: their mean times
/// the exposure's `scale`, still linear.
#[must_use]
pub fn resolve(sum: DVec3, count: u32, scale: f64) -> DVec3 {
    sum / f64::from(count) * scale
}
