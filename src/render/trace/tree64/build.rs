//! The 64-tree's build: one pass over the linear octree's sorted keys, each node
//! written once when the keys have left it, into an exact-size buffer.
//!
//! Keys come in Morton order, so the nodes a key lies in are a path from the root, and
//! the path of the next key shares a prefix with it: the nodes below the shared part
//! are finished (no later key reaches them) and are closed, the new key's nodes below
//! it opened. A key at padded octree level `p` (levels counted from the 64-tree's root,
//! `2 * levels` to the voxels, so an odd depth's virtual root adds one on top) marks its
//! node at level `(p - 1) / 2`: one cell full when `p` is even, the 2x2x2 group of 8
//! cells full when `p` is odd (a full octree node at an odd level); the nodes opened
//! above it mark the child they open as present. Which levels two keys share is read
//! off the highest bit of the XOR of their start codes (one node level a digit pair).
//! O(keys * levels opened), against O(keys * depth) for a recursive partition of the
//! keys (the traversal octree's build), and no per-node work on child keys.
//!
//! Each level's closed nodes are appended to a buffer of that level, in Morton order;
//! a node's first inner child is the length of the next level's buffer when the node
//! is opened (every node of the next level closed before it belongs to an earlier
//! node), and when it closes its children, the buffer's last, are put from Morton
//! order (digits `hi lo`: coordinates `2 hi + lo`) into child order (`x + 4 y + 16 z`,
//! the order the walk's ranks count). The lowest level's buffer, by far the largest, becomes the tree's buffer in
//! place and the upper levels are appended behind it, their child indices offset to
//! word indices (see `Tree64` for the layout), `PAD` zero words behind them; the buffer
//! is then shrunk to its length.

use super::{LEVELS, PAD, UPPER_WORDS};
use crate::octree::NodeKey;

/// The 8 cells of a node's 2x2x2 group 0 (bits `x + 4 y + 16 z`, `x, y, z` in 0..2);
/// the group of octree digit `d` is this shifted by `2 * spread(d)`.
const GROUP: u64 = 0x0033_0033;

/// The bits `x + 2 y + 4 z` of a Morton digit moved to bits 0, 2, 4: the low bit of
/// each axis' coordinate in a 4x4x4 node.
#[inline(always)]
fn spread(digit: u64) -> u64 {
    (digit & 1) | (digit & 2) << 1 | (digit & 4) << 2
}

/// The child cell (`x + 4 y + 16 z`) of a node of a pair of Morton digits `hi lo` (six
/// bits, `hi` the coarser): each axis' coordinate is `2 hi + lo`.
#[inline(always)]
fn cell(pair: u64) -> u64 {
    2 * spread(pair >> 3 & 7) + spread(pair & 7)
}

/// `MORTON[c]`: the place of cell `c` (`x + 4 y + 16 z`) in Morton order, the pair of
/// digits `hi lo` with `hi` the high bits of the coordinates, `lo` the low ones.
const MORTON: [u8; 64] = {
    let mut order = [0u8; 64];
    let mut c = 0;
    while c < 64 {
        let (x, y, z) = (c & 3, c >> 2 & 3, c >> 4 & 3);
        order[c] = ((x >> 1 | (y >> 1) << 1 | (z >> 1) << 2) << 3 | (x & 1) | (y & 1) << 1 | (z & 1) << 2) as u8;
        c += 1;
    }
    order
};

/// Puts the inner children `block` of a node, closed in Morton order, in child order
/// (the order of the cells `x + 4 y + 16 z` of `inner`, which the walk's ranks count).
fn to_cell_order<T: Copy>(block: &mut [T], inner: u64, scratch: &mut Vec<T>) {
    // `rank[m]`: the child-order place of the inner cell at Morton place `m`.
    let (mut rank, mut morton) = ([0u8; 64], 0u64);
    let mut bits = inner;
    let mut i = 0;
    while bits != 0 {
        let m = MORTON[bits.trailing_zeros() as usize];
        morton |= 1 << m;
        rank[m as usize] = i;
        i += 1;
        bits &= bits - 1;
    }
    scratch.clear();
    scratch.extend_from_slice(block);
    let mut bits = morton;
    for &child in scratch.iter() {
        block[rank[bits.trailing_zeros() as usize] as usize] = child;
        bits &= bits - 1;
    }
}

