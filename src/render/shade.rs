//! The shading stage, the same for every visibility method: the local Phong term with
//! shadows, on the normal the options choose, and Whitted's reflected and transmitted
//! rays ([`super::whitted`]).
//!
//! Local term (seed: lighting): `I_c = ka Ia C + sum_i f_i Ii (kd C cos(alpha_i) + ks
//! cos^n(theta_i))`, with `cos(alpha) = N . L`, `R = 2 N (N . L) - L`, `cos(theta) =
//! R . V`, `C` the material's colour or texture at the point, and `f_i` the fraction of
//! light `i` reaching the point: 1 without shadows, else the transmittance of what lies
//! between ([`Scene::transmittance`]). Shadow rays leave the surface a thousandth of a
//! voxel along the face's axis normal; with smooth normals, two voxels along the
//! shading normal from the smooth surface's point ([`SurfacePoint::texture_at`]),
//! clear of the voxel staircase (which would shadow it at grazing light).
//!
//! Normals: [`Normals::Axis`] is the entered face's axis normal; [`Normals::Smooth`]
//! the source shape's normal where there is one, else (and always with
//! [`Normals::Octree`]) the octree's occupancy gradient
//! ([`super::normals::smooth_normal`]); a smooth normal falls back to the axis normal
//! where it would face away from the viewer. A material's bump map then
//! tilts it.

use glam::DVec3;

use super::scene::{Scene, SceneHit, SceneSolid};
use super::traverse::Hit;

/// Which normal shades a surface.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Normals {
    /// The entered voxel face's axis normal (exact for the voxel solid).
    #[default]
    Axis,
    /// The source shape's normal where the solid was voxelized from a shape that
    /// knows its surface ([`crate::shape::Shape::surface`]) and the hit lies within
    /// two voxels of that surface; else the octree's estimate.
    Smooth,
    /// Estimated from the octree's occupancy around the hit ([`super::normals`]).
    Octree,
}

impl std::str::FromStr for Normals {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "axis" => Ok(Normals::Axis),
            "smooth" => Ok(Normals::Smooth),
            "octree" => Ok(Normals::Octree),
            other => Err(format!("{other:?} is not axis, smooth or octree")),
        }
    }
}

/// How the shading stage works.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadeOptions {
    /// Trace shadow rays.
    pub shadows: bool,
    /// Which normal shades.
    pub normals: Normals,
    /// Longest chain of reflected and refracted rays after the primary one.
    pub max_depth: u32,
    /// A secondary ray is traced only when its weight in the pixel exceeds this.
    pub cutoff: f64,
}

impl Default for ShadeOptions {
    fn default() -> Self {
        ShadeOptions { shadows: true, normals: Normals::Axis, max_depth: 6, cutoff: 1e-3 }
    }
}

/// The geometric and the shading normal at a hit of the ray direction `dir`, both unit
/// and facing the ray (for a hit with no face, the origin inside: `-dir`), from the
/// raw smooth estimate `smooth` (outward; `None` with axis normals).
#[must_use]
pub fn normals_at(solid: &SceneSolid, hit: &Hit, dir: DVec3, p: DVec3, smooth: Option<DVec3>) -> (DVec3, DVec3) {
    let axis = hit.normal(dir);
    let geometric = if axis == DVec3::ZERO { -dir } else { axis };
    let shading = smooth.filter(|n| n.dot(dir) < 0.0).unwrap_or(geometric);
    let shading = match &solid.material.bump {
        Some(bump) => bump.perturb(p, shading),
        None => shading,
    };
    (geometric, shading)
}

/// A shaded point: where a ray of direction `dir` hit solid `solid`, with the
/// geometric and shading normals of [`normals_at`].
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// Index of the solid.
    pub solid: usize,
    /// The point.
    pub p: DVec3,
    /// Unit direction of the arriving ray.
    pub dir: DVec3,
    /// The face's axis normal, facing the ray.
    pub geometric: DVec3,
    /// The normal that shades.
    pub normal: DVec3,
    /// The smooth estimate of the outward normal, when smooth normals are on.
    pub smooth: Option<DVec3>,
    /// Where the material's texture is looked up ([`SceneSolid::smooth_at`]).
    pub texture_at: DVec3,
}

impl SurfacePoint {
    /// The point where the ray `origin + t dir` (unit `dir`) hits `sh`.
    #[must_use]
    pub fn new(scene: &Scene, origin: DVec3, dir: DVec3, sh: &SceneHit, mode: Normals) -> Self {
        let p = origin + dir * sh.hit.t;
        let solid = &scene.solids[sh.solid];
        let (smooth, texture_at) = solid.smooth_at(p, mode);
        let (geometric, normal) = normals_at(solid, &sh.hit, dir, p, smooth);
        SurfacePoint { solid: sh.solid, p, dir, geometric, normal, smooth, texture_at }
    }
}

/// The local (Phong) term at `s` (see the module doc), and the shadow rays cast.
#[must_use]
pub fn local(scene: &Scene, s: &SurfacePoint, shadows: bool) -> (DVec3, u64) {
    let solid = &scene.solids[s.solid];
    let m = &solid.material;
    let (p, geometric, n) = (s.p, s.geometric, s.normal);
    let v = -s.dir;
    let h = solid.tree.domain().voxel_size();
    // With smooth normals the staircase next to the point would shadow a surface the
    // smooth normal turns to the light: shadow rays start clear of it.
    let start = match s.smooth {
        Some(_) => s.texture_at + n * (2.0 * h),
        None => p + geometric * (1e-3 * h),
    };
    let c = m.color_at(s.texture_at);
    let mut color = scene.ambient * c * m.ka;
    let mut rays = 0;
    for light in &scene.lights {
        let (l, _) = light.towards(p);
        let cos_alpha = n.dot(l);
        if cos_alpha <= 0.0 {
            continue;
        }
        let passed = if shadows {
            rays += 1;
            let (l, distance) = light.towards(start);
            scene.transmittance(start, l, distance)
        } else {
            1.0
        };
        if passed == 0.0 {
            continue;
        }
        let r = n * (2.0 * cos_alpha) - l;
        let cos_theta = r.dot(v).max(0.0);
        color += light.color() * passed * (c * (m.kd * cos_alpha) + DVec3::splat(m.ks * cos_theta.powf(m.shininess)));
    }
    (color, rays)
}

/// sRGB encoding of a linear value in `[0, 1]` (IEC 61966-2-1), to 8 bits.
#[must_use]
pub fn to_srgb8(linear: f64) -> u8 {
    let c = linear.clamp(0.0, 1.0);
    let s = if c <= 0.003_130_8 { 12.92 * c } else { 1.055 * c.powf(1.0 / 2.4) - 0.055 };
    (s * 255.0 + 0.5) as u8
}
