//! The convex hull of a solid: the convex hull of its voxels' corners, voxelized into
//! the same domain, exactly.
//!
//! The hull of a union of boxes is the hull of their corners, so only the nodes'
//! corners matter, and of those only the candidates for hull vertices are kept: a
//! vertex is the lowest or highest corner of its row along x (for its y and z), and a
//! vertex of the 2D hull of its z plane's row ends (Andrew's monotone chain, exact in
//! integers). The 3D hull of what is left is exact ([`crate::shape`]'s quickhull on
//! lattice points: every predicate in `i128`), and so is the voxelization: in doubled
//! lattice units a voxel's centre `2 v + 1` is in the hull when `n . (2 v + 1) <= 2 d`
//! for every plane `n . x <= d`, and a node is full when its highest centre along
//! every plane's normal passes, empty when its lowest fails one. Each node hands its
//! children only the planes that still cross it, so the walk (the voxelization
//! driver's: Morton order, canonical merge, parallel top levels, budget, progress)
//! costs the planes near a node, not all of them. Voxels are decided by their centres
//! (`<=`: a centre on a plane is inside), as every voxelizer decides them.
//!
//! Departures: no other filters (a 3D hull vertex is also extreme along y and z rows;
//! the x rows and z planes already leave `O(n^{5/3})` points of an `n^3` lattice).

use std::sync::Arc;

use rustc_hash::FxHashMap;

use super::driver::{Decision, Plan, VoxelizeOptions, Voxelizer};
use super::linear::LinearOctree;
use super::node::NodeKey;
use crate::error::{Error, Result};
use crate::morton;
use crate::shape::{HULL_LIMIT, convex_hull, distinct_planes};

impl LinearOctree {
    /// The convex hull of the solid's voxels (of their corners), voxelized into the
    /// same domain (see the module doc). An empty solid's hull is empty; a flat one
    /// (its corners on one plane cannot be: a voxel has volume) never happens.
    ///
    /// Refuses (before voxelizing) when the estimate of the result exceeds
    /// `options.budget`.
    pub fn hull(&self, options: &VoxelizeOptions) -> Result<LinearOctree> {
        let domain = *self.domain();
        if self.is_empty() {
            return Ok(LinearOctree::empty(domain));
        }
        let points = candidates(self);
        debug_assert!(points.iter().flatten().all(|c| c.abs() < HULL_LIMIT));
        let faces = convex_hull(&points).ok_or_else(|| Error::invalid("hull", "the solid's corners are flat"))?;
        let planes: Vec<Plane> = distinct_planes(&faces).into_iter().map(|(n, d, _)| Plane { n, d2: 2 * d }).collect();
        // The hull's surface is at most the box of the solid's; nodes near it as a
        // shape's voxelization estimates them.
        let side = f64::from(domain.resolution());
        let estimate = (2.0 * 6.0 * side * side * 8.0 * 2.0) as u64 + 4096;
        let plan = Plan::new("taking the hull", estimate, domain, options)?;
        let all: Arc<[u32]> = (0..planes.len() as u32).collect();
        Ok(plan.run(&PlaneVoxelizer { planes }, all)?.0)
    }
}

/// The corners that can be hull vertices (module doc), as lattice points.
fn candidates(tree: &LinearOctree) -> Vec<[i64; 3]> {
    // (y, z) -> the least and greatest x of a corner on that row.
    let mut rows: FxHashMap<(u32, u32), (u32, u32)> = FxHashMap::default();
    for key in tree.keys() {
        let lo = morton::decode(key.start());
        let size = 1u32 << key.k();
        for (y, z) in [(lo[1], lo[2]), (lo[1] + size, lo[2]), (lo[1], lo[2] + size), (lo[1] + size, lo[2] + size)] {
            let row = rows.entry((y, z)).or_insert((lo[0], lo[0] + size));
            row.0 = row.0.min(lo[0]);
            row.1 = row.1.max(lo[0] + size);
        }
    }
    let mut planes: FxHashMap<u32, Vec<[i64; 2]>> = FxHashMap::default();
    for (&(y, z), &(x0, x1)) in &rows {
        let plane = planes.entry(z).or_default();
        plane.push([i64::from(x0), i64::from(y)]);
        plane.push([i64::from(x1), i64::from(y)]);
    }
    let mut points = Vec::new();
    let mut zs: Vec<u32> = planes.keys().copied().collect();
    zs.sort_unstable();
    for z in zs {
        for [x, y] in hull_2d(planes.remove(&z).expect("a plane")) {
            points.push([x, y, i64::from(z)]);
        }
    }
    points
}

