//! Radiosity: diffuse interreflection between the solids of a scene, solved once and
//! shown from any camera (seed section 8).
//!
//! In a closed environment of ideal diffuse surfaces each patch's radiosity is
//! `B_i = E_i + rho_i sum_j F_ij B_j`, with the form factors
//! `F_ij = (1/A_i) int int cos(theta_i) cos(theta_j) / (pi r^2) V dA_j dA_i` and
//! reciprocity `A_i F_ij = A_j F_ji`. The octree gives both halves: the surface is
//! cut into patches (`patches`: rectangles up to a size, elements below them; for a
//! solid made from a shape, tiles of the planar regions of its true surface,
//! `surface_patches`, `regions`, `cover`; for any other, the exposed faces of its full
//! nodes merged into coplanar rectangles; where a solid made from a shape touches
//! another, the faces between them are no patch), and its ray walk is the visibility term (`form_factor`:
//! ray-traced form factors after Wallace et al. 1989, on all cores). The system is
//! solved by progressive refinement (`shoot`, Cohen et al. 1988; near receivers take
//! the shooter's elements one by one, far ones what that leaves, `near_field`; a
//! patch's form factors kept for its next shot, `form_factor_cache`), stopped at a fraction of unshot energy or a
//! shot count, with the ambient correction for display, or ([`Solver::Gathering`]) as
//! the chapter writes it, `[F][B] = [E]` with the whole form-factor matrix, by
//! Gauss-Seidel iteration to a tolerance (`gather`).
//! Optionally ([`RadiosityOptions::subdivide`]), elements are split where the solution
//! varies (adaptive subdivision, Cohen et al. 1986): once refinement reaches
//! [`SUBDIVIDE_AT`], round after round, then refinement goes on to `until`.
//!
//! Units: radiance throughout (`B` is the radiosity over pi), so a material's
//! `emission` is its emitted radiance and a surface's `B` is the radiance it shows;
//! the diffuse reflectance is `color * kd` ([`Material::diffuse_reflectance`]).
//!
//! Display ([`Illumination`]): a surface point (on the voxels the renderer draws) finds
//! its patch (a surface tile within a voxel or two of it) and interpolates the
//! displayed values (`B_j + rho_j ambient`) of the four element centres around it
//! bilinearly (Gouraud's interpolation on the element grid; after subdivision, on the
//! grid of the level of the leaf holding the point, each centre taking the value of
//! the leaf holding it), reading centres beyond
//! the patch's border from the coplanar patch there, so values run on smoothly across
//! the patches of one face (they step only where element sizes change). The shading
//! stage shows it in place of the Phong term, and Whitted's mirrors and glass trace on
//! top (two passes).
//!
//! A solution is saved in a `.rad` file (`file`, docs/FORMAT.md) tied to its scene by
//! a fingerprint of the solids' voxels, materials and lights ([`fingerprint`]).
//!
//! [`Material::diffuse_reflectance`]: crate::render::Material::diffuse_reflectance

mod cover;
mod file;
mod form_factor;
mod form_factor_cache;
mod gather;
mod near_field;
mod patch;
mod patches;
mod regions;
mod shoot;
mod surface_patches;

use std::path::Path;

use glam::DVec3;

use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::fnv::Fnv1a;
use crate::progress::{CancelOnly, Progress, stop_if_cancelled};
use crate::render::scene::{Illumination, Light, Scene};
use patches::Patches;
use shoot::{Shooter, Stop};

pub use gather::{MAX_FORM_FACTOR_BYTES, MAX_ITERATIONS, form_factor_matrix_bytes};

/// How the radiosity system is solved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Solver {
    /// Progressive refinement: the brightest patch shoots its unshot light, until a
    /// fraction of the emitted light is left (Cohen et al. 1988).
    #[default]
    Shooting,
    /// The chapter's `[F][B] = [E]`: the whole form-factor matrix, then Gauss-Seidel
    /// sweeps to a tolerance.
    Gathering,
}

