//! Smooth surface normals estimated from the octree: the negated occupancy gradient
//! over a ball of voxels around the surface point.
//!
//! `n ~ -sum_c occ(c) w(|c - q|) (c - q)`, over the voxel centres `c` within `r + 1/2`
//! voxels of the point `q` (voxel units), with `w(s) = 1 - s^2 / (r + 1/2)^2`: a
//! smooth, symmetric window, so a flat surface at any orientation gives a normal close
//! to its own, and the estimate varies continuously with `q` (no per-voxel facets in
//! reflections and refractions). Where a lattice plane through the point splits the
//! window's cube into a full and an empty half (a flat face), the face's axis normal.
//!
//! Method: the cube of `2r + 2` voxels around `q` is read as one bit pattern a row of
//! voxels along x (`Window`); a row at offsets `(dy, dz)` with `rho^2 = dy^2 + dz^2`
//! adds, over its full voxels inside the ball, `(a S1 - S3 / R^2, dy (a S0 - S2 / R^2),
//! dz (a S0 - S2 / R^2))` with `a = 1 - rho^2 / R^2`, `R = r + 1/2` and `Sk = sum dx^k`,
//! so a query costs a pass over the rows' set bits. [`NormalField`], the renderer's
//! form, reads the rows from cached 16^3 bricks of the octree's occupancy, which
//! neighbouring hits share.

use std::sync::Arc;

use dashmap::DashMap;
use glam::DVec3;
use rustc_hash::FxBuildHasher;

use crate::octree::LinearOctree;

/// Default window radius in voxels.
pub const SMOOTH_RADIUS: u32 = 4;

/// Largest window radius: windows of up to 16 voxels a side.
pub const MAX_RADIUS: u32 = 7;

/// The outward unit normal estimated at the world point `p` with window radius
/// `radius` voxels (at most [`MAX_RADIUS`]); `None` where the window is uniformly full
/// or empty (no gradient).
#[cfg(test)]
fn smooth_normal(tree: &LinearOctree, p: DVec3, radius: u32) -> Option<DVec3> {
    let (q, lo, size) = placement(tree, p, radius);
    let full = tree.occupancy(lo, size as u32);
    let mut window = Window::empty(lo, size);
    for (i, _) in full.iter().enumerate().filter(|(_, f)| **f) {
        window.rows[i / size] |= 1 << (i % size);
    }
    window.normal(q, radius)
}

/// The window around the world point `p`: the point in voxel units, the window's
/// lowest voxel and its size, `2 radius + 2` (the voxels whose centres can lie within
/// `radius + 1/2` of the point).
fn placement(tree: &LinearOctree, p: DVec3, radius: u32) -> (DVec3, [i64; 3], usize) {
    let radius = radius.min(MAX_RADIUS);
    let d = tree.domain();
    let q = (p - d.min()) / d.voxel_size();
    let lo = (q - DVec3::splat(f64::from(radius) + 1.0)).floor();
    (q, lo.to_array().map(|c| c as i64), 2 * radius as usize + 2)
}

/// Occupancy of a cube of voxels: `rows[y + size z]` bit `x` is voxel `lo + (x, y, z)`.
struct Window {
    lo: [i64; 3],
    size: usize,
    rows: [u32; 256],
}

impl Window {
    fn empty(lo: [i64; 3], size: usize) -> Self {
        Window { lo, size, rows: [0; 256] }
    }

    /// The estimate at `q` (voxel units), see the module doc.
    fn normal(&self, q: DVec3, radius: u32) -> Option<DVec3> {
        if let Some(n) = self.flat(q) {
            return Some(n);
        }
        let s = self.size;
        let reach = f64::from(radius.min(MAX_RADIUS)) + 0.5;
        let r2 = reach * reach;
        let offset = |a: usize, i: usize| (self.lo[a] + i as i64) as f64 + 0.5 - q[a];
        let dx: [f64; 16] = std::array::from_fn(|i| offset(0, i));
        let dx2 = dx.map(|v| v * v);
        let mut gradient = DVec3::ZERO;
        for z in 0..s {
            let dz = offset(2, z);
            for y in 0..s {
                let dy = offset(1, y);
                let rho2 = dy * dy + dz * dz;
                let mut bits = self.rows[y + s * z];
                if rho2 >= r2 || bits == 0 {
                    continue;
                }
                let limit = r2 - rho2;
                let (mut s0, mut s1, mut s2, mut s3) = (0.0, 0.0, 0.0, 0.0);
                while bits != 0 {
                    let i = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    if dx2[i] < limit {
                        s0 += 1.0;
                        s1 += dx[i];
                        s2 += dx2[i];
                        s3 += dx2[i] * dx[i];
                    }
                }
                let a = 1.0 - rho2 / r2;
                let across = a * s0 - s2 / r2;
                gradient += DVec3::new(a * s1 - s3 / r2, dy * across, dz * across);
            }
        }
        (-gradient).try_normalize()
    }

