//! Radiosity: diffuse interreflection between the solids of a scene, solved once and
//! shown from any camera (seed section 8).
//!
//! In a closed environment of ideal diffuse surfaces each patch's radiosity is
//! `B_i = E_i + rho_i sum_j F_ij B_j`, with the form factors
//! `F_ij = (1/A_i) int int cos(theta_i) cos(theta_j) / (pi r^2) V dA_j dA_i` and
//! reciprocity `A_i F_ij = A_j F_ji`. The octree gives both halves: the exposed faces
//! of its full nodes are the patches (`patches`: coplanar rectangles up to a size,
//! elements below them), and its ray walk is the visibility term (`form_factor`:
//! ray-traced form factors after Wallace et al. 1989, on all cores). The system is
//! solved by progressive refinement (`shoot`, Cohen et al. 1988), stopped at a
//! fraction of unshot energy or a shot count, with the ambient correction for display.
//!
//! Units: radiance throughout (`B` is the radiosity over pi), so a material's
//! `emission` is its emitted radiance and a surface's `B` is the radiance it shows;
//! the diffuse reflectance is `color * kd` ([`Material::diffuse_reflectance`]).
//!
//! Display ([`Illumination`]): a surface point finds its patch and interpolates the
//! displayed values (`B_j + rho_j ambient`) of the four element centres around it
//! bilinearly (Gouraud's interpolation on the element grid), reading centres beyond
//! the patch's border from the coplanar patch there, so values run on smoothly across
//! the patches of one face (they step only where element sizes change). The shading
//! stage shows it in place of the Phong term, and Whitted's mirrors and glass trace on
//! top (two passes).
//!
//! A solution is saved in a `.rad` file (`file`, docs/FORMAT.md) tied to its scene by
//! a fingerprint of the solids' voxels, materials and lights ([`fingerprint`]).
//!
//! [`Material::diffuse_reflectance`]: crate::render::Material::diffuse_reflectance

mod file;
mod form_factor;
mod patches;
mod shoot;

use std::path::Path;

use glam::DVec3;

use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::fnv::Fnv1a;
use crate::progress::Progress;
use crate::render::scene::{Illumination, Light, Scene};
use patches::Patches;
use shoot::{Shooter, Stop};

/// Default unshot fraction at which refinement stops (`--until`).
pub const DEFAULT_UNTIL: f64 = 0.01;
/// Default elements along a patch side.
pub const DEFAULT_ELEMENTS: u32 = 4;
/// Default patch edge as a fraction of the scene's longest extent.
pub const DEFAULT_PATCH_FRACTION: f64 = 1.0 / 8.0;

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
    /// Refuse a solution whose patches and elements would exceed this.
    pub budget: MemoryBudget,
}

impl Default for RadiosityOptions {
    fn default() -> Self {
        RadiosityOptions {
            until: DEFAULT_UNTIL,
            max_shots: None,
            patch_size: None,
            elements: DEFAULT_ELEMENTS,
            budget: MemoryBudget::default(),
        }
    }
}

/// What a solution holds and how it was reached.
#[derive(Clone, Debug, PartialEq)]
pub struct RadiosityStats {
    /// Patches (shooters).
    pub patches: usize,
    /// Elements (receivers).
    pub elements: usize,
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
    /// The unshot fraction before the first shot and after each (empty for a loaded
    /// solution).
    pub history: Vec<f64>,
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
            return Err(Error::invalid("until", format!("{} is outside [0, 1)", options.until)));
        }
        let size = patch_size(scene, options)?;
        let mesh = Patches::build(scene, size, options.elements, options.budget)?;
        let mut shooter = Shooter::new(scene, &mesh);
        shooter.run(Stop { until: options.until, max_shots: options.max_shots }, progress);
        let stats = RadiosityStats {
            patches: mesh.patches.len(),
            elements: mesh.elements.len(),
            shots: shooter.shots,
            unshot_fraction: shooter.unshot_fraction(),
            rays: shooter.rays,
            emitted: shooter.emitted,
            absorbed: shooter.absorbed,
            escaped: shooter.escaped,
            history: std::mem::take(&mut shooter.history),
        };
        let timeline = std::mem::take(&mut shooter.timeline);
        let ambient = shooter.ambient();
        let radiosity = std::mem::take(&mut shooter.radiosity);
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

    /// Each element as (centre, unit normal, area, displayed radiance `B + rho
    /// ambient`), in element order.
    pub fn elements(&self) -> impl ExactSizeIterator<Item = (DVec3, DVec3, f64, DVec3)> + '_ {
        self.mesh.elements.iter().zip(&self.radiosity).map(|(e, b)| {
            let rho = self.mesh.patches[e.patch as usize].reflectance;
            (e.center, e.normal, e.area, *b + rho * self.ambient)
        })
    }

    /// The raw radiosities (without the ambient term), element order: what the `.rad`
    /// file stores.
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
        let elements = &self.mesh.elements[p.first as usize..(p.first + p.nu * p.nv) as usize];
        let sum: f64 =
            elements.iter().map(|e| e.area * form_factor::element_to_patch(scene, e, &self.mesh.patches[j]).0).sum();
        sum / p.area
    }

    /// Writes the solution as a `.rad` file, atomically; returns the bytes written.
    pub fn save(&self, path: impl AsRef<Path>) -> Result<u64> {
        file::save(self, path.as_ref())
    }

    /// Reads the `.rad` file at `path` for `scene`: refused with a clear error when it is
    /// not one, is damaged, or belongs to another scene. Its patches are rebuilt from the
    /// scene (within `budget`) and must match the file's counts.
    pub fn load(path: impl AsRef<Path>, scene: &Scene, budget: MemoryBudget) -> Result<Radiosity> {
        file::load(path.as_ref(), scene, budget)
    }

    /// The displayed value (`B + rho ambient`) of the element holding `(s, t)` of
    /// patch `i`.
    fn element_value(&self, i: usize, s: f64, t: f64) -> DVec3 {
        let p = &self.mesh.patches[i];
        let k = ((s * f64::from(p.nu)) as u32).min(p.nu - 1);
        let j = ((t * f64::from(p.nv)) as u32).min(p.nv - 1);
        self.radiosity[(p.first + j * p.nu + k) as usize] + p.reflectance * self.ambient
    }

    /// How much of its light a point keeps near element borders (a tenth of a voxel's
    /// width of the line: 0.5) and patch borders (0.15); 1 elsewhere.
    fn border_shade(&self, i: usize, s: f64, t: f64) -> f64 {
        let p = &self.mesh.patches[i];
        let (w, h) = (f64::from(p.rect.w), f64::from(p.rect.h));
        let line = 0.1;
        // Distances in voxels to the nearest patch and element border.
        let patch = (s * w).min((1.0 - s) * w).min((t * h).min((1.0 - t) * h));
        let to_grid = |x: f64, n: u32, len: f64| {
            let f = x * f64::from(n);
            (f - f.round()).abs() * len / f64::from(n)
        };
        let element = to_grid(s, p.nu, w).min(to_grid(t, p.nv, h));
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
    /// point. Centres beyond the patch's border are read from the element of the
    /// coplanar patch there (so values run on across patches of one face), or, where
    /// no patch is, from the patch's own border element.
    fn interpolate(&self, solid: usize, face: DVec3, i: usize, s: f64, t: f64) -> DVec3 {
        let p = &self.mesh.patches[i];
        let (nu, nv) = (f64::from(p.nu), f64::from(p.nv));
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
