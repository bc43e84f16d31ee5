//! The one interface every ray-casting structure of the benchmark answers: built from
//! its input, then asked for the closest hit or any hit of each ray (the library's
//! [`RayCast`]).
//!
//! All contenders answer the same questions about the same rays: the closest hit
//! (distance along the unit ray and the surface normal facing the ray) for primary and
//! random rays, and "anything before `t_max`?" for shadow rays.

use glam::DVec3;
use rayon::prelude::*;

use octsolid::{Ray, RayCast};

use super::rays::RaySet;

/// A closest hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Distance along the ray (the ray's direction is a unit vector).
    pub t: f64,
    /// Unit normal of the surface hit, facing the ray (`normal . dir <= 0`).
    pub normal: DVec3,
}

/// A ray-casting structure under test: a [`RayCast`] that can be built from its input
/// and says what it costs.
pub trait Contender: RayCast + Send + Sync + Sized {
    /// What it is built from (an octree, a triangle mesh).
    type Input: ?Sized + Sync;

    /// Builds the structure; this is what the benchmark's build time measures.
    fn build(input: &Self::Input) -> Self;

    /// Bytes the structure keeps to answer queries (see each contender for what is counted).
    fn bytes(&self) -> usize;

    /// Number of nodes of the structure (inner nodes of the octree, BVH nodes).
    fn node_count(&self) -> usize;

    /// Its hit as a [`SurfaceHit`] (distance and the normal facing `ray`).
    fn surface(&self, hit: Self::Hit, ray: &Ray) -> SurfaceHit;

    /// The closest hit of `ray` with `t < ray.t_max`, as a [`SurfaceHit`].
    fn closest_hit(&self, ray: &Ray) -> Option<SurfaceHit> {
        self.hit(ray).map(|h| self.surface(h, ray))
    }

    /// Traces a ray set in the current rayon pool (chunks of 256 rays a task) and returns
    /// the number of rays that hit (closest hits, or occluded shadow rays).
    fn trace(&self, rays: &RaySet) -> u64 {
        let any = rays.kind.any_hit();
        rays.rays
            .par_chunks(256)
            .map(|chunk| {
                chunk.iter().filter(|r| if any { self.occluded(r) } else { self.hit(r).is_some() }).count() as u64
            })
            .sum()
    }
}
