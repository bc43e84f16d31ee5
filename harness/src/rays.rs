//! The ray sets every contender traces: the same rays, in the same order, for all.
//!
//! - **Primary** (coherent): one ray a pixel through the centre of each pixel of a
//!   square `size x size` image from a camera framing the solid ([`Camera::frame`]).
//! - **Shadow**: from each primary hit point (found by the octree, the reference) towards a
//!   point light far above the scene, `t_max` = the distance to the light. The origin is
//!   lifted off the surface by `1e-3` voxel back along the primary ray, so it lies outside
//!   the solid for every contender.
//! - **Random** (incoherent): origins uniform on the sphere around the solid's box (radius
//!   1.5 times its half diagonal, so outside the solid), each aimed at a point uniform in
//!   the box; seeded, so the set is the same on every run.

use glam::DVec3;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;

use octsolid::Aabb;
use octsolid::render::{Camera, Traversal};
use octsolid::{Ray, RayCast};

/// What a ray set asks and how its rays are spread.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum RayKind {
    /// Camera rays, one a pixel: coherent; closest hit.
    Primary,
    /// From primary hits to a light: any hit before the light.
    Shadow,
    /// Random origins and directions through the scene's box: incoherent; closest hit.
    Random,
    /// Cosine-weighted rays leaving primary hits (issue 41's set,
    /// [`crate::secondary_rays()`]): incoherent; closest hit.
    Bounce,
}

impl RayKind {
    /// The kinds of the matrix, in report order (the bounce rays and the shadow rays
    /// from primary hits are [`crate::secondary_rays()`]'s, measured in their own section).
    pub const ALL: [RayKind; 3] = [RayKind::Primary, RayKind::Shadow, RayKind::Random];

    /// Lower-case name, e.g. `primary`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Primary => "primary",
            RayKind::Shadow => "shadow",
            RayKind::Random => "random",
            RayKind::Bounce => "bounce",
        }
    }

    /// Whether the query is "any hit before `t_max`" (shadow) rather than the closest hit.
    #[must_use]
    pub fn any_hit(self) -> bool {
        self == RayKind::Shadow
    }
}

/// Rays of one kind.
#[derive(Clone, Debug, PartialEq)]
pub struct RaySet {
    /// Their kind.
    pub kind: RayKind,
    /// The rays.
    pub rays: Vec<Ray>,
}

/// Primary rays of a `size x size` image of `bounds` seen from `view` with `up`,
/// row-major from the top left.
#[must_use]
pub fn primary_rays(bounds: &Aabb, view: DVec3, up: DVec3, size: u32) -> RaySet {
    let camera = Camera::frame(bounds, view, up, 1.0);
    let n = f64::from(size);
    let rays = (0..size * size)
        .map(|i| {
            let (x, y) = (f64::from(i % size) + 0.5, f64::from(i / size) + 0.5);
            camera.ray(2.0 * x / n - 1.0, 1.0 - 2.0 * y / n, 1.0)
        })
        .collect();
    RaySet { kind: RayKind::Primary, rays }
}

/// The light of the shadow rays: far above and to the side of `bounds`,
/// `center + (2, 3, 4) * diagonal`.
#[must_use]
pub fn light_position(bounds: &Aabb) -> DVec3 {
    bounds.center() + DVec3::new(2.0, 3.0, 4.0) * bounds.size().length()
}

/// Shadow rays from the points where `primary` rays hit the octree, towards `light`.
#[must_use]
pub fn shadow_rays(octree: &Traversal, primary: &RaySet, light: DVec3) -> RaySet {
    let lift = 1e-3 * octree.domain().voxel_size();
    let rays = primary
        .rays
        .par_iter()
        .filter_map(|r| {
            let hit = octree.hit(r)?;
            let origin = r.origin + r.dir * (hit.t - lift);
            let to = light - origin;
            Some(Ray { origin, dir: to.normalize(), t_max: to.length() })
        })
        .collect();
    RaySet { kind: RayKind::Shadow, rays }
}

/// `count` random rays through `bounds` from the sphere around it, seeded by `seed`.
#[must_use]
pub fn random_rays(bounds: &Aabb, count: usize, seed: u64) -> RaySet {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let center = bounds.center();
    let radius = 1.5 * 0.5 * bounds.size().length();
    let rays = (0..count)
        .map(|_| {
            // A uniform point on the unit sphere: z uniform in [-1, 1], angle uniform.
            let z: f64 = rng.random_range(-1.0..1.0);
            let phi: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            let s = (1.0 - z * z).sqrt();
            let origin = center + DVec3::new(s * phi.cos(), s * phi.sin(), z) * radius;
            let target = bounds.min + bounds.size() * DVec3::new(rng.random(), rng.random(), rng.random());
            Ray { origin, dir: (target - origin).normalize(), t_max: f64::INFINITY }
        })
        .collect();
    RaySet { kind: RayKind::Random, rays }
}
