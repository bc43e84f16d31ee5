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
//! their node, so no brick is both read and counted in bulk.
//!
//! A brick on a square need not be read either when it is full and each of the 26
//! bricks around it is full or empty (outside the domain counts as empty): all that its
//! measurement reads (the brick and a margin of 5 voxels) is then given by which of the
//! 27 are full, its [`Pattern`], so every brick of one pattern measures alike and the
//! pattern is measured once ([`super::area`]). Big nodes' edges, corners and the
//! seams where they continue a face are such bricks: they cost 27 searches of the keys,
//! not a brick read (74^3 voxels).
//!
//! Cost: the keys, the exposed node faces, and the bricks on their rims (27 key
//! searches each, and a read for those beside smaller nodes); a big exposed face costs
//! its rim, not its area, and a solid of big nodes reads no brick.

use rayon::prelude::*;

use super::beyond::{Beyond, CubeFace, walk_beyond};
use crate::morton;
use crate::octree::window::keys_meeting;
use crate::octree::{LinearOctree, NodeKey};

/// Keys a parallel task handles.
const CHUNK: usize = 4096;
/// Bricks smaller than `2^3` voxels are always read: a read's margin (5 voxels) must
/// lie within the bricks around it for the [`Pattern`] to decide it.
const PATTERN_MIN_K: u32 = 3;

/// The boundary of a solid by bricks of `2^k` voxels a side.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct BoundaryBricks {
    /// The bricks to read, as the Morton codes of their brick coordinates, sorted.
    pub read: Vec<u64>,
    /// The voxel faces of the bricks counted in bulk, all on flat exposed squares.
    pub bulk_faces: u64,
    /// The full bricks whose 26 neighbours are each full or empty, as the Morton codes
    /// of their brick coordinates with their [`Pattern`], sorted, none also in `read`:
    /// each is measured as any brick of its pattern is.
    pub patterned: Vec<(u64, Pattern)>,
}

/// Which of the 27 bricks around a brick (bit `x + 3y + 9z` for offsets `x, y, z` in
/// `-1..=1`, shifted by one) are full, when each is full or empty (outside the domain
/// counts as empty).
pub(super) type Pattern = u32;

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
        let mut patterned = parts.iter().flat_map(|p| p.patterned.iter().copied()).collect::<Vec<_>>();
        patterned.par_sort_unstable();
        patterned.dedup();
        let mut read = parts.into_iter().flat_map(|p| p.read).collect::<Vec<_>>();
        read.par_sort_unstable();
        read.dedup();
        BoundaryBricks { read, bulk_faces, patterned }
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
                    Beyond::Outside => self.add_square(tree, Square::of_cube(keys[index], axis, plane, k), true),
                    Beyond::Empty(cube) => self.add_square(tree, square(cube), true),
                    Beyond::Mixed(cube, _) => self.add_square(tree, square(cube), false),
                    Beyond::Full(..) => {}
                });
            }
        }
    }

    /// Adds the bricks of `square`: all of them, or (when `flat`: nothing full beyond
    /// it) its rim, counting the faces of the inner ones in bulk.
    fn add_square(&mut self, tree: &LinearOctree, s: Square, flat: bool) {
        let n = s.bricks;
        let inner = flat && n >= 3;
        let mut add = |i: u32, j: u32| {
            let mut b = s.first;
            b[(s.axis + 1) % 3] += i;
            b[(s.axis + 2) % 3] += j;
            let code = morton::encode(b[0], b[1], b[2]);
            let pattern = if s.k >= PATTERN_MIN_K { pattern_around(tree, b, s.k) } else { None };
            match pattern {
                Some(pattern) => self.patterned.push((code, pattern)),
                None => self.read.push(code),
            }
        };
        // All the bricks, or the rim only: rows 0 and n - 1 whole, the others at their ends.
        for i in 0..n {
            if !inner || i == 0 || i == n - 1 {
                (0..n).for_each(|j| add(i, j));
            } else {
                add(i, 0);
                add(i, n - 1);
            }
        }
        if inner {
            self.bulk_faces += u64::from(n - 2).pow(2) << (2 * s.k);
        }
    }
}

/// The [`Pattern`] around the brick at brick coordinates `b` (of `2^k` voxels): `None`
/// when the brick is not full or a brick around it is partly full.
fn pattern_around(tree: &LinearOctree, b: [u32; 3], k: u32) -> Option<Pattern> {
    let bricks = i64::from(tree.domain().resolution() >> k);
    let mut pattern = 0;
    for bit in 0..27 {
        let c: [i64; 3] = std::array::from_fn(|a| i64::from(b[a]) + [bit % 3, bit / 3 % 3, bit / 9][a] - 1);
        if c.iter().all(|v| (0..bricks).contains(v)) {
            let cube = NodeKey::new(morton::encode(c[0] as u32, c[1] as u32, c[2] as u32) << (3 * k), k);
            match keys_meeting(tree.keys(), cube) {
                [] => {}
                [one] if one.k() >= k => pattern |= 1 << bit,
                _ => return None,
            }
        }
    }
    (pattern & 1 << 13 != 0).then_some(pattern)
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
    fn a_solid_of_big_nodes_is_measured_without_reading_a_brick() {
        // A full domain at depth 20 (an 81-byte file): its 6 faces' rims were 196,608
        // brick reads (23 s); they are bricks of a few patterns now.
        let domain = Domain::new(DVec3::ZERO, 1.0, 20).unwrap();
        let full = LinearOctree::full(domain);
        let bricks = BoundaryBricks::of(&full, 6);
        assert!(bricks.read.is_empty());
        // Rims of the 6 faces of 2^14 bricks a side: the surface's bricks, less the
        // inner squares counted in bulk.
        let side = 1u64 << 14;
        assert_eq!(bricks.patterned.len() as u64, side.pow(3) - (side - 2).pow(3) - 6 * (side - 2).pow(2));
        assert_eq!(bricks.bulk_faces, (6 * (side - 2).pow(2)) << 12);
        // Boxes of big nodes side by side (their seams continue a face) and apart.
        let domain = Domain::new(DVec3::ZERO, 1.0, 18).unwrap();
        let cube = |min: [u32; 3], size| Node { level: 0, min, size };
        let s = 1 << 15;
        let slab = (0..4).map(|i| cube([i * s, 0, 0], s));
        let apart = cube([0, 4 * s, 4 * s], 2 * s);
        let tree = LinearOctree::from_nodes(domain, slab.chain([apart])).unwrap();
        let bricks = BoundaryBricks::of(&tree, 6);
        assert!(bricks.read.is_empty() && !bricks.patterned.is_empty());
        assert!(bricks.patterned.windows(2).all(|w| w[0].0 < w[1].0));
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
            assert!(bricks.patterned.windows(2).all(|w| w[0].0 < w[1].0), "sorted and distinct");
            let patterned: Vec<u64> = bricks.patterned.iter().map(|p| p.0).collect();
            assert!(patterned.iter().all(|b| bricks.read.binary_search(b).is_err()), "read or patterned");
            assert_eq!(patterned.is_empty(), k < PATTERN_MIN_K);
            // Every brick with faces is read, measured by its pattern, or lies on a flat
            // square counted in bulk.
            let read_faces: u64 = bricks.read.iter().chain(&patterned).filter_map(|b| want.get(b)).sum();
            let total: u64 = want.values().sum();
            assert_eq!(read_faces + bricks.bulk_faces, total, "k = {k}");
            assert!(bricks.bulk_faces > 0, "inner bricks on the 32-voxel nodes' faces at k = {k}");
        }
    }
}
