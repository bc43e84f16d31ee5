//! Progressive refinement: the patch with the most unshot light shoots it to every
//! element (Cohen, Chen, Wallace and Greenberg, "A progressive refinement approach to
//! fast radiosity image generation", 1988).
//!
//! In radiance units (`B = L`, the radiosity over pi, so emission is the material's
//! emitted radiance), a shot of patch `i` with unshot radiance `dB_i` gives each
//! element `j`
//!
//! ```text
//! dB_j = rho_j dB_i F(dA_j -> A_i)
//! ```
//!
//! (`F(dA_j -> A_i) = A_i F_ij / A_j` by reciprocity, so the receiver's form factor is
//! the one the rays compute), adds it to `B_j` and `dB_j A_j / A_patch` to its patch's
//! unshot radiance, and zeroes `dB_i`. The shooter is the patch of largest unshot
//! power `pi A_i (dB_r + dB_g + dB_b)` (ties: the lowest index). Point lights shoot
//! first, once each: irradiance `I cos(theta) / r^2` where a ray reaches the light,
//! `dB_j = rho_j E / pi`; directional lights the same with `I cos(theta)`.
//!
//! Stopping: when the unshot power falls to `until` times the emitted power (the
//! patches' `pi A E` and the point lights' `4 pi I`, summed over red, green and blue),
//! or after `max_shots` shots. Energy book-keeping: what a shot sends either reaches
//! elements (absorbed `(1 - rho)` of it, the rest becomes their unshot light) or
//! escapes (hits nothing, or what lies outside the environment), so emitted = absorbed
//! + escaped + unshot at every step.
//!
//! Ambient term for display (Cohen et al. 1988): `ambient = R sum_i dB_i A_i / sum_i
//! A_i`, `R = 1 / (1 - rho_avg)` with the area-averaged reflectance, each element then
//! showing `B_j + rho_j ambient`, so early pictures are not too dark.
//!
//! Threads: each shot computes the elements' increments in parallel into a vector in
//! element order and adds them up in that order, so the solution is the same bits on
//! any number of threads.

use glam::DVec3;
use rayon::prelude::*;

use super::form_factor::element_to_patch;
use super::patches::Patches;
use crate::progress::Progress;
use crate::ray::RayCast;
use crate::render::scene::{Light, Scene};

use std::f64::consts::PI;

/// How far to refine.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stop {
    pub until: f64,
    pub max_shots: Option<u64>,
}

/// The state of a progressive solution.
pub(crate) struct Shooter<'a> {
    scene: &'a Scene,
    patches: &'a Patches,
    /// Each element's radiosity (radiance units, without the ambient term).
    pub radiosity: Vec<DVec3>,
    /// Each patch's unshot radiance.
    pub unshot: Vec<DVec3>,
    /// Shots so far (lights included).
    pub shots: u64,
    /// Rays cast.
    pub rays: u64,
    /// Power emitted, absorbed and escaped so far (sum of the three channels).
    pub emitted: f64,
    pub absorbed: f64,
    pub escaped: f64,
    /// The unshot fraction after each shot (index 0: before any).
    pub history: Vec<f64>,
    /// Seconds since refinement started after each shot (index 0: 0).
    pub timeline: Vec<f64>,
}

/// Sum of a colour's channels.
fn total(c: DVec3) -> f64 {
    c.x + c.y + c.z
}

/// The power a point light emits, `4 pi I` summed over the channels; 0 for a
/// directional light (its power is what the scene's patches receive of it).
fn point_power(light: &Light) -> f64 {
    match light {
        Light::Point { color, .. } => 4.0 * PI * total(*color),
        Light::Directional { .. } => 0.0,
    }
}

impl<'a> Shooter<'a> {
    /// Every element at its patch's emission, every patch's emission unshot.
    pub fn new(scene: &'a Scene, patches: &'a Patches) -> Self {
        let radiosity = patches.elements.iter().map(|e| patches.patches[e.patch as usize].emission).collect();
        let unshot: Vec<DVec3> = patches.patches.iter().map(|p| p.emission).collect();
        let from_patches: f64 = patches.patches.iter().map(|p| PI * p.area * total(p.emission)).sum();
        let from_lights: f64 = scene.lights.iter().map(point_power).sum();
        let mut s = Shooter {
            scene,
            patches,
            radiosity,
            unshot,
            shots: 0,
            rays: 0,
            emitted: from_patches + from_lights,
            absorbed: 0.0,
            escaped: 0.0,
            history: Vec::new(),
            timeline: vec![0.0],
        };
        s.history.push(s.unshot_fraction_with(from_lights));
        s
    }

    /// The patches' unshot power.
    fn unshot_power(&self) -> f64 {
        self.patches.patches.iter().zip(&self.unshot).map(|(p, u)| PI * p.area * total(*u)).sum()
    }

    fn unshot_fraction_with(&self, pending: f64) -> f64 {
        if self.emitted > 0.0 { (self.unshot_power() + pending) / self.emitted } else { 0.0 }
    }

    /// Unshot power over emitted power (0 when nothing emits).
    pub fn unshot_fraction(&self) -> f64 {
        self.unshot_fraction_with(0.0)
    }

