//! What lies beyond a node's face: the one walk the component count (which nodes touch
//! a node across a face) and the area estimator's brick search (which parts of a big
//! node's face are exposed) share.
//!
//! Method (the walk of `mesh::boundary`'s exposed squares): the cube of the node's size
//! across the face is looked up in the key list by a galloping search from a hint: the
//! node's own place, or where the same face of the node before it found its cube
//! (walks in Morton order find their neighbours in nearly increasing order). Holding no full voxel,
//! or lying inside one full node, it is reported whole; partly full, it splits into its
//! four children touching the face, each with its slice of keys, down to a given
//! level, where a partly full cube is reported as such. Aligned cubes nest, so the
//! reported cubes tile the face, and at level 0 none is partly full.

use std::ops::Range;

use crate::octree::NodeKey;
use crate::octree::window::range_meeting_near;

/// One face of a cube of the implicit tree whose keys (itself, when it is a node) end
/// just before `keys[next]`.
#[derive(Clone, Copy, Debug)]
pub(super) struct CubeFace {
    /// The cube: a node, or a partly full cube.
    pub cube: NodeKey,
    /// Index of the first key after the cube's in the list.
    pub next: usize,
    /// Axis of the face's normal.
    pub axis: usize,
    /// Whether the outward normal points to `+axis`.
    pub positive: bool,
    /// Where the search for the keys beyond starts: the cube's own place, or what
    /// [`walk_beyond`] returned for the same face of the cube before it in Morton
    /// order, whose neighbours lie near (the nearer, the shorter the gallop).
    pub hint: usize,
}

impl CubeFace {
    /// The face of the node `keys[index]` normal to `axis`, searched from the node.
    pub(super) fn of_node(keys: &[NodeKey], index: usize, axis: usize, positive: bool) -> CubeFace {
        CubeFace { cube: keys[index], next: index + 1, axis, positive, hint: index }
    }
}

/// What fills a cube across a node face, as [`walk_beyond`] reports it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(super) enum Beyond {
    /// The face lies on the domain's boundary: nothing beyond it.
    Outside,
    /// The cube holds no full voxel.
    Empty(NodeKey),
    /// The cube lies inside the full node of this index in the key list.
    Full(NodeKey, usize),
    /// The cube, at the walk's finest level (or the face's cube's size, when smaller),
    /// is partly full: the keys inside it are `keys[range]`.
    Mixed(NodeKey, Range<usize>),
}

/// Reports the cubes across `face` of the canonical key list `keys` (depth `depth`)
/// that touch the face, each empty, inside one full node, or partly full at `k =
/// min_k` (or the node's own `k` when smaller; see the module doc);
/// [`Beyond::Outside`] alone on the domain's boundary. Returns where the keys beyond
/// start in the list (the next hint).
pub(super) fn walk_beyond(
    keys: &[NodeKey],
    depth: u8,
    face: CubeFace,
    min_k: u32,
    visit: &mut impl FnMut(Beyond),
) -> usize {
    let key = face.cube;
    // The same-size cube across the face (aligned: the plane is a multiple of the size).
    let Some(start) = step(key.start(), face.axis, key.k(), face.positive, depth) else {
        visit(Beyond::Outside);
        return face.hint;
    };
    let cube = NodeKey::new(start, key.k());
    let walk = Walk { keys, axis: face.axis, near: u64::from(!face.positive), min_k };
    let next = face.next;
    let range = match keys.get(next) {
        // The cube right after the node in Morton order: the next key starts in it
        // (covering it when as large), or after it.
        _ if cube.start() != key.end() => range_meeting_near(keys, face.hint, cube),
        Some(n) if n.start() == cube.start() && n.k() >= cube.k() => next..next + 1,
        Some(n) if n.start() < cube.end() => range_meeting_near(keys, next, cube),
        _ => next..next,
    };
    let found = range.start;
    walk.descend(range, cube, visit);
    found
}

