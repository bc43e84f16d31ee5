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
//! unshot radiance, and zeroes `dB_i`.
//!
//! Near field (module `near_field`): an element near the shooter receives from the
//! shooter's elements one by one, each with its own unshot radiance `dB_k`, the far
//! elements from the mean `dB_i` less what the near ones took in excess,
//! `dB_far = dB_i - (sum_k N_k dB_k - dB_i sum_k N_k) / M`, so a shot delivers what it
//! would with the mean everywhere, never more than it sends. Each patch also keeps
//! the unshot radiance of each of its base elements (their area-weighted mean is the
//! patch's `dB_i`), and each shot's `N_k` and `M` come from the receivers' own form
//! factors (a near receiver's to the whole patch is the sum of its form factors to
//! the elements).
//!
//! The shooter is the patch of largest unshot power `pi A_i (dB_r + dB_g + dB_b)`
//! (ties: the lowest index). Point lights shoot
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
//! showing `B_j + rho_j ambient`, so early pictures are not too dark (never below
//! zero: the negative unshot light subdivision can leave darkens nothing).
//!
//! Adaptive subdivision ([`Shooter::subdivide`], after Cohen, Greenberg, Immel and
//! Brock 1986): once refinement has stopped, a leaf element whose radiosity differs
//! from an edge neighbour's (the leaf just beyond the middle of each of its edges, on
//! its own face plane, across patch borders too) by more than `threshold` times the
//! scene's mean radiosity (area-weighted, red + green + blue, over the elements of
//! patches that do not emit) is split into four, where it may be (see `patches`).
//! Each child gathers what the element would have received had it been there from
//! the start: from every light already shot, and from every patch `j` the radiance
//! `S_j` it has shot in all, `dB_c = rho_c (sum_lights E / pi + sum_j S_j F(dA_c -> A_j))`
//! (form factors are fixed, so the order of shots does not matter; a patch near the
//! child gives it its elements' own shot radiance, a far one what it shot to its far
//! receivers, `sum dB_far`, as a shot would). The parent's
//! share of the energy book is replaced by its children's: the change of received
//! power moves between escaped and received, the change of reflected power goes into
//! the patch's unshot light (which can so grow, or fall below zero: a patch that has
//! shot more than its finer elements reflect then shoots negative light, chosen by the
//! magnitude of its unshot power). Refinement then goes on to `until` on the finer
//! elements, and subdivision is tried again, one level deeper each round.
//!
//! Form factors do not change from shot to shot, so a patch's are kept after its
//! first shot and its later shots read them instead of casting rays (module
//! `form_factor_cache`, within a memory limit): the same bits.
//!
//! Threads: each shot computes the elements' increments in parallel into a vector in
//! element order and adds them up in that order, so the solution is the same bits on
//! any number of threads.

use glam::DVec3;
use rayon::prelude::*;

use smallvec::SmallVec;

use super::form_factor::element_to_patch;
use super::form_factor_cache::{FormFactorCache, Row};
use super::near_field::{element_parts, far_light, is_near};
use super::patch::Patch;
use super::patches::{Element, Patches};
use crate::budget::MemoryBudget;
use crate::progress::Progress;
use crate::render::scene::{Cast, Light, Scene};

use std::f64::consts::PI;

/// The unshot fraction the progress bar counts down to when asked to shoot until none
/// is left (`until` 0): near the rounding of the patches' total power.
const UNSHOT_FLOOR: f64 = 1e-12;

/// How far to refine.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stop {
    pub until: f64,
    pub max_shots: Option<u64>,
}

/// The state of a progressive solution.
pub(crate) struct Shooter<'a> {
    scene: &'a Scene,
    /// The patches and elements (owned: subdivision adds elements).
    pub patches: Patches,
    /// Each element's radiosity (radiance units, without the ambient term).
    pub radiosity: Vec<DVec3>,
    /// Each element's received radiance before reflection (irradiance over pi).
    incident: Vec<DVec3>,
    /// Each patch's unshot radiance.
    pub unshot: Vec<DVec3>,
    /// Each base element's unshot radiance (0 for the elements subdivision adds); a
    /// patch's `unshot` is their area-weighted mean.
    element_unshot: Vec<DVec3>,
    /// Each base element's radiance shot so far (its patch's `shot`, element by element).
    element_shot: Vec<DVec3>,
    /// Each patch's radiance shot so far, all its shots added.
    shot: Vec<DVec3>,
    /// Each patch's radiance shot to its far receivers so far (module `near_field`).
    far_shot: Vec<DVec3>,
    /// The scene's lights shot so far (they shoot first, in order, once each).
    lights_shot: usize,
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
    /// When refinement started.
    started: std::time::Instant,
    /// Form factors of past shots, for the shooters' next (module `form_factor_cache`).
    cache: FormFactorCache,
}

