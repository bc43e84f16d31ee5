//! Whitted ray tracing: the local term plus mirror-reflected and refracted light,
//! traced recursively (seed: the Whitted model `I = I_c + k_s I_s + k_t I_t`).
//!
//! At a hit of a material with reflectance `kr` and transmittance `kt`:
//! `I = (1 - kr - kt) I_c + kr I(reflected ray) + kt I(transmitted ray)`, so a pixel
//! never gets more light than the brightest local term or background it sees
//! (`kr + kt <= 1`). The transmitted ray refracts into the solid (Snell, index `ior`
//! from 1), walks to where it leaves ([`SceneSolid::exit`]), refracts out, and goes on;
//! on total internal reflection it reflects inside and walks again. Limits: at most
//! `max_depth` secondary rays in a chain, and a ray whose weight in the pixel falls
//! below `cutoff` is not traced (its light is dropped: black). Rays start a thousandth
//! of a voxel off the voxel face, on the side of the face they leave from.
//! Simplification: a ray inside a transparent solid sees only that solid (transparent
//! solids should not touch others).
//!
//! Smooth normals on a voxel staircase: directions follow the smooth normal, even where
//! that sends a ray back through the voxel face it starts on. The staircase then shows
//! slivers (voxels outside the smooth surface: a ray meets one where the smooth normal
//! says it is leaving, `super::slivers`; a ray that starts inside one is the same case)
//! and notches (empty voxels inside it: a ray inside the solid leaves into one where
//! the smooth normal says it is entering); rays pass both as if the smooth surface were
//! the solid's, up to `MAX_SLIVERS` (256) a sample, without using up the recursion
//! depth.

use std::cell::Cell;

use glam::DVec3;

use super::ShadeOptions;
use super::normals::{SurfacePoint, smooth_at};
use super::optics::{reflect, refract};
use super::phong::local;
use super::slivers::{self, MAX_SLIVERS};
use crate::ray::{Ray, RayCast};
use crate::render::scene::{Cast, Scene, SceneHit, SceneSolid};
use crate::render::trace::Hit;

/// The light seen along `ray` (unit direction) whose first hit is `sh`, and the rays
/// cast to find it after the primary one (secondary and shadow rays).
#[must_use]
pub fn radiance(scene: &Scene, ray: &Ray, sh: &SceneHit, options: &ShadeOptions) -> (DVec3, u64) {
    let s = SurfacePoint::new(scene, ray, sh, options.normals);
    let tracer = Tracer { scene, options, rays: Cell::new(0), slivers: Cell::new(0) };
    let light = tracer.at_surface(&s, 0, 1.0);
    (light, tracer.rays.get())
}

/// One sample's recursive tracer.
struct Tracer<'a> {
    scene: &'a Scene,
    options: &'a ShadeOptions,
    /// Rays cast so far.
    rays: Cell<u64>,
    /// Staircase slivers passed so far.
    slivers: Cell<u32>,
}

