//! Issue 41's incoherent ray sets: rays leaving the primary hits of one view of a solid.
//!
//! - **Primary**: one ray a pixel centre of a `size x size` pinhole view, eye
//!   [`EYE`] = (8, 9, 22), looking at the centre of the solid's box, y up, [`FOV_Y`] =
//!   30 degrees (the view of BENCHMARKS.md "Against Embree" and `walk_one`).
//! - Every primary ray the octree's walk hits gives a point `p` on a voxel face with
//!   the face's normal `n` (facing the ray, so out of the solid). The secondary rays
//!   start at `p + 3 sqrt(3) h n`, [`LIFT_DIAGONALS`] = 3 voxel diagonals off the
//!   surface (`h` the voxel edge), far enough that the source mesh, which lies within a
//!   voxel of the voxel surface, is behind the origin for every contender:
//!   - **bounce**: a cosine-weighted direction about `n` (Malley's method: a uniform
//!     point of the unit disc in the tangent plane lifted onto the hemisphere; the
//!     tangent frame is Duff et al.'s branchless orthonormal basis, "Building an
//!     Orthonormal Basis, Revisited", JCGT 2017), closest hit, `t_max` infinite;
//!   - **shadow**: towards the point light [`light_position`] (above and to the side
//!     of the box), any hit, `t_max` the distance to the light.
//!
//! Deterministic: the two uniform numbers of pixel `i`'s bounce ray come from a
//! xoshiro256++ generator seeded with `seed` mixed with `i` (SplitMix64's finalizer),
//! so the set does not depend on the thread count or on which pixels hit. Primary hits
//! are the walk's of today ([`Traversal::hit`]); a new walk must answer the same rays.

use glam::DVec3;
use rand::rngs::Xoshiro256PlusPlus;
use rand::{RngExt, SeedableRng};
use rayon::prelude::*;

use octsolid::Aabb;
use octsolid::render::{Camera, Traversal};
use octsolid::{Ray, RayCast};

use super::rays::{RayKind, RaySet, light_position};

/// The eye of the view.
pub const EYE: DVec3 = DVec3::new(8.0, 9.0, 22.0);

/// Vertical field of view of the view, degrees.
pub const FOV_Y: f64 = 30.0;

/// Voxel diagonals between a primary hit and the origin of its secondary rays.
pub const LIFT_DIAGONALS: f64 = 3.0;

/// The seed of the bounce rays in the report and `walk_one`.
pub const SEED: u64 = 41;

/// The three ray sets of one view, in the same pixel order.
#[derive(Clone, Debug, PartialEq)]
pub struct SecondaryRays {
    /// One ray a pixel, row-major from the top left; closest hit.
    pub primary: RaySet,
    /// Cosine-weighted rays about the normal at each primary hit; closest hit.
    pub bounce: RaySet,
    /// From each primary hit to the light; any hit.
    pub shadow: RaySet,
}

impl SecondaryRays {
    /// The three sets, in report order.
    #[must_use]
    pub fn sets(&self) -> [&RaySet; 3] {
        [&self.primary, &self.bounce, &self.shadow]
    }
}

/// The camera of the view of a solid with box `bounds`.
#[must_use]
pub fn view_camera(bounds: &Aabb) -> Camera {
    Camera::look_at(EYE, bounds.center(), DVec3::Y, FOV_Y)
}

/// One ray a pixel centre of a `size x size` image of `camera`, row-major from the top left.
#[must_use]
pub fn view_rays(camera: &Camera, size: u32) -> Vec<Ray> {
    let n = f64::from(size);
    (0..size * size)
        .map(|i| {
            let (x, y) = (f64::from(i % size) + 0.5, f64::from(i / size) + 0.5);
            camera.ray(2.0 * x / n - 1.0, 1.0 - 2.0 * y / n, 1.0)
        })
        .collect()
}

/// A cosine-weighted unit direction about the unit normal `n` from two uniform numbers
/// in `[0, 1)`: `u1` the squared radius and `u2` the angle of a point of the unit disc.
#[must_use]
pub fn cosine_direction(n: DVec3, u1: f64, u2: f64) -> DVec3 {
    // Duff et al. 2017, listing 3.
    let sign = 1.0f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    let t = DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x);
    let s = DVec3::new(b, sign + n.y * n.y * a, -n.y);
    let r = u1.sqrt();
    let phi = std::f64::consts::TAU * u2;
    (t * (r * phi.cos()) + s * (r * phi.sin()) + n * (1.0 - u1).max(0.0).sqrt()).normalize()
}

/// The generator of pixel `i`'s random numbers.
fn pixel_rng(seed: u64, i: usize) -> Xoshiro256PlusPlus {
    // SplitMix64's finalizer, so neighbouring pixels get unrelated seeds.
    let mut z = seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    Xoshiro256PlusPlus::seed_from_u64(z ^ (z >> 31))
}

