//! The keys meeting a node: the one search the descents over a key list share.
//!
//! Walks that descend the implicit tree of a canonical key list (the exact translate,
//! box classification for resampling, dense occupancy, the boundary mesh's face
//! neighbours) need, at each node, the run of keys that overlap the node's Morton range
//! `[s, e)`. Aligned cubes nest or are disjoint, so a key starting at or before `s`
//! that reaches past `s` either covers the whole node or starts at `s`; every other key
//! meeting the node starts inside it. Hence two binary searches find the run: the last
//! key starting at or before `s` (does it reach past `s`?), then the first key starting
//! at or after `e`.
//!
//! Convention: when one key covers the node, the run is that key alone, so callers
//! read the three cases off the slice: `[]` (the node is empty), `[key] if key.k() >=
//! node.k()` (the node is full: a meeting key at least the node's size covers it) and
//! anything else (partly full; a canonical list has no set of keys filling a node
//! without one covering it). Each case needs the run to hold every key of the list
//! that meets the node, which a parent's run does for its children: descents narrow
//! the run as they go down.

use std::ops::Range;

use super::node::NodeKey;

/// The keys of the sorted, disjoint run `keys` that meet `node` (just the covering key
/// when one covers it), given that `keys` holds every key of the list meeting `node`.
/// Two binary searches over `keys`: `O(log |keys|)`.
#[must_use]
pub(crate) fn keys_meeting(keys: &[NodeKey], node: NodeKey) -> &[NodeKey] {
    let (s, e) = (node.start(), node.end());
    // Step 1: the last key starting at or before `s` covers the node, starts at `s`
    // inside it, or lies before it.
    let first = keys.partition_point(|k| k.start() <= s);
    let from = match first.checked_sub(1) {
        Some(i) if keys[i].end() >= e => return &keys[i..first],
        Some(i) if keys[i].end() > s => i,
        _ => first,
    };
    // Step 2: the keys starting inside the node.
    &keys[from..first + keys[first..].partition_point(|k| k.start() < e)]
}

/// [`keys_meeting`] over a whole key list, searched by galloping from index `hint`:
/// `O(log distance)` rather than `O(log n)`, for walks that look at nodes near a key
/// they hold (the face neighbours of `keys[hint]`, most of which lie near it in Morton
/// order). Same result as `keys_meeting(keys, node)`.
#[must_use]
pub(crate) fn keys_meeting_near(keys: &[NodeKey], hint: usize, node: NodeKey) -> &[NodeKey] {
    &keys[range_meeting_near(keys, hint, node)]
}

/// [`keys_meeting_near`] as index range into `keys`, for walks that need the keys'
/// places in the list (the component count's union-find).
#[must_use]
pub(crate) fn range_meeting_near(keys: &[NodeKey], hint: usize, node: NodeKey) -> Range<usize> {
    let (s, e) = (node.start(), node.end());
    // Step 1: the first key starting at or after `s`; the key before it covers the
    // node when it reaches past `s` (it starts before `s`, so it is larger).
    let lo = seek(keys, hint, s);
    if lo > 0 && keys[lo - 1].end() > s {
        return lo - 1..lo;
    }
    // Step 2: the keys starting inside the node (a first one starting at `s` and at
    // least the node's size covers it and is then the only one).
    lo..seek(keys, lo, e)
}

/// The index of the first key starting at or after Morton code `code`
/// (`partition_point`), galloping from index `from`.
fn seek(keys: &[NodeKey], from: usize, code: u64) -> usize {
    let before = |i: usize| keys[i].start() < code;
    let (mut lo, mut hi);
    if from < keys.len() && before(from) {
        // Forward: keys[lo] is before the code; grow the step until keys[hi] is not.
        (lo, hi) = (from, from + 1);
        let mut step = 1;
        while hi < keys.len() && before(hi) {
            lo = hi;
            step *= 2;
            hi = (hi + step).min(keys.len());
        }
        lo += 1;
    } else {
        // Backward: keys[hi] (or the end) is not before the code.
        (lo, hi) = (from.min(keys.len()), from.min(keys.len()));
        let mut step = 1;
        while lo > 0 && !before(lo - 1) {
            hi = lo - 1;
            lo = lo.saturating_sub(step);
            step *= 2;
        }
    }
    lo + keys[lo..hi].partition_point(|k| k.start() < code)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::{Domain, LinearOctree, Node};
    use glam::DVec3;

    /// Brute force: every key overlapping the node's range, or the covering key alone.
    fn oracle(keys: &[NodeKey], node: NodeKey) -> Vec<NodeKey> {
        let meeting: Vec<NodeKey> =
            keys.iter().copied().filter(|k| k.start() < node.end() && node.start() < k.end()).collect();
        match meeting.iter().find(|k| k.start() <= node.start() && node.end() <= k.end()) {
            Some(&cover) => vec![cover],
            None => meeting,
        }
    }

    #[test]
    fn both_searches_find_exactly_the_keys_meeting_every_node() {
        // A depth-4 solid with nodes of every size: voxels, 2-cubes, 4-cubes, an 8-cube.
        let domain = Domain::new(DVec3::ZERO, 1.0, 4).unwrap();
        let cube = |min, size| Node { level: 0, min, size };
        let blocks = [cube([0, 0, 0], 8), cube([8, 0, 0], 4), cube([12, 4, 0], 2), cube([0, 8, 8], 4)];
        let voxels = (0..16u32).flat_map(|x| (0..16u32).flat_map(move |y| (0..16u32).map(move |z| [x, y, z])));
        let scattered = voxels.filter(|&[x, y, z]| (x * 7 + y * 3 + z * 5) % 11 < 3).map(|v| cube(v, 1));
        let tree = LinearOctree::from_nodes(domain, blocks.into_iter().chain(scattered)).unwrap();
        let keys = tree.keys();
        assert!((0..=3).all(|k| keys.iter().any(|key| key.k() == k)), "nodes of every size up to 8");
        let mut cases = [0usize; 3];
        for k in 0..=4u32 {
            for start in (0..domain.voxel_total()).step_by(1 << (3 * k)) {
                let node = NodeKey::new(start, k);
                let want = oracle(keys, node);
                assert_eq!(keys_meeting(keys, node), want, "{node:?}");
                for hint in [0, keys.len() / 3, keys.len() - 1, keys.len()] {
                    assert_eq!(keys_meeting_near(keys, hint, node), want, "{node:?} from {hint}");
                    assert_eq!(&keys[range_meeting_near(keys, hint, node)], want, "{node:?} from {hint}");
                }
                // A parent's run holds every key meeting its children.
                if let Some(child) = node.child(5) {
                    assert_eq!(keys_meeting(&want, child), oracle(keys, child), "{child:?} in {node:?}");
                }
                cases[match want.as_slice() {
                    [] => 0,
                    [key] if key.k() >= node.k() => 1,
                    _ => 2,
                }] += 1;
            }
        }
        assert!(cases.iter().all(|&c| c > 10), "empty, covered and mixed nodes all seen: {cases:?}");
    }
}
