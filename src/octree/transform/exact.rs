//! Exact whole-voxel transforms: translation, mirrors and quarter-turn rotations.
//!
//! Exactness: every method here moves voxels to voxels by an integer map, so the
//! result is exactly the moved voxel set (no sampling, no rounding), canonical.
//!
//! Cost, for an octree of `n` nodes:
//! - [`LinearOctree::mirror`] and [`LinearOctree::rotate90`] map every node to exactly
//!   one node (the domain's edge, a node's position and its size are all multiples of
//!   the node's size, and the map sends sibling sets to sibling sets), so they cost one
//!   map and one sort, O(n log n) time, and keep the node count.
//! - [`LinearOctree::translate`] builds the result top down over the target's implicit
//!   tree: a target node whose preimage box (the node moved back by the offset) holds
//!   only full voxels is emitted whole, one with none is dropped, a mixed one is split.
//!   The preimage is classified against short runs of source keys, found for each node
//!   by binary search inside its parent's runs. Where the preimage is an aligned cube
//!   (the offset is a multiple of the node's size) the source keys in it are copied,
//!   shifted, without descending further. Nodes come out sorted and canonical: no sort,
//!   no merge. Work: the `m` output nodes plus the visited nodes (eight per mixed node,
//!   so near the moved surface), each visit a few binary searches over short runs:
//!   about O((n + m) log n), and O(n) when the offset is a multiple of the node sizes.
//!   Parts moved out of the domain are clipped (lost): a translation is only
//!   reversible when nothing leaves the domain.
//!
//! The general case, any affine map and any target domain, sampled at voxel centres,
//! is [`LinearOctree::resample`].

use super::resample::classify_in;
use crate::morton;
use crate::octree::linear::LinearOctree;
use crate::octree::node::{Node, NodeKey};
use crate::octree::window::keys_meeting;
use crate::shape::Class;

impl LinearOctree {
    /// The solid moved by `offset` whole voxels (voxel `v` goes to `v + offset`).
    ///
    /// Voxels moved outside the domain are clipped: they are dropped, not wrapped, so
    /// `translate(o).translate(-o)` gives back only the part that stayed inside. Any
    /// offset is accepted; one of at least the resolution on some axis gives the empty
    /// solid.
    #[must_use]
    pub fn translate(&self, offset: [i64; 3]) -> LinearOctree {
        let n = i64::from(self.domain().resolution());
        if offset.iter().any(|&o| o <= -n || o >= n) {
            return LinearOctree::empty(*self.domain());
        }
        if offset == [0; 3] {
            return self.clone();
        }
        // From here every |offset| < n <= 2^21, so nothing below can overflow.
        let shift = Shift { n };
        let lo = offset.map(|o| -o);
        // The root's block of domain-sized cubes: only the domain itself holds keys.
        let windows = std::array::from_fn(|d| {
            let c: [i64; 3] = std::array::from_fn(|a| lo[a].div_euclid(n) + ((d as i64 >> a) & 1));
            if c == [0; 3] { self.keys() } else { &[][..] }
        });
        let mut keys = Vec::new();
        shift.visit(NodeKey::new(0, u32::from(self.depth())), lo, windows, &mut keys);
        LinearOctree::from_canonical(*self.domain(), keys)
    }

    /// The solid mirrored across the domain's middle plane perpendicular to `axis`
    /// (0 = x, 1 = y, 2 = z): voxel coordinate `c -> N - 1 - c`. Its own inverse.
    ///
    /// # Panics
    /// When `axis > 2`.
    #[must_use]
    pub fn mirror(&self, axis: usize) -> LinearOctree {
        assert!(axis < 3, "axis {axis} is not 0, 1 or 2");
        let n = self.domain().resolution();
        self.map_nodes(|mut min, size| {
            min[axis] = n - min[axis] - size;
            min
        })
    }

