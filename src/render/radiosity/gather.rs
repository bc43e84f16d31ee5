//! Gathering: the radiosity system as the chapter writes it, `[F][B] = [E]`, its
//! form-factor matrix built whole and solved by Gauss-Seidel iteration (Cohen and
//! Greenberg, "The hemi-cube", 1985; Cohen and Wallace, "Radiosity and realistic
//! image synthesis", 1993, chapter 5).
//!
//! The chapter's equations, one a patch, are `B_i = E_i + rho_i sum_j F_ij B_j`, that
//! is `[F][B] = [E]` with `F_ii = 1` and `-rho_i F_ij` off the diagonal. Here, as in
//! shooting (module `shoot`), the unknowns are the elements' radiosities and the
//! sources the patches: element `e` of patch `p(e)` gathers
//!
//! ```text
//! B_e = E_e + rho_e sum_j F(dA_e -> A_j) B_j,    B_j = sum_{e in j} (A_e / A_j) B_e
//! ```
//!
//! with the same form factors (module `form_factor`: the exact unoccluded form factor
//! of the rectangle times its ray-cast visibility) and the lights' direct light in
//! `E_e` (`rho_e` times what a light gives the element, as shooting's first shots).
//! Near field as in shooting (module `near_field`): an element within `NEAR` patch
//! edges of patch `j`'s centre gathers from `j`'s elements one by one,
//! `sum_k F(dA_e -> A_k) B_k`, instead of `F(dA_e -> A_j) B_j` (those entries are kept
//! beside the matrix, whose `F_ej` is then zero), and the far elements gather `j`'s far
//! light, `B_far,j = B_j - (sum_k N_k B_k - B_j sum_k N_k) / M_j` with the near
//! receivers' shares `N_k = sum_{e near} A_e F(dA_e -> A_k)` and the far ones' weight
//! `M_j = sum_{e far} A_e F(dA_e -> A_j)`, so what `j` gives is what its mean would
//! give. Progressive refinement converges to the same fixed point (a shot's far light
//! is the same linear function of the shooter's elements' unshot light, and the shots
//! add up to their radiosity), so both solvers agree to their tolerances.
//!
//! Gauss-Seidel: the elements in order, each new `B_e` at once folded into its patch's
//! `B_j`, so later elements gather it in the same sweep. The system is diagonally
//! dominant (`rho < 1`, each row's form factors sum to at most about one), so the
//! sweeps converge. After each sweep the residual `r_e = E_e + rho_e sum_j F_ej B_j -
//! B_e` is measured; iteration stops when the largest `|r_e|` (red + green + blue) is
//! at most `tolerance` times the largest `B_e`, or after [`MAX_ITERATIONS`] sweeps.
//!
//! Cost: the matrix holds one `f64` a leaf element and patch (`8 n_e n_p` bytes),
//! refused above [`MAX_FORM_FACTOR_BYTES`] and above the memory budget before it is
//! built; every entry casts its visibility rays (as one shot per patch would), the
//! rows in parallel, each row's entries in patch order (the same bits on any number
//! of threads). Departures from the book: elements gather from patches (the book's
//! patch-to-patch `F_ij` is the area-weighted mean of a patch's element rows), and no
//! ambient term is needed (the solution is converged, nothing is left unshot).

use glam::DVec3;
use rayon::prelude::*;

use super::form_factor::element_to_patch;
use super::near_field::{element_parts, far_light, is_near};
use super::patches::Patches;
use super::shoot::{from_light, point_power, total};
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::progress::{Progress, stop_if_cancelled};
use crate::render::scene::{Light, Scene};

use std::f64::consts::PI;

/// The largest form-factor matrix gathering builds, in bytes (whatever the budget).
pub const MAX_FORM_FACTOR_BYTES: u64 = 4 << 30;

/// Most Gauss-Seidel sweeps.
pub const MAX_ITERATIONS: u64 = 1000;

