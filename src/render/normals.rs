//! Smooth surface normals estimated from the octree: the negated occupancy gradient
//! over a ball of voxels around the hit voxel.
//!
//! `n ~ -sum_d occ(v + d) w(|d|) d`, over integer offsets `d` with `|d| <= r`, with
//! `w(s) = 1 - s^2 / (r + 1/2)^2` (a smooth, symmetric window, so a flat surface at
//! any orientation gives a normal close to its own), normalized. Cost: one
//! [`LinearOctree::occupancy`] of a `(2r + 1)^3` cube a query.

use glam::DVec3;

use crate::octree::LinearOctree;

/// Default window radius in voxels.
pub const SMOOTH_RADIUS: u32 = 4;

/// The outward unit normal estimated at `voxel` with window radius `radius` voxels;
/// `None` where the window is uniformly full or empty around it (no gradient).
#[must_use]
pub fn smooth_normal(tree: &LinearOctree, voxel: [u32; 3], radius: u32) -> Option<DVec3> {
    let r = i64::from(radius);
    let size = 2 * radius + 1;
    let lo = voxel.map(|c| i64::from(c) - r);
    let full = tree.occupancy(lo, size);
    let reach = (radius as f64 + 0.5).powi(2);
    let mut gradient = DVec3::ZERO;
    let s = size as usize;
    for (i, _) in full.iter().enumerate().filter(|(_, f)| **f) {
        let d = DVec3::new((i % s) as f64, (i / s % s) as f64, (i / (s * s)) as f64) - DVec3::splat(r as f64);
        let w = 1.0 - d.length_squared() / reach;
        if w > 0.0 {
            gradient += d * w;
        }
    }
    (-gradient).try_normalize()
}