impl Solver {
    /// Every value, in the order `--help` lists them.
    pub const ALL: [Solver; 2] = [Solver::Shooting, Solver::Gathering];

    /// The value's one spelling (the command line's, `Display`'s).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Solver::Shooting => "shooting",
            Solver::Gathering => "gathering",
        }
    }
}

crate::spelling::spelled!(Solver);

/// Default relative residual at which gathering stops (`--tolerance`).
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// Default unshot fraction at which refinement stops (`--until`). The ambient term
/// stands in for the light not yet shot, spread evenly; in an open room most of it
/// would never reach the dark corners it is added to, so stopping at 1% showed the
/// darkest region of Mitsuba's Cornell box (a block's front towards the open side) 21%
/// too bright, at 0.1% 4% (BENCHMARKS.md, "Radiosity against Mitsuba").
pub const DEFAULT_UNTIL: f64 = 0.001;
/// Default elements along a patch side.
pub const DEFAULT_ELEMENTS: u32 = 4;
/// Default patch edge as a fraction of the scene's longest extent.
pub const DEFAULT_PATCH_FRACTION: f64 = 1.0 / 8.0;
/// The unshot fraction at which adaptive subdivision looks for elements to split (or
/// `until`, if larger): the direct light and the first bounces are laid down, and the
/// rest of the refinement goes to the finer elements.
pub const SUBDIVIDE_AT: f64 = 0.1;
/// Most elements adaptive subdivision may make, as a multiple of the base elements.
pub const DEFAULT_MAX_ELEMENTS_FACTOR: usize = 4;

/// How to solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RadiosityOptions {
    /// Stop when the unshot power is at most this fraction of the emitted power.
    pub until: f64,
    /// Stop after this many shots (lights included), if given.
    pub max_shots: Option<u64>,
    /// Longest patch edge in world units (default: [`DEFAULT_PATCH_FRACTION`] of the
    /// scene's longest extent).
    pub patch_size: Option<f64>,
    /// Elements along a patch side (at most one a voxel).
    pub elements: u32,
    /// Adaptive subdivision: split an element into four where its radiosity differs
    /// from an edge neighbour's by more than this times the scene's mean radiosity,
    /// and refine on the finer elements (`None`: the base elements only). Round after
    /// round, one level deeper each, up to four levels below the base grid.
    pub subdivide: Option<f64>,
    /// Most elements (leaves) subdivision may leave (default:
    /// [`DEFAULT_MAX_ELEMENTS_FACTOR`] times the base elements).
    pub max_elements: Option<usize>,
    /// Refuse a solution whose patches and elements would exceed this (and, when
    /// gathering, its form-factor matrix).
    pub budget: MemoryBudget,
    /// Progressive refinement (the default) or gathering.
    pub solver: Solver,
    /// Gathering: stop when the largest residual is at most this times the largest
    /// radiosity (red + green + blue), in `(0, 1)`.
    pub tolerance: f64,
}

impl Default for RadiosityOptions {
    fn default() -> Self {
        RadiosityOptions {
            until: DEFAULT_UNTIL,
            max_shots: None,
            patch_size: None,
            elements: DEFAULT_ELEMENTS,
            subdivide: None,
            max_elements: None,
            budget: MemoryBudget::default(),
            solver: Solver::Shooting,
            tolerance: DEFAULT_TOLERANCE,
        }
    }
}

