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
//!
//! Written colours ([`ColorSpec`], the scene files' `color` values) take one of the
//! forms of [`COLOR_FORMS`]. `"#rrggbb"` is the same linear components as `[r, g, b]`
//! in steps of 1/255 (`rr / 255`), not sRGB-decoded, like every other form. Reading
//! refuses what the models cannot mean rather than clamping it: a component outside
//! `[0, 1]`, a hue outside `[0, 360]` degrees, and an HSI colour whose RGB lies outside
//! `[0, 1]` (a saturation that intensity cannot reach); only the rounding of the HSI
//! formulas (within 1e-9) is clamped.

use std::fmt;

use glam::DVec3;
use serde::de::{self, Deserialize, Deserializer, IgnoredAny, MapAccess, SeqAccess, Visitor};

use crate::error::{Number, Vector};

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

/// The forms a written colour takes, as error messages list them.
pub const COLOR_FORMS: &str =
    "[r, g, b], { rgb = [r, g, b] }, { cmy = [c, m, y] }, { hsi = [hue, saturation, intensity] } or \"#rrggbb\"";

/// A colour as a file writes it (one of [`COLOR_FORMS`]), read and checked into linear
/// RGB; see the module doc for the ranges.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ColorSpec(DVec3);

impl ColorSpec {
    /// Linear RGB, every channel in `[0, 1]`.
    #[must_use]
    pub fn rgb(self) -> DVec3 {
        self.0
    }

    /// The colour of the model named `model` (`rgb`, `cmy` or `hsi`) with components
    /// `c`, checked; the error says what is refused.
    pub fn from_model(model: &str, c: [f64; 3]) -> Result<ColorSpec, String> {
        match model {
            "rgb" => unit_components(c).map(ColorSpec),
            "cmy" => unit_components(c).map(|cmy| ColorSpec(cmy_to_rgb(cmy))),
            "hsi" => from_hsi(c).map(ColorSpec),
            other => Err(unknown_model(other)),
        }
    }

    /// The colour of `"#rrggbb"` (six hex digits, either case): `rr / 255`, ...
    pub fn from_hex(text: &str) -> Result<ColorSpec, String> {
        let digits = text.strip_prefix('#').filter(|d| d.len() == 6 && d.bytes().all(|b| b.is_ascii_hexdigit()));
        let Some(rrggbb) = digits.and_then(|d| u32::from_str_radix(d, 16).ok()) else {
            return Err(format!("invalid colour: \"{text}\" is not \"#rrggbb\"; a colour is {COLOR_FORMS}"));
        };
        let channel = |shift: u32| f64::from(rrggbb >> shift & 0xff) / 255.0;
        Ok(ColorSpec(DVec3::new(channel(16), channel(8), channel(0))))
    }
}

/// The refusal of a colour model that is not `rgb`, `cmy` or `hsi`.
fn unknown_model(model: &str) -> String {
    format!("invalid colour: unknown model `{model}`; a colour is {COLOR_FORMS}")
}

/// `c` as a vector when every component lies in `[0, 1]`.
fn unit_components(c: [f64; 3]) -> Result<DVec3, String> {
    match c.iter().find(|x| !(0.0..=1.0).contains(*x)) {
        Some(&x) => {
            Err(format!("invalid colour: component {} of {} is outside 0..1", Number(x), Vector(DVec3::from_array(c))))
        }
        None => Ok(DVec3::from_array(c)),
    }
}

/// RGB of `[hue, saturation, intensity]`, refused unless the hue is in `[0, 360]`, the
/// others in `[0, 1]`, and the RGB in `[0, 1]` up to the formulas' rounding.
fn from_hsi([h, s, i]: [f64; 3]) -> Result<DVec3, String> {
    if !(0.0..=360.0).contains(&h) {
        return Err(format!("invalid colour: hue {} is outside 0..360 degrees", Number(h)));
    }
    if let Some((what, x)) = [("saturation", s), ("intensity", i)].into_iter().find(|(_, x)| !(0.0..=1.0).contains(x)) {
        return Err(format!("invalid colour: {what} {} is outside 0..1", Number(x)));
    }
    let rgb = hsi_to_rgb(Hsi { h, s, i });
    const ROUNDING: f64 = 1e-9;
    if rgb.cmplt(DVec3::splat(-ROUNDING)).any() || rgb.cmpgt(DVec3::splat(1.0 + ROUNDING)).any() {
        return Err(format!("invalid colour: hsi {:?} gives rgb {:?}, outside 0..1", [h, s, i], rgb.to_array()));
    }
    Ok(rgb.clamp(DVec3::ZERO, DVec3::ONE))
}

impl<'de> Deserialize<'de> for ColorSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_any(ColorVisitor)
    }
}

/// Reads any of [`COLOR_FORMS`]; every refusal lists them or names the bad value.
struct ColorVisitor;

impl<'de> Visitor<'de> for ColorVisitor {
    type Value = ColorSpec;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "a colour: {COLOR_FORMS}")
    }

    fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<ColorSpec, A::Error> {
        ColorSpec::from_model("rgb", components(seq)?).map_err(de::Error::custom)
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<ColorSpec, A::Error> {
        let forms = || de::Error::custom(format!("invalid colour: a table of one model; a colour is {COLOR_FORMS}"));
        let model: String = map.next_key()?.ok_or_else(forms)?;
        // The model first: a misspelt one is named, whatever its components.
        if !["rgb", "cmy", "hsi"].contains(&model.as_str()) {
            return Err(de::Error::custom(unknown_model(&model)));
        }
        let Components(c) = map.next_value()?;
        if map.next_key::<IgnoredAny>()?.is_some() {
            return Err(forms());
        }
        ColorSpec::from_model(&model, c).map_err(de::Error::custom)
    }

    fn visit_str<E: de::Error>(self, text: &str) -> Result<ColorSpec, E> {
        ColorSpec::from_hex(text).map_err(E::custom)
    }
}

/// Three numbers of a colour model.
struct Components([f64; 3]);

impl<'de> Deserialize<'de> for Components {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Three;
        impl<'de> Visitor<'de> for Three {
            type Value = Components;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "three numbers; a colour is {COLOR_FORMS}")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> Result<Components, A::Error> {
                components(seq).map(Components)
            }
        }
        d.deserialize_seq(Three)
    }
}

/// Exactly three numbers from `seq`; the error counts what was there.
fn components<'de, A: SeqAccess<'de>>(mut seq: A) -> Result<[f64; 3], A::Error> {
    let mut c = [0.0; 3];
    let mut n = 0usize;
    while n < 3 {
        match seq.next_element::<f64>()? {
            Some(x) => c[n] = x,
            None => break,
        }
        n += 1;
    }
    while seq.next_element::<IgnoredAny>()?.is_some() {
        n += 1;
    }
    if n != 3 {
        return Err(de::Error::custom(format!("invalid colour: {n} components, not 3; a colour is {COLOR_FORMS}")));
    }
    Ok(c)
}
