//! A solid cut by an axis-aligned plane: the part at or below a lattice plane, what a
//! section view shows (the cut face is the solid's own voxel faces on the plane, a
//! filled cap, since the solid is solid).
//!
//! One pass over the sorted nodes: a node wholly below the plane is kept, one wholly
//! above dropped, and one the plane crosses replaced by its children, recursively
//! (the plane is a lattice plane, so the recursion ends at voxels at the latest). The
//! children of a node take its place in Morton order, so the output stays sorted; no
//! eight siblings can all survive a cut of their parent, so it stays canonical. Cost:
//! the nodes, plus eight for each node crossed at each level.

use super::{LinearOctree, NodeKey};
use crate::shape::Axis;

impl LinearOctree {
    /// The voxels whose index along `axis` is below `plane` (voxel units of the
    /// domain, `0..=2^depth`; a plane past either end keeps everything or nothing).
    #[must_use]
    pub fn below_plane(&self, axis: Axis, plane: u32) -> LinearOctree {
        let (a, depth) = (axis.index(), self.depth());
        let mut keys = Vec::with_capacity(self.node_count());
        let mut crossed: Vec<NodeKey> = Vec::new();
        for &key in self.keys() {
            crossed.push(key);
            while let Some(key) = crossed.pop() {
                let node = key.node(depth);
                let (lo, hi) = (node.min[a], node.min[a] + node.size);
                if hi <= plane {
                    keys.push(key);
                } else if lo < plane {
                    // Children in reverse, so they pop in Morton order.
                    crossed.extend((0..8).rev().filter_map(|i| key.child(i)));
                }
            }
        }
        LinearOctree::from_keys(*self.domain(), keys).expect("a cut keeps the keys sorted and disjoint")
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::Domain;

    /// Against the voxels one by one, on every plane of every axis.
    #[test]
    fn keeps_exactly_the_voxels_below_the_plane() {
        let d = Domain::new(glam::DVec3::ZERO, 1.0, 4).unwrap();
        let mut seed = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        // Large nodes and single voxels: a ball of voxels plus scattered ones.
        let voxels: Vec<[u32; 3]> = (0..16u32)
            .flat_map(|x| (0..16u32).flat_map(move |y| (0..16u32).map(move |z| [x, y, z])))
            .filter(|v| v.iter().map(|&c| (f64::from(c) - 7.5).powi(2)).sum::<f64>() < 36.0)
            .chain((0..60).map(|_| [0; 3].map(|_| (next() % 16) as u32)))
            .collect();
        let tree = LinearOctree::from_voxels(d, voxels.clone()).unwrap();
        for axis in [Axis::X, Axis::Y, Axis::Z] {
            for plane in 0..=17 {
                let cut = tree.below_plane(axis, plane);
                cut.validate().unwrap();
                for x in 0..16 {
                    for y in 0..16 {
                        for z in 0..16 {
                            let v = [x, y, z];
                            let expected = tree.contains_voxel(v) && v[axis.index()] < plane;
                            assert_eq!(cut.contains_voxel(v), expected, "{axis:?} {plane} {v:?}");
                        }
                    }
                }
            }
        }
    }
}
