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
//!
//! The encoding is that formula's value in floating point ([`srgb8_formula`]), looked
//! up instead of computed (a `powf` a channel was a third of a fast frame's work):
//! 8 bits take 255 steps, at the thresholds `t_1 < ... < t_255`, `t_k` the least
//! `f64` the formula gives `k` or more (found once by bisection over the bit patterns
//! of `[0, 1]`, which order as the values do). The table cuts `[0, 1]` into
//! [`BUCKETS`] equal buckets, each with the code below its threshold window and that
//! window (`t_k (1 +- WINDOW)`), if one meets it: thresholds lie at least `1 / (255 *
//! 12.92)` apart, more than a bucket and two windows, so a bucket meets at most one. A value
//! below its bucket's window has the bucket's code, one at or above it the next; one
//! inside it is given to the formula. Why this is the formula's value everywhere: the
//! formula is a chain of monotone roundings (a product by a positive constant, a
//! subtraction, a truncation) around `powf`, whose error (well under an ulp) could
//! make it step back only between doubles a few ulps apart; [`WINDOW`], relatively
//! 1e-12, is thousands of ulps, so outside the windows the formula is monotone and
//! its codes are those the thresholds count. The unit tests check the table against
//! the formula around every threshold and bucket edge and at random values.

use std::sync::LazyLock;

use glam::DVec3;
use image::Rgb;

use crate::error::{Error, Result};

/// Largest exposure in stops either way: `2^64` is far past any radiance a scene can
/// hold, and keeps the scale a normal finite number.
pub const MAX_EXPOSURE_STOPS: f64 = 64.0;

/// Equal buckets of `[0, 1)` in the table (a power of two, so `c * BUCKETS` is exact);
/// `1.0` itself has a bucket of its own after them.
const BUCKETS: usize = 4096;
/// Half-width, relative to the threshold, of the window around a threshold where the
/// formula decides.
const WINDOW: f64 = 1e-12;

/// sRGB encoding of a linear value `c` in `[0, 1]` (clamped; NaN gives 0), to 8 bits:
/// `s = 12.92 c` for `c <= 0.0031308`, else `1.055 c^(1/2.4) - 0.055`, then
/// `(255 s + 0.5)` truncated, as computed in `f64` but looked up in a table.
#[must_use]
pub fn to_srgb8(linear: f64) -> u8 {
    encode(&SRGB8, linear)
}

/// [`to_srgb8`] by the table `table` ([`SRGB8`], fetched once for several channels).
#[inline]
fn encode(table: &[Bucket], linear: f64) -> u8 {
    // Clamped to [0, 1], NaN to 0 (the formula's code for both).
    let c = if linear >= 0.0 { linear.min(1.0) } else { 0.0 };
    // The bucket `floor(c * BUCKETS)` (exact: a power of two; at most BUCKETS).
    let bucket = &table[(c * BUCKETS as f64) as u32 as usize];
    if c < bucket.below {
        bucket.code
    } else if c >= bucket.above {
        bucket.code + 1
    } else {
        srgb8_formula(c)
    }
}

/// sRGB encoding by the formula of the module doc, to 8 bits (NaN gives 0): the
/// definition [`to_srgb8`] looks up.
fn srgb8_formula(linear: f64) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}

/// One bucket of [`SRGB8`]: the code of the values below the threshold window that
/// meets the bucket (all of the bucket's when none does: the window is then
/// `[inf, inf)`), and that window.
#[derive(Clone, Copy, Debug)]
struct Bucket {
    code: u8,
    below: f64,
    above: f64,
}

