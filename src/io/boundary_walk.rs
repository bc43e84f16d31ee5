//! Whether faces in increasing order are boundary faces of a solid: the check a reader
//! of a surface section makes of every face, by a walk along the nodes rather than a
//! search of them a face.
//!
//! A face tested alone (`surface::is_boundary_face`) takes two binary searches over
//! the whole key list (the voxel and its neighbour; some twenty probes each at a
//! million nodes, most of them cache misses). A section's faces come sorted by voxel,
//! so the node holding a face's voxel is at or after the one of the face before; and
//! the neighbour across a face differs from the voxel in one coordinate, along which
//! Morton order increases, so its node is after the voxel's towards `+axis` and before
//! it towards `-axis`, and near it. Both are found by galloping search from the voxel's
//! node (Bentley and Yao, *An almost optimal algorithm for unbounded searching*, 1976:
//! probes 1, 2, 4, ... keys away until one passes the code, then bisection of the last
//! step), a few probes where a search of the whole list takes twenty.
//!
//! The neighbour's code is stepped without decoding the voxel, by dilated integer
//! arithmetic on the axis's bits of the code (Raman and Wise, *Converting to and from
//! Dilated Integers*, IEEE Trans. Computers 57(4), 2008): the other axes' bits set to
//! one carry an increment across them, and set to zero borrow a decrement; an axis
//! whose bits are all one (or all zero) has no neighbour in the domain that way.
//!
//! The faces are checked in chunks in parallel, each walk from its chunk's first face;
//! the answer is the first face that fails in the given order, whatever the threads.

use rayon::prelude::*;

use crate::octree::{LinearOctree, NodeKey};
use crate::surface::FaceKey;

/// Faces one task walks.
const CHUNK: usize = 1 << 14;
/// Bits 0, 3, 6, ... of a Morton code: the x coordinate's.
const X_BITS: u64 = 0x1249_2492_4924_9249;

/// The index of the first of `items` whose face (`key` of it) is not a boundary face of
/// `tree` (its voxel empty, or its neighbour across the face full), `None` when every
/// one is. The faces must come in increasing order for the walk to be fast; any
/// order gives the right answer.
pub(crate) fn first_not_on_boundary<T: Sync>(
    tree: &LinearOctree,
    items: &[T],
    key: impl Fn(&T) -> FaceKey + Sync,
) -> Option<usize> {
    let walk = Walk::new(tree);
    items.par_chunks(CHUNK).enumerate().find_map_first(|(c, chunk)| {
        let mut hint = 0;
        chunk.iter().position(|item| !walk.is_boundary_face(key(item), &mut hint)).map(|i| c * CHUNK + i)
    })
}

/// A solid's keys and its domain's Morton bits of each axis.
struct Walk<'a> {
    keys: &'a [NodeKey],
    axis_bits: [u64; 3],
}

impl<'a> Walk<'a> {
    fn new(tree: &'a LinearOctree) -> Self {
        // Depth 21 at most: 63 bits.
        let used = (1u64 << (3 * u32::from(tree.domain().depth()))) - 1;
        Walk { keys: tree.keys(), axis_bits: [X_BITS & used, (X_BITS << 1) & used, (X_BITS << 2) & used] }
    }

    /// Whether `face` is a boundary face; `hint` is a key index near its voxel's node
    /// (the previous face's), moved to it.
    fn is_boundary_face(&self, face: FaceKey, hint: &mut usize) -> bool {
        let Some(at) = last_starting_at_or_before(self.keys, *hint, face.voxel) else { return false };
        *hint = at;
        let node = self.keys[at];
        if face.voxel >= node.end() {
            return false;
        }
        let Some(n) = self.neighbour(face) else { return true };
        if n >= node.start() && n < node.end() {
            return false;
        }
        last_starting_at_or_before(self.keys, at, n).is_none_or(|i| n >= self.keys[i].end())
    }

    /// The Morton code of the voxel across `face`, `None` outside the domain.
    fn neighbour(&self, face: FaceKey) -> Option<u64> {
        let bits = self.axis_bits[face.axis()];
        let lane = face.voxel & bits;
        let stepped = if face.positive() {
            if lane == bits {
                return None;
            }
            (lane | !bits).wrapping_add(1) & bits
        } else {
            if lane == 0 {
                return None;
            }
            (lane - 1) & bits
        };
        Some(stepped | (face.voxel & !bits))
    }
}

