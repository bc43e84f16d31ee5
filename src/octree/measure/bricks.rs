//! Where a solid's boundary is: the bricks (aligned cubes of `2^k` voxels) the area
//! estimator must read voxel by voxel, and the voxel faces it can count in bulk.
//!
//! A brick holds boundary faces (of its full voxels) when it is partly full, or when it
//! is full and lies on a face of its node that is exposed, all or in part. The first
//! kind are the bricks meeting a key smaller than a brick (one pass over the keys);
//! the second are found by walking beyond each face of every key of at least a brick
//! ([`walk_beyond`](super::beyond::walk_beyond) down to brick level): a brick-sized
//! cube beyond that is partly full makes its neighbouring brick one to read. An exposed
//! square of `n x n` bricks (empty or outside the domain beyond it) is read only on its
//! rim of bricks; each of its `(n - 2)^2` inner bricks has the face plane as the only
//! boundary within a brick (full behind, empty in front, its node at least four bricks
//! thick), so its `4^k` faces are counted in bulk. Inner bricks lie on no other face of
//! their node, so no brick is both read and counted in bulk. Cost: the keys, the
//! exposed node faces, and the bricks read; a big exposed face costs its rim, not its
//! area.

use rayon::prelude::*;

use super::beyond::{Beyond, CubeFace, walk_beyond};
use crate::morton;
use crate::octree::{LinearOctree, NodeKey};

/// Keys a parallel task handles.
const CHUNK: usize = 4096;

/// The boundary of a solid by bricks of `2^k` voxels a side.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct BoundaryBricks {
    /// The bricks to read, as the Morton codes of their brick coordinates, sorted.
    pub read: Vec<u64>,
    /// The voxel faces of the bricks counted in bulk, all on flat exposed squares.
    pub bulk_faces: u64,
}

impl BoundaryBricks {
    /// The boundary of `tree` by bricks of `2^k` voxels (`k <= depth`).
    pub(super) fn of(tree: &LinearOctree, k: u32) -> BoundaryBricks {
        let keys = tree.keys();
        let parts: Vec<BoundaryBricks> = keys
            .par_chunks(CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let mut part = BoundaryBricks::default();
                for (i, key) in chunk.iter().enumerate() {
                    if key.k() < k {
                        let brick = key.start() >> (3 * k);
                        if part.read.last() != Some(&brick) {
                            part.read.push(brick);
                        }
                    } else {
                        part.add_exposed(tree, c * CHUNK + i, k);
                    }
                }
                part
            })
            .collect();
        let bulk_faces = parts.iter().map(|p| p.bulk_faces).sum();
        let mut read = parts.into_iter().flat_map(|p| p.read).collect::<Vec<_>>();
        read.par_sort_unstable();
        read.dedup();
        BoundaryBricks { read, bulk_faces }
    }

    /// Adds the bricks of the node `keys[index]` (at least a brick) on its exposed faces.
    fn add_exposed(&mut self, tree: &LinearOctree, index: usize, k: u32) {
        let (keys, depth) = (tree.keys(), tree.depth());
        let node = keys[index].node(depth);
        for axis in 0..3 {
            for positive in [false, true] {
                let face = CubeFace::of_node(keys, index, axis, positive);
                // The layer of bricks inside the node along the face.
                let plane = if positive { node.min[axis] + node.size - 1 } else { node.min[axis] };
                let square = |cube: NodeKey| Square::of_cube(cube, axis, plane, k);
                walk_beyond(keys, depth, face, k, &mut |beyond| match beyond {
                    Beyond::Outside => self.add_square(Square::of_cube(keys[index], axis, plane, k), true),
                    Beyond::Empty(cube) => self.add_square(square(cube), true),
                    Beyond::Mixed(cube, _) => self.add_square(square(cube), false),
                    Beyond::Full(..) => {}
                });
            }
        }
    }

    /// Adds the bricks of `square`: all of them, or (when `flat`: nothing full beyond
    /// it) its rim, counting the faces of the inner ones in bulk.
    fn add_square(&mut self, s: Square, flat: bool) {
        let n = s.bricks;
        let inner = flat && n >= 3;
        for i in 0..n {
            for j in 0..n {
                if !inner || i == 0 || j == 0 || i == n - 1 || j == n - 1 {
                    let mut b = s.first;
                    b[(s.axis + 1) % 3] += i;
                    b[(s.axis + 2) % 3] += j;
                    self.read.push(morton::encode(b[0], b[1], b[2]));
                }
            }
        }
        if inner {
            self.bulk_faces += u64::from(n - 2).pow(2) << (2 * s.k);
        }
    }
}