impl Tracer<'_> {
    /// Light along a secondary ray, `depth` rays deep, `weight` its share of the pixel.
    fn trace(&self, origin: DVec3, dir: DVec3, depth: u32, weight: f64) -> DVec3 {
        self.count(1);
        match self.scene.hit_as(&Ray::new(origin, dir), Cast::Bounce) {
            // The origin lies inside a solid (a ray started at a voxel's edge or corner,
            // or under a sliver of the staircase): light passes on through a
            // transparent one and out of a sliver; an opaque one shows nothing.
            Some(sh) if sh.hit.axis.is_none() => {
                let solid = &self.scene.solids[sh.solid];
                if solid.material.transmittance > 0.0 && depth < self.options.max_depth {
                    self.through(solid, origin, dir, depth + 1, weight)
                } else if self.slivers.get() < MAX_SLIVERS
                    && slivers::is_sliver(solid, origin, dir, self.options.normals)
                {
                    self.slivers.set(self.slivers.get() + 1);
                    self.pass_through(solid, origin, dir, depth, weight)
                } else {
                    DVec3::ZERO
                }
            }
            Some(sh) => self.at_surface(
                &SurfacePoint::new(self.scene, &Ray::new(origin, dir), &sh, self.options.normals),
                depth,
                weight,
            ),
            None => self.scene.background,
        }
    }

    /// Light along a ray that arrives at the voxel face `s`.
    fn at_surface(&self, s: &SurfacePoint, depth: u32, weight: f64) -> DVec3 {
        if s.smooth.is_some_and(|n| n.dot(s.dir) > 0.0) && self.slivers.get() < MAX_SLIVERS {
            // A sliver of the voxel staircase that the smooth surface leaves outside
            // (at silhouettes, and next to where a grazing ray left the solid): no
            // surface, the ray goes on.
            self.slivers.set(self.slivers.get() + 1);
            let solid = &self.scene.solids[s.solid];
            return self.pass_through(solid, s.p - s.geometric * self.eps(solid), s.dir, depth, weight);
        }
        self.at_hit(s, depth, weight)
    }

    /// Light along a ray that arrives at the surface point `s`.
    fn at_hit(&self, s: &SurfacePoint, depth: u32, weight: f64) -> DVec3 {
        let solid = &self.scene.solids[s.solid];
        let m = &solid.material;
        let (kr, kt) = (m.reflectance, m.transmittance);
        let dir = s.dir;
        let (local, shadow_rays) = local(self.scene, s, self.options.shadows);
        self.count(shadow_rays);
        let mut color = local * (1.0 - kr - kt);
        if depth >= self.options.max_depth || kr + kt == 0.0 {
            return color;
        }
        let (p, geometric, n) = (s.p, s.geometric, s.normal);
        let eps = self.eps(solid);
        // Light that does not pass (total internal reflection) is reflected.
        let mut mirrored = kr;
        if kt * weight > self.options.cutoff {
            match refract(dir, n, 1.0, m.ior) {
                Some(t) => color += self.through(solid, p - geometric * eps, t, depth + 1, weight * kt) * kt,
                None => mirrored += kt,
            }
        }
        if mirrored * weight > self.options.cutoff {
            let r = reflect(dir, n);
            color += self.trace(p + geometric * eps, r, depth + 1, weight * mirrored) * mirrored;
        }
        color
    }

    fn count(&self, rays: u64) {
        self.rays.set(self.rays.get() + rays);
    }

    /// Rays start this far off a surface of `solid`.
    fn eps(&self, solid: &SceneSolid) -> f64 {
        slivers::eps(solid)
    }

    /// Light along a ray that starts inside `solid` and crosses it without refraction.
    fn pass_through(&self, solid: &SceneSolid, origin: DVec3, dir: DVec3, depth: u32, weight: f64) -> DVec3 {
        self.count(1);
        self.trace(slivers::past(solid, origin, dir), dir, depth, weight)
    }

    /// Light carried by a ray that travels inside `solid` from `origin`.
    fn through(&self, solid: &SceneSolid, mut origin: DVec3, mut dir: DVec3, mut depth: u32, weight: f64) -> DVec3 {
        let eps = self.eps(solid);
        while depth <= self.options.max_depth {
            self.count(1);
            let Some(exit) = solid.exit(&Ray::new(origin, dir)) else {
                // Leaves through the domain's boundary: no surface there.
                return self.trace(origin, dir, depth, weight);
            };
            if exit.axis.is_none() {
                // The origin is already outside (it started at a voxel's edge or corner).
                return self.trace(origin, dir, depth + 1, weight);
            }
            let p = origin + dir * exit.t;
            let (geometric, n, smooth) = outward(solid, &exit, dir, p, self.options);
            if smooth.is_some_and(|n| n.dot(dir) < 0.0) && self.slivers.get() < MAX_SLIVERS {
                // A notch of the staircase inside the smooth surface: no surface, the
                // ray goes on to where it meets the solid again.
                self.slivers.set(self.slivers.get() + 1);
                self.count(1);
                if let Some(back) = solid.walker(Cast::Bounce).hit(&Ray::new(p + geometric * eps, dir)) {
                    let q = p + geometric * eps + dir * back.t;
                    origin = q - back.normal(dir) * eps;
                    continue;
                }
            }
            match refract(dir, n, solid.material.ior, 1.0) {
                Some(t) => return self.trace(p + geometric * eps, t, depth, weight),
                None => {
                    dir = reflect(dir, n);
                    origin = p - geometric * eps;
                    depth += 1;
                }
            }
        }
        DVec3::ZERO
    }
}

/// The outward geometric and shading normals where a ray inside `solid` leaves it at
/// `exit` (a hit of the complement through a face), both facing along the ray, and
/// the raw smooth estimate (with smooth normals).
fn outward(
    solid: &SceneSolid,
    exit: &Hit,
    dir: DVec3,
    p: DVec3,
    options: &ShadeOptions,
) -> (DVec3, DVec3, Option<DVec3>) {
    let geometric = -exit.normal(dir);
    let (smooth, _) = smooth_at(solid, p, options.normals);
    let n = smooth.filter(|n| n.dot(dir) > 0.0).unwrap_or(geometric);
    (geometric, solid.material.bump.map_or(n, |b| b.perturb(p, n)), smooth)
}
