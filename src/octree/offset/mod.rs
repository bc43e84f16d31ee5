//! Offsets, shells and rounds: a solid grown or shrunk by a ball, exactly to the voxel,
//! from the Euclidean distance computed only in the band the ball reaches.
//!
//! Definitions (distances in voxels, Euclidean, from a voxel's centre to the voxels of
//! the other phase as cubes):
//!
//! - **offset by `D > 0`** (dilation by the ball of radius `D`): the solid and every
//!   voxel whose centre lies less than `D` from it: the Minkowski sum of the voxel
//!   solid with the open ball, sampled at voxel centres;
//! - **offset by `D < 0`** (erosion): the full voxels whose centre lies at least `|D|`
//!   from every empty voxel (voxels outside the domain are empty), the complement's
//!   dilation's complement;
//! - **shell** of thickness `T`: the solid minus its offset by `-T` (the wall inside
//!   the surface), or, outward, the offset by `T` minus the solid;
//! - **round** by `R`: convex edges by the opening (offset by `-R`, then by `R`: what no
//!   ball of radius `R` inside the solid can reach goes), concave edges by the closing
//!   (offset by `R`, then by `-R`); both: the opening, then the closing.
//!
//! Measured from the cubes, not the centres, an offset is the true offset of the voxel
//! solid sampled at the centres, so for a cube of side `a` (voxels) these follow
//! Steiner's formula as the lattice samples it: grown by `r`, `a^3 + 6 a^2 r + 3 pi a
//! r^2 + 4/3 pi r^3`; shrunk, `(a - 2r)^3`.
//!
//! Along the surface ([`LinearOctree::offset_along_surface`], with a solid's crossings
//! through [`FaceCrossings`]; `surface::offset_with_surface` over Hermite data): the
//! distance is measured to the true surface near each voxel's nearest site, the
//! tangent planes of its crossings ([`subvoxel`]), so a curved solid's offsets lose
//! the staircase's half-voxel bias (a sphere's shell within 0.2% of
//! `4/3 pi (R^3 - (R - t)^3)` at depth 9, where the cubes give 1-4% too much), and the
//! result's crossings are interpolated from that distance. The rule the dense brute
//! force checks: a voxel of the phase the step spreads into flips when `d(p) < |D|`
//! for its nearest site by the cube metric (of equally near sites, any).
//!
//! Method: over the cubes, [`tiles`] takes the tiles of 8^3 voxels the ball can reach
//! (the mixed ones and those within reach of them, never the coarse full and empty
//! nodes far from the surface) and runs the exact separable transform of the squared
//! distance to the other phase ([`edt`]: lower envelopes of parabolas, Felzenszwalb
//! and Huttenlocher 2012, in integers after Meijster et al. 2000; for small reaches the
//! minimum over the window of the reach, in vector lanes) along whole lines of
//! them, each voxel once a pass; along a surface, [`features`] carries each voxel's
//! nearest site through the same passes over the same tiles (the feature transform).
//! The voxels that change are Morton runs, cut into keys and combined with the solid by
//! one set operation. The result is canonical and the same on any number of threads.
//! Voxels beyond the domain are never added: a solid grown past the domain's faces is
//! cut by them.
//!
//! Other metrics ([`Metric`]: Manhattan, the octahedron; Chebyshev, the cube) replace
//! the ball by their own unit ball over the cubes: the same passes over the same tiles
//! with their own costs an axis (the window of the reach at every reach); along a
//! surface the distance is Euclidean only.
//!
//! Memory: a step is refused before it starts when the estimate of its band
//! ([`LinearOctree::offset_estimate`]) exceeds the budget; shells and rounds first
//! check the largest of their steps' estimates, each taken on the input, so they are
//! refused before any step runs (each step is still checked as it starts, its band
//! being an intermediate solid's).

mod band;
mod edt;
mod features;
mod metric;
mod step;
mod subvoxel;
mod tiles;
mod window;

