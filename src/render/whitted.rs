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
//! of a voxel off the surface, on the side they travel to. Simplification: a ray inside
//! a transparent solid sees only that solid (transparent solids should not touch
//! others).

use std::cell::Cell;

use glam::DVec3;

use super::optics::{reflect, refract};
use super::scene::{Scene, SceneHit, SceneSolid};
use super::shade::{Normals, ShadeOptions, SurfacePoint, local};
use super::traverse::Hit;

/// The light seen along the ray `origin + t dir` (unit `dir`) whose first hit is `sh`,
/// and the rays cast to find it after the primary one (secondary and shadow rays).
#[must_use]
pub fn radiance(scene: &Scene, origin: DVec3, dir: DVec3, sh: &SceneHit, options: &ShadeOptions) -> (DVec3, u64) {
    let s = SurfacePoint::new(scene, origin, dir, sh, options.normals);
    let tracer = Tracer { scene, options, rays: Cell::new(0) };
    let light = tracer.at_hit(&s, 0, 1.0);
    (light, tracer.rays.get())
}

/// One sample's recursive tracer.
struct Tracer<'a> {
    scene: &'a Scene,
    options: &'a ShadeOptions,
    /// Rays cast so far.
    rays: Cell<u64>,
}

impl Tracer<'_> {
    /// Light along a secondary ray, `depth` rays deep, `weight` its share of the pixel.
    fn trace(&self, origin: DVec3, dir: DVec3, depth: u32, weight: f64) -> DVec3 {
        self.count(1);
        match self.scene.hit(origin, dir, f64::INFINITY) {
            // The origin lies inside a solid (a ray started at a voxel's edge or corner):
            // light passes on through a transparent one, an opaque one shows nothing.
            Some(sh) if sh.hit.axis.is_none() => {
                let solid = &self.scene.solids[sh.solid];
                if solid.material.transmittance > 0.0 && depth < self.options.max_depth {
                    self.through(solid, origin, dir, depth + 1, weight)
                } else {
                    DVec3::ZERO
                }
            }
            Some(sh) => {
                let solid = &self.scene.solids[sh.solid];
                let s = SurfacePoint::new(self.scene, origin, dir, &sh, self.options.normals);
                if solid.material.transmittance > 0.0 && s.smooth.is_some_and(|n| n.dot(dir) > 0.0) {
                    // A sliver of the voxel staircase that the smooth surface leaves
                    // outside: no surface, the ray goes on.
                    let inside = s.p - s.geometric * self.eps(solid);
                    return self.pass_through(solid, inside, dir, depth + 1, weight);
                }
                self.at_hit(&s, depth, weight)
            }
            None => self.scene.background,
        }
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
        let eps = 1e-3 * solid.tree.domain().voxel_size();
        // Light that does not pass (total internal reflection) is reflected.
        let mut mirrored = kr;
        if kt * weight > self.options.cutoff {
            match bend(n, geometric, |n| refract(dir, n, 1.0, m.ior), -1.0) {
                Some(t) => color += self.through(solid, p - geometric * eps, t, depth + 1, weight * kt) * kt,
                None => mirrored += kt,
            }
        }
        if mirrored * weight > self.options.cutoff {
            let r = bend(n, geometric, |n| Some(reflect(dir, n)), 1.0).expect("reflection always exists");
            color += self.trace(p + geometric * eps, r, depth + 1, weight * mirrored) * mirrored;
        }
        color
    }

    fn count(&self, rays: u64) {
        self.rays.set(self.rays.get() + rays);
    }

    /// Rays start this far off a surface of `solid`.
    fn eps(&self, solid: &SceneSolid) -> f64 {
        1e-3 * solid.tree.domain().voxel_size()
    }

    /// Light along a ray that starts inside `solid` and crosses it without refraction.
    fn pass_through(&self, solid: &SceneSolid, origin: DVec3, dir: DVec3, depth: u32, weight: f64) -> DVec3 {
        self.count(1);
        match solid.exit(origin, dir) {
            Some(exit) if exit.axis.is_some() && depth <= self.options.max_depth => {
                let p = origin + dir * exit.t;
                self.trace(p - exit.normal(dir) * self.eps(solid), dir, depth, weight)
            }
            _ => self.trace(origin, dir, depth, weight),
        }
    }

    /// Light carried by a ray that travels inside `solid` from `origin`.
    fn through(&self, solid: &SceneSolid, mut origin: DVec3, mut dir: DVec3, mut depth: u32, weight: f64) -> DVec3 {
        let eps = 1e-3 * solid.tree.domain().voxel_size();
        while depth <= self.options.max_depth {
            self.count(1);
            let Some(exit) = solid.exit(origin, dir) else {
                // Leaves through the domain's boundary: no surface there.
                return self.trace(origin, dir, depth, weight);
            };
            if exit.axis.is_none() {
                // The origin is already outside (it started at a voxel's edge or corner).
                return self.trace(origin, dir, depth + 1, weight);
            }
            let p = origin + dir * exit.t;
            let (geometric, n, smooth) = outward(solid, &exit, dir, p, self.options);
            if smooth.is_some_and(|n| n.dot(dir) < 0.0) {
                // A notch of the staircase inside the smooth surface: no surface, the
                // ray goes on to where it meets the solid again.
                self.count(1);
                if let Some(back) = solid.traversal.hit(p + geometric * eps, dir, f64::INFINITY) {
                    let q = p + geometric * eps + dir * back.t;
                    origin = q - back.normal(dir) * eps;
                    depth += 1;
                    continue;
                }
            }
            match bend(n, geometric, |n| refract(dir, n, solid.material.ior, 1.0), 1.0) {
                Some(t) => return self.trace(p + geometric * eps, t, depth, weight),
                None => {
                    dir = bend(n, geometric, |n| Some(reflect(dir, n)), -1.0).expect("reflection always exists");
                    origin = p - geometric * eps;
                    depth += 1;
                }
            }
        }
        DVec3::ZERO
    }
}

/// A new direction `make(n)` from the shading normal `n`, on the side `side` (+1: the
/// side the geometric normal `geometric` points to, -1: the other): where a shading
/// normal far from the geometric one would send the ray through the wrong side of the
/// voxel face, the geometric normal bends it instead.
/// Total internal reflection (`None`) by the shading normal stands.
fn bend(n: DVec3, geometric: DVec3, make: impl Fn(DVec3) -> Option<DVec3>, side: f64) -> Option<DVec3> {
    match make(n) {
        Some(v) if v.dot(geometric) * side <= 0.0 && n != geometric => make(geometric),
        other => other,
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
    let smooth = match options.normals {
        Normals::Axis => None,
        Normals::Smooth => solid.smooth_normal(p),
    };
    let n = smooth.filter(|n| n.dot(dir) > 0.0).unwrap_or(geometric);
    (geometric, solid.material.bump.map_or(n, |b| b.perturb(p, n)), smooth)
}