/// A node being filled.
#[derive(Clone, Copy, Default)]
struct Open {
    present: u64,
    full: u64,
    /// Index of its first inner child in the next level's buffer.
    first: usize,
}

/// Builds the words of a 64-tree of `levels` levels over `keys` (sorted, disjoint, not
/// the whole root: some key is below it). Returns the words, the root's word index
/// and the number of nodes.
pub(super) fn words(keys: &[NodeKey], levels: u32) -> (Vec<u64>, usize, usize) {
    let padded = 2 * levels;
    let bottom = levels as usize - 1;
    // The upper levels' nodes (present, full, first), and the lowest level's masks.
    let mut upper: Vec<Vec<[u64; 3]>> = vec![Vec::new(); bottom];
    let mut lowest: Vec<u64> = Vec::new();
    let mut open = [Open::default(); LEVELS];
    // Levels `0..top` are open.
    let mut top = 1usize;
    let mut prev = 0u64;
    let (mut scratch_upper, mut scratch_lowest) = (Vec::new(), Vec::new());
    let mut close = |level: usize, node: Open, upper: &mut Vec<Vec<[u64; 3]>>, lowest: &mut Vec<u64>| {
        if level == bottom {
            debug_assert_eq!(node.present, node.full, "a voxel cell is empty or full");
            lowest.push(node.full);
            return;
        }
        let inner = node.present & !node.full;
        let children = node.first..node.first + inner.count_ones() as usize;
        if level + 1 == bottom {
            to_cell_order(&mut lowest[children], inner, &mut scratch_lowest);
        } else {
            to_cell_order(&mut upper[level + 1][children], inner, &mut scratch_upper);
        }
        upper[level].push([node.present, node.full, node.first as u64]);
    };
    let len = |level: usize, upper: &Vec<Vec<[u64; 3]>>, lowest: &Vec<u64>| {
        if level == bottom { lowest.len() } else { upper[level].len() }
    };
    for key in keys {
        let s = key.start();
        let p = padded - key.k();
        debug_assert!(p >= 1, "a key below the root");
        let level = (p as usize - 1) / 2;
        // The deepest node holding the previous key's start too: level `j` holds both
        // while their codes agree above its children's `3 (padded - 2 j)` bits.
        let bits = 64 - (s ^ prev).leading_zeros();
        let shared = (3 * padded - bits) as usize / 6;
        let keep = (shared.min(level) + 1).min(top);
        while top > keep {
            top -= 1;
            close(top, open[top], &mut upper, &mut lowest);
        }
        while top <= level {
            let above = &mut open[top - 1];
            above.present |= 1 << cell(s >> (3 * (padded as usize - 2 * top)) & 63);
            let first = if top < bottom { len(top + 1, &upper, &lowest) } else { 0 };
            open[top] = Open { present: 0, full: 0, first };
            top += 1;
        }
        let node = &mut open[level];
        let mask = if p % 2 == 1 {
            GROUP << (2 * spread(s >> (3 * (padded - p)) & 7))
        } else {
            1 << cell(s >> (3 * (padded - p)) & 63)
        };
        node.present |= mask;
        node.full |= mask;
        prev = s;
    }
    while top > 0 {
        top -= 1;
        close(top, open[top], &mut upper, &mut lowest);
    }
    // The lowest level first, then the upper levels from the root down.
    let nodes = lowest.len() + upper.iter().map(Vec::len).sum::<usize>();
    let mut words = lowest;
    let upper_words: usize = upper.iter().map(|l| UPPER_WORDS * l.len()).sum();
    words.reserve_exact(upper_words + PAD);
    let mut base = words.len();
    let root = if bottom == 0 { 0 } else { base };
    for (level, nodes) in upper.iter().enumerate() {
        // Where the next level starts: the lowest level at 0, an upper one behind this.
        let next = if level + 1 == bottom { 0 } else { base + UPPER_WORDS * nodes.len() };
        let stride = if level + 1 == bottom { 1 } else { UPPER_WORDS };
        for &[present, full, first] in nodes {
            words.extend([present, full, (next + stride * first as usize) as u64]);
        }
        base += UPPER_WORDS * nodes.len();
    }
    words.extend([0; PAD]);
    words.shrink_to_fit();
    (words, root, nodes)
}