/// The radiance a light gives element `e` before reflection (irradiance over pi: what
/// a white Lambertian surface would reflect), 0 where its shadow ray is blocked.
pub(super) fn from_light(scene: &Scene, patches: &Patches, e: &Element, light: &Light) -> DVec3 {
    let ray = light.shadow_ray(e.origin);
    let cos = e.normal.dot(ray.dir);
    let face = patches.patches[e.patch as usize].normal.dot(ray.dir);
    if cos <= 0.0 || face <= 0.0 || scene.occluded_as(&ray, Cast::Shadow) {
        return DVec3::ZERO;
    }
    let falloff = match light {
        Light::Point { .. } => 1.0 / (ray.t_max * ray.t_max),
        Light::Directional { .. } => 1.0,
    };
    light.color() * (cos * falloff / PI)
}

/// Sum of a colour's channels.
pub(super) fn total(c: DVec3) -> f64 {
    c.x + c.y + c.z
}

/// What a receiver takes of a shooting patch.
enum Take {
    /// A far receiver: its form factor to the patch, to be multiplied by the far light.
    Far(f64),
    /// A near receiver: the radiance from the patch's elements one by one, and its
    /// form factor to the whole patch (the sum of those to the elements).
    Near { light: DVec3, form_factor: f64 },
}

/// A near receiver's take of `parts` (the shooter's elements with their light) from
/// its form factors to them, `factors`, in the parts' order.
fn near_take(factors: &[f64], parts: &[(Patch, DVec3)]) -> Take {
    let (mut light, mut form_factor) = (DVec3::ZERO, 0.0);
    for (f, (_, u)) in factors.iter().zip(parts) {
        light += *u * *f;
        form_factor += *f;
    }
    Take::Near { light, form_factor }
}

/// The form factors of `e` to `shooter`: to each of `parts` (its elements and their
/// own light, [`element_parts`]) when `e` is near it, else to the whole patch; and the
/// rays cast.
fn factors(scene: &Scene, e: &Element, shooter: &Patch, parts: &[(Patch, DVec3)]) -> (Factors, u32) {
    if !parts.is_empty() && is_near(e, shooter) {
        let mut rays = 0;
        let near = parts
            .iter()
            .map(|(part, _)| {
                let (f, r) = element_to_patch(scene, e, part);
                rays += r;
                f
            })
            .collect();
        return (Factors::Near(near), rays);
    }
    let (f, rays) = element_to_patch(scene, e, shooter);
    (Factors::Far(f), rays)
}

/// A receiver's form factors to a shooting patch: to the whole patch (far), or to
/// each of its elements (near).
enum Factors {
    Far(f64),
    Near(SmallVec<[f64; 16]>),
}

/// What `e` takes of `shooter` (see [`factors`]), and the rays cast.
fn take(scene: &Scene, e: &Element, shooter: &Patch, parts: &[(Patch, DVec3)]) -> (Take, u32) {
    match factors(scene, e, shooter, parts) {
        (Factors::Near(f), rays) => (near_take(&f, parts), rays),
        (Factors::Far(f), rays) => (Take::Far(f), rays),
    }
}

/// The power a point light emits, `4 pi I` summed over the channels; 0 for a
/// directional light (its power is what the scene's patches receive of it).
pub(super) fn point_power(light: &Light) -> f64 {
    match light {
        Light::Point { color, .. } => 4.0 * PI * total(*color),
        Light::Directional { .. } => 0.0,
    }
}

