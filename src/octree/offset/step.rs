//! One morphological step of an offset: a ball's radius in voxels and whether it grows
//! or shrinks the solid, with the reach and the squared-distance limit the sparse tiles
//! ([`super::tiles`], and along a surface [`super::features`]) compute from it, and what
//! a step gives.

use super::metric::Metric;
use super::subvoxel::NewCrossing;

/// What a step gives: the Morton runs of the voxels that change, and along a surface
/// the crossings of the result's faces (sorted by voxel and direction).
pub(super) type Changes = (Vec<(u64, u64)>, Vec<NewCrossing>);

/// One morphological step: grow (dilate) or shrink (erode) by a ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Step {
    /// The ball's radius in voxels (between voxel centres), positive.
    pub radius: f64,
    /// Dilation (add empty voxels near full ones) or erosion (the reverse).
    pub grow: bool,
    /// The distance measured (Euclidean along a surface).
    pub metric: Metric,
}

impl Step {
    /// `R`: the most voxels a step can reach along one axis (a voxel `o` voxels away
    /// is `|o| - 1/2` away, which must be under the radius).
    pub(super) fn reach(self) -> u32 {
        ((self.radius + 0.5).ceil() - 1.0).clamp(0.0, f64::from(u32::MAX / 4)) as u32
    }

    /// `R` along the surface: a voxel changes only when its nearest site's cube lies
    /// under `radius + 1/2` away (see [`super::subvoxel`]), so `|o| < radius + 1`.
    pub(super) fn reach_along_surface(self) -> u32 {
        self.radius.ceil().clamp(0.0, f64::from(u32::MAX / 4)) as u32
    }

    /// A voxel changes when its sum of costs ([`Metric::axis_cost`]) is at most this:
    /// Euclidean, four times its squared distance strictly under `4 radius^2`.
    pub(super) fn limit(self) -> i64 {
        self.metric.limit(self.radius)
    }
}