/// What a solution holds and how it was reached.
#[derive(Clone, Debug, PartialEq)]
pub struct RadiosityStats {
    /// Patches (shooters).
    pub patches: usize,
    /// Elements (receivers: the leaves, after any subdivision).
    pub elements: usize,
    /// Elements split by adaptive subdivision (each into four).
    pub splits: usize,
    /// Shots made, lights included.
    pub shots: u64,
    /// Unshot power over emitted power at the end.
    pub unshot_fraction: f64,
    /// Rays cast (0 for a loaded solution).
    pub rays: u64,
    /// Power emitted (sum of red, green and blue; 0 for a loaded solution): emitted =
    /// absorbed + escaped + unshot.
    pub emitted: f64,
    /// Power absorbed by the elements.
    pub absorbed: f64,
    /// Power shot that reached no element (left the environment): what shots sent
    /// less what elements received, so slightly negative where the estimated form
    /// factors of a shooter add up to a little more than one.
    pub escaped: f64,
    /// The unshot fraction before the first shot and after each (gathering: the
    /// relative residual after each sweep; empty for a loaded solution).
    pub history: Vec<f64>,
    /// Gathering's Gauss-Seidel sweeps (0 for shooting and a loaded solution).
    pub iterations: u64,
    /// Gathering's final relative residual: the largest `|E_e + rho_e sum_j F_ej B_j -
    /// B_e|` over the largest `B_e` (0 for shooting and a loaded solution).
    pub residual: f64,
}

/// A radiosity solution of a scene: its patches and elements and each element's
/// radiosity. Put it in [`Scene::illumination`] to render with it.
#[derive(Clone, Debug)]
pub struct Radiosity {
    mesh: Patches,
    /// Each element's radiosity, radiance units, without the ambient term.
    radiosity: Vec<DVec3>,
    ambient: DVec3,
    fingerprint: u64,
    patch_size: f64,
    elements: u32,
    stats: RadiosityStats,
    /// Seconds from the start of refinement to each entry of `stats.history` (empty for
    /// a loaded solution): timing, so not part of the stats two runs share.
    timeline: Vec<f64>,
    /// Show each element flat with its borders drawn (patch borders darker), instead of
    /// interpolating: a picture of the mesh the solution lives on.
    show_elements: bool,
}

/// The patch size `options` ask for in `scene`.
fn patch_size(scene: &Scene, options: &RadiosityOptions) -> Result<f64> {
    match options.patch_size {
        Some(s) => Ok(s),
        None => {
            let b = scene.bounds().ok_or_else(|| Error::invalid("radiosity", "the scene's solids are empty"))?;
            Ok(b.size().max_element() * DEFAULT_PATCH_FRACTION)
        }
    }
}

impl Radiosity {
    /// Solves `scene` by progressive refinement (see the module doc); `progress` counts
    /// thousandths of the way to `options.until`.
    pub fn solve(scene: &Scene, options: &RadiosityOptions, progress: &dyn Progress) -> Result<Radiosity> {
        if !(options.until.is_finite() && (0.0..1.0).contains(&options.until)) {
            return Err(Error::invalid("until", format!("{} is outside [0, 1)", crate::error::Number(options.until))));
        }
        if let Some(t) = options.subdivide
            && !(t.is_finite() && t > 0.0)
        {
            return Err(Error::invalid(
                "subdivision threshold",
                format!("{} must be a finite positive number", crate::error::Number(t)),
            ));
        }
        let size = patch_size(scene, options)?;
        let mesh = Patches::build(scene, size, options.elements, options.budget, progress)?;
        if options.solver == Solver::Gathering {
            return Self::gathered(scene, options, size, mesh, progress);
        }
        let base = mesh.elements.len();
        let mut shooter = Shooter::new(scene, mesh, options.budget);
        let stop = Stop { until: options.until, max_shots: options.max_shots };
        if let Some(threshold) = options.subdivide {
            // Split where the light has been laid down (most of it: the lights and the
            // brightest patches have shot), then refine on the finer elements.
            let first = Stop { until: options.until.max(SUBDIVIDE_AT), ..stop };
            shooter.run(first, &CancelOnly(progress));
            let max_leaves = options.max_elements.unwrap_or(base.saturating_mul(DEFAULT_MAX_ELEMENTS_FACTOR));
            let max_total = shooter.patches.elements_within(options.budget);
            for _ in 0..patches::MAX_LEVEL {
                if shooter.subdivide(threshold, max_leaves, max_total) == 0 {
                    break;
                }
                shooter.run(first, &CancelOnly(progress));
            }
        }
        shooter.run(stop, progress);
        stop_if_cancelled(progress)?;
        let ambient = shooter.ambient();
        let unshot_fraction = shooter.unshot_fraction();
        let Shooter { patches: mesh, radiosity, shots, rays, emitted, absorbed, escaped, history, timeline, .. } =
            shooter;
        let stats = RadiosityStats {
            patches: mesh.patches.len(),
            elements: mesh.leaf_count(),
            splits: mesh.splits.len(),
            shots,
            unshot_fraction,
            rays,
            emitted,
            absorbed,
            escaped,
            history,
            iterations: 0,
            residual: 0.0,
        };
        Ok(Radiosity {
            mesh,
            radiosity,
            ambient,
            fingerprint: fingerprint(scene),
            patch_size: size,
            elements: options.elements,
            stats,
            timeline,
            show_elements: false,
        })
    }

