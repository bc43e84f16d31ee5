//! Textures: colour from an image through a projection, and procedural solid textures.
//!
//! Projections map a surface point `p` to texture coordinates `(u, v)` in `[0, 1)^2`:
//! - planar along an axis: `(u, v) = frac((p_a1 - o_a1) / s, (p_a2 - o_a2) / s)` with
//!   `(a1, a2)` the two other axes in cyclic order;
//! - cylindrical about an axis through `c`: `u = atan2(q_a2, q_a1) / 2pi` (in `[0, 1)`),
//!   `v = frac(q_axis / s)`, with `q = p - c`;
//! - spherical about `c`: `u = atan2(q_a2, q_a1) / 2pi` (longitude), `v = acos(q_axis / |q|)
//!   / pi` (colatitude: 0 at the pole on `+axis`, 1 at the other).
//!
//! Solid textures are functions of the point itself (no seams):
//! - checker: colour `a` where `floor(x/s) + floor(y/s) + floor(z/s)` is even, else `b`;
//! - wood: rings of the distance `r` to an axis, `w = frac(r / s + 0.4 noise(p / s))`,
//!   colour `a` to `b` by `w`;
//! - marble: veins `m = (1 + sin((x / s) * pi + 5 turbulence(p / s))) / 2`, colour `a` to
//!   `b` by `m`, with `turbulence(p) = sum_k |noise(2^k p)| / 2^k` over five octaves.
//!
//! `noise` is Perlin's improved gradient noise (2002) on a fixed permutation, in about
//! `[-1, 1]`, zero at the lattice points.

use glam::DVec3;
use image::RgbImage;

use crate::render::film::resolve::from_srgb8;
use crate::shape::Axis;

/// How a surface point finds its place in an image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Mapping {
    /// Along an axis: the image tiles the plane of the two other axes.
    Planar {
        /// The axis the image is projected along.
        axis: Axis,
        /// A point where a tile's corner lies.
        origin: DVec3,
        /// Edge of one tile.
        scale: f64,
    },
    /// Wrapped once around an axis.
    Cylindrical {
        /// The cylinder's axis direction.
        axis: Axis,
        /// A point on the axis (`v = 0` there).
        center: DVec3,
        /// Length along the axis over which the image repeats.
        scale: f64,
    },
    /// Longitude and colatitude.
    Spherical {
        /// Direction of the pole (`v = 0`).
        axis: Axis,
        /// The sphere's centre.
        center: DVec3,
    },
}

impl Mapping {
    /// Texture coordinates of `p`, in `[0, 1)` (colatitude in `[0, 1]`); see the module doc.
    #[must_use]
    pub fn uv(&self, p: DVec3) -> (f64, f64) {
        let frac = |t: f64| t - t.floor();
        match *self {
            Mapping::Planar { axis, origin, scale } => {
                let (_, [a, b]) = axis.split(p - origin);
                (frac(a / scale), frac(b / scale))
            }
            Mapping::Cylindrical { axis, center, scale } => {
                let (h, [a, b]) = axis.split(p - center);
                (longitude(a, b), frac(h / scale))
            }
            Mapping::Spherical { axis, center } => {
                let q = p - center;
                let (h, [a, b]) = axis.split(q);
                let r = q.length();
                let v = if r > 0.0 { (h / r).clamp(-1.0, 1.0).acos() / std::f64::consts::PI } else { 0.0 };
                (longitude(a, b), v)
            }
        }
    }
}

/// `atan2(b, a) / 2pi` in `[0, 1)`.
fn longitude(a: f64, b: f64) -> f64 {
    let u = b.atan2(a) / std::f64::consts::TAU;
    let u = if u < 0.0 { u + 1.0 } else { u };
    if u >= 1.0 { 0.0 } else { u }
}

/// What gives a surface its colour.
#[derive(Clone, Debug, PartialEq)]
pub enum Texture {
    /// An image placed by a mapping, sampled bilinearly, repeating.
    Image {
        /// The image (sRGB bytes, decoded to linear when sampled).
        texels: std::sync::Arc<RgbImage>,
        /// Where each point finds its texel.
        mapping: Mapping,
    },
    /// A 3D checkerboard.
    Checker {
        /// Edge of one cube.
        size: f64,
        /// Colour of the even cubes (the one holding the origin).
        a: DVec3,
        /// Colour of the odd cubes.
        b: DVec3,
    },
    /// Wood: noisy concentric rings about an axis.
    Wood {
        /// Direction of the trunk.
        axis: Axis,
        /// A point on the trunk's axis.
        center: DVec3,
        /// Distance between rings.
        size: f64,
        /// Colour at the start of a ring.
        a: DVec3,
        /// Colour at its end.
        b: DVec3,
    },
    /// Marble: turbulent veins across x.
    Marble {
        /// Scale of the veins.
        size: f64,
        /// Colour between veins.
        a: DVec3,
        /// Colour of the veins.
        b: DVec3,
    },
}

