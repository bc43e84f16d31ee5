//! Colour models: RGB (the renderer's own), CMY and HSI, as the seed chapter defines them.
//!
//! Components are in `[0, 1]`; hue is in degrees, `[0, 360)`.
//! - CMY: `(C, M, Y) = (1, 1, 1) - (R, G, B)`.
//! - HSI: `I = (R + G + B) / 3`, `S = 1 - 3 min(R, G, B) / (R + G + B)`,
//!   `theta = acos( ((R - G) + (R - B)) / 2 / sqrt((R - G)^2 + (R - B)(G - B)) )`,
//!   `H = theta` when `B <= G`, else `360 - theta`. Grey (`R = G = B`) has no hue: `H = 0`;
//!   black has no saturation either: `S = 0`.
//! - HSI back to RGB, by sector of the hue (the inverse of the above): for `H` in
//!   `[0, 120)`, `B = I (1 - S)`, `R = I (1 + S cos H / cos(60 - H))`, `G = 3I - R - B`;
//!   the sectors `[120, 240)` and `[240, 360)` are the same with `H - 120`, `H - 240` and
//!   the channels rotated (R, G, B) -> (G, B, R) -> (B, R, G).

use glam::DVec3;

/// A colour in the HSI model: hue in degrees, saturation and intensity in `[0, 1]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hsi {
    /// Hue, degrees in `[0, 360)`: 0 red, 120 green, 240 blue.
    pub h: f64,
    /// Saturation: 0 grey, 1 a pure hue mixed with no white.
    pub s: f64,
    /// Intensity: the mean of the three channels.
    pub i: f64,
}

/// CMY from RGB: `(1, 1, 1) - rgb`.
#[must_use]
pub fn rgb_to_cmy(rgb: DVec3) -> DVec3 {
    DVec3::ONE - rgb
}

/// RGB from CMY: `(1, 1, 1) - cmy`.
#[must_use]
pub fn cmy_to_rgb(cmy: DVec3) -> DVec3 {
    DVec3::ONE - cmy
}

/// HSI from RGB (see the module doc for the formulas and the grey and black cases).
#[must_use]
pub fn rgb_to_hsi(rgb: DVec3) -> Hsi {
    let (r, g, b) = (rgb.x, rgb.y, rgb.z);
    let sum = r + g + b;
    let i = sum / 3.0;
    let s = if sum > 0.0 { 1.0 - 3.0 * rgb.min_element() / sum } else { 0.0 };
    let denominator = ((r - g) * (r - g) + (r - b) * (g - b)).sqrt();
    let h = if denominator > 0.0 {
        let theta = (0.5 * ((r - g) + (r - b)) / denominator).clamp(-1.0, 1.0).acos().to_degrees();
        if b <= g { theta } else { 360.0 - theta }
    } else {
        0.0
    };
    Hsi { h: if h >= 360.0 { h - 360.0 } else { h }, s, i }
}

/// RGB from HSI (the sector formulas of the module doc). Hue is taken modulo 360.
/// Saturations a colour of that intensity cannot reach give channels outside `[0, 1]`.
#[must_use]
pub fn hsi_to_rgb(hsi: Hsi) -> DVec3 {
    let h = hsi.h.rem_euclid(360.0);
    let sector = ((h / 120.0).floor() as usize).min(2);
    let h = (h - 120.0 * sector as f64).to_radians();
    let low = hsi.i * (1.0 - hsi.s);
    let high = hsi.i * (1.0 + hsi.s * h.cos() / (std::f64::consts::FRAC_PI_3 - h).cos());
    let rest = 3.0 * hsi.i - low - high;
    // (first, second, third) = (high, rest, low) in the sector's channel order.
    match sector {
        0 => DVec3::new(high, rest, low),
        1 => DVec3::new(low, high, rest),
        _ => DVec3::new(rest, low, high),
    }
}