    /// The solid turned by `quarter_turns` x 90 degrees about the line through the
    /// domain's centre parallel to `axis` (0 = x, 1 = y, 2 = z), right-handed: +1 about
    /// z takes +x to +y, so voxel `(x, y, z)` goes to `(N - 1 - y, x, z)`; about x,
    /// `(x, y, z) -> (x, N - 1 - z, y)`; about y, `(x, y, z) -> (z, y, N - 1 - x)`.
    /// Negative turns go the other way; four turns are the identity.
    ///
    /// # Panics
    /// When `axis > 2`.
    #[must_use]
    pub fn rotate90(&self, axis: usize, quarter_turns: i32) -> LinearOctree {
        assert!(axis < 3, "axis {axis} is not 0, 1 or 2");
        let turns = quarter_turns.rem_euclid(4);
        if turns == 0 {
            return self.clone();
        }
        let n = self.domain().resolution();
        // (u, v, axis) is a right-handed frame: +u turns to +v.
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        self.map_nodes(|mut min, size| {
            for _ in 0..turns {
                // The cube [min, min + size) under the continuous map (u, v) -> (N - v, u).
                let (mu, mv) = (min[u], min[v]);
                min[u] = n - mv - size;
                min[v] = mu;
            }
            min
        })
    }

    /// Applies a symmetry of the domain's octree (a bijection of aligned cubes that
    /// keeps sizes and sibling sets), given by each cube's new lowest voxel; then sorts.
    pub(super) fn map_nodes(&self, f: impl Fn([u32; 3], u32) -> [u32; 3]) -> LinearOctree {
        let mut keys: Vec<NodeKey> = self
            .nodes()
            .map(|Node { min, size, .. }| {
                let c = f(min, size);
                NodeKey::new(morton::encode(c[0], c[1], c[2]), size.trailing_zeros())
            })
            .collect();
        // Disjoint keys sort by their raw bits exactly as by Morton start.
        keys.sort_unstable();
        // Eight siblings map to eight siblings, so no new merge appears: still canonical.
        LinearOctree::from_canonical(*self.domain(), keys)
    }
}

/// A translation pulled from the source, top down over the target's implicit tree.
///
/// A target node of size `s` has the preimage box `B = [lo, lo + s)`. `B` meets at most
/// eight aligned source cubes of size `s`: the block at grid positions `base + d`,
/// `d in {0, 1}^3`, `base = floor(lo / s)`. For each the node carries the run of source
/// keys meeting that cube (`windows[d]`; just the covering key when one covers it).
/// `B` is all full when every part `B ∩ cube` is and all empty when no part has a full
/// voxel; each part is classified against its own short run. The children's preimages
/// tile `B` and meet the 3 x 3 x 3 cubes of half the size at `floor(lo / (s/2)) + 0..3`,
/// each inside one of the node's cubes, so their runs come from binary searches in the
/// node's runs. Target nodes come out in Morton order, and a node that is all full is
/// emitted whole, so the output is canonical with no sort and no merge.
struct Shift {
    /// Voxels a side.
    n: i64,
}

impl Shift {
    /// Lowest voxel of the aligned cube of `size` voxels at grid position `c`, `None`
    /// when it lies outside the domain.
    fn cube_min(&self, c: [i64; 3], size: i64) -> Option<[u32; 3]> {
        c.iter().all(|&c| c >= 0 && c * size < self.n).then(|| c.map(|c| (c * size) as u32))
    }

    /// Appends the canonical target nodes inside `node`, whose preimage starts at `lo`.
    fn visit(&self, node: NodeKey, lo: [i64; 3], windows: [&[NodeKey]; 8], out: &mut Vec<NodeKey>) {
        let k = node.k();
        let s = 1i64 << k;
        let base = lo.map(|c| c.div_euclid(s));
        if (0..3).all(|a| base[a] * s == lo[a]) {
            // Step 0: the preimage is one aligned cube (always so for voxels). The offset
            // is then a multiple of every smaller size too: the source keys in the cube
            // move whole and keep their Morton order.
            if let Some(cmin) = self.cube_min(base, s) {
                let from = morton::encode(cmin[0], cmin[1], cmin[2]);
                match windows[0] {
                    [key] if key.k() >= k => out.push(node),
                    window => {
                        out.extend(window.iter().map(|key| NodeKey::new(key.start() - from + node.start(), key.k())))
                    }
                }
            }
            return;
        }
        // Step 1: classify the preimage part by part; what lies outside the domain is empty.
        // Step 2: emit, drop, or recurse (the preimage is not one voxel: see step 0).
        match self.preimage_class(k, lo, base, &windows) {
            Class::Inside => out.push(node),
            Class::Outside => {}
            Class::Boundary => self.split(node, lo, base, &windows, out),
        }
    }