impl Texture {
    /// The linear RGB colour at the surface point `p`.
    #[must_use]
    pub fn color(&self, p: DVec3) -> DVec3 {
        match self {
            Texture::Image { texels, mapping } => {
                let (u, v) = mapping.uv(p);
                // Pictures stand upright: up the plane's second axis or the cylinder's
                // axis is up the image; the sphere's pole is its top row.
                let down = match mapping {
                    Mapping::Spherical { .. } => v,
                    _ => 1.0 - v,
                };
                bilinear(texels, u, down)
            }
            Texture::Checker { size, a, b } => {
                let c = (p / *size).floor();
                if (c.x + c.y + c.z).rem_euclid(2.0) == 0.0 { *a } else { *b }
            }
            Texture::Wood { axis, center, size, a, b } => {
                let (_, [x, y]) = axis.split(p - *center);
                let ring = x.hypot(y) / size + 0.4 * noise(p / *size);
                a.lerp(*b, ring - ring.floor())
            }
            Texture::Marble { size, a, b } => {
                let q = p / *size;
                let m = 0.5 * (1.0 + (q.x * std::f64::consts::PI + 5.0 * turbulence(q)).sin());
                a.lerp(*b, m)
            }
        }
    }
}

/// Bilinear sample of `image` (sRGB bytes, decoded to linear) at `(u, down)`, `u` the
/// fraction of its width from the left, `down` of its height from the top; the image
/// repeats in both directions.
fn bilinear(image: &RgbImage, u: f64, down: f64) -> DVec3 {
    let (w, h) = (image.width() as i64, image.height() as i64);
    let (x, y) = (u * w as f64 - 0.5, down * h as f64 - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |i: i64, j: i64| {
        let p = image.get_pixel(i.rem_euclid(w) as u32, j.rem_euclid(h) as u32);
        DVec3::new(from_srgb8(p[0]), from_srgb8(p[1]), from_srgb8(p[2]))
    };
    let (i, j) = (x0 as i64, y0 as i64);
    let top = texel(i, j).lerp(texel(i + 1, j), fx);
    let bottom = texel(i, j + 1).lerp(texel(i + 1, j + 1), fx);
    top.lerp(bottom, fy)
}

/// Perlin's improved noise at `p` (see the module doc).
#[must_use]
pub(crate) fn noise(p: DVec3) -> f64 {
    let cell = p.floor();
    let f = p - cell;
    let [x, y, z] = cell.to_array().map(|c| (c.rem_euclid(256.0)) as usize);
    let fade = |t: f64| t * t * t * (t * (t * 6.0 - 15.0) + 10.0);
    let (u, v, w) = (fade(f.x), fade(f.y), fade(f.z));
    let perm = |i: usize| usize::from(PERMUTATION[i & 255]);
    let hash = |i: usize, j: usize, k: usize| perm(perm(perm(i) + j) + k);
    let grad = |h: usize, d: DVec3| {
        // The twelve edge directions of a cube (and four repeats), by the low four bits.
        let h = h & 15;
        let a = if h < 8 { d.x } else { d.y };
        let b = if h < 4 {
            d.y
        } else if h == 12 || h == 14 {
            d.x
        } else {
            d.z
        };
        (if h & 1 == 0 { a } else { -a }) + (if h & 2 == 0 { b } else { -b })
    };
    let corner = |dx: usize, dy: usize, dz: usize| {
        let offset = DVec3::new(dx as f64, dy as f64, dz as f64);
        grad(hash(x + dx, y + dy, z + dz), f - offset)
    };
    let lerp = |t: f64, a: f64, b: f64| a + t * (b - a);
    lerp(
        w,
        lerp(v, lerp(u, corner(0, 0, 0), corner(1, 0, 0)), lerp(u, corner(0, 1, 0), corner(1, 1, 0))),
        lerp(v, lerp(u, corner(0, 0, 1), corner(1, 0, 1)), lerp(u, corner(0, 1, 1), corner(1, 1, 1))),
    )
}

/// `sum_k |noise(2^k p)| / 2^k`, five octaves.
#[must_use]
pub(crate) fn turbulence(p: DVec3) -> f64 {
    (0..5).map(|k| noise(p * f64::from(1 << k)).abs() / f64::from(1 << k)).sum()
}

/// A fixed permutation of 0..=255: the identity shuffled (Fisher-Yates) by a
/// xorshift64 generator from a fixed seed, at compile time.
const PERMUTATION: [u8; 256] = {
    let mut p = [0u8; 256];
    let mut i = 0;
    while i < 256 {
        p[i] = i as u8;
        i += 1;
    }
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut i = 255;
    while i > 0 {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let j = (state % (i as u64 + 1)) as usize;
        let t = p[i];
        p[i] = p[j];
        p[j] = t;
        i -= 1;
    }
    p
};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    #[test]
    fn noise_is_zero_at_lattice_points_and_within_one() {
        let mut rng = Rng(99);
        let mut max_noise: f64 = 0.0;
        for _ in 0..20_000 {
            let p = rng.vec(-50.0, 50.0);
            max_noise = max_noise.max(noise(p).abs());
            assert_eq!(noise(p.floor()), 0.0);
        }
        assert!(max_noise <= 1.0 && max_noise > 0.5, "noise range {max_noise}");
    }
}
