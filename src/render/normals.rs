//! Smooth surface normals estimated from the octree: the negated occupancy gradient
//! over a ball of voxels around the surface point.
//!
//! `n ~ -sum_c occ(c) w(|c - q|) (c - q)`, over the voxel centres `c` within `r + 1/2`
//! voxels of the point `q` (voxel units), with `w(s) = 1 - s^2 / (r + 1/2)^2`: a
//! smooth, symmetric window, so a flat surface at any orientation gives a normal close
//! to its own, and the estimate varies continuously with `q` (no per-voxel facets in
//! reflections and refractions). Cost: one [`LinearOctree::occupancy`] of a
//! `(2r + 2)^3` cube a query; where a lattice plane through the point splits that cube
//! into a full and an empty half (a flat face), the face's axis normal, found by a
//! few box classifications instead.

use glam::DVec3;

use crate::octree::LinearOctree;
use crate::shape::Class;

/// Default window radius in voxels.
pub const SMOOTH_RADIUS: u32 = 4;

/// The outward unit normal estimated at the world point `p` with window radius
/// `radius` voxels; `None` where the window is uniformly full or empty (no gradient).
#[must_use]
pub fn smooth_normal(tree: &LinearOctree, p: DVec3, radius: u32) -> Option<DVec3> {
    let d = tree.domain();
    let q = (p - d.min()) / d.voxel_size();
    let reach = f64::from(radius) + 0.5;
    // Voxels whose centres can lie within `reach` of q.
    let lo = (q - DVec3::splat(reach + 0.5)).floor();
    let size = 2 * radius + 2;
    if let Some(n) = flat(tree, lo, size, q) {
        return Some(n);
    }
    let full = tree.occupancy(lo.to_array().map(|c| c as i64), size);
    let s = size as usize;
    let mut gradient = DVec3::ZERO;
    for (i, _) in full.iter().enumerate().filter(|(_, f)| **f) {
        let c = lo + DVec3::new((i % s) as f64, (i / s % s) as f64, (i / (s * s)) as f64) + DVec3::splat(0.5);
        let offset = c - q;
        let w = 1.0 - offset.length_squared() / (reach * reach);
        if w > 0.0 {
            gradient += offset * w;
        }
    }
    (-gradient).try_normalize()
}

/// The axis normal when the window (the cube of `size` voxels from `lo`) is cut by a
/// lattice plane through `q` into a full half and an empty half: a flat face, whose
/// estimate would be that axis up to the window's discretization. Two box
/// classifications an axis, which stop early on uniform nodes.
fn flat(tree: &LinearOctree, lo: DVec3, size: u32, q: DVec3) -> Option<DVec3> {
    let n = i64::from(tree.domain().resolution());
    let lo = lo.to_array().map(|c| c as i64);
    if lo.iter().any(|&c| c < 0 || c + i64::from(size) > n) {
        return None;
    }
    let lo = lo.map(|c| c as u32);
    let hi = lo.map(|c| c + size);
    for a in 0..3 {
        let k = q[a].round() as u32;
        if k <= lo[a] || k >= hi[a] {
            continue;
        }
        let (mut below_hi, mut above_lo) = (hi, lo);
        below_hi[a] = k;
        above_lo[a] = k;
        let mut axis = DVec3::ZERO;
        match (tree.classify_voxel_box(lo, below_hi), tree.classify_voxel_box(above_lo, hi)) {
            (Class::Inside, Class::Outside) => axis[a] = 1.0,
            (Class::Outside, Class::Inside) => axis[a] = -1.0,
            _ => continue,
        }
        return Some(axis);
    }
    None
}