#[cfg(test)]
mod tests {
    use super::super::Tree64;
    use crate::octree::{Domain, LinearOctree, Node, NodeKey};
    use crate::test_util::Rng;
    use glam::DVec3;

    /// Voxels of the solid `keys` in the Morton range `[start, start + len)`.
    fn overlap(keys: &[NodeKey], start: u64, len: u64) -> u64 {
        keys.iter().map(|k| (k.end().min(start + len)).saturating_sub(k.start().max(start))).sum()
    }

    /// Checks node `i` at `level`, of Morton prefix `prefix` (its code above its cells'
    /// `2 (levels - level)` digits), against the keys, and the nodes below it; returns
    /// the words and nodes met.
    fn check(t: &Tree64, keys: &[NodeKey], i: usize, level: usize, prefix: u64) -> (usize, usize) {
        let bottom = t.levels as usize - 1;
        let upper = usize::from(level < bottom);
        let node = t.node(i, upper);
        let (mut words, mut nodes) = (1 + 2 * upper, 1);
        let below = 2 * (t.levels as usize - level - 1);
        let len = 1u64 << (3 * below);
        let mut rank = 0;
        for cell in 0..64u64 {
            let (x, y, z) = (cell & 3, cell >> 2 & 3, cell >> 4 & 3);
            let hi = (x >> 1) | (y >> 1) << 1 | (z >> 1) << 2;
            let lo = (x & 1) | (y & 1) << 1 | (z & 1) << 2;
            let code = (prefix << 6 | hi << 3 | lo) << (3 * below);
            let v = overlap(keys, code, len);
            assert_eq!(
                node.present >> cell & 1 == 1,
                v > 0,
                "present, level {level} cell {cell} levels {} keys {:?}",
                t.levels,
                keys.iter().map(|k| (k.start(), k.k())).collect::<Vec<_>>()
            );
            assert_eq!(node.full >> cell & 1 == 1, v == len, "full, level {level} cell {cell}");
            if v > 0 && v < len {
                let stride = if level + 1 < bottom { super::UPPER_WORDS } else { 1 };
                let (w, n) = check(t, keys, node.first + rank * stride, level + 1, code >> (3 * below));
                (words, nodes) = (words + w, nodes + n);
                rank += 1;
            }
        }
        (words, nodes)
    }

    /// Every node's masks against the voxels the keys hold in each cell (Morton range
    /// overlaps, counted by brute force), every inner child where its parent's first
    /// index and rank place it, and every word of the buffer some node's but the zero padding, at every
    /// depth 1-8 (odd depths' padded root among them), on solids of nodes at every
    /// level, odd levels' full nodes among them.
    #[test]
    fn every_node_holds_its_cells_solid() {
        let mut rng = Rng(0x64b0_11d5);
        for depth in 1..=8u8 {
            let domain = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
            let n = domain.resolution();
            for _ in 0..6 {
                let nodes: Vec<Node> = (0..1 + rng.below(60))
                    .map(|_| {
                        let k = rng.below(u64::from(depth)) as u32;
                        let min = [0; 3].map(|_| (rng.below(u64::from(n >> k)) as u32) << k);
                        Node { level: depth - k as u8, min, size: 1 << k }
                    })
                    .collect();
                let tree = LinearOctree::from_nodes(domain, nodes).unwrap();
                let t = Tree64::new(&tree);
                let whole = tree.keys().len() == 1 && tree.keys()[0].k() == u32::from(depth);
                if whole {
                    assert!(t.words.is_empty());
                    continue;
                }
                let (words, nodes) = check(&t, tree.keys(), t.root, 0, 0);
                assert_eq!((words + super::PAD, nodes), (t.words.len(), t.node_count()), "depth {depth}");
                assert!(t.words[words..].iter().all(|&w| w == 0), "padding");
                assert_eq!(t.words.capacity(), t.words.len());
            }
        }
    }
}