use band::changed_runs;
pub use metric::Metric;
use step::Step;
pub use subvoxel::{FaceCrossings, NewCrossing, Staircase};

use super::linear::LinearOctree;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::progress::{NoProgress, Progress, Stages, stop_if_cancelled};

/// Options of an offset, shell or round.
#[derive(Clone, Copy)]
pub struct OffsetOptions<'a> {
    /// Refuse a step when its estimated memory exceeds this.
    pub budget: MemoryBudget,
    /// Receives progress in tiles of the band, three passes each over the cubes, four
    /// along a surface (a round's two or four steps as the stages of one job).
    pub progress: &'a dyn Progress,
    /// The distance measured over the cubes ([`Metric`], Euclidean by default; along a
    /// surface only Euclidean).
    pub metric: Metric,
}

impl Default for OffsetOptions<'_> {
    fn default() -> Self {
        OffsetOptions { budget: MemoryBudget::default(), progress: &NoProgress, metric: Metric::Euclidean }
    }
}

impl LinearOctree {
    /// The solid grown (`distance > 0`) or shrunk (`distance < 0`) by a ball of radius
    /// `|distance|` voxels (see the module doc); up to half a voxel nothing changes.
    ///
    /// Fails when `distance` is not finite or a step's estimate exceeds the budget.
    pub fn offset(&self, distance_in_voxels: f64, options: &OffsetOptions) -> Result<LinearOctree> {
        Ok(self.step(distance_in_voxels, None, options)?.0)
    }

    /// The solid grown or shrunk by `distance` voxels measured to its true surface,
    /// the one `surface`'s crossings describe (the sub-voxel rule of `subvoxel`,
    /// in the module doc), and the crossings of the result's boundary faces in the
    /// band, from the distance field (each face once, sorted by voxel and direction).
    /// Every boundary face of the result between two voxels of the domain is in the
    /// band when `distance` is not 0 (a face has a mixed tile, or a free tile touching
    /// a site tile, on one side; see `tiles`), so it gets one; the domain's own faces
    /// get none (they keep `surface`'s).
    ///
    /// Fails when `distance` is not finite or a step's estimate exceeds the budget.
    pub fn offset_along_surface(
        &self,
        distance_in_voxels: f64,
        surface: &dyn FaceCrossings,
        options: &OffsetOptions,
    ) -> Result<(LinearOctree, Vec<NewCrossing>)> {
        self.step(distance_in_voxels, Some(surface), options)
    }

    /// The memory one step of `distance` voxels (along a surface when `along_surface`)
    /// is estimated to need, from its band: over the cubes, one array of the passes' values a voxel
    /// of its tiles; along a surface, a nearest site a voxel of its tiles, their
    /// occupancy and the crossings out; and the trees in and out; 0 when the step
    /// reaches no voxel or `distance` is not finite.
    /// Past half the machine's memory the band is not made, and what the step needs at
    /// least is returned (more than that).
    #[must_use]
    pub fn offset_estimate(&self, distance_in_voxels: f64, along_surface: bool) -> u64 {
        self.estimate_within(distance_in_voxels, along_surface, MemoryBudget::half_of_ram().0)
    }

    /// [`LinearOctree::offset_estimate`], its band not made past `cap` bytes.
    fn estimate_within(&self, distance_in_voxels: f64, along_surface: bool, cap: u64) -> u64 {
        if !distance_in_voxels.is_finite() {
            return 0;
        }
        // The Euclidean limit is the largest, so its estimate bounds the others'.
        let step = Step { radius: distance_in_voxels.abs(), grow: distance_in_voxels > 0.0, metric: Metric::Euclidean };
        band::estimate(self, step, along_surface, cap)
    }

