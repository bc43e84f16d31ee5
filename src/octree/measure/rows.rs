//! The occupancy of a small cube of voxels as rows of bits along x, read from the
//! linear octree: the input of the area estimator's bitwise face and edge tests.
//!
//! Layout: `rows[y + size z]` bit `x` is voxel `lo + (x, y, z)`, for cubes of up to 128
//! voxels a side; voxels outside the domain are empty. Method (that of
//! `LinearOctree::occupancy`): a descent of the implicit tree into the children that
//! meet the cube, from the aligned cubes of its size or more that meet it (at most two
//! an axis, found by galloping from one to the next in Morton order, not from a
//! common ancestor, which can be the root); a node inside one key paints its part of
//! the cube row by row, a node holding no key is skipped, and a node inside the cube
//! (or holding few keys) has its keys painted one by one, clipped. Cost: the keys
//! meeting the cube, the searches along its faces, and its rows.

use crate::morton;
use crate::octree::window::{keys_meeting, range_meeting_near};
use crate::octree::{LinearOctree, NodeKey};

/// Largest cube edge: a row is one [`Row`].
pub(super) const MAX_SIZE: usize = Row::BITS as usize;

/// One row of voxels along x, bit `x` the voxel at offset `x`.
pub(super) type Row = u128;

/// A partly full node with at most this many keys has them painted one by one rather
/// than searched for child by child.
const PAINT_DIRECTLY: usize = 16;

/// A cube of voxels' occupancy, one [`Row`] a row along x (see the module doc).
#[derive(Clone, Debug, Default)]
pub(super) struct Rows {
    size: usize,
    rows: Vec<Row>,
}

impl Rows {
    /// Reads the cube of `size` voxels a side (at most [`MAX_SIZE`]) with lowest voxel
    /// `lo` into `self`, reusing its buffer.
    pub(super) fn read(&mut self, tree: &LinearOctree, lo: [i64; 3], size: usize) {
        debug_assert!(size <= MAX_SIZE);
        self.size = size;
        self.rows.clear();
        self.rows.resize(size * size, 0);
        let n = i64::from(tree.domain().resolution());
        let clo = lo.map(|c| c.clamp(0, n));
        let chi: [i64; 3] = std::array::from_fn(|a| (lo[a] + size as i64).clamp(0, n));
        if (0..3).any(|a| clo[a] >= chi[a]) {
            return;
        }
        let paint = Paint { lo, clo: clo.map(|c| c as u32), chi: chi.map(|c| c as u32) };
        // The aligned cubes of at least the cube's size meeting it (at most two an
        // axis), in Morton order, each found by galloping from the one before.
        let j = (size.next_power_of_two().trailing_zeros()).min(u32::from(tree.depth()));
        let (first, last) = (paint.clo.map(|c| c >> j), paint.chi.map(|c| (c - 1) >> j));
        let mut cubes: Vec<NodeKey> = (first[2]..=last[2])
            .flat_map(|z| (first[1]..=last[1]).flat_map(move |y| (first[0]..=last[0]).map(move |x| [x, y, z])))
            .map(|c| NodeKey::new(morton::encode(c[0] << j, c[1] << j, c[2] << j), j))
            .collect();
        cubes.sort_unstable();
        let keys = tree.keys();
        let mut hint = keys.partition_point(|k| k.end() <= cubes[0].start());
        for cube in cubes {
            let range = range_meeting_near(keys, hint, cube);
            hint = range.end;
            paint.visit(&keys[range], cube, self);
        }
    }

    /// The row at offsets `(y, z)` from the cube's corner.
    #[inline]
    pub(super) fn row(&self, y: usize, z: usize) -> Row {
        self.rows[y + self.size * z]
    }
}

/// The cube being read: its corner, and its part inside the domain `[clo, chi)`.
struct Paint {
    lo: [i64; 3],
    clo: [u32; 3],
    chi: [u32; 3],
}

