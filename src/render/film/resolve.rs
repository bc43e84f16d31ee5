//! From linear radiance to pixels and back: the box-filter average of a pixel's
//! samples and the sRGB transfer function (IEC 61966-2-1), each written once.
//!
//! Encode: `s = 12.92 c` for `c <= 0.0031308`, else `1.055 c^(1/2.4) - 0.055`, then
//! rounded to 8 bits; decode is its inverse with the threshold `0.04045`.

use glam::DVec3;
use image::Rgb;

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

/// The pixel of `count` samples whose linear colours add up to `sum`: their mean,
/// sRGB-encoded.
#[must_use]
pub fn resolve(sum: DVec3, count: u32) -> Rgb<u8> {
    let c = sum / f64::from(count);
    Rgb([to_srgb8(c.x), to_srgb8(c.y), to_srgb8(c.z)])
}
