//! Node keys: one `u64` a node that sorts in Morton order and encodes the level.
//!
//! Encoding (a contract: the `.oct` format and every algorithm rely on it):
//!
//! ```text
//! key = (start << 1) | (1 << 3k)
//! ```
//!
//! where `start` is the Morton code of the node's first voxel and `k = depth - level`
//! is how many levels the node sits above the voxels, so it covers the Morton range
//! `[start, start + 8^k)`. `start` is a multiple of `8^k`, so its lowest set bit is
//! above bit `3k` and the marker bit is the key's lowest set bit: `k = tz(key) / 3`.
//! With `start < 2^63` the key fits in 64 bits. Disjoint nodes sort by `start`, which
//! is Morton order; keys need no depth to give their range, only to give the level.

use crate::morton;

/// A node of a linear octree, packed in 8 bytes (see the module doc for the encoding).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[repr(transparent)]
pub struct NodeKey(u64);

const _: () = assert!(std::mem::size_of::<NodeKey>() == 8);

impl NodeKey {
    /// The node covering Morton codes `[start, start + 8^k)`.
    ///
    /// # Panics
    /// In debug builds, when `start` is not a multiple of `8^k` or `k > 21`.
    #[inline]
    #[must_use]
    pub fn new(start: u64, k: u32) -> Self {
        debug_assert!(k <= morton::MAX_BITS && start & ((1u64 << (3 * k)) - 1) == 0);
        NodeKey((start << 1) | (1u64 << (3 * k)))
    }

    /// The key from its raw bits, `None` when the bits are no valid key (zero, or a
    /// marker that is not on a multiple of three).
    #[inline]
    #[must_use]
    pub fn from_bits(bits: u64) -> Option<Self> {
        (bits != 0 && bits.trailing_zeros().is_multiple_of(3)).then_some(NodeKey(bits))
    }

    /// The raw 64 bits.
    #[inline]
    #[must_use]
    pub fn bits(self) -> u64 {
        self.0
    }

    /// Levels above the voxels: the node is a cube of `2^k` voxels a side.
    #[inline]
    #[must_use]
    pub fn k(self) -> u32 {
        self.0.trailing_zeros() / 3
    }

    /// Morton code of the first voxel.
    #[inline]
    #[must_use]
    pub fn start(self) -> u64 {
        (self.0 & (self.0 - 1)) >> 1
    }

    /// Number of voxels, `8^k`: the marker bit `1 << 3k`, the key's lowest set bit.
    #[inline]
    #[must_use]
    pub fn len(self) -> u64 {
        self.0 & self.0.wrapping_neg()
    }

    /// Keys are never empty; present for API symmetry with `len`.
    #[inline]
    #[must_use]
    pub fn is_empty(self) -> bool {
        false
    }

    /// One past the last voxel's Morton code.
    #[inline]
    #[must_use]
    pub fn end(self) -> u64 {
        self.last() + 1
    }

    /// Morton code of the last voxel, `start + 8^k - 1`: `key | (key - 1)` sets every
    /// bit below the marker, which shifted down are the start's `3k` low bits, all set.
    #[inline]
    #[must_use]
    pub fn last(self) -> u64 {
        (self.0 | (self.0 - 1)) >> 1
    }

    /// Level in an octree of depth `depth` (0 = root).
    ///
    /// # Panics
    /// In debug builds, when the node is larger than the root (`k > depth`).
    #[inline]
    #[must_use]
    pub fn level(self, depth: u8) -> u8 {
        debug_assert!(self.k() <= u32::from(depth), "node of k = {} above a depth-{depth} root", self.k());
        depth.wrapping_sub(self.k() as u8)
    }

    /// The node's geometry: level, lowest voxel and edge in voxels.
    #[inline]
    #[must_use]
    pub fn node(self, depth: u8) -> Node {
        Node { level: self.level(depth), min: morton::decode(self.start()), size: 1 << self.k() }
    }

    /// The parent node (one level up).
    #[inline]
    #[must_use]
    pub fn parent(self) -> NodeKey {
        let k = self.k() + 1;
        NodeKey::new(self.start() & !((1u64 << (3 * k)) - 1), k)
    }

    /// Child `i` in Morton order (`0..8`); `None` for a voxel.
    #[inline]
    #[must_use]
    pub fn child(self, i: u64) -> Option<NodeKey> {
        let k = self.k().checked_sub(1)?;
        Some(NodeKey::new(self.start() + i * (1u64 << (3 * k)), k))
    }
}

/// A node's geometry in integer voxel coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Node {
    /// Level: 0 is the whole domain, `depth` is one voxel.
    pub level: u8,
    /// The lowest voxel it covers.
    pub min: [u32; 3],
    /// Edge length in voxels, `2^(depth - level)`.
    pub size: u32,
}

impl Node {
    /// The key of this node; `None` when it is not an aligned power-of-two cube inside
    /// the largest grid a key can address (`2^21` voxels a side).
    #[must_use]
    pub fn key(&self) -> Option<NodeKey> {
        let limit = 1u64 << morton::MAX_BITS;
        let fits = self.min.iter().all(|&c| u64::from(c) + u64::from(self.size) <= limit);
        if !fits || !self.size.is_power_of_two() || self.min.iter().any(|c| c % self.size != 0) {
            return None;
        }
        Some(NodeKey::new(morton::encode(self.min[0], self.min[1], self.min[2]), self.size.trailing_zeros()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_round_trips_and_sorts_in_morton_order() {
        let a = NodeKey::new(0, 2);
        assert_eq!((a.start(), a.k(), a.len(), a.end()), (0, 2, 64, 64));
        let b = NodeKey::new(64, 0);
        assert!(a < b);
        assert_eq!(b.parent().parent(), NodeKey::new(64, 2));
        assert_eq!(a.child(7).unwrap(), NodeKey::new(56, 1));
        let root = NodeKey::new(0, 21);
        assert_eq!(root.len(), 1 << 63);
        assert_eq!(root.node(21), Node { level: 0, min: [0, 0, 0], size: 1 << 21 });
        assert!(NodeKey::from_bits(0).is_none() && NodeKey::from_bits(2).is_none());
        let n = Node { level: 3, min: [4, 0, 4], size: 4 };
        assert_eq!(n.key().unwrap().node(5), n);
        assert!(Node { level: 0, min: [1 << 21, 0, 0], size: 1 }.key().is_none(), "beyond 2^21 voxels");
        assert!(Node { level: 0, min: [0, 0, 0], size: 1 << 22 }.key().is_none());
    }

    #[test]
    fn range_from_the_bits_is_the_range_from_start_and_level() {
        // The bit tricks of `len`, `end` and `last` against `8^k` counted from `k`.
        for k in 0..=21u32 {
            let len = 8u64.pow(k);
            // Starts whose node ends by 2^63 (the last one ends there).
            let starts = [0, 1, 5, (1u64 << 63) / len - 1].map(|i| i.saturating_mul(len));
            for start in starts.into_iter().filter(|&s| s <= (1u64 << 63) - len) {
                let key = NodeKey::new(start, k);
                assert_eq!((key.start(), key.k(), key.len()), (start, k, len), "{start} at k = {k}");
                assert_eq!((key.last(), key.end()), (start + (len - 1), start + len), "{start} at k = {k}");
            }
        }
    }
}
