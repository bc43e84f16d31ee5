//! Rays and the one query interface of everything a ray can hit.
//!
//! A [`Ray`] is `origin + t dir` for `0 <= t < t_max`; `t` is in the ray's own
//! parameter, a distance when `dir` is a unit vector (every ray octsolid makes has a
//! unit direction, except rays already moved into a domain's voxel units). A
//! [`RayCast`] answers the two questions of pbrt's `Intersect` and `IntersectP`: the
//! closest hit before `t_max`, and whether there is any (shadow rays). The traversal
//! octree, scenes and the benchmark harness's BVH contenders implement it.

use glam::DVec3;

/// A ray `origin + t dir`, `0 <= t < t_max`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point.
    pub origin: DVec3,
    /// Direction (a unit vector wherever `t` is read as a distance).
    pub dir: DVec3,
    /// Hits at or beyond this parameter do not count (`f64::INFINITY`: none beyond).
    pub t_max: f64,
}

impl Ray {
    /// The ray from `origin` along `dir`, unbounded.
    #[must_use]
    pub const fn new(origin: DVec3, dir: DVec3) -> Self {
        Ray { origin, dir, t_max: f64::INFINITY }
    }

    /// The ray from `origin` along `dir` up to (not including) `t_max`.
    #[must_use]
    pub const fn segment(origin: DVec3, dir: DVec3, t_max: f64) -> Self {
        Ray { origin, dir, t_max }
    }

    /// This ray with its far end at `t_max`.
    #[must_use]
    pub const fn until(self, t_max: f64) -> Self {
        Ray { t_max, ..self }
    }

    /// The point at parameter `t`: `origin + dir t`.
    #[must_use]
    pub fn at(&self, t: f64) -> DVec3 {
        self.origin + self.dir * t
    }
}

/// Anything a ray can hit: the closest hit, and any hit.
pub trait RayCast {
    /// What a hit reports.
    type Hit;

    /// The closest hit with `0 <= t < ray.t_max`, if any.
    fn hit(&self, ray: &Ray) -> Option<Self::Hit>;

    /// Whether anything lies on the ray before `ray.t_max` (a shadow ray's question;
    /// implementations answer it without working out the hit where they can).
    fn occluded(&self, ray: &Ray) -> bool {
        self.hit(ray).is_some()
    }
}
