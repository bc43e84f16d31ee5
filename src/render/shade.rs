//! The shading stage: Phong lighting with hard shadows, the same for every
//! visibility method.
//!
//! `I = ka Ia C + sum_i [not shadowed] Ii (kd C cos(alpha_i) + ks cos^n(theta_i))`, with
//! `cos(alpha) = N . L`, `R = 2 N (N . L) - L`, `cos(theta) = R . V` (seed: lighting).
//! Shadow rays leave the surface a thousandth of a voxel along the normal.

use glam::DVec3;

use super::scene::{Scene, SceneHit};

/// Linear RGB seen along the ray `origin + t dir` (unit `dir`) that hit `sh`.
#[must_use]
pub fn shade(scene: &Scene, origin: DVec3, dir: DVec3, sh: &SceneHit, shadows: bool) -> DVec3 {
    let solid = &scene.solids[sh.solid];
    let m = &solid.material;
    let n = sh.hit.normal(dir);
    let n = if n == DVec3::ZERO { -dir } else { n };
    let p = origin + dir * sh.hit.t;
    let v = -dir;
    let lift = p + n * (1e-3 * solid.tree.domain().voxel_size());
    let mut color = scene.ambient * m.color * m.ka;
    for light in &scene.lights {
        let (l, distance) = light.towards(p);
        let cos_alpha = n.dot(l);
        if cos_alpha <= 0.0 {
            continue;
        }
        if shadows && scene.occluded(lift, l, distance) {
            continue;
        }
        let r = n * (2.0 * cos_alpha) - l;
        let cos_theta = r.dot(v).max(0.0);
        color += light.color() * (m.color * (m.kd * cos_alpha) + DVec3::splat(m.ks * cos_theta.powf(m.shininess)));
    }
    color
}

/// sRGB encoding of a linear value in `[0, 1]` (IEC 61966-2-1), to 8 bits.
#[must_use]
pub fn to_srgb8(linear: f64) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}
