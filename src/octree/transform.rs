//! Exact whole-voxel transforms: translation, mirrors and quarter-turn rotations.
//!
//! Mirrors and quarter turns map every node to exactly one node (the domain's edge, a
//! node's position and its size are all multiples of the node's size), so they cost
//! one map and one sort, O(n log n), and keep the node count. A translation by a
//! multiple of a node's size moves the node whole; any other node is cut into the
//! aligned nodes of its moved cube (work proportional to the cube's surface). Parts
//! moved out of the domain are clipped. The general case, any affine map, is
//! [`LinearOctree::resample`].

use super::linear::LinearOctree;
use super::node::{Node, NodeKey};
use crate::morton;

impl LinearOctree {
    /// The solid moved by `offset` whole voxels; what leaves the domain is clipped.
    #[must_use]
    pub fn translate(&self, offset: [i64; 3]) -> LinearOctree {
        let n = i64::from(self.domain().resolution());
        let max_k = u32::from(self.depth());
        let mut keys = Vec::with_capacity(self.node_count());
        for node in self.nodes() {
            let size = i64::from(node.size);
            let lo: [i64; 3] = std::array::from_fn(|a| i64::from(node.min[a]) + offset[a]);
            if lo.iter().all(|&c| c >= 0 && c + size <= n && c % size == 0) {
                // Step 1: aligned and inside: the node moves whole.
                let c = lo.map(|c| c as u32);
                keys.push(NodeKey::new(morton::encode(c[0], c[1], c[2]), node.size.trailing_zeros()));
            } else {
                // Step 2: clip the moved cube to the domain and cut it into aligned nodes.
                let clo = lo.map(|c| c.clamp(0, n));
                let chi: [i64; 3] = std::array::from_fn(|a| (lo[a] + size).clamp(0, n));
                if (0..3).all(|a| clo[a] < chi[a]) {
                    let (clo, chi) = (clo.map(|c| c as u32), chi.map(|c| c as u32));
                    box_nodes(NodeKey::new(0, max_k), clo, chi, &mut keys);
                }
            }
        }
        LinearOctree::from_keys_unsorted(*self.domain(), keys)
    }

    /// The solid mirrored across the domain's middle plane perpendicular to `axis`
    /// (0 = x, 1 = y, 2 = z): voxel coordinate `c -> N - 1 - c`.
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

    /// The solid turned by `quarter_turns` x 90 degrees about the axis `axis` through
    /// the domain's centre, right-handed (+1 about z takes +x to +y): voxel `(x, y, z)`
    /// goes to `(N - 1 - y, x, z)`.
    ///
    /// # Panics
    /// When `axis > 2`.
    #[must_use]
    pub fn rotate90(&self, axis: usize, quarter_turns: i32) -> LinearOctree {
        assert!(axis < 3, "axis {axis} is not 0, 1 or 2");
        let n = self.domain().resolution();
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let turns = quarter_turns.rem_euclid(4);
        self.map_nodes(|mut min, size| {
            for _ in 0..turns {
                // Continuous map (u, v) -> (N - v, u) applied to the cube [min, min + size).
                let (mu, mv) = (min[u], min[v]);
                min[u] = n - mv - size;
                min[v] = mu;
            }
            min
        })
    }

    /// Applies a bijection of aligned cubes given by their lowest voxel, then sorts.
    fn map_nodes(&self, f: impl Fn([u32; 3], u32) -> [u32; 3]) -> LinearOctree {
        let mut keys: Vec<NodeKey> = self
            .nodes()
            .map(|Node { min, size, .. }| {
                let c = f(min, size);
                NodeKey::new(morton::encode(c[0], c[1], c[2]), size.trailing_zeros())
            })
            .collect();
        keys.sort_unstable();
        // Sibling sets map to sibling sets, so the list stays canonical.
        LinearOctree::from_canonical(*self.domain(), keys)
    }
}

/// Appends the aligned nodes inside `node` that cover the integer box `[lo, hi)`,
/// top-down in Morton order.
fn box_nodes(node: NodeKey, lo: [u32; 3], hi: [u32; 3], out: &mut Vec<NodeKey>) {
    let min = morton::decode(node.start());
    let size = 1u32 << node.k();
    let inside = (0..3).all(|a| lo[a] <= min[a] && min[a] + size <= hi[a]);
    let disjoint = (0..3).any(|a| min[a] + size <= lo[a] || min[a] >= hi[a]);
    if inside {
        out.push(node);
    } else if !disjoint {
        for i in 0..8 {
            box_nodes(node.child(i).expect("a partly covered node is not a voxel"), lo, hi, out);
        }
    }
}