/// Bytes of the form-factor matrix of `elements` leaf elements and `patches` patches.
#[must_use]
pub fn form_factor_matrix_bytes(elements: usize, patches: usize) -> u64 {
    (elements as u64).saturating_mul(patches as u64).saturating_mul(8)
}

/// A gathered solution and how it was reached.
pub(crate) struct Gathered {
    /// Each element's radiosity (radiance units).
    pub radiosity: Vec<DVec3>,
    /// Gauss-Seidel sweeps made.
    pub iterations: u64,
    /// The relative residual after each sweep.
    pub history: Vec<f64>,
    /// Rays cast for the form factors and the lights.
    pub rays: u64,
    /// Power emitted, absorbed and escaped (sum of the three channels).
    pub emitted: f64,
    pub absorbed: f64,
    pub escaped: f64,
}

/// Solves `patches` of `scene` by gathering (see the module doc); `progress` counts
/// the matrix's rows.
pub(crate) fn gather(
    scene: &Scene,
    patches: &Patches,
    tolerance: f64,
    budget: MemoryBudget,
    progress: &dyn Progress,
) -> Result<Gathered> {
    let (n_e, n_p) = (patches.elements.len(), patches.patches.len());
    let bytes = form_factor_matrix_bytes(n_e, n_p);
    let what = format!("a form-factor matrix of {n_e} elements by {n_p} patches");
    if bytes > MAX_FORM_FACTOR_BYTES {
        return Err(Error::invalid(
            "gathering",
            format!(
                "{what} takes {:.1} GiB, more than the {} GiB gathering allows: use shooting or larger patches",
                bytes as f64 / f64::from(1u32 << 30),
                MAX_FORM_FACTOR_BYTES >> 30
            ),
        ));
    }
    budget.check(what, bytes)?;
    // A stop during the build leaves rows empty; the solve then makes no sweep.
    let (system, rays) = System::build(scene, patches, progress);
    let (radiosity, far_b, iterations, history) = system.solve(tolerance, progress);
    stop_if_cancelled(progress)?;
    let (emitted, absorbed) = system.energy_book(scene, &radiosity, &far_b);
    Ok(Gathered { radiosity, iterations, history, rays, emitted, absorbed, escaped: emitted - absorbed })
}

/// What one element's row gives besides its form factors: its light from the lights,
/// its near-field entries `(k, F(dA_e -> A_k))` and the rays cast.
type Row = (DVec3, Vec<(u32, f64)>, u64);

/// The linear system: the form factors, each element's source and what it needs.
struct System<'a> {
    patches: &'a Patches,
    /// `F(dA_e -> A_j)`, row `e` at `e n_p`; zero where `e` is near `j`.
    matrix: Vec<f64>,
    /// Each element's near-field entries: `(k, F(dA_e -> A_k))` for the elements `k`
    /// of the patches it is near.
    near: Vec<Vec<(u32, f64)>>,
    /// Each element's `N_k`: its near receivers' `sum A_e F(dA_e -> A_k)`.
    near_share: Vec<f64>,
    /// Each patch's `sum_k N_k` over its elements.
    near_sum: Vec<f64>,
    /// Each patch's `M_j`: its far receivers' `sum A_e F(dA_e -> A_j)`.
    far_weight: Vec<f64>,
    /// Each element's light from the scene's lights, before reflection.
    lit: Vec<DVec3>,
    /// Each element's `E_e`: its patch's emission plus its reflected direct light.
    source: Vec<DVec3>,
    /// The elements that gather: leaves of some area.
    live: Vec<usize>,
}