impl<'a> Shooter<'a> {
    /// Every element at its patch's emission, every patch's emission unshot; form
    /// factors kept for later shots within `budget` (module `form_factor_cache`).
    pub fn new(scene: &'a Scene, patches: Patches, budget: MemoryBudget) -> Self {
        let radiosity = patches.elements.iter().map(|e| patches.patches[e.patch as usize].emission).collect();
        let unshot: Vec<DVec3> = patches.patches.iter().map(|p| p.emission).collect();
        let element_unshot: Vec<DVec3> = patches
            .elements
            .iter()
            .map(|e| if e.level == 0 { patches.patches[e.patch as usize].emission } else { DVec3::ZERO })
            .collect();
        let (incident, shot) = (vec![DVec3::ZERO; patches.elements.len()], vec![DVec3::ZERO; patches.patches.len()]);
        let patches_count = patches.patches.len();
        let from_patches: f64 = patches.patches.iter().map(|p| PI * p.area * total(p.emission)).sum();
        let from_lights: f64 = scene.lights.iter().map(point_power).sum();
        let mut s = Shooter {
            scene,
            patches,
            radiosity,
            incident,
            unshot,
            element_shot: vec![DVec3::ZERO; element_unshot.len()],
            element_unshot,
            far_shot: shot.clone(),
            shot,
            lights_shot: 0,
            shots: 0,
            rays: 0,
            emitted: from_patches + from_lights,
            absorbed: 0.0,
            escaped: 0.0,
            history: Vec::new(),
            timeline: vec![0.0],
            started: std::time::Instant::now(),
            cache: FormFactorCache::new(patches_count, budget),
        };
        s.history.push(s.unshot_fraction_with(from_lights));
        s
    }

    /// The patches' unshot power (its magnitude: negative light after a subdivision
    /// counts as much as positive).
    fn unshot_power(&self) -> f64 {
        self.patches.patches.iter().zip(&self.unshot).map(|(p, u)| PI * p.area * total(*u).abs()).sum()
    }

    fn unshot_fraction_with(&self, pending: f64) -> f64 {
        if self.emitted > 0.0 { (self.unshot_power() + pending) / self.emitted } else { 0.0 }
    }

    /// Unshot power over emitted power (0 when nothing emits).
    pub fn unshot_fraction(&self) -> f64 {
        self.unshot_fraction_with(0.0)
    }

    /// Refines until `stop`; progress counts thousandths of the way, on a log scale,
    /// from all unshot to `until` (to [`UNSHOT_FLOOR`] when `until` is 0), or of the
    /// shots allowed, whichever is further. Stops early, between shots, when
    /// `progress` is cancelled (the caller returns `Cancelled`).
    pub fn run(&mut self, stop: Stop, progress: &dyn Progress) {
        progress.start(1000);
        let mut shown = 0u64;
        let allowed = |shots: u64| stop.max_shots.is_none_or(|m| shots < m);
        let lights: Vec<Light> = self.scene.lights[self.lights_shot..].to_vec();
        let mut pending: f64 = lights.iter().map(point_power).sum();
        for light in &lights {
            if !allowed(self.shots) || progress.cancelled() {
                break;
            }
            self.shoot_light(light);
            self.lights_shot += 1;
            if let Light::Point { .. } = light {
                pending -= point_power(light);
            }
            self.history.push(self.unshot_fraction_with(pending.max(0.0)));
            self.timeline.push(self.started.elapsed().as_secs_f64());
        }
        loop {
            let fraction = self.unshot_fraction();
            let goal = if stop.until > 0.0 { stop.until } else { UNSHOT_FLOOR };
            let by_energy =
                if fraction > 0.0 && goal < 1.0 { (fraction.ln() / goal.ln()).clamp(0.0, 1.0) } else { 1.0 };
            let by_shots = stop.max_shots.map_or(0.0, |m| (self.shots as f64 / m.max(1) as f64).min(1.0));
            let done = (by_energy.max(by_shots) * 1000.0) as u64;
            if done > shown {
                progress.advance(done - shown);
                shown = done;
            }
            if fraction <= stop.until || !allowed(self.shots) || progress.cancelled() {
                break;
            }
            let Some(i) = self.brightest() else { break };
            self.shoot_patch(i);
            self.history.push(self.unshot_fraction());
            self.timeline.push(self.started.elapsed().as_secs_f64());
        }
        progress.finish();
    }