    /// Refines until `stop`; progress counts thousandths of the way, on a log scale,
    /// from all unshot to `until`.
    pub fn run(&mut self, stop: Stop, progress: &dyn Progress) {
        progress.start(1000);
        let started = std::time::Instant::now();
        let mut shown = 0u64;
        let allowed = |shots: u64| stop.max_shots.is_none_or(|m| shots < m);
        let lights = self.scene.lights.clone();
        let mut pending: f64 = lights.iter().map(point_power).sum();
        for light in &lights {
            if !allowed(self.shots) {
                break;
            }
            self.shoot_light(light);
            if let Light::Point { .. } = light {
                pending -= point_power(light);
            }
            self.history.push(self.unshot_fraction_with(pending.max(0.0)));
            self.timeline.push(started.elapsed().as_secs_f64());
        }
        loop {
            let fraction = self.unshot_fraction();
            let done = if fraction > 0.0 && stop.until > 0.0 && stop.until < 1.0 {
                ((fraction.ln() / stop.until.ln()).clamp(0.0, 1.0) * 1000.0) as u64
            } else {
                1000
            };
            if done > shown {
                progress.advance(done - shown);
                shown = done;
            }
            if fraction <= stop.until || !allowed(self.shots) {
                break;
            }
            let Some(i) = self.brightest() else { break };
            self.shoot_patch(i);
            self.history.push(self.unshot_fraction());
            self.timeline.push(started.elapsed().as_secs_f64());
        }
        progress.finish();
    }

    /// The patch of most unshot power, `None` when none has any.
    fn brightest(&self) -> Option<usize> {
        let mut best = None;
        let mut most = 0.0;
        for (i, (p, u)) in self.patches.patches.iter().zip(&self.unshot).enumerate() {
            let power = p.area * total(*u);
            if power > most {
                most = power;
                best = Some(i);
            }
        }
        best
    }

    /// Adds each element's increment (received radiance before reflection, in element
    /// order), keeping the energy book.
    fn receive(&mut self, incident: &[DVec3], shot_power: f64) {
        let mut received = 0.0;
        for (j, inc) in incident.iter().enumerate() {
            if *inc == DVec3::ZERO {
                continue;
            }
            let e = &self.patches.elements[j];
            let patch = &self.patches.patches[e.patch as usize];
            let reflected = *inc * patch.reflectance;
            self.radiosity[j] += reflected;
            self.unshot[e.patch as usize] += reflected * (e.area / patch.area);
            let power = PI * e.area * total(*inc);
            received += power;
            self.absorbed += power - PI * e.area * total(reflected);
        }
        self.escaped += shot_power - received;
        self.shots += 1;
    }

    /// Shoots patch `i`'s unshot light.
    pub fn shoot_patch(&mut self, i: usize) {
        let shooter = &self.patches.patches[i];
        let light = std::mem::take(&mut self.unshot[i]);
        let scene = self.scene;
        let found: Vec<(DVec3, u32)> = self
            .patches
            .elements
            .par_iter()
            .with_min_len(64)
            .map(|e| {
                if e.patch as usize == i {
                    return (DVec3::ZERO, 0);
                }
                let (f, rays) = element_to_patch(scene, e, shooter);
                (light * f, rays)
            })
            .collect();
        self.rays += found.iter().map(|(_, r)| u64::from(*r)).sum::<u64>();
        let incident: Vec<DVec3> = found.into_iter().map(|(l, _)| l).collect();
        self.receive(&incident, PI * shooter.area * total(light));
    }

    /// Shoots a light source's light (point lights: `4 pi I` of power).
    fn shoot_light(&mut self, light: &Light) {
        let scene = self.scene;
        let incident: Vec<DVec3> = self
            .patches
            .elements
            .par_iter()
            .with_min_len(64)
            .map(|e| {
                let ray = light.shadow_ray(e.origin);
                let cos = e.normal.dot(ray.dir);
                let face = self.patches.patches[e.patch as usize].normal.dot(ray.dir);
                if cos <= 0.0 || face <= 0.0 || scene.occluded(&ray) {
                    return DVec3::ZERO;
                }
                let falloff = match light {
                    Light::Point { .. } => 1.0 / (ray.t_max * ray.t_max),
                    Light::Directional { .. } => 1.0,
                };
                // Irradiance over pi: the radiance a white Lambertian surface would reflect.
                light.color() * (cos * falloff / PI)
            })
            .collect();
        self.rays += self.patches.elements.len() as u64;
        let power = match light {
            Light::Point { .. } => point_power(light),
            Light::Directional { .. } => {
                incident.iter().zip(&self.patches.elements).map(|(l, e)| PI * e.area * total(*l)).sum()
            }
        };
        if let Light::Directional { .. } = light {
            self.emitted += power;
        }
        self.receive(&incident, power);
    }

    /// The ambient term of the module doc.
    pub fn ambient(&self) -> DVec3 {
        let area: f64 = self.patches.patches.iter().map(|p| p.area).sum();
        if area <= 0.0 {
            return DVec3::ZERO;
        }
        let rho: DVec3 = self.patches.patches.iter().map(|p| p.reflectance * p.area).sum::<DVec3>() / area;
        let unshot: DVec3 =
            self.patches.patches.iter().zip(&self.unshot).map(|(p, u)| *u * p.area).sum::<DVec3>() / area;
        unshot / (DVec3::ONE - rho.min(DVec3::splat(0.999)))
    }
}