impl<'a> System<'a> {
    /// The matrix, row by row in parallel, and the sources; the rays cast.
    fn build(scene: &Scene, patches: &'a Patches, progress: &dyn Progress) -> (Self, u64) {
        let (n_e, n_p) = (patches.elements.len(), patches.patches.len());
        let is_live = |e: usize| patches.elements[e].is_leaf() && patches.elements[e].area > 0.0;
        progress.start(n_e as u64);
        let mut matrix = vec![0.0f64; n_e * n_p];
        let rows: Vec<Row> = matrix
            .par_chunks_mut(n_p.max(1))
            .enumerate()
            .with_min_len(16)
            .map(|(e, row)| {
                if progress.cancelled() {
                    return (DVec3::ZERO, Vec::new(), 0); // `gather` returns `Cancelled`.
                }
                let result = if is_live(e) { Self::row(scene, patches, e, row) } else { (DVec3::ZERO, Vec::new(), 0) };
                progress.advance(1);
                result
            })
            .collect();
        progress.finish();
        let rays = rows.iter().map(|r| r.2).sum();
        let (lit, mut near): (Vec<DVec3>, Vec<_>) = rows.into_iter().map(|r| (r.0, r.1)).unzip();
        let live: Vec<usize> = (0..n_e).filter(|&e| is_live(e)).collect();
        let mut far_weight = vec![0.0; n_p];
        for &e in &live {
            let area = patches.elements[e].area;
            for (m, f) in far_weight.iter_mut().zip(&matrix[e * n_p..(e + 1) * n_p]) {
                *m += area * f;
            }
        }
        // A patch without far receivers gives its near ones its mean (module
        // `near_field`): their entries go back into the matrix, summed.
        let patch_of = |k: u32| patches.elements[k as usize].patch as usize;
        for (e, entries) in near.iter_mut().enumerate() {
            for &(k, f) in entries.iter() {
                if far_weight[patch_of(k)] <= 0.0 {
                    matrix[e * n_p + patch_of(k)] += f;
                }
            }
            entries.retain(|&(k, _)| far_weight[patch_of(k)] > 0.0);
        }
        let (mut near_share, mut near_sum) = (vec![0.0; n_e], vec![0.0; n_p]);
        for &e in &live {
            for &(k, f) in &near[e] {
                let share = patches.elements[e].area * f;
                near_share[k as usize] += share;
                near_sum[patch_of(k)] += share;
            }
        }
        let source = (0..n_e)
            .map(|e| {
                let p = &patches.patches[patches.elements[e].patch as usize];
                p.emission + lit[e] * p.reflectance
            })
            .collect();
        (System { patches, matrix, near, near_share, near_sum, far_weight, lit, source, live }, rays)
    }

    /// Element `e`'s row of form factors (to every patch but its own), its near-field
    /// entries, its light from the lights, and the rays cast.
    fn row(scene: &Scene, patches: &Patches, e: usize, row: &mut [f64]) -> Row {
        let element = &patches.elements[e];
        let mut rays = scene.lights.len() as u64;
        let mut near = Vec::new();
        for (j, (f, patch)) in row.iter_mut().zip(&patches.patches).enumerate() {
            if j == element.patch as usize {
                continue;
            }
            let count = (patch.nu * patch.nv) as usize;
            let parts = element_parts(patch, &vec![DVec3::ZERO; count]);
            if !parts.is_empty() && is_near(element, patch) {
                for (k, (part, _)) in parts.iter().enumerate() {
                    let (ff, r) = element_to_patch(scene, element, part);
                    near.push((patch.first + k as u32, ff));
                    rays += u64::from(r);
                }
            } else {
                let (ff, r) = element_to_patch(scene, element, patch);
                *f = ff;
                rays += u64::from(r);
            }
        }
        let lit = scene.lights.iter().map(|l| from_light(scene, patches, element, l)).sum();
        (lit, near, rays)
    }

    /// `rho_e`.
    fn rho(&self, e: usize) -> DVec3 {
        self.patches.patches[self.patches.elements[e].patch as usize].reflectance
    }

    /// `A_e / A_p(e)`.
    fn share(&self, e: usize) -> f64 {
        let el = &self.patches.elements[e];
        el.area / self.patches.patches[el.patch as usize].area
    }