/// The vertices of the 2D convex hull of `points` (Andrew's monotone chain; exact).
fn hull_2d(mut points: Vec<[i64; 2]>) -> Vec<[i64; 2]> {
    points.sort_unstable();
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let cross = |o: [i64; 2], a: [i64; 2], b: [i64; 2]| (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
    let mut hull: Vec<[i64; 2]> = Vec::with_capacity(2 * points.len());
    for pass in [false, true] {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &[i64; 2]>> =
            if pass { Box::new(points.iter().rev()) } else { Box::new(points.iter()) };
        for &p in iter {
            while hull.len() >= start + 2 && cross(hull[hull.len() - 2], hull[hull.len() - 1], p) <= 0 {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// A plane `n . x <= d2 / 2` in lattice units (`d2` doubled for centres `2 v + 1`).
struct Plane {
    n: [i128; 3],
    d2: i128,
}

/// Decides nodes by the planes still crossing their parent (module doc).
struct PlaneVoxelizer {
    planes: Vec<Plane>,
}

impl Voxelizer for PlaneVoxelizer {
    type Node = Arc<[u32]>;
    type Counters = ();

    fn decide(&self, key: NodeKey, node: Arc<[u32]>, (): &mut ()) -> Decision<Arc<[u32]>> {
        let lo = morton::decode(key.start()).map(|c| 2 * i128::from(c) + 1);
        let span = 2 * (i128::from(1u32 << key.k()) - 1);
        let mut crossing = Vec::new();
        for &i in node.iter() {
            let plane = &self.planes[i as usize];
            let (mut least, mut most) = (0i128, 0i128);
            for (n, low) in plane.n.iter().zip(lo) {
                let (low, high) = (n * low, n * (low + span));
                least += low.min(high);
                most += low.max(high);
            }
            if least > plane.d2 {
                return Decision::Empty;
            }
            if most > plane.d2 {
                crossing.push(i);
            }
        }
        if crossing.is_empty() {
            return Decision::Full;
        }
        let crossing: Arc<[u32]> = if crossing.len() == node.len() { node } else { crossing.into() };
        Decision::Split(std::array::from_fn(|_| crossing.clone()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::Domain;
    use crate::shape::Csg;
    use glam::DVec3;

    /// Brute force: every plane through three of `corners` with all of them on one
    /// side is a hull plane (as `n . x <= d`, lattice units).
    fn brute_planes(corners: &[[i128; 3]]) -> Vec<([i128; 3], i128)> {
        let mut planes = Vec::new();
        for (i, a) in corners.iter().enumerate() {
            for (j, b) in corners.iter().enumerate().skip(i + 1) {
                for c in corners.iter().skip(j + 1) {
                    let (u, w) = ([0, 1, 2].map(|k| b[k] - a[k]), [0, 1, 2].map(|k| c[k] - a[k]));
                    let n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
                    if n == [0; 3] {
                        continue;
                    }
                    let d: i128 = (0..3).map(|k| n[k] * a[k]).sum();
                    let side = |p: &[i128; 3]| (0..3).map(|k| n[k] * p[k]).sum::<i128>() - d;
                    if corners.iter().all(|p| side(p) <= 0) {
                        planes.push((n, d));
                    } else if corners.iter().all(|p| side(p) >= 0) {
                        planes.push((n.map(|x| -x), -d));
                    }
                }
            }
        }
        planes
    }

    /// Whether the voxel `v`'s centre is inside every plane (doubled units).
    fn inside(planes: &[([i128; 3], i128)], v: [u32; 3]) -> bool {
        let c = v.map(|x| 2 * i128::from(x) + 1);
        planes.iter().all(|(n, d)| (0..3).map(|k| n[k] * c[k]).sum::<i128>() <= 2 * d)
    }

    /// Brute force over every corner of the scattered voxels (module doc's oracle).
    #[test]
    fn the_hull_of_scattered_voxels_is_the_brute_force_hull_of_their_corners() {
        let domain = Domain::new(DVec3::ZERO, 1.0, 4).unwrap();
        let mut seed = 12345u64;
        for round in 0..6 {
            let mut voxels = Vec::new();
            for _ in 0..3 + round {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                let v = [(seed >> 20) as u32 % 16, (seed >> 30) as u32 % 16, (seed >> 40) as u32 % 16];
                voxels.push(v);
            }
            let tree = LinearOctree::from_voxels(domain, voxels.iter().copied()).unwrap();
            let hull = tree.hull(&VoxelizeOptions::default()).unwrap();
            let corners: Vec<[i128; 3]> = voxels
                .iter()
                .flat_map(|v| (0..8).map(move |c| [0, 1, 2].map(|a| i128::from(v[a] + (c >> a & 1)))))
                .collect();
            let planes = brute_planes(&corners);
            let mut count = 0;
            for x in 0..16u32 {
                for y in 0..16u32 {
                    for z in 0..16u32 {
                        let want = inside(&planes, [x, y, z]);
                        assert_eq!(hull.contains_voxel([x, y, z]), want, "round {round} voxel {x} {y} {z}");
                        count += usize::from(want);
                    }
                }
            }
            assert_eq!(hull.voxel_count(), count as u64);
        }
    }

    /// Non-convex solids at depth 5 (a box minus a ball, with a ball beside it): the
    /// brute force over the corners of their voxels that lie at both ends of their
    /// lines along x, y and z (a point between two others on a line is no hull vertex,
    /// so the hull of these is the hull of all corners).
    #[test]
    fn the_hull_of_a_difference_at_depth_5_is_the_brute_force_hull_of_its_corners() {
        use crate::octree::voxelize;
        use crate::shape::{Cuboid, Sphere};
        let domain = Domain::new(DVec3::ZERO, 1.0, 5).unwrap();
        let cases = [
            (DVec3::new(0.4, 0.45, 0.5), DVec3::new(0.5, 0.3, 0.4), DVec3::new(0.6, 0.6, 0.7), 0.25),
            (DVec3::new(0.5, 0.5, 0.4), DVec3::new(0.6, 0.5, 0.3), DVec3::new(0.3, 0.3, 0.3), 0.3),
        ];
        for (n, (centre, size, hole, radius)) in cases.into_iter().enumerate() {
            let shape = (Csg::from(Cuboid::new(centre, size).unwrap()) - Sphere::new(hole, radius).unwrap())
                | Sphere::new(DVec3::new(0.8, 0.2, 0.75), 0.1).unwrap();
            let tree = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
            let hull = tree.hull(&VoxelizeOptions::default()).unwrap();
            // Every corner of a full voxel, then those at both ends of their three lines.
            let mut corners = std::collections::BTreeSet::new();
            for v in (0..32u32 * 32 * 32).map(|i| [i % 32, i / 32 % 32, i / 1024]).filter(|&v| tree.contains_voxel(v)) {
                for c in 0..8u32 {
                    corners.insert([0, 1, 2].map(|a| i128::from(v[a] + (c >> a & 1))));
                }
            }
            let extreme = |p: &[i128; 3]| {
                (0..3).all(|a| {
                    let step = |s: i128| {
                        let mut q = *p;
                        q[a] += s;
                        corners.contains(&q)
                    };
                    !(step(-1) && step(1))
                })
            };
            let kept: Vec<[i128; 3]> = corners.iter().filter(|p| extreme(p)).copied().collect();
            assert!(kept.len() < 400, "case {n}: {} corners for the brute force", kept.len());
            let planes = brute_planes(&kept);
            let mut count = 0u64;
            for i in 0..32u32 * 32 * 32 {
                let v = [i % 32, i / 32 % 32, i / 1024];
                let want = inside(&planes, v);
                assert_eq!(hull.contains_voxel(v), want, "case {n} voxel {v:?}");
                count += u64::from(want);
                assert!(!tree.contains_voxel(v) || want, "case {n}: the hull holds the solid");
            }
            assert_eq!(hull.voxel_count(), count);
            assert!(count > tree.voxel_count(), "case {n}: the solid is not convex");
        }
    }
}