    /// The axis normal when a lattice plane through (the rounded) `q` cuts the window
    /// into a full half and an empty half.
    fn flat(&self, q: DVec3) -> Option<DVec3> {
        let s = self.size;
        let all = (1u32 << s) - 1;
        for a in 0..3 {
            let k = q[a].round() as i64 - self.lo[a];
            if k <= 0 || k >= s as i64 {
                continue;
            }
            let k = k as usize;
            // The rows expected when the half below the plane is full.
            let below_full = |y: usize, z: usize| match a {
                0 => (1u32 << k) - 1,
                1 if y < k => all,
                2 if z < k => all,
                _ => 0,
            };
            let rows = || (0..s * s).map(|i| (self.rows[i], below_full(i % s, i / s)));
            let mut axis = DVec3::ZERO;
            if rows().all(|(row, want)| row == want) {
                axis[a] = 1.0;
            } else if rows().all(|(row, want)| row == all ^ want) {
                axis[a] = -1.0;
            } else {
                continue;
            }
            return Some(axis);
        }
        None
    }
}

/// Voxels a side of a cached brick.
const BRICK: i64 = 16;

/// A brick's occupancy: `rows[y + 16 z]` bit `x`.
type Brick = [u16; 256];

/// The smooth normals of one solid ([`smooth_normal`] with radius [`SMOOTH_RADIUS`]),
/// reading the occupancy from 16^3 bricks read from the octree on first use. Safe to
/// share between threads; the normals do not depend on the order of the queries and
/// equal [`smooth_normal`]'s.
#[derive(Clone, Debug, Default)]
pub struct NormalField {
    bricks: DashMap<[i64; 3], Arc<Brick>, FxBuildHasher>,
}

impl NormalField {
    /// An empty field (no brick read yet).
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// The outward unit normal of `tree` at the world point `p`, as [`smooth_normal`].
    #[must_use]
    pub fn normal(&self, tree: &LinearOctree, p: DVec3) -> Option<DVec3> {
        let (q, lo, size) = placement(tree, p, SMOOTH_RADIUS);
        let first = lo.map(|c| c.div_euclid(BRICK));
        let last = lo.map(|c| (c + size as i64 - 1).div_euclid(BRICK));
        // The window's bricks: one or two an axis (none read where it needs only one).
        let bricks: [Option<Arc<Brick>>; 8] = std::array::from_fn(|i| {
            let b: [i64; 3] = std::array::from_fn(|a| first[a] + ((i >> a) & 1) as i64);
            if (0..3).any(|a| b[a] > last[a]) { None } else { self.brick(tree, b) }
        });
        let mut window = Window::empty(lo, size);
        let shift = lo[0].rem_euclid(BRICK);
        for z in 0..size {
            let wz = lo[2] + z as i64;
            for y in 0..size {
                let wy = lo[1] + y as i64;
                let slot = (wy.div_euclid(BRICK) - first[1]) * 2 + (wz.div_euclid(BRICK) - first[2]) * 4;
                let at = (wy.rem_euclid(BRICK) + BRICK * wz.rem_euclid(BRICK)) as usize;
                let row = |dx: i64| bricks[(slot + dx) as usize].as_ref().map_or(0, |b| u32::from(b[at]));
                let both = u64::from(row(0)) | u64::from(row(1)) << BRICK;
                window.rows[y + size * z] = (both >> shift) as u32 & ((1u32 << size) - 1);
            }
        }
        window.normal(q, SMOOTH_RADIUS)
    }