    /// `sum_j F_ej B_far,j`, with the near patches' elements `sum_k F_ek B_k`.
    fn gathered(&self, e: usize, b: &[DVec3], far_b: &[DVec3]) -> DVec3 {
        let n_p = far_b.len();
        let far: DVec3 = self.matrix[e * n_p..(e + 1) * n_p].iter().zip(far_b).map(|(f, bj)| *bj * *f).sum();
        far + self.near[e].iter().map(|&(k, f)| b[k as usize] * f).sum::<DVec3>()
    }

    /// Patch `j`'s far light from its mean `B_j` and its `sum_k N_k B_k`.
    fn far(&self, j: usize, patch_b: DVec3, weighted: DVec3) -> DVec3 {
        far_light(patch_b, weighted - patch_b * self.near_sum[j], self.far_weight[j])
    }

    /// Gauss-Seidel from the sources: the elements' radiosities and the patches' far
    /// light, the sweeps and the relative residual after each.
    fn solve(&self, tolerance: f64, stop: &dyn Progress) -> (Vec<DVec3>, Vec<DVec3>, u64, Vec<f64>) {
        let patches = self.patches;
        let n_p = patches.patches.len();
        let mut b = self.source.clone();
        // Each patch's mean B_j and sum_k N_k B_k, kept up to date, and its far light.
        let (mut patch_b, mut weighted) = (vec![DVec3::ZERO; n_p], vec![DVec3::ZERO; n_p]);
        for &e in &self.live {
            let p = patches.elements[e].patch as usize;
            patch_b[p] += b[e] * self.share(e);
            weighted[p] += b[e] * self.near_share[e];
        }
        let mut far_b: Vec<DVec3> = (0..n_p).map(|j| self.far(j, patch_b[j], weighted[j])).collect();
        let mut history = Vec::new();
        let mut iterations = 0;
        while iterations < MAX_ITERATIONS && !stop.cancelled() {
            iterations += 1;
            for &e in &self.live {
                let new = self.source[e] + self.rho(e) * self.gathered(e, &b, &far_b);
                let p = patches.elements[e].patch as usize;
                patch_b[p] += (new - b[e]) * self.share(e);
                weighted[p] += (new - b[e]) * self.near_share[e];
                far_b[p] = self.far(p, patch_b[p], weighted[p]);
                b[e] = new;
            }
            let largest_residual = self
                .live
                .par_iter()
                .map(|&e| total((self.source[e] + self.rho(e) * self.gathered(e, &b, &far_b) - b[e]).abs()))
                .reduce(|| 0.0, f64::max);
            let largest = b.iter().map(|v| total(v.abs())).fold(0.0, f64::max);
            let residual = if largest > 0.0 { largest_residual / largest } else { 0.0 };
            history.push(residual);
            if residual <= tolerance {
                break;
            }
        }
        (b, far_b, iterations, history)
    }

    /// Power emitted (the patches' `pi A E`, the point lights' `4 pi I`, what the
    /// elements receive of directional lights) and absorbed (`(1 - rho)` of what the
    /// elements receive), summed over the channels.
    fn energy_book(&self, scene: &Scene, b: &[DVec3], far_b: &[DVec3]) -> (f64, f64) {
        let patches = self.patches;
        let mut emitted: f64 = patches.patches.iter().map(|p| PI * p.area * total(p.emission)).sum();
        emitted += scene.lights.iter().map(point_power).sum::<f64>();
        let mut absorbed = 0.0;
        for &e in &self.live {
            let incident = self.lit[e] + self.gathered(e, b, far_b);
            absorbed += PI * patches.elements[e].area * total(incident * (DVec3::ONE - self.rho(e)));
        }
        for light in &scene.lights {
            if let Light::Directional { .. } = light {
                let incident = self.live.iter().map(|&e| {
                    let el = &patches.elements[e];
                    PI * el.area * total(from_light(scene, patches, el, light))
                });
                emitted += incident.sum::<f64>();
            }
        }
        (emitted, absorbed)
    }
}