    /// Whether the preimage `[lo, lo + 2^k)` (block `base` of size-`2^k` cubes, their
    /// runs `windows`) is all full, all empty or mixed; voxels outside the domain are
    /// empty.
    fn preimage_class(&self, k: u32, lo: [i64; 3], base: [i64; 3], windows: &[&[NodeKey]; 8]) -> Class {
        let s = 1i64 << k;
        let clipped = lo.iter().any(|&c| c < 0 || c + s > self.n);
        let (mut full, mut empty) = (false, clipped);
        for (d, window) in windows.iter().enumerate() {
            let c: [i64; 3] = std::array::from_fn(|a| base[a] + ((d as i64 >> a) & 1));
            let Some(cmin) = self.cube_min(c, s) else { continue };
            if (0..3).any(|a| i64::from(cmin[a]) >= lo[a] + s) {
                continue; // B is aligned on that axis and ends before this cube.
            }
            let class = match window {
                [] => Class::Outside,
                [key] if key.k() >= k => Class::Inside,
                _ => {
                    let cube = NodeKey::new(morton::encode(cmin[0], cmin[1], cmin[2]), k);
                    let plo: [u32; 3] = std::array::from_fn(|a| lo[a].max(i64::from(cmin[a])) as u32);
                    let phi: [u32; 3] = std::array::from_fn(|a| (lo[a] + s).min(i64::from(cmin[a]) + s) as u32);
                    classify_in(window, cube, plo, phi)
                }
            };
            match class {
                Class::Inside => full = true,
                Class::Outside => empty = true,
                Class::Boundary => (full, empty) = (true, true),
            }
            if full && empty {
                break;
            }
        }
        match (full, empty) {
            (true, false) => Class::Inside,
            (false, _) => Class::Outside,
            (true, true) => Class::Boundary,
        }
    }

    /// Visits the eight children of the mixed `node` (preimage at `lo`, block `base`,
    /// runs `windows`), each with the runs of its own block of half-size cubes.
    fn split(&self, node: NodeKey, lo: [i64; 3], base: [i64; 3], windows: &[&[NodeKey]; 8], out: &mut Vec<NodeKey>) {
        let k = node.k();
        let (s, h) = (1i64 << k, 1i64 << (k - 1));
        let gbase = lo.map(|c| c.div_euclid(h));
        // The runs of the 3 x 3 x 3 half-size cubes, index x + 3y + 9z.
        let grid: [&[NodeKey]; 27] = std::array::from_fn(|g| {
            let c: [i64; 3] = [gbase[0] + (g % 3) as i64, gbase[1] + (g / 3 % 3) as i64, gbase[2] + (g / 9) as i64];
            let Some(cmin) = self.cube_min(c, h).filter(|m| (0..3).all(|a| i64::from(m[a]) < lo[a] + s)) else {
                return &[][..]; // Outside the domain, or beyond B.
            };
            // The node's cube holding it (a cube meeting B lies in one), as an
            // index into the node's block.
            let up: [i64; 3] = std::array::from_fn(|a| (c[a] >> 1) - base[a]);
            debug_assert!(up.iter().all(|u| (0..2).contains(u)), "{up:?}");
            let window = windows[(up[0] + 2 * up[1] + 4 * up[2]) as usize];
            keys_meeting(window, NodeKey::new(morton::encode(cmin[0], cmin[1], cmin[2]), k - 1))
        });
        for i in 0..8 {
            let child = node.child(i as u64).expect("a mixed preimage is not one voxel");
            let bit = [i & 1, (i >> 1) & 1, (i >> 2) & 1];
            let clo: [i64; 3] = std::array::from_fn(|a| lo[a] + bit[a] as i64 * h);
            // The child's block starts at gbase + bit.
            let cwindows = std::array::from_fn(|d| {
                grid[(bit[0] + (d & 1)) + 3 * (bit[1] + ((d >> 1) & 1)) + 9 * (bit[2] + ((d >> 2) & 1))]
            });
            self.visit(child, clo, cwindows, out);
        }
    }
}
