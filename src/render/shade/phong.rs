//! The local term of the Phong model, written once for voxel solids and for polygons
//! (seed: lighting):
//!
//! `I_c = ka Ia C + sum_i f_i Ii (kd C cos(alpha_i) + ks cos^n(theta_i))`, with
//! `cos(alpha) = N . L`, `R = 2 N (N . L) - L`, `cos(theta) = R . V`, `C` the
//! material's colour or texture at the point, and `f_i` the fraction of light `i`
//! reaching the point: 1 without shadows, else the transmittance of what lies between
//! (`slivers::transmittance`). Shadow rays leave the surface a thousandth of a voxel
//! along the face's axis normal; with smooth normals, a thousandth of a voxel along
//! the shading normal from the smooth surface's point ([`SurfacePoint::texture_at`]),
//! and walk their own solid from clear of its voxel staircase (which would shadow
//! the surface at grazing light), every other solid from the surface.

use glam::DVec3;

use super::normals::SurfacePoint;
use super::slivers;
use crate::render::scene::{Light, Material, Scene};

/// The Phong model at a point of normal `n` seen along `v` (both unit, from the
/// point), of colour `c` in the material `m`, under the ambient light `ambient` and
/// `lights`; `passed(light)` is the fraction `f_i` of a light that reaches the point,
/// asked only of lights in front of the surface (`N . L > 0`).
pub(crate) fn phong(
    m: &Material,
    c: DVec3,
    ambient: DVec3,
    (p, n, v): (DVec3, DVec3, DVec3),
    lights: &[Light],
    mut passed: impl FnMut(&Light) -> f64,
) -> DVec3 {
    let mut color = ambient * c * m.ka;
    for light in lights {
        let l = light.direction_from(p);
        let cos_alpha = n.dot(l);
        if cos_alpha <= 0.0 {
            continue;
        }
        let passed = passed(light);
        if passed == 0.0 {
            continue;
        }
        color += light.color() * passed * (c * (m.kd * cos_alpha) + DVec3::splat(specular(m, n, l, v, cos_alpha)));
    }
    color
}

/// The specular term `ks cos^n(theta)` of a light in the direction `l` at a point of
/// normal `n` seen along `v`, `cos_alpha = N . L`. Without a specular coefficient
/// (`ks` zero, as for matte floors) `ks` itself: `ks cos^n` is that zero, with its sign,
/// for every finite `cos^n`, so skipping `powf` changes no bit.
fn specular(m: &Material, n: DVec3, l: DVec3, v: DVec3, cos_alpha: f64) -> f64 {
    if m.ks == 0.0 {
        return m.ks;
    }
    let r = n * (2.0 * cos_alpha) - l;
    let cos_theta = r.dot(v).max(0.0);
    if cos_theta == 0.0 && m.shininess > 0.0 {
        // `0^n` is `+0` for every `n > 0`: the same bits without `powf`.
        return m.ks * 0.0;
    }
    m.ks * cos_theta.powf(m.shininess)
}

/// The local term at `s`, and the shadow rays cast (when `shadows`): the scene's
/// precomputed illumination where it has one (radiosity: emitted plus diffusely
/// reflected light), else the Phong term (see the module doc) plus the material's
/// emission.
#[must_use]
pub fn local(scene: &Scene, s: &SurfacePoint, shadows: bool) -> (DVec3, u64) {
    if let Some(light) = scene.illumination.as_ref().and_then(|i| i.radiance(s.solid, s.p, s.geometric)) {
        return (light, 0);
    }
    let solid = &scene.solids[s.solid];
    let m = &solid.material;
    let (p, geometric, n) = (s.p, s.geometric, s.normal);
    // From a thousandth of a voxel off the surface; with smooth normals its own octree
    // from clear of its staircase.
    let h = solid.tree.domain().voxel_size();
    let (start, lift) = match s.smooth {
        Some(_) => (s.texture_at + n * (1e-3 * h), n * slivers::clear_of_staircase(h, s.on_shape)),
        None => (p + geometric * (1e-3 * h), DVec3::ZERO),
    };
    let mut rays = 0;
    let color = phong(m, m.color_at(s.texture_at), scene.ambient, (p, n, -s.dir), &scene.lights, |light| {
        if !shadows {
            return 1.0;
        }
        rays += 1;
        slivers::transmittance(scene, s.solid, &light.shadow_ray(start), lift)
    });
    (color + m.emission, rays)
}