/// A square of `bricks x bricks` bricks of `2^k` voxels in one layer normal to `axis`.
#[derive(Clone, Copy, Debug)]
struct Square {
    axis: usize,
    k: u32,
    /// Brick coordinates of its lowest brick.
    first: [u32; 3],
    bricks: u32,
}

impl Square {
    /// The bricks at voxel coordinate `plane` along `axis` that face the cube `cube`
    /// (a cube of at least a brick, beside or in that layer).
    fn of_cube(cube: NodeKey, axis: usize, plane: u32, k: u32) -> Square {
        let mut first = morton::decode(cube.start()).map(|c| c >> k);
        first[axis] = plane >> k;
        Square { axis, k, first, bricks: 1 << (cube.k() - k) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::{Domain, Node};
    use glam::DVec3;

    /// Brute force: per brick, its full voxels' faces towards empty voxels (or out of
    /// the domain).
    fn faces_by_brick(tree: &LinearOctree, k: u32) -> std::collections::BTreeMap<u64, u64> {
        let n = tree.domain().resolution() as i64;
        let full = |v: [i64; 3]| v.iter().all(|&c| (0..n).contains(&c)) && tree.contains_voxel(v.map(|c| c as u32));
        let mut out = std::collections::BTreeMap::new();
        for code in 0..tree.domain().voxel_total() {
            let v = morton::decode(code).map(i64::from);
            if !full(v) {
                continue;
            }
            let faces = (0..6)
                .filter(|d| {
                    let mut w = v;
                    w[d / 2] += if d % 2 == 0 { 1 } else { -1 };
                    !full(w)
                })
                .count() as u64;
            if faces > 0 {
                *out.entry(code >> (3 * k)).or_insert(0) += faces;
            }
        }
        out
    }

    #[test]
    fn read_bricks_and_bulk_faces_cover_every_boundary_face_once() {
        let domain = Domain::new(DVec3::ZERO, 1.0, 6).unwrap();
        let cube = |min: [u32; 3], size| Node { level: 0, min, size };
        // Big aligned nodes (flat faces with inner bricks), a ragged part, the domain's faces.
        let nodes = [cube([0, 0, 0], 32), cube([32, 0, 0], 16), cube([48, 16, 0], 4), cube([0, 32, 32], 32)]
            .into_iter()
            .chain((0..40).map(|i| cube([33 + i % 7, 20 + i / 7, 40 + i % 3], 1)));
        let tree = LinearOctree::from_nodes(domain, nodes).unwrap();
        for k in [1, 2, 3] {
            let bricks = BoundaryBricks::of(&tree, k);
            let want = faces_by_brick(&tree, k);
            assert!(bricks.read.windows(2).all(|w| w[0] < w[1]), "sorted and distinct");
            // Every brick with faces is read or lies on a flat square counted in bulk.
            let read_faces: u64 = bricks.read.iter().filter_map(|b| want.get(b)).sum();
            let total: u64 = want.values().sum();
            assert_eq!(read_faces + bricks.bulk_faces, total, "k = {k}");
            assert!(bricks.bulk_faces > 0, "inner bricks on the 32-voxel nodes' faces at k = {k}");
        }
    }
}