/// The Morton code `code` of a voxel whose coordinate along `axis` is a multiple of
/// `2^k`, moved by `2^k` along `axis` (back when `!positive`); `None` when that leaves
/// the domain of depth `depth`. Only the coordinate's bits change: the masked add or
/// subtract carries through the other axes' bits.
fn step(code: u64, axis: usize, k: u32, positive: bool, depth: u8) -> Option<u64> {
    if k >= u32::from(depth) {
        return None; // the root: nothing around it
    }
    // Bits 3i + axis for i < depth: the coordinate's bits inside the domain.
    let lane = (0x1249_2492_4924_9249 & ((1u64 << (3 * u32::from(depth))) - 1)) << axis;
    let unit = 1u64 << (3 * k + axis as u32);
    let own = code & lane;
    let moved = if positive {
        // The carry out of the top bit wraps round to a smaller coordinate.
        Some(((own | !lane).wrapping_add(unit)) & lane).filter(|&m| m > own)
    } else {
        own.checked_sub(unit).map(|m| m & lane)
    }?;
    Some(code & !lane | moved)
}

/// The fixed part of one walk: the key list, the face's axis, which children of a
/// cube touch the face (their bit `axis` is `near`), the finest level.
struct Walk<'a> {
    keys: &'a [NodeKey],
    axis: usize,
    near: u64,
    min_k: u32,
}

