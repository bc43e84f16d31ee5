//! The band of a morphological step: which voxels a ball of radius `D` can change, and
//! the step's entry point: over the cubes, the sparse tiles of [`super::tiles`]; along
//! a surface, the same tiles with each voxel's nearest site ([`super::features`]).
//!
//! A dilation by `D` adds the empty voxels whose centre lies under `D` from a full
//! voxel; an erosion removes the full voxels whose centre lies under `D` from an empty
//! one (voxels outside the domain are empty). Either changes only voxels within `R =
//! ceil(D + 1/2) - 1` voxels on each axis of a voxel of the other phase; along a
//! surface (the sub-voxel rule of [`super::subvoxel`]) within `ceil(D)` (a voxel whose
//! nearest cube lies `D + 1/2` away can still be under `D` from the surface).
//!
//! Coarse nodes far from the surface are never read. The tiles are transformed in
//! parallel and joined in Morton order, so the result does not depend on the number
//! of threads.

use super::features;
use super::metric::Metric;
use super::step::{Changes, Step};
use super::subvoxel::FaceCrossings;
use super::tiles::TileBand;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::octree::LinearOctree;
use crate::progress::Progress;

/// `step` over the cubes with a radius no larger than the domain needs: every voxel
/// centre lies within `sqrt 3 n` of every voxel (Euclidean; `3n` Manhattan, `n`
/// Chebyshev), so radii of `2n + 2` (`3n + 2`, `n + 2`) and more all flip the same
/// voxels (and the distances stay small).
fn clamped(tree: &LinearOctree, step: Step) -> Step {
    let n = f64::from(tree.domain().resolution());
    let all = match step.metric {
        Metric::Euclidean => 2.0 * n + 2.0,
        Metric::Manhattan => 3.0 * n + 2.0,
        Metric::Chebyshev => n + 2.0,
    };
    Step { radius: step.radius.min(all), ..step }
}

/// The memory `step` (along a surface when `along_surface`) is estimated to need; 0
/// when it reaches no voxel. Past `cap` bytes the band is not made: what it needs at
/// least is returned, more than `cap`.
pub(super) fn estimate(tree: &LinearOctree, step: Step, along_surface: bool, cap: u64) -> u64 {
    let step = clamped(tree, step);
    if along_surface {
        return match features::band(tree, step, cap) {
            Ok(band) => band.map_or(0, |band| features::estimate(&band, step)),
            Err(least) => least,
        };
    }
    match step.reach() {
        0 => 0,
        r => TileBand::of(tree, step, r, cap).map_or_else(|least| least, |band| band.estimate),
    }
}

/// The Morton runs of the voxels of `tree` that `step` changes, sorted, and, along a
/// surface, the crossings of the result's boundary faces in the band from its
/// distance field.
pub(super) fn changed_runs(
    tree: &LinearOctree,
    step: Step,
    surface: Option<&dyn FaceCrossings>,
    budget: MemoryBudget,
    progress: &dyn Progress,
) -> Result<Changes> {
    let step = clamped(tree, step);
    let job = || format!("offset by {} voxels", crate::error::in_voxels(step.radius));
    let Some(surface) = surface else {
        let r = step.reach();
        if r == 0 {
            return Ok((Vec::new(), Vec::new()));
        }
        if step.limit() >= i64::from(u32::MAX) {
            return Err(too_far(step));
        }
        let band = TileBand::of(tree, step, r, budget.0).map_err(|least| budget.refusal(job(), least))?;
        budget.check(job(), band.estimate)?;
        return Ok((band.changed_runs(tree, step, step.limit(), progress), Vec::new()));
    };
    let Some(band) = features::band(tree, step, budget.0).map_err(|least| budget.refusal(job(), least))? else {
        return Ok((Vec::new(), Vec::new()));
    };
    if !features::holds(step) {
        return Err(too_far(step));
    }
    budget.check(job(), features::estimate(&band, step))?;
    Ok(features::changed_runs(tree, step, &band, surface, progress))
}

/// The error of a step whose distances the transform cannot hold.
fn too_far(step: Step) -> Error {
    Error::invalid(
        "offset distance",
        format!("{} voxels is more than the band transform holds on this domain", crate::error::in_voxels(step.radius)),
    )
}