/// The ray sets of a `size x size` view of the solid of `octree` (see the
/// module doc), framed by `bounds` (the source mesh's box: the view looks at its
/// centre, the light is placed from it), bounce rays seeded by `seed`. Runs in the
/// current rayon pool.
#[must_use]
pub fn secondary_rays(octree: &Traversal, bounds: &Aabb, size: u32, seed: u64) -> SecondaryRays {
    let lift = LIFT_DIAGONALS * 3f64.sqrt() * octree.domain().voxel_size();
    let light = light_position(bounds);
    let primary = view_rays(&view_camera(bounds), size);
    let pairs: Vec<(Ray, Ray)> = primary
        .par_iter()
        .enumerate()
        .filter_map(|(i, r)| {
            let hit = octree.hit(r)?;
            let n = hit.normal(r.dir);
            if n == DVec3::ZERO {
                return None; // the eye inside the solid: no face to leave
            }
            let origin = r.origin + r.dir * hit.t + n * lift;
            let mut rng = pixel_rng(seed, i);
            let (u1, u2): (f64, f64) = (rng.random(), rng.random());
            let bounce = Ray { origin, dir: cosine_direction(n, u1, u2), t_max: f64::INFINITY };
            let to = light - origin;
            Some((bounce, Ray { origin, dir: to.normalize(), t_max: to.length() }))
        })
        .collect();
    let (bounce, shadow) = pairs.into_iter().unzip();
    SecondaryRays {
        primary: RaySet { kind: RayKind::Primary, rays: primary },
        bounce: RaySet { kind: RayKind::Bounce, rays: bounce },
        shadow: RaySet { kind: RayKind::Shadow, rays: shadow },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
    use octsolid::shape::Sphere;

    /// A ball of radius 0.9 at depth 6 and the rays of a 256x256 view of it (the
    /// ball about 34 pixels across from the eye 25 units away), made in a pool of
    /// `threads` threads.
    fn ball_rays(threads: usize, seed: u64) -> (Traversal, Aabb, SecondaryRays) {
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
        let tree = voxelize(&Sphere::new(DVec3::ZERO, 0.9).unwrap(), domain, &VoxelizeOptions::default()).unwrap();
        let bounds = Aabb::new(DVec3::splat(-0.9), DVec3::splat(0.9));
        let octree = Traversal::new(&tree);
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let rays = pool.install(|| secondary_rays(&octree, &bounds, 256, seed));
        (octree, bounds, rays)
    }

    #[test]
    fn secondary_rays_leave_every_primary_hit_three_diagonals_out() {
        let (octree, bounds, rays) = ball_rays(2, SEED);
        let lift = 3.0 * 3f64.sqrt() * 2.0 / 64.0;
        let light = light_position(&bounds);
        let hits: Vec<(Ray, octsolid::render::Hit)> =
            rays.primary.rays.iter().filter_map(|r| Some((*r, octree.hit(r)?))).collect();
        // A disc about 34 pixels across: some 900 hits, one bounce and one shadow ray each.
        assert!((700..1100).contains(&hits.len()), "{}", hits.len());
        assert_eq!(rays.bounce.rays.len(), hits.len());
        assert_eq!(rays.shadow.rays.len(), hits.len());
        for (((primary, hit), bounce), shadow) in hits.iter().zip(&rays.bounce.rays).zip(&rays.shadow.rays) {
            let p = primary.origin + primary.dir * hit.t;
            let n = hit.normal(primary.dir);
            assert!((bounce.origin - (p + n * lift)).length() < 1e-12);
            assert_eq!(bounce.origin, shadow.origin);
            assert!((bounce.dir.length() - 1.0).abs() < 1e-12 && bounce.dir.dot(n) >= 0.0);
            assert_eq!(bounce.t_max, f64::INFINITY);
            assert!((shadow.origin + shadow.dir * shadow.t_max - light).length() < 1e-9);
            // The origin is outside the ball: lifted along an outward face normal from
            // a surface point at least 0.9 - sqrt(3) h from the centre (the
            // voxelization is within a voxel diagonal of the sphere).
            assert!(p.length() > 0.9 - 3f64.sqrt() * 2.0 / 64.0 && p.dot(n) > 0.0);
            assert!(octree.hit(bounce).is_none_or(|h| h.t > 0.0), "a bounce ray starts inside the solid");
        }
    }

    #[test]
    fn the_sets_are_the_same_on_any_thread_count_and_the_seed_moves_only_bounces() {
        let (_, _, two) = ball_rays(2, SEED);
        let (_, _, one) = ball_rays(1, SEED);
        assert_eq!(one, two);
        let (_, _, other) = ball_rays(2, SEED + 1);
        assert_eq!(other.shadow, two.shadow);
        assert_eq!(other.primary, two.primary);
        let same = other.bounce.rays.iter().zip(&two.bounce.rays).filter(|(a, b)| a.dir == b.dir).count();
        assert_eq!(same, 0);
    }

    #[test]
    fn cosine_directions_have_the_cosine_law_mean() {
        // For a cosine-weighted hemisphere, E[cos] = 2/3 and E[cos^2] = 1/2; every
        // direction is unit and on the normal's side. Checked for normals along and
        // against every axis, and an oblique one.
        let normals = [DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y, DVec3::Z, -DVec3::Z, DVec3::new(1.0, -2.0, 2.0) / 3.0];
        for n in normals {
            let mut rng = pixel_rng(7, 0);
            let count = 200_000;
            let (mut c1, mut c2) = (0.0, 0.0);
            for _ in 0..count {
                let d = cosine_direction(n, rng.random(), rng.random());
                assert!((d.length() - 1.0).abs() < 1e-12);
                let c = d.dot(n);
                assert!(c >= 0.0, "{n} {d}");
                c1 += c;
                c2 += c * c;
            }
            let (m1, m2) = (c1 / f64::from(count), c2 / f64::from(count));
            assert!((m1 - 2.0 / 3.0).abs() < 0.005 && (m2 - 0.5).abs() < 0.005, "{n}: {m1} {m2}");
        }
    }
}
