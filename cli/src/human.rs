//! How numbers and names read in human output: coordinates without the float noise of
//! their last bits (`0.02`, not `0.020000000000000018`), the names a user types
//! (`front-to-back`, not `FrontToBack`). `--json` keeps every bit.

use glam::DVec3;
use octsolid::render::Method;
use octsolid::shape::Axis;

/// `x` to 12 significant digits, trailing zeros dropped; scientific notation outside
/// `1e-5..1e12`.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{}", if x == 0.0 { 0.0 } else { x });
    }
    if !(1e-5..1e12).contains(&x.abs()) {
        let s = format!("{x:.11e}");
        let (mantissa, exponent) = s.split_once('e').expect("scientific notation");
        let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
        return format!("{mantissa}e{exponent}");
    }
    let digits = (11 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.digits$}");
    let s = if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.') } else { &s };
    if s == "-0" { "0".to_owned() } else { s.to_owned() }
}

/// A point as `[x, y, z]` of [`num`]s.
pub(crate) fn point(p: impl Into<DVec3>) -> String {
    let p = p.into();
    format!("[{}, {}, {}]", num(p.x), num(p.y), num(p.z))
}

/// A visibility method by its `--method` name.
pub(crate) fn method(m: Method) -> &'static str {
    match m {
        Method::Trace => "trace",
        Method::FrontToBack => "front-to-back",
        Method::Painter => "painter",
        Method::ZBuffer => "zbuffer",
        Method::ScanLine => "scanline",
    }
}

/// An axis by its name.
pub(crate) fn axis(a: Axis) -> &'static str {
    match a {
        Axis::X => "x",
        Axis::Y => "y",
        Axis::Z => "z",
    }
}

/// `n` and the noun, plural unless `n` is 1: `1 solid`, `3 solids`, `1 mesh`, `2 meshes`.
pub(crate) fn count(n: usize, one: &str, many: &str) -> String {
    if n == 1 { format!("1 {one}") } else { format!("{n} {many}") }
}

#[cfg(test)]
mod tests {
    use super::num;

    #[test]
    fn numbers_lose_their_float_noise_and_keep_their_value() {
        for (x, s) in [
            (0.020000000000000018, "0.02"),
            (-0.020000000000000018, "-0.02"),
            (0.9993750000000001, "0.999375"),
            (80.0, "80"),
            (1.0 / 3.0, "0.333333333333"),
            (12345.678, "12345.678"),
            (0.0, "0"),
            (-0.0, "0"),
            (2.5e-7, "2.5e-7"),
            (3e14, "3e14"),
        ] {
            assert_eq!(num(x), s, "{x:?}");
        }
    }
}