    /// The patch of most unshot power (in magnitude), `None` when none has any.
    fn brightest(&self) -> Option<usize> {
        let mut best = None;
        let mut most = 0.0;
        for (i, (p, u)) in self.patches.patches.iter().zip(&self.unshot).enumerate() {
            let power = p.area * total(*u).abs();
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
            self.incident[j] += *inc;
            self.unshot[e.patch as usize] += reflected * (e.area / patch.area);
            let base = self.patches.base_element(j);
            self.element_unshot[base] += reflected * (e.area / self.patches.elements[base].area);
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
        self.shot[i] += light;
        let scene = self.scene;
        // The shooter's elements with their unshot light, for the receivers near it.
        let (first, count) = (shooter.first as usize, (shooter.nu * shooter.nv) as usize);
        let parts = element_parts(shooter, &self.element_unshot[first..first + count]);
        for k in first..first + count {
            self.element_shot[k] += std::mem::take(&mut self.element_unshot[k]);
        }
        let skipped = |e: &Element| e.patch as usize == i || !e.is_leaf() || e.area <= 0.0;
        let found: Vec<(Option<Take>, u32)> = if let Some(row) = self.cache.row(i) {
            // A shot before this one left its form factors (module `form_factor_cache`).
            self.patches
                .elements
                .par_iter()
                .with_min_len(64)
                .enumerate()
                .map(|(j, e)| {
                    if skipped(e) {
                        return (None, 0);
                    }
                    let take = match row.near(j as u32) {
                        Some(f) => near_take(f, &parts),
                        None => Take::Far(row.far[j]),
                    };
                    (Some(take), 0)
                })
                .collect()
        } else {
            let computed: Vec<(Option<Factors>, u32)> = self
                .patches
                .elements
                .par_iter()
                .with_min_len(64)
                .map(|e| {
                    if skipped(e) {
                        return (None, 0);
                    }
                    let (f, rays) = factors(scene, e, shooter, &parts);
                    (Some(f), rays)
                })
                .collect();
            let n = computed.len();
            let mut row = self.cache.has_room_for(n).then(|| Row::new(vec![0.0; n], parts.len()));
            let found = computed
                .into_iter()
                .enumerate()
                .map(|(j, (f, rays))| {
                    let take = f.map(|f| match f {
                        Factors::Far(f) => {
                            if let Some(row) = &mut row {
                                row.far[j] = f;
                            }
                            Take::Far(f)
                        }
                        Factors::Near(f) => {
                            if let Some(row) = &mut row {
                                row.push_near(j as u32, &f);
                            }
                            near_take(&f, &parts)
                        }
                    });
                    (take, rays)
                })
                .collect();
            if let Some(row) = row {
                self.cache.keep(i, row);
            }
            found
        };
        self.rays += found.iter().map(|(_, r)| u64::from(*r)).sum::<u64>();
        // The near receivers' excess over the mean and the far receivers' weight, in
        // element order; then the far light (module `near_field`).
        let (mut excess, mut far_weight) = (DVec3::ZERO, 0.0);
        for (e, (t, _)) in self.patches.elements.iter().zip(&found) {
            match t {
                Some(Take::Near { light: l, form_factor: f }) => excess += (*l - light * *f) * e.area,
                Some(Take::Far(f)) => far_weight += e.area * f,
                None => {}
            }
        }
        let far = far_light(light, excess, far_weight);
        self.far_shot[i] += far;
        let incident: Vec<DVec3> = found
            .into_iter()
            .map(|(t, _)| match t {
                // Without far receivers, the near ones take the mean (module `near_field`).
                Some(Take::Near { light: l, form_factor: f }) => {
                    if far_weight > 0.0 {
                        l
                    } else {
                        light * f
                    }
                }
                Some(Take::Far(f)) => far * f,
                None => DVec3::ZERO,
            })
            .collect();
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
            .map(|e| if e.is_leaf() && e.area > 0.0 { from_light(scene, &self.patches, e, light) } else { DVec3::ZERO })
            .collect();
        self.rays += self.patches.leaf_count() as u64;
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

    /// One round of adaptive subdivision (see the module doc): splits the leaves whose
    /// radiosity differs from a neighbour's by more than `threshold` times the mean,
    /// while the leaves stay at most `max_elements`; each child gathers its light.
    /// Returns the elements split.
    /// `max_total` bounds all elements, split ones included (the memory budget's).
    pub fn subdivide(&mut self, threshold: f64, max_elements: usize, max_total: usize) -> usize {
        let mesh = &self.patches;
        let (mut weighted, mut area) = (0.0, 0.0);
        for (e, b) in mesh.elements.iter().zip(&self.radiosity) {
            if e.is_leaf() && mesh.patches[e.patch as usize].emission == DVec3::ZERO {
                weighted += e.area * total(*b);
                area += e.area;
            }
        }
        if area <= 0.0 || weighted <= 0.0 {
            return 0;
        }
        let limit = threshold * weighted / area;
        let radiosity = &self.radiosity;
        let candidates: Vec<usize> = (0..mesh.elements.len())
            .into_par_iter()
            .with_min_len(256)
            .filter(|&e| {
                mesh.can_split(e) && mesh.edge_neighbours(e).any(|n| total((radiosity[n] - radiosity[e]).abs()) > limit)
            })
            .collect();
        // A split adds four elements, three leaves.
        let room =
            (max_elements.saturating_sub(mesh.leaf_count()) / 3).min(max_total.saturating_sub(mesh.elements.len()) / 4);
        let split: Vec<usize> = candidates.into_iter().take(room).collect();
        if !split.is_empty() {
            self.cache.clear();
        }
        let scene = self.scene;
        let mut parents = Vec::with_capacity(split.len());
        for &e in &split {
            parents.push((e, self.patches.split(scene, e) as usize));
        }
        // What each child would have received from the start: the lights shot and every
        // patch's light shot so far (each child in parallel, its sum in patch order).
        let lights = &scene.lights[..self.lights_shot];
        let (mesh, shot, far_shot, element_shot) = (&self.patches, &self.shot, &self.far_shot, &self.element_shot);
        let gathered: Vec<(DVec3, u64)> = parents
            .par_iter()
            .flat_map_iter(|&(_, first)| first..first + 4)
            .map(|c| {
                let child = &mesh.elements[c];
                if child.area <= 0.0 {
                    return (DVec3::ZERO, 0);
                }
                let mut inc: DVec3 = lights.iter().map(|l| from_light(scene, mesh, child, l)).sum();
                let mut rays = lights.len() as u64;
                for (j, (patch, s)) in mesh.patches.iter().zip(shot).enumerate() {
                    if *s == DVec3::ZERO || j == child.patch as usize {
                        continue;
                    }
                    let (first, count) = (patch.first as usize, (patch.nu * patch.nv) as usize);
                    let parts = if is_near(child, patch) {
                        element_parts(patch, &element_shot[first..first + count])
                    } else {
                        Vec::new()
                    };
                    let (t, r) = take(scene, child, patch, &parts);
                    inc += match t {
                        Take::Near { light, .. } => light,
                        Take::Far(f) => far_shot[j] * f,
                    };
                    rays += u64::from(r);
                }
                (inc, rays)
            })
            .collect();
        // The parents' share of the book replaced by the children's.
        for (n, &(parent, first)) in parents.iter().enumerate() {
            let e = self.patches.elements[parent];
            let patch = &self.patches.patches[e.patch as usize];
            let (rho, emission, patch_area) = (patch.reflectance, patch.emission, patch.area);
            let old = self.incident[parent];
            let (mut received, mut reflected) = (-PI * e.area * total(old), -PI * e.area * total(old * rho));
            let mut unshot = -old * rho * (e.area / patch_area);
            let base = self.patches.base_element(parent);
            let base_area = self.patches.elements[base].area;
            let mut base_unshot = -old * rho * (e.area / base_area);
            for (c, (inc, rays)) in (first..first + 4).zip(&gathered[4 * n..4 * n + 4]) {
                let area = self.patches.elements[c].area;
                self.radiosity.push(emission + *inc * rho);
                self.incident.push(*inc);
                self.element_unshot.push(DVec3::ZERO);
                self.element_shot.push(DVec3::ZERO);
                self.rays += rays;
                received += PI * area * total(*inc);
                reflected += PI * area * total(*inc * rho);
                unshot += *inc * rho * (area / patch_area);
                base_unshot += *inc * rho * (area / base_area);
            }
            self.unshot[e.patch as usize] += unshot;
            self.element_unshot[base] += base_unshot;
            self.absorbed += received - reflected;
            self.escaped -= received;
        }
        split.len()
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
        // Never below zero: negative unshot light (after subdivision) darkens nothing.
        (unshot / (DVec3::ONE - rho.min(DVec3::splat(0.999)))).max(DVec3::ZERO)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::{Domain, VoxelizeOptions, voxelize};
    use crate::render::Material;
    use crate::shape::Cuboid;

    /// A closed room (the hollow of a box in a box) with a lamp under its ceiling and a
    /// block on its floor, at depth 5.
    fn room() -> Scene {
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 5).unwrap();
        let cuboid = |min: DVec3, max: DVec3| Cuboid::new((min + max) * 0.5, max - min).unwrap();
        let tree = |shape: &dyn crate::shape::Shape| voxelize(shape, domain, &VoxelizeOptions::default()).unwrap();
        let diffuse = |rho: f64, emission: f64| Material {
            color: DVec3::splat(rho),
            kd: 1.0,
            emission: DVec3::splat(emission),
            ..Material::default()
        };
        let mut scene = Scene::new();
        let walls = cuboid(DVec3::splat(-0.875), DVec3::splat(0.875)) - cuboid(DVec3::splat(-0.5), DVec3::splat(0.5));
        scene.add("room", tree(&walls), diffuse(0.7, 0.0));
        scene.add(
            "lamp",
            tree(&cuboid(DVec3::new(-0.125, -0.125, 0.375), DVec3::new(0.125, 0.125, 0.5))),
            diffuse(0.6, 2.0),
        );
        scene.add("block", tree(&cuboid(DVec3::new(-0.3125, -0.3125, -0.5), DVec3::ZERO)), diffuse(0.6, 0.0));
        scene
    }

    #[test]
    fn kept_form_factors_give_the_bits_of_form_factors_cast_at_every_shot() {
        let scene = room();
        // A budget of nothing keeps no row: every shot casts its rays.
        let solve = |budget: MemoryBudget| {
            let patches = Patches::build(&scene, 0.25, 4, MemoryBudget::unlimited(), &crate::NoProgress).unwrap();
            let mut s = Shooter::new(&scene, patches, budget);
            let stop = Stop { until: 1e-3, max_shots: Some(400) };
            s.run(stop, &crate::NoProgress);
            // A subdivision round empties the cache; the shots after it must agree too.
            s.subdivide(0.25, usize::MAX, usize::MAX);
            s.run(Stop { until: 1e-4, max_shots: Some(600) }, &crate::NoProgress);
            s
        };
        let (kept, cast) = (solve(MemoryBudget::unlimited()), solve(MemoryBudget(0)));
        let bits = |s: &Shooter| s.radiosity.iter().flat_map(|v| v.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&kept), bits(&cast));
        assert_eq!(kept.shots, cast.shots);
        assert_eq!(
            (kept.absorbed.to_bits(), kept.escaped.to_bits()),
            (cast.absorbed.to_bits(), cast.escaped.to_bits())
        );
        // Patches shot more than once, and their later shots cast no ray.
        assert!(kept.shots > kept.patches.patches.len() as u64, "{} shots", kept.shots);
        assert!(kept.rays < cast.rays, "{} rays kept against {} cast", kept.rays, cast.rays);
    }

    /// The thousandths reported as a run goes, in order.
    #[derive(Default)]
    struct Steps(std::sync::Mutex<Vec<u64>>);

    impl Progress for Steps {
        fn advance(&self, n: u64) {
            self.0.lock().unwrap().push(n);
        }
    }

    #[test]
    fn shooting_until_nothing_is_left_moves_its_progress_by_energy_and_shots() {
        let scene = room();
        // Until 0 and at most 40 shots: the bar moves shot by shot (each shot both
        // lowers the unshot energy and spends a fortieth of the shots), never jumping
        // to the end before the last shot, and ends full.
        let patches = Patches::build(&scene, 0.25, 4, MemoryBudget::unlimited(), &crate::NoProgress).unwrap();
        let mut s = Shooter::new(&scene, patches, MemoryBudget::unlimited());
        let steps = Steps::default();
        s.run(Stop { until: 0.0, max_shots: Some(40) }, &steps);
        let steps = steps.0.into_inner().unwrap();
        assert_eq!(s.shots, 40);
        assert_eq!(steps.iter().sum::<u64>(), 1000, "{steps:?}");
        assert!(steps.len() >= 20 && steps[..steps.len() - 1].iter().all(|&n| n < 500), "{steps:?}");
    }
}