/// The index of the last of `keys` (sorted by start) starting at or before `code`,
/// `None` when all start after it: galloping search from `hint` (module doc).
fn last_starting_at_or_before(keys: &[NodeKey], hint: usize, code: u64) -> Option<usize> {
    let at_or_before = |i: usize| keys[i].start() <= code;
    let hint = hint.min(keys.len().checked_sub(1)?);
    let (lo, hi) = if at_or_before(hint) {
        // Forward: `lo` starts at or before the code, `hi` after it (or is the end).
        let (mut lo, mut step) = (hint, 1);
        let hi = loop {
            match lo.checked_add(step).filter(|&p| p < keys.len()) {
                None => break keys.len(),
                Some(p) if at_or_before(p) => (lo, step) = (p, step * 2),
                Some(p) => break p,
            }
        };
        (lo, hi)
    } else {
        // Backward: `hi` starts after the code; find a `lo` at or before it.
        let (mut hi, mut step) = (hint, 1);
        let lo = loop {
            if hi == 0 {
                return None;
            }
            let p = hi.saturating_sub(step);
            if at_or_before(p) {
                break p;
            }
            (hi, step) = (p, step * 2);
        };
        (lo, hi)
    };
    Some(lo + keys[lo + 1..hi].partition_point(|k| k.start() <= code))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::Domain;
    use crate::test_util::Rng;
    use glam::DVec3;

    /// The oracle: whether `face` is a boundary face, from the voxels' coordinates
    /// and a search of the whole key list each.
    fn is_boundary_face(tree: &LinearOctree, face: FaceKey) -> bool {
        let (mut v, n, a) = (face.voxel(), tree.domain().resolution(), face.axis());
        if !tree.contains_voxel(v) {
            return false;
        }
        let beyond = if face.positive() { v[a] + 1 == n } else { v[a] == 0 };
        v[a] = if face.positive() { v[a] + 1 } else { v[a].wrapping_sub(1) };
        beyond || !tree.contains_voxel(v)
    }

    /// A random solid of voxels and larger nodes at `depth`.
    fn random_solid(depth: u8, fill: f64, seed: u64) -> LinearOctree {
        let domain = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
        let n = domain.resolution();
        let mut rng = Rng(seed);
        let voxels: Vec<[u32; 3]> = (0..n)
            .flat_map(|x| (0..n).flat_map(move |y| (0..n).map(move |z| [x, y, z])))
            .filter(|_| rng.unit() < fill)
            .collect();
        LinearOctree::from_voxels(domain, voxels).unwrap()
    }

    #[test]
    fn the_walk_answers_as_the_search_of_each_face_does() {
        for (depth, fill, seed) in [(1, 0.5, 1), (3, 0.3, 2), (4, 0.7, 3), (5, 0.95, 4), (4, 0.0, 5), (3, 1.0, 6)] {
            let tree = random_solid(depth, fill, seed);
            let n = tree.domain().resolution();
            // Every face of every voxel, in increasing order, and each alone.
            let mut faces: Vec<FaceKey> = (0..n)
                .flat_map(|x| {
                    (0..n).flat_map(move |y| (0..n).flat_map(move |z| (0..6).map(move |d| FaceKey::new([x, y, z], d))))
                })
                .collect();
            faces.sort_unstable();
            let walk = Walk::new(&tree);
            let mut hint = 0;
            for &face in &faces {
                let expected = is_boundary_face(&tree, face);
                assert_eq!(walk.is_boundary_face(face, &mut hint), expected, "depth {depth} {face:?} walked");
                let mut far = tree.keys().len();
                assert_eq!(walk.is_boundary_face(face, &mut far), expected, "depth {depth} {face:?} from the end");
            }
            let first = faces.iter().position(|&f| !is_boundary_face(&tree, f));
            assert_eq!(first_not_on_boundary(&tree, &faces, |f| *f), first);
            let boundary: Vec<FaceKey> = faces.iter().copied().filter(|&f| is_boundary_face(&tree, f)).collect();
            assert_eq!(first_not_on_boundary(&tree, &boundary, |f| *f), None);
        }
    }

    #[test]
    fn the_stepped_code_is_the_neighbours() {
        let tree = random_solid(3, 0.5, 7);
        let walk = Walk::new(&tree);
        let n = tree.domain().resolution();
        for x in 0..n {
            for y in 0..n {
                for z in 0..n {
                    for d in 0..6 {
                        let face = FaceKey::new([x, y, z], d);
                        let mut v = [x, y, z];
                        let a = face.axis();
                        let inside = if face.positive() { v[a] + 1 < n } else { v[a] > 0 };
                        v[a] = if face.positive() { v[a] + 1 } else { v[a].wrapping_sub(1) };
                        let expected = inside.then(|| FaceKey::new(v, 0).voxel);
                        assert_eq!(walk.neighbour(face), expected, "{face:?}");
                    }
                }
            }
        }
    }

    #[test]
    fn galloping_finds_the_last_start_from_any_hint() {
        let tree = random_solid(4, 0.4, 8);
        let keys = tree.keys();
        for code in (0..tree.domain().voxel_total()).step_by(7) {
            let expected = keys.partition_point(|k| k.start() <= code).checked_sub(1);
            for hint in [0, 1, keys.len() / 3, keys.len() - 1, keys.len(), usize::MAX] {
                assert_eq!(last_starting_at_or_before(keys, hint, code), expected, "{code} from {hint}");
            }
        }
        assert_eq!(last_starting_at_or_before(&[], 0, 5), None);
    }
}