    /// Refuses `job` before any of its steps (offsets by `steps` voxels) runs when the
    /// largest of their estimates ([`LinearOctree::offset_estimate`], each taken on this
    /// solid) exceeds `budget`, naming that estimate and the budget. A later step's
    /// band is an intermediate solid's, so each step is checked again as it starts.
    pub fn check_offset_steps(
        &self,
        job: impl Into<String>,
        steps: &[f64],
        along_surface: bool,
        budget: MemoryBudget,
    ) -> Result<()> {
        let estimate = steps.iter().map(|&d| self.estimate_within(d, along_surface, budget.0)).max().unwrap_or(0);
        budget.check(job, estimate)
    }

    /// One morphological step by either rule.
    fn step(
        &self,
        distance_in_voxels: f64,
        surface: Option<&dyn FaceCrossings>,
        options: &OffsetOptions,
    ) -> Result<(LinearOctree, Vec<NewCrossing>)> {
        if !distance_in_voxels.is_finite() {
            return Err(Error::invalid("offset distance", format!("{distance_in_voxels} is not finite")));
        }
        if surface.is_some() && options.metric != Metric::Euclidean {
            return Err(Error::invalid(
                "offset metric",
                format!("along a surface the distance is Euclidean, not {}: offset the voxels alone", options.metric),
            ));
        }
        let grow = distance_in_voxels > 0.0;
        let step = Step { radius: distance_in_voxels.abs(), grow, metric: options.metric };
        let (runs, crossings) = changed_runs(self, step, surface, options.budget, options.progress)?;
        stop_if_cancelled(options.progress)?;
        if runs.is_empty() {
            return Ok((self.clone(), crossings));
        }
        let changed = LinearOctree::from_sorted_runs(*self.domain(), runs);
        let tree = if grow { self.union(&changed)? } else { self.difference(&changed)? };
        Ok((tree, crossings))
    }

    /// The wall of `thickness` voxels inside the surface (the solid minus its offset by
    /// `-thickness`), or outside it when `outward` (the offset by `thickness` minus the
    /// solid).
    ///
    /// Fails when `thickness` is not finite and positive or the budget is exceeded.
    pub fn shell(&self, thickness_in_voxels: f64, outward: bool, options: &OffsetOptions) -> Result<LinearOctree> {
        positive("shell thickness", thickness_in_voxels)?;
        let step = if outward { thickness_in_voxels } else { -thickness_in_voxels };
        self.check_offset_steps(
            format!("shell of {} voxels", crate::error::in_voxels(thickness_in_voxels)),
            &[step],
            false,
            options.budget,
        )?;
        if outward {
            self.offset(thickness_in_voxels, options)?.difference(self)
        } else {
            self.difference(&self.offset(-thickness_in_voxels, options)?)
        }
    }

    /// The solid with its convex edges (`convex`: the opening by a ball of `radius`
    /// voxels) and its concave edges (`concave`: the closing) rounded; both: the
    /// opening, then the closing.
    ///
    /// Fails when `radius` is not finite and positive or the budget is exceeded.
    pub fn round(
        &self,
        radius_in_voxels: f64,
        convex: bool,
        concave: bool,
        options: &OffsetOptions,
    ) -> Result<LinearOctree> {
        positive("round radius", radius_in_voxels)?;
        let steps = if convex || concave { vec![-radius_in_voxels, radius_in_voxels] } else { Vec::new() };
        self.check_offset_steps(
            format!("round by {} voxels", crate::error::in_voxels(radius_in_voxels)),
            &steps,
            false,
            options.budget,
        )?;
        // Two offsets a kind of edge, on one bar.
        let stages = Stages::new(options.progress, 2 * (u64::from(convex) + u64::from(concave)));
        let options = &OffsetOptions { progress: &stages, ..*options };
        let mut tree = self.clone();
        if convex {
            tree = tree.offset(-radius_in_voxels, options)?.offset(radius_in_voxels, options)?;
        }
        if concave {
            tree = tree.offset(radius_in_voxels, options)?.offset(-radius_in_voxels, options)?;
        }
        Ok(tree)
    }
}

/// Fails unless `value` is finite and positive.
fn positive(what: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(what, format!("{} is not a finite positive number of voxels", crate::error::Number(value))))
    }
}