/// The encoding's table: [`BUCKETS`] buckets of `[0, 1)` and one for `1.0`.
static SRGB8: LazyLock<Vec<Bucket>> = LazyLock::new(|| {
    let windows: Vec<(f64, f64)> = thresholds().iter().map(|t| (t * (1.0 - WINDOW), t * (1.0 + WINDOW))).collect();
    (0..=BUCKETS)
        .map(|i| {
            let (start, end) = (i as f64 / BUCKETS as f64, (i + 1) as f64 / BUCKETS as f64);
            // Codes whose window ends at or before the bucket.
            let code = windows.iter().filter(|&&(_, above)| above <= start).count() as u8;
            match windows.iter().find(|&&(below, above)| below < end && above > start) {
                Some(&(below, above)) => Bucket { code, below, above },
                None => Bucket { code, below: f64::INFINITY, above: f64::INFINITY },
            }
        })
        .collect()
});

/// `t_k` for `k = 1..=255`: the least value in `[0, 1]` the formula encodes as `k` or
/// more, by bisection over the bit patterns (positive doubles order as their bits).
fn thresholds() -> Vec<f64> {
    (1..=255u8)
        .map(|k| {
            // Invariant: formula(lo) < k <= formula(hi).
            let (mut lo, mut hi) = (0.0f64.to_bits(), 1.0f64.to_bits());
            while hi - lo > 1 {
                let mid = lo + (hi - lo) / 2;
                if srgb8_formula(f64::from_bits(mid)) >= k {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            f64::from_bits(hi)
        })
        .collect()
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
#[inline]
pub fn resolve(sum: DVec3, count: u32, scale: f64) -> DVec3 {
    sum / f64::from(count) * scale
}

/// A linear colour's 8-bit sRGB pixel ([`to_srgb8`] of each channel, the table
/// fetched once).
#[must_use]
#[inline]
pub fn srgb8_pixel(c: DVec3) -> Rgb<u8> {
    let table = &*SRGB8;
    Rgb([encode(table, c.x), encode(table, c.y), encode(table, c.z)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    /// The doubles `n` steps either side of `x` (bit patterns of positive doubles).
    fn around(x: f64, n: u64) -> impl Iterator<Item = f64> {
        let bits = x.to_bits();
        (bits.saturating_sub(n)..=bits + n).map(f64::from_bits)
    }

    #[test]
    fn thresholds_step_once_and_lie_more_than_a_bucket_apart() {
        let t = thresholds();
        for (k, &tk) in (1..=255u8).zip(&t) {
            assert_eq!(srgb8_formula(tk), k);
            assert_eq!(srgb8_formula(f64::from_bits(tk.to_bits() - 1)), k - 1);
        }
        // The closest windows' gap is more than a bucket: a bucket meets one at most.
        let gap = t.windows(2).map(|w| w[1] * (1.0 - WINDOW) - w[0] * (1.0 + WINDOW)).fold(f64::INFINITY, f64::min);
        assert!(gap > 1.0 / BUCKETS as f64, "closest windows {gap} apart");
    }

    #[test]
    fn the_table_gives_the_formulas_code() {
        let check = |x: f64| assert_eq!(to_srgb8(x), srgb8_formula(x), "at {x:e} ({:#x})", x.to_bits());
        for t in thresholds() {
            // Around the threshold, the window's edges, and just past them.
            for x in [t, t * (1.0 - WINDOW), t * (1.0 + WINDOW), t * (1.0 - 2.0 * WINDOW), t * (1.0 + 2.0 * WINDOW)] {
                around(x, 300).for_each(check);
            }
        }
        for i in 0..=BUCKETS {
            around(i as f64 / BUCKETS as f64, 50).for_each(check);
        }
        let mut rng = Rng(20);
        for _ in 0..1_000_000 {
            check(rng.unit());
            check(rng.unit() * 0.01);
            // Any double of [0, 1], small ones as likely as large.
            check(f64::from_bits(rng.below(1.0f64.to_bits() + 1)));
        }
        let specials = [0.0, -0.0, f64::MIN_POSITIVE, 5e-324, 1.0, 1.5, -1e-300, -3.0, 1e300, f64::INFINITY];
        for x in specials.into_iter().chain([f64::NEG_INFINITY, f64::NAN, 0.003_130_8]) {
            check(x);
        }
        assert_eq!(to_srgb8(f64::NAN), 0);
    }
}
