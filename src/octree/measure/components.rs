//! The connected components of a solid: maximal sets of full voxels joined through
//! shared faces. Voxels that meet only along an edge or at a corner are not connected
//! (6-connectivity of the full voxels), so two cubes touching along an edge are two
//! components.
//!
//! Method: a union-find (disjoint sets, union by lower index, path halving) over the
//! nodes, each node joined to the nodes beyond its three positive faces
//! ([`walk_beyond`]: a galloping search from the node's place in Morton order, then
//! the children touching the face): every pair of face-adjacent nodes has one on the
//! negative side of the other along some axis, so each pair is found once. A node is
//! connected inside (a cube), so the components of the nodes are those of the voxels.
//! No grid: the cost is the nodes' faces and their neighbours, `O(n log)` at worst.
//! The nodes are cut into chunks joined in parallel within themselves; the pairs that
//! cross chunks are joined after, in chunk order.

use rayon::prelude::*;

use super::beyond::{Beyond, NodeFace, walk_beyond};
use crate::octree::LinearOctree;

/// Nodes a parallel task joins.
const CHUNK: usize = 1 << 14;

impl LinearOctree {
    /// The number of face-connected components of the full voxels (see the module
    /// doc); 0 for the empty solid.
    #[must_use]
    pub fn components(&self) -> u64 {
        let (keys, depth) = (self.keys(), self.depth());
        let mut parent: Vec<usize> = (0..keys.len()).collect();
        let crossing: Vec<Vec<(usize, usize)>> = parent
            .par_chunks_mut(CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let base = c * CHUNK;
                let mut sets = Sets { parent: chunk, base };
                let mut crossing = Vec::new();
                for i in base..base + sets.parent.len() {
                    for axis in 0..3 {
                        walk_beyond(keys, depth, NodeFace { index: i, axis, positive: true }, 0, &mut |b| {
                            if let Beyond::Full(_, j) = b {
                                if sets.holds(j) { sets.union(i, j) } else { crossing.push((i, j)) }
                            }
                        });
                    }
                }
                crossing
            })
            .collect();
        let mut sets = Sets { parent: &mut parent, base: 0 };
        for (i, j) in crossing.into_iter().flatten() {
            sets.union(i, j);
        }
        // Roots are their own parents, however far paths were halved.
        parent.iter().enumerate().filter(|&(i, &p)| i == p).count() as u64
    }
}

/// Disjoint sets over the indices `base..base + parent.len()`; a root is its own
/// parent and is the lowest index of its set.
struct Sets<'a> {
    parent: &'a mut [usize],
    base: usize,
}

impl Sets<'_> {
    /// Whether index `i` is one of these sets'.
    fn holds(&self, i: usize) -> bool {
        (self.base..self.base + self.parent.len()).contains(&i)
    }

    /// The root of `i`'s set, halving the path on the way.
    fn find(&mut self, mut i: usize) -> usize {
        loop {
            let p = self.parent[i - self.base];
            if p == i {
                return i;
            }
            let grand = self.parent[p - self.base];
            self.parent[i - self.base] = grand;
            i = grand;
        }
    }

    /// Joins the sets of `i` and `j` under the lower root.
    fn union(&mut self, i: usize, j: usize) {
        let (a, b) = (self.find(i), self.find(j));
        if a != b {
            let (low, high) = (a.min(b), a.max(b));
            self.parent[high - self.base] = low;
        }
    }
}
