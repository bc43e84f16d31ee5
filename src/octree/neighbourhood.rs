//! Dense occupancy of a small box of voxels, read from the linear octree: the input of
//! local estimates such as smooth normals; as one flag a voxel, or as one bit a voxel
//! in rows along x.
//!
//! Method: a descent of the implicit tree from the smallest aligned node holding the
//! (clipped) box, into the children that meet it; a node wholly covered by one key
//! fills its part of the box, a node holding no key is skipped. Each visit narrows the
//! run of keys by two binary searches. Cost: the nodes meeting the box plus its volume.

use std::ops::Range;

use super::linear::LinearOctree;
use super::node::NodeKey;
use super::transform::enclosing_node;
use super::window::keys_meeting;
use crate::morton;

impl LinearOctree {
    /// Whether each voxel of the cube of `size` voxels a side with lowest voxel `lo` is
    /// full, x fastest then y then z (`index = x + size (y + size z)`, offsets from
    /// `lo`). Voxels outside the domain are empty.
    #[must_use]
    pub fn occupancy(&self, lo: [i64; 3], size: u32) -> Vec<bool> {
        let s = size as usize;
        let mut out = vec![false; s * s * s];
        self.fill_rows(lo, size, &mut |row, xs| out[s * row..][xs].fill(true));
        out
    }

    /// The same cube's occupancy as bit rows: `rows[y + size z]` bit `x` is voxel `lo +
    /// (x, y, z)`, for `size` at most 32; `rows` holds at least `size^2` rows, which
    /// must be zero on entry.
    pub(crate) fn occupancy_rows(&self, lo: [i64; 3], size: u32, rows: &mut [u32]) {
        debug_assert!(size <= 32 && rows.len() >= (size * size) as usize);
        self.fill_rows(lo, size, &mut |row, xs| rows[row] |= (((1u64 << xs.len()) - 1) << xs.start) as u32);
    }

    /// Calls `mark(y + size z, x range)` for the full voxels of the cube, a run of a row
    /// at a time (offsets from `lo`; nothing outside the domain).
    fn fill_rows(&self, lo: [i64; 3], size: u32, mark: &mut dyn FnMut(usize, Range<usize>)) {
        let n = i64::from(self.domain().resolution());
        let clo = lo.map(|c| c.clamp(0, n));
        let chi: [i64; 3] = std::array::from_fn(|a| (lo[a] + i64::from(size)).clamp(0, n));
        if (0..3).any(|a| clo[a] >= chi[a]) {
            return;
        }
        let (clo, chi) = (clo.map(|c| c as u32), chi.map(|c| c as u32));
        let fill = Fill { lo, size: size as usize, clo, chi };
        fill.visit(self.keys(), enclosing_node(clo, chi), mark);
    }
}

/// The box being filled: its corner and size, and its part inside the domain.
struct Fill {
    lo: [i64; 3],
    size: usize,
    clo: [u32; 3],
    chi: [u32; 3],
}

impl Fill {
    /// Fills the full voxels of `node` (which meets the box) from the sorted run `keys`.
    fn visit(&self, keys: &[NodeKey], node: NodeKey, mark: &mut dyn FnMut(usize, Range<usize>)) {
        let window = match keys_meeting(keys, node) {
            [] => return,
            [key] if key.k() >= node.k() => return self.set(node, mark),
            window => window,
        };
        let half = 1u32 << (node.k() - 1);
        for i in 0..8 {
            let child = node.child(i).expect("a partly full node is not a voxel");
            let c = morton::decode(child.start());
            if (0..3).all(|a| c[a] < self.chi[a] && c[a] + half > self.clo[a]) {
                self.visit(window, child, mark);
            }
        }
    }

    /// Marks the voxels of the full `node` that lie in the box.
    fn set(&self, node: NodeKey, mark: &mut dyn FnMut(usize, Range<usize>)) {
        let min = morton::decode(node.start());
        let size = 1u32 << node.k();
        let a: [u32; 3] = std::array::from_fn(|i| min[i].max(self.clo[i]));
        let b: [u32; 3] = std::array::from_fn(|i| (min[i] + size).min(self.chi[i]));
        let offset = |i: usize, c: u32| (i64::from(c) - self.lo[i]) as usize;
        for z in a[2]..b[2] {
            for y in a[1]..b[1] {
                mark(offset(1, y) + self.size * offset(2, z), offset(0, a[0])..offset(0, b[0]));
            }
        }
    }
}