    /// The brick at brick coordinates `b`, read on first use; `None` outside the domain.
    fn brick(&self, tree: &LinearOctree, b: [i64; 3]) -> Option<Arc<Brick>> {
        let n = i64::from(tree.domain().resolution());
        if b.iter().any(|&c| c < 0 || c * BRICK >= n) {
            return None;
        }
        if let Some(brick) = self.bricks.get(&b) {
            return Some(Arc::clone(&brick));
        }
        let full = tree.occupancy(b.map(|c| c * BRICK), BRICK as u32);
        let mut rows = [0u16; 256];
        for (i, _) in full.iter().enumerate().filter(|(_, f)| **f) {
            rows[i / 16] |= 1 << (i % 16);
        }
        Some(Arc::clone(&self.bricks.entry(b).or_insert_with(|| Arc::new(rows))))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::{Domain, VoxelizeOptions, voxelize};
    use crate::shape::{Csg, Cuboid, Sphere};
    use crate::test_util::Rng;

    #[test]
    fn smooth_normals_of_a_voxelized_sphere_follow_the_sphere() {
        let center = DVec3::new(0.013, -0.021, 0.007);
        let sphere = Sphere::new(center, 0.8).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 9).unwrap();
        let tree = voxelize(&sphere, domain, &VoxelizeOptions::default()).unwrap();
        // Surface voxels: full with an empty face neighbour; every 7th of them.
        let mut rng = Rng(5);
        let (mut total, mut good) = (0, 0);
        for node in tree.nodes().filter(|n| n.size == 1) {
            let v = node.min;
            let exposed = (0..6).any(|f| {
                let mut w = v.map(i64::from);
                w[f / 2] += if f % 2 == 0 { -1 } else { 1 };
                !tree.contains_voxel(w.map(|c| c as u32))
            });
            if !exposed || rng.below(7) != 0 {
                continue;
            }
            total += 1;
            let want = (domain.voxel_center(v) - center).normalize();
            let got =
                smooth_normal(&tree, domain.voxel_center(v), SMOOTH_RADIUS).expect("a surface voxel has a gradient");
            if got.angle_between(want).to_degrees() < 5.0 {
                good += 1;
            }
        }
        assert!(total > 10_000, "{total} surface voxels sampled");
        assert!(good as f64 >= 0.95 * total as f64, "{good} of {total} within 5 degrees");
    }

    #[test]
    fn the_cached_normal_field_equals_the_direct_estimate() {
        // A carved sphere and a slab reaching the domain's faces (windows cut by the
        // boundary), at a depth where 16-voxel bricks straddle every window.
        let sphere = Sphere::new(DVec3::new(0.11, -0.07, 0.2), 0.62).unwrap();
        let notch = Cuboid::new(DVec3::new(0.5, 0.0, 0.5), DVec3::splat(0.5)).unwrap();
        let slab = Cuboid::new(DVec3::new(0.0, 0.0, -0.8), DVec3::new(2.5, 2.5, 0.3)).unwrap();
        let solid = (Csg::leaf(sphere) - Csg::leaf(notch)) | Csg::leaf(slab);
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 7).unwrap();
        let tree = voxelize(&solid, domain, &VoxelizeOptions::default()).unwrap();
        let field = NormalField::new();
        let mut rng = Rng(77);
        let mut some = 0;
        for _ in 0..20_000 {
            let p = rng.vec(-1.0, 1.0);
            let want = smooth_normal(&tree, p, SMOOTH_RADIUS);
            assert_eq!(field.normal(&tree, p), want, "at {p}");
            some += usize::from(want.is_some());
        }
        assert!(some > 2_000, "{some} points near the surface");
        // The slab's top face (voxelized at the lattice plane nearest z = -0.65) is flat:
        // exactly its axis.
        for _ in 0..1_000 {
            let p = DVec3::new(rng.unit() * 1.2 - 0.6, rng.unit() * 1.2 - 0.6, -0.65);
            if (p - DVec3::new(0.11, -0.07, 0.2)).length() > 0.62 + 0.3 {
                assert_eq!(field.normal(&tree, p), Some(DVec3::Z), "at {p}");
            }
        }
    }
}