    /// The gathering solver on the patches `mesh` (see [`Solver::Gathering`]).
    fn gathered(
        scene: &Scene,
        options: &RadiosityOptions,
        size: f64,
        mesh: Patches,
        progress: &dyn Progress,
    ) -> Result<Radiosity> {
        if options.subdivide.is_some() {
            return Err(Error::invalid(
                "radiosity solver",
                "adaptive subdivision refines a shooting solution; gathering solves on the base elements",
            ));
        }
        if !(options.tolerance.is_finite() && options.tolerance > 0.0 && options.tolerance < 1.0) {
            return Err(Error::invalid(
                "tolerance",
                format!("{} is outside (0, 1)", crate::error::Number(options.tolerance)),
            ));
        }
        let started = std::time::Instant::now();
        let g = gather::gather(scene, &mesh, options.tolerance, options.budget, progress)?;
        let stats = RadiosityStats {
            patches: mesh.patches.len(),
            elements: mesh.leaf_count(),
            splits: 0,
            shots: 0,
            unshot_fraction: 0.0,
            rays: g.rays,
            emitted: g.emitted,
            absorbed: g.absorbed,
            escaped: g.escaped,
            residual: g.history.last().copied().unwrap_or(0.0),
            history: g.history,
            iterations: g.iterations,
        };
        let seconds = started.elapsed().as_secs_f64();
        Ok(Radiosity {
            mesh,
            radiosity: g.radiosity,
            ambient: DVec3::ZERO,
            fingerprint: fingerprint(scene),
            patch_size: size,
            elements: options.elements,
            timeline: vec![seconds; stats.history.len()],
            stats,
            show_elements: false,
        })
    }

    /// How it was solved.
    #[must_use]
    pub fn stats(&self) -> &RadiosityStats {
        &self.stats
    }

    /// Seconds from the start of refinement to each entry of [`RadiosityStats::history`]
    /// (empty for a loaded solution).
    #[must_use]
    pub fn timeline(&self) -> &[f64] {
        &self.timeline
    }

    /// This solution shown element by element, flat, with element borders darkened and
    /// patch borders darker still (a picture of the patches and elements), or
    /// interpolated (the default).
    #[must_use]
    pub fn showing_elements(mut self, show: bool) -> Self {
        self.show_elements = show;
        self
    }

    /// The ambient term added (times each element's reflectance) for display.
    #[must_use]
    pub fn ambient(&self) -> DVec3 {
        self.ambient
    }