impl Walk<'_> {
    /// Reports `cube`, or its children touching the face; `range` holds the keys
    /// meeting `cube` as `keys_meeting` gives them (the covering key alone when one
    /// covers it).
    fn descend(&self, range: Range<usize>, cube: NodeKey, visit: &mut impl FnMut(Beyond)) {
        match &self.keys[range.clone()] {
            [] => return visit(Beyond::Empty(cube)),
            [key] if key.k() >= cube.k() => return visit(Beyond::Full(cube, range.start)),
            _ if cube.k() <= self.min_k => return visit(Beyond::Mixed(cube, range)),
            _ => {}
        }
        // Partly full: every key of the range starts inside the cube.
        let mut from = range.start;
        for c in (0..8u64).filter(|c| (c >> self.axis) & 1 == self.near) {
            let Some(child) = cube.child(c) else { return };
            let lo = from + self.keys[from..range.end].partition_point(|k| k.start() < child.start());
            let hi = lo + self.keys[lo..range.end].partition_point(|k| k.start() < child.end());
            self.descend(lo..hi, child, visit);
            from = hi;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::morton;
    use crate::octree::{Domain, LinearOctree};
    use crate::test_util::Rng;
    use glam::DVec3;

    /// A random depth-4 solid with nodes of several sizes.
    fn random_tree(rng: &mut Rng) -> LinearOctree {
        let domain = Domain::new(DVec3::ZERO, 1.0, 4).unwrap();
        let mut voxels = Vec::new();
        for _ in 0..6 {
            let (k, c) = (rng.below(3) as u32, [0; 3].map(|_| rng.below(16) as u32));
            let m = c.map(|v| v >> k << k);
            for dz in 0..1 << k {
                for dy in 0..1 << k {
                    for dx in 0..1 << k {
                        voxels.push([m[0] + dx, m[1] + dy, m[2] + dz]);
                    }
                }
            }
        }
        voxels.extend((0..300).map(|_| [0; 3].map(|_| rng.below(16) as u32)));
        LinearOctree::from_voxels(domain, voxels).unwrap()
    }

    #[test]
    fn a_step_moves_one_coordinate_and_stops_at_the_domain() {
        let mut rng = Rng(3);
        for _ in 0..2000 {
            let depth = 1 + rng.below(21) as u8;
            let k = rng.below(u64::from(depth)) as u32;
            let v = [0; 3].map(|_| (rng.below(1 << depth) as u32) >> k << k);
            let (axis, positive) = (rng.below(3) as usize, rng.below(2) == 1);
            let mut w = v.map(i64::from);
            w[axis] += if positive { 1 << k } else { -(1 << k) };
            let want = w
                .iter()
                .all(|&c| (0..1 << depth).contains(&c))
                .then(|| morton::encode(w[0] as u32, w[1] as u32, w[2] as u32));
            assert_eq!(step(morton::encode(v[0], v[1], v[2]), axis, k, positive, depth), want, "{v:?} {axis} {k}");
        }
    }

    /// The faces to walk: every node's, and those of the partly full parents of voxels
    /// (cubes that are no node), each with the index of the first key after it.
    fn cubes(keys: &[NodeKey]) -> Vec<(NodeKey, usize)> {
        let mut out: Vec<_> = (0..keys.len()).map(|i| (keys[i], i + 1)).collect();
        for i in (0..keys.len()).filter(|&i| keys[i].k() == 0) {
            let parent = keys[i].parent();
            out.push((parent, i + keys[i..].partition_point(|k| k.start() < parent.end())));
        }
        out
    }

    #[test]
    fn the_reported_cubes_tile_the_face_and_say_what_fills_them() {
        let mut rng = Rng(31);
        for _ in 0..10 {
            let tree = random_tree(&mut rng);
            let (keys, depth) = (tree.keys(), tree.depth());
            for (n, (cube, next)) in cubes(keys).into_iter().enumerate() {
                let node = cube.node(depth);
                for (axis, positive, min_k) in [(0, true, 0), (1, false, 1), (2, true, 2), (0, false, 0)] {
                    // Any hint will do: the search gallops from it.
                    let hint = [0, next - 1, keys.len() - 1, keys.len()][n % 4];
                    let face = CubeFace { cube, next, axis, positive, hint };
                    let mut beyond = Vec::new();
                    walk_beyond(keys, depth, face, min_k, &mut |b| beyond.push(b));
                    check_tiling(&tree, node, face, min_k, &beyond);
                }
            }
        }
    }

    /// Each voxel across the face lies in exactly one reported cube, which says rightly
    /// what fills it, and the cubes' sides tile the face.
    fn check_tiling(tree: &LinearOctree, node: crate::octree::Node, face: CubeFace, min_k: u32, beyond: &[Beyond]) {
        let (keys, axis) = (tree.keys(), face.axis);
        let across = node.min[axis] as i64 + if face.positive { i64::from(node.size) } else { -1 };
        if !(0..16).contains(&across) {
            return assert_eq!(beyond, [Beyond::Outside]);
        }
        let cube_of = |b: &Beyond| match b {
            Beyond::Empty(c) | Beyond::Full(c, _) | Beyond::Mixed(c, _) => Some(*c),
            Beyond::Outside => None,
        };
        for (u, v) in (0..node.size).flat_map(|u| (0..node.size).map(move |v| (u, v))) {
            let mut p = node.min;
            p[axis] = across as u32;
            p[(axis + 1) % 3] += u;
            p[(axis + 2) % 3] += v;
            let code = morton::encode(p[0], p[1], p[2]);
            let holding: Vec<_> =
                beyond.iter().filter(|b| cube_of(b).is_some_and(|c| c.start() <= code && code < c.end())).collect();
            assert_eq!(holding.len(), 1, "{p:?}");
            match holding[0] {
                Beyond::Empty(_) => assert!(!tree.contains_voxel(p)),
                Beyond::Full(c, j) => {
                    assert!(keys[*j].start() <= c.start() && c.end() <= keys[*j].end());
                    assert!(tree.contains_voxel(p));
                }
                Beyond::Mixed(c, range) => {
                    assert!(c.k() <= min_k && c.k() > 0, "{c:?}");
                    let inside: Vec<usize> =
                        (0..keys.len()).filter(|&i| c.start() <= keys[i].start() && keys[i].end() <= c.end()).collect();
                    assert_eq!(*range, inside[0]..inside[0] + inside.len(), "{c:?}");
                    assert!(keys[range.clone()].iter().map(|k| k.len()).sum::<u64>() < c.len(), "{c:?} is full");
                }
                Beyond::Outside => unreachable!(),
            }
        }
        let area: u32 = beyond.iter().filter_map(cube_of).map(|c| 1u32 << (2 * c.k())).sum();
        assert_eq!(area, node.size * node.size);
    }
}