impl Paint {
    /// Paints the full voxels of `node` (which meets the cube) from the sorted run `keys`.
    fn visit(&self, keys: &[NodeKey], node: NodeKey, out: &mut Rows) {
        let window = match keys_meeting(keys, node) {
            [] => return,
            [key] if key.k() >= node.k() => return self.fill(node, out),
            window => window,
        };
        let min = morton::decode(node.start());
        let size = 1u32 << node.k();
        if window.len() <= PAINT_DIRECTLY || (0..3).all(|a| self.clo[a] <= min[a] && min[a] + size <= self.chi[a]) {
            // Each key of the window lies in the node: painted clipped, no more searches.
            return window.iter().for_each(|&key| self.fill(key, out));
        }
        let half = size / 2;
        for i in 0..8 {
            let child = node.child(i).expect("a partly full node is not a voxel");
            let c = morton::decode(child.start());
            if (0..3).all(|a| c[a] < self.chi[a] && c[a] + half > self.clo[a]) {
                self.visit(window, child, out);
            }
        }
    }

    /// Sets the voxels of the full `node` that lie in the cube (if any).
    fn fill(&self, node: NodeKey, out: &mut Rows) {
        let min = morton::decode(node.start());
        if node.k() == 0 {
            // A voxel, the most common key near a surface: one bit.
            if (0..3).all(|i| self.clo[i] <= min[i] && min[i] < self.chi[i]) {
                let [x, y, z]: [usize; 3] = std::array::from_fn(|i| (i64::from(min[i]) - self.lo[i]) as usize);
                out.rows[y + out.size * z] |= 1 << x;
            }
            return;
        }
        let size = 1u32 << node.k();
        // The node's part of the cube, in offsets from its corner.
        let mut a = [0usize; 3];
        let mut b = [0usize; 3];
        for i in 0..3 {
            let (lo, hi) = (min[i].max(self.clo[i]), (min[i] + size).min(self.chi[i]));
            if lo >= hi {
                return; // a key of a directly painted window outside the cube
            }
            a[i] = (i64::from(lo) - self.lo[i]) as usize;
            b[i] = (i64::from(hi) - self.lo[i]) as usize;
        }
        let width = b[0] - a[0];
        let bits = if width == MAX_SIZE { Row::MAX } else { ((1 << width) - 1) << a[0] };
        for z in a[2]..b[2] {
            let row = &mut out.rows[out.size * z..][a[1]..b[1]];
            row.iter_mut().for_each(|r| *r |= bits);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::Domain;
    use crate::test_util::Rng;
    use glam::DVec3;

    #[test]
    fn rows_match_voxel_lookups_inside_and_outside_the_domain() {
        let domain = Domain::new(DVec3::ZERO, 1.0, 6).unwrap();
        let mut rng = Rng(5);
        let voxels = (0..4000).map(|_| [0; 3].map(|_| rng.below(64) as u32));
        let blocks = (0..8).flat_map(|i| (0..512).map(move |j| [8 * i + j % 8, j / 8 % 8, 40 + j / 64]));
        let tree = LinearOctree::from_voxels(domain, voxels.chain(blocks)).unwrap();
        let mut rows = Rows::default();
        for (lo, size) in
            [([-5i64, 3, 30], 48usize), ([20, -8, 50], 64), ([-30, -9, -2], 128), ([0, 0, 0], 64), ([60, 60, 60], 10)]
        {
            rows.read(&tree, lo, size);
            for (x, y, z) in (0..size).flat_map(|x| (0..size).flat_map(move |y| (0..size).map(move |z| (x, y, z)))) {
                let v = [lo[0] + x as i64, lo[1] + y as i64, lo[2] + z as i64];
                let inside = v.iter().all(|&c| (0..64).contains(&c));
                let want = inside && tree.contains_voxel(v.map(|c| c as u32));
                assert_eq!(rows.row(y, z) >> x & 1 == 1, want, "{v:?} in {lo:?} + {size}");
            }
        }
    }
}