    /// The scene fingerprint it was solved for.
    #[must_use]
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
    }

    /// Each element (leaf) as (centre, unit normal, area, displayed radiance `B + rho
    /// ambient`), in element order.
    pub fn elements(&self) -> impl Iterator<Item = (DVec3, DVec3, f64, DVec3)> + '_ {
        self.mesh.elements.iter().zip(&self.radiosity).filter(|(e, _)| e.is_leaf()).map(|(e, b)| {
            let rho = self.mesh.patches[e.patch as usize].reflectance;
            (e.center, e.normal, e.area, *b + rho * self.ambient)
        })
    }

    /// The raw radiosities (without the ambient term), element order, split elements
    /// (their values when they were split) included: what the `.rad` file stores.
    #[must_use]
    pub fn radiosities(&self) -> &[DVec3] {
        &self.radiosity
    }

    /// The patch holding the point `p` on the face of outward axis normal `face` of
    /// solid `solid`.
    #[must_use]
    pub fn patch_at(&self, solid: usize, p: DVec3, face: DVec3) -> Option<usize> {
        self.mesh.find(solid, p, face).map(|(i, _, _)| i)
    }

    /// A patch's area.
    #[must_use]
    pub fn patch_area(&self, patch: usize) -> f64 {
        self.mesh.patches[patch].area
    }

    /// The patch-to-patch form factor `F_ij` as the solver sees it: the area-weighted
    /// mean over patch `i`'s elements of their form factors to patch `j` (module
    /// `form_factor`), with the visibility of `scene`'s solids.
    #[must_use]
    pub fn form_factor(&self, scene: &Scene, i: usize, j: usize) -> f64 {
        let p = &self.mesh.patches[i];
        let elements = self.mesh.elements.iter().filter(|e| e.patch as usize == i && e.is_leaf());
        let sum: f64 =
            elements.map(|e| e.area * form_factor::element_to_patch(scene, e, &self.mesh.patches[j]).0).sum();
        sum / p.area
    }

    /// Writes the solution as a `.rad` file, atomically; returns the bytes written.
    ///
    /// # Errors
    /// A `path` not named `.rad` is refused before anything is written (a solution
    /// written over its scene named by mistake lost it), as are the writer's own errors.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<u64> {
        crate::file_kind::FileKind::of(path.as_ref(), &[crate::file_kind::FileKind::Rad])?;
        file::write(self, path.as_ref())
    }

    /// Reads the `.rad` file at `path` for `scene`: refused with a clear error when it is
    /// not one, is damaged, or belongs to another scene. Its patches are rebuilt from the
    /// scene (within `budget`) and must match the file's counts.
    pub fn read(path: impl AsRef<Path>, scene: &Scene, budget: MemoryBudget) -> Result<Radiosity> {
        file::read(path.as_ref(), scene, budget)
    }

    /// The displayed value (`B + rho ambient`) of the leaf element holding `(s, t)` of
    /// patch `i`.
    fn element_value(&self, i: usize, s: f64, t: f64) -> DVec3 {
        let p = &self.mesh.patches[i];
        self.radiosity[self.mesh.shown_leaf(i, s, t)] + p.reflectance * self.ambient
    }

    /// The element grid `(nu, nv)` of patch `i` at the level of the leaf holding `(s, t)`.
    fn grid_at(&self, i: usize, s: f64, t: f64) -> (u32, u32) {
        let p = &self.mesh.patches[i];
        let level = self.mesh.elements[self.mesh.leaf_at(i, s, t)].level;
        (p.nu << level, p.nv << level)
    }

    /// How much of its light a point keeps near element borders (a tenth of a voxel's
    /// width of the line: 0.5) and patch borders (0.15); 1 elsewhere.
    fn border_shade(&self, i: usize, s: f64, t: f64) -> f64 {
        let (w, h) = self.mesh.sides_in_voxels(i);
        let line = 0.1;
        // Distances in voxels to the nearest patch and element border.
        let patch = (s * w).min((1.0 - s) * w).min((t * h).min((1.0 - t) * h));
        let to_grid = |x: f64, n: u32, len: f64| {
            let f = x * f64::from(n);
            (f - f.round()).abs() * len / f64::from(n)
        };
        let (nu, nv) = self.grid_at(i, s, t);
        let element = to_grid(s, nu, w).min(to_grid(t, nv, h));
        if patch < 1.5 * line {
            0.15
        } else if element < line {
            0.5
        } else {
            1.0
        }
    }

    /// The displayed radiance at `(s, t)` of patch `i` (on the face of outward normal
    /// `face` of solid `solid`): bilinear between the four element centres around the
    /// point, on the grid of the level of the leaf holding it (the centres' values are
    /// those of the leaves holding them, coarser or finer). Centres beyond the patch's
    /// border are read from the element of the coplanar patch there (so values run on
    /// across patches of one face), or, where no patch is, from the patch's own border
    /// element.
    fn interpolate(&self, solid: usize, face: DVec3, i: usize, s: f64, t: f64) -> DVec3 {
        let p = &self.mesh.patches[i];
        let (nu, nv) = self.grid_at(i, s, t);
        let (nu, nv) = (f64::from(nu), f64::from(nv));
        let (x, y) = (s * nu - 0.5, t * nv - 0.5);
        let (k0, j0) = (x.floor(), y.floor());
        let (fx, fy) = (x - k0, y - j0);
        let value = |dk: f64, dj: f64| {
            let (cs, ct) = ((k0 + dk + 0.5) / nu, (j0 + dj + 0.5) / nv);
            if (0.0..=1.0).contains(&cs) && (0.0..=1.0).contains(&ct) {
                return self.element_value(i, cs, ct);
            }
            match self.mesh.find(solid, p.point(cs, ct), face) {
                Some((n, ns, nt)) => self.element_value(n, ns, nt),
                None => self.element_value(i, cs.clamp(0.0, 1.0), ct.clamp(0.0, 1.0)),
            }
        };
        let low = value(0.0, 0.0) * (1.0 - fx) + value(1.0, 0.0) * fx;
        let high = value(0.0, 1.0) * (1.0 - fx) + value(1.0, 1.0) * fx;
        low * (1.0 - fy) + high * fy
    }
}

