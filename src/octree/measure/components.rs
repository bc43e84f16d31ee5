//! The connected components of a solid: maximal sets of full voxels joined through
//! shared faces. Voxels that meet only along an edge or at a corner are not connected
//! (6-connectivity of the full voxels), so two cubes touching along an edge are two
//! components.
//!
//! Method: a union-find (disjoint sets, union by lower index, path halving) over the
//! nodes, each node joined to the nodes beyond its three positive faces
//! ([`walk_beyond`]: a galloping search from where the node before it found its
//! neighbour across the same face, then the children touching the face). Every pair
//! of face-adjacent nodes has one on the negative side of the other along some axis,
//! so each pair is found once. A node is connected inside (a cube), so the components
//! of the nodes are those of the voxels. Departure, for the commonest keys: the
//! voxels of one partly full `2^3` cube (whose keys are all voxels) join among
//! themselves by their places in it, and reach beyond through the cube's three walks,
//! not three each. No grid: the cost is the nodes' faces and their neighbours, each
//! found in `O(log distance)` in Morton order. The nodes are cut into chunks joined
//! in parallel within themselves; the pairs that cross chunks are joined after, in
//! chunk order, so the count never depends on the number of threads. Memory: one
//! `usize` a node (the sets), and the pairs that cross chunks.

use rayon::prelude::*;

use super::beyond::{Beyond, CubeFace, walk_beyond};
use crate::octree::{LinearOctree, NodeKey};

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
                let mut joiner =
                    Joiner { keys, depth, sets: Sets { parent: chunk, base: c * CHUNK }, crossing: Vec::new() };
                joiner.chunk();
                joiner.crossing
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

/// Joins the nodes of one chunk: pairs within it in its sets, the others kept.
struct Joiner<'a> {
    keys: &'a [NodeKey],
    depth: u8,
    sets: Sets<'a>,
    /// Pairs with a node outside the chunk, joined after.
    crossing: Vec<(usize, usize)>,
}

impl Joiner<'_> {
    /// Joins every node of the chunk to its neighbours beyond its positive faces. A
    /// node is joined by three walks; the voxels of one partly full `2^3` cube (all
    /// its keys are voxels) are joined among themselves by their places in it and to
    /// what lies beyond by the cube's three walks, not their own: three walks for up
    /// to seven voxels, three quarters of the keys near a surface.
    fn chunk(&mut self) {
        let (keys, end) = (self.keys, self.sets.base + self.sets.parent.len());
        let mut i = self.sets.base;
        // The voxels of a cube begun in the chunk before are that chunk's.
        while i < end && i > 0 && keys[i].k() == 0 && keys[i - 1].k() == 0 && keys[i - 1].parent() == keys[i].parent() {
            i += 1;
        }
        let mut hints = [i; 3];
        while i < end {
            if keys[i].k() == 0 {
                i = self.voxels(i, &mut hints);
            } else {
                for (axis, hint) in hints.iter_mut().enumerate() {
                    let face = CubeFace { hint: *hint, ..CubeFace::of_node(keys, i, axis, true) };
                    *hint = walk_beyond(keys, self.depth, face, 0, &mut |b| {
                        if let Beyond::Full(_, j) = b {
                            self.join(i, j);
                        }
                    });
                }
                i += 1;
            }
        }
    }

    /// Joins the voxels of the `2^3` cube holding voxel `keys[first]` (its first), and
    /// returns the index after them.
    fn voxels(&mut self, first: usize, hints: &mut [usize; 3]) -> usize {
        let keys = self.keys;
        let cube = keys[first].parent();
        // The index of each of the cube's eight voxels that is full.
        let mut at = [usize::MAX; 8];
        let mut next = first;
        while next < keys.len() && keys[next].start() < cube.end() {
            at[(keys[next].start() & 7) as usize] = next;
            next += 1;
        }
        for c in (0..8).filter(|&c| at[c] != usize::MAX) {
            for bit in [1, 2, 4].into_iter().filter(|b| c & b == 0 && at[c | b] != usize::MAX) {
                self.join(at[c], at[c | bit]);
            }
        }
        for (axis, hint) in hints.iter_mut().enumerate() {
            let bit = 1 << axis;
            let face = CubeFace { cube, next, axis, positive: true, hint: *hint };
            *hint = walk_beyond(keys, self.depth, face, 1, &mut |b| match b {
                // One node beyond: the voxels on this side join it.
                Beyond::Full(_, j) => {
                    for c in (0..8).filter(|c| c & bit != 0 && at[*c] != usize::MAX) {
                        self.join(at[c], j);
                    }
                }
                // Voxels beyond: each on the near side joins the one facing it here.
                Beyond::Mixed(_, range) => {
                    for j in range {
                        let c = (keys[j].start() & 7) as usize;
                        if c & bit == 0 && at[c | bit] != usize::MAX {
                            self.join(at[c | bit], j);
                        }
                    }
                }
                Beyond::Outside | Beyond::Empty(_) => {}
            });
        }
        next
    }

    /// Joins nodes `i` and `j`, now when both are the chunk's, else after.
    fn join(&mut self, i: usize, j: usize) {
        if self.sets.holds(i) && self.sets.holds(j) {
            self.sets.union(i, j);
        } else {
            self.crossing.push((i, j));
        }
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
