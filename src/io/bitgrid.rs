//! Dense occupancy bits of a box of voxels and the canonical octree they make.
//!
//! Layout: voxel `(x, y, z)` of a `dims` box is bit `(x * dims.z + z) * dims.y + y`
//! (x slowest, then z, y fastest: the order binvox stores voxels in), so a run of
//! stored voxels is a run of bits. The box sits at the lattice origin of a cube of
//! `2^depth` voxels a side, `depth` the smallest holding it; voxels beyond the box
//! are empty.
//!
//! Octree: a pyramid of two bit sets a level, `full` (every voxel of the node set)
//! and `any` (some voxel set), each level half the last (rounded up; a node reaching
//! beyond the box is never full), then a descent from the root in Morton order that
//! emits a node when it is full and skips it when it is empty. An emitted node's parent
//! was not full, so the keys come out sorted and canonical. Memory: the bits (one a
//! voxel of the box, not of the cube) and the pyramid (at most 2/7 more for `full` and
//! `any` above level 0); work: one pass over the bits a level, then the nodes visited.

use crate::error::Result;
use crate::morton;
use crate::octree::{Domain, LinearOctree, NodeKey};

/// Occupancy bits of a box of voxels (module doc).
pub(crate) struct BitGrid {
    dims: [u64; 3],
    words: Vec<u64>,
}

/// One pyramid level: its dims and its `full` and `any` bits, same layout.
struct Level {
    dims: [u64; 3],
    full: Vec<u64>,
    any: Vec<u64>,
}

fn bit(words: &[u64], i: u64) -> bool {
    words[(i >> 6) as usize] >> (i & 63) & 1 == 1
}

fn set(words: &mut [u64], i: u64) {
    words[(i >> 6) as usize] |= 1 << (i & 63);
}

impl Level {
    fn index(&self, x: u64, y: u64, z: u64) -> u64 {
        (x * self.dims[2] + z) * self.dims[1] + y
    }

    /// `(full, any)` of cell `c`; cells beyond the dims are empty.
    fn get(&self, c: [u64; 3]) -> (bool, bool) {
        if (0..3).any(|a| c[a] >= self.dims[a]) {
            return (false, false);
        }
        let i = self.index(c[0], c[1], c[2]);
        (bit(&self.full, i), bit(&self.any, i))
    }

    /// The level above: a cell is full when its eight children are, any when one is.
    fn coarser(&self) -> Level {
        let dims = self.dims.map(|d| d.div_ceil(2));
        let words = (dims.iter().product::<u64>()).div_ceil(64) as usize;
        let mut up = Level { dims, full: vec![0; words], any: vec![0; words] };
        for x in 0..dims[0] {
            for z in 0..dims[2] {
                for y in 0..dims[1] {
                    let (mut full, mut any) = (true, false);
                    for i in 0..8u64 {
                        let (f, a) = self.get([2 * x + (i & 1), 2 * y + (i >> 1 & 1), 2 * z + (i >> 2)]);
                        full &= f;
                        any |= a;
                    }
                    let i = up.index(x, y, z);
                    if full {
                        set(&mut up.full, i);
                    }
                    if any {
                        set(&mut up.any, i);
                    }
                }
            }
        }
        up
    }
}

impl BitGrid {
    /// Bytes [`BitGrid::new`] and [`BitGrid::to_octree`] need for `dims`, at most.
    pub(crate) fn estimate_bytes(dims: [u64; 3]) -> u64 {
        let voxels = dims.iter().fold(1u64, |p, &d| p.saturating_mul(d));
        // The bits, `full` and `any` of the pyramid above them, and a copy of level 0.
        voxels.div_ceil(8).saturating_mul(3)
    }

    /// An empty grid of `dims` voxels (each at least 1).
    pub(crate) fn new(dims: [u64; 3]) -> Self {
        let voxels: u64 = dims.iter().product();
        BitGrid { dims, words: vec![0; voxels.div_ceil(64) as usize] }
    }

    /// Sets the `len` voxels from linear index `start` on (module doc's order).
    pub(crate) fn set_run(&mut self, start: u64, len: u64) {
        let (mut i, end) = (start, start + len);
        // Bits up to a word boundary, whole words, then the rest.
        while i < end && i % 64 != 0 {
            set(&mut self.words, i);
            i += 1;
        }
        while i + 64 <= end {
            self.words[(i >> 6) as usize] = u64::MAX;
            i += 64;
        }
        while i < end {
            set(&mut self.words, i);
            i += 1;
        }
    }

    /// The canonical octree of the set voxels over `domain`, whose resolution must
    /// hold the box.
    pub(crate) fn to_octree(&self, domain: Domain) -> Result<LinearOctree> {
        let depth = u32::from(domain.depth());
        debug_assert!(self.dims.iter().all(|&d| d <= u64::from(domain.resolution())));
        // Step 1: the pyramid, level 0 = the voxels.
        let mut levels = vec![Level { dims: self.dims, full: self.words.clone(), any: self.words.clone() }];
        for _ in 0..depth {
            let up = levels.last().expect("level 0").coarser();
            levels.push(up);
        }
        // Step 2: descent from the root, children in Morton order.
        let mut keys = Vec::new();
        let mut stack = vec![(depth, [0u64; 3])];
        while let Some((k, c)) = stack.pop() {
            let (full, any) = levels[k as usize].get(c);
            if full {
                let lo = c.map(|v| (v << k) as u32);
                keys.push(NodeKey::new(morton::encode(lo[0], lo[1], lo[2]), k));
            } else if any && k > 0 {
                // Pushed in reverse so that child 0 is visited first.
                for i in (0..8u64).rev() {
                    stack.push((k - 1, [2 * c[0] + (i & 1), 2 * c[1] + (i >> 1 & 1), 2 * c[2] + (i >> 2)]));
                }
            }
        }
        LinearOctree::from_keys(domain, keys)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn octree_of_bits_matches_the_voxels() {
        // A ragged box of 5 x 3 x 6 with a pseudo-random fill, in a depth-3 cube.
        let dims = [5u64, 3, 6];
        let mut grid = BitGrid::new(dims);
        let mut voxels = Vec::new();
        let mut s = 0x9e37_79b9_u64;
        for x in 0..5 {
            for z in 0..6 {
                for y in 0..3 {
                    s ^= s << 13;
                    s ^= s >> 7;
                    s ^= s << 17;
                    if !s.is_multiple_of(3) || x < 2 {
                        grid.set_run((x * 6 + z) * 3 + y, 1);
                        voxels.push([x as u32, y as u32, z as u32]);
                    }
                }
            }
        }
        let domain = Domain::new(DVec3::ZERO, 1.0, 3).unwrap();
        let tree = grid.to_octree(domain).unwrap();
        assert_eq!(tree, LinearOctree::from_voxels(domain, voxels).unwrap());
        // A full box of 4^3 is one node.
        let mut grid = BitGrid::new([4, 4, 4]);
        grid.set_run(0, 64);
        assert_eq!(grid.to_octree(domain).unwrap().node_count(), 1);
    }
}