/// A solution is shown through the scene's [`Scene::illumination`] (wrap it in an
/// `Arc`); the scene must be the one it was solved for.
impl Illumination for Radiosity {
    fn radiance(&self, solid: usize, p: DVec3, face: DVec3) -> Option<DVec3> {
        let (i, s, t) = self.mesh.find(solid, p, face)?;
        if self.show_elements {
            return Some(self.element_value(i, s, t) * self.border_shade(i, s, t));
        }
        Some(self.interpolate(solid, face, i, s, t))
    }
}

/// A 64-bit FNV-1a hash of what a solution depends on: each solid's domain, voxels
/// (its node keys), diffuse reflectance and emission, and the lights. Names, cameras,
/// textures and Phong's other coefficients do not change a solution and are left out.
#[must_use]
pub fn fingerprint(scene: &Scene) -> u64 {
    struct Fnv(Fnv1a);
    impl Fnv {
        fn bytes(&mut self, b: &[u8]) {
            self.0.write(b);
        }
        fn f(&mut self, v: f64) {
            self.0.write_f64(v);
        }
        fn v(&mut self, v: DVec3) {
            self.f(v.x);
            self.f(v.y);
            self.f(v.z);
        }
    }
    let mut h = Fnv(Fnv1a::new());
    h.bytes(&(scene.solids.len() as u64).to_le_bytes());
    for s in &scene.solids {
        let d = s.tree.domain();
        h.v(d.min());
        h.f(d.edge());
        h.bytes(&[d.depth()]);
        h.bytes(&(s.tree.keys().len() as u64).to_le_bytes());
        for k in s.tree.keys() {
            h.bytes(&k.bits().to_le_bytes());
        }
        h.v(s.material.diffuse_reflectance());
        h.v(s.material.emission);
    }
    h.bytes(&(scene.lights.len() as u64).to_le_bytes());
    for l in &scene.lights {
        match *l {
            Light::Point { position, color } => {
                h.bytes(b"p");
                h.v(position);
                h.v(color);
            }
            Light::Directional { direction, color } => {
                h.bytes(b"d");
                h.v(direction);
                h.v(color);
            }
        }
    }
    h.0.finish()
}
