//! The 64-tree: a traversal tree of 4x4x4 nodes built from the linear octree, for the
//! ray walk of `walk` (a contender beside the traversal octree, [`super::Traversal`]).
//!
//! After the sparse 64-trees of voxel engines (dubiousconst282's study of 64-tree
//! walks; Laine and Karras's octree for the comparison): a node is a cube of
//! 4x4x4 children, each empty, full or inner, with two 64-bit masks (present, full)
//! and the index of its first inner child (child `i = x + 4 y + 16 z`; `inner =
//! present & !full`).
//!
//! Levels: a node spans two octree levels, so a domain of even depth `d` has `d / 2`
//! levels and the root is the domain. Departure for odd depth: the root is a virtual
//! 4x4x4 node of twice the domain's edge whose low 2x2x2 children are the domain's
//! octants (the rest absent); every level below it is whole. So the root's edge is
//! always `4^levels`, and the walk's arithmetic is the same at every level.
//!
//! Layout (a contract, `Tree64::words`): one buffer of 64-bit words. A node of the
//! lowest level, whose children are voxels, is one word, its full children (present
//! and full are the same there); a node above it three: present, full, and the word
//! index of its first inner child. The lowest level's nodes come first, then the
//! upper levels from the root down, each level's nodes in Morton order, so the inner
//! children of a node lie together in child order, child `i` at `first + stride *
//! popcount(inner & ((1 << i) - 1))`, `stride` the words of a node of the child's
//! level. Departure from the study's node (two masks and a child pointer at every
//! level): the lowest level, most of the nodes, keeps one mask, so the tree takes
//! about a third of the bytes it would, and less than the traversal octree's 8 bytes
//! an inner node on every solid measured (a lowest node holds what the octree spends
//! its two lowest levels, one to nine nodes, on; BENCHMARKS.md). The walk reads a node
//! as three words at `i`, `i + k`, `i + 2 k` with `k` 1 above the lowest level and 0
//! on it, no branch, out of the three words from `i` on, one bounds check: `PAD` zero
//! words behind the last node keep them in the buffer after a lowest node too.
//!
//! Built in one pass over the sorted keys (`build`), into an exact-size buffer.

mod build;
mod walk;

use super::lanes::Isa;
use super::traversal::{Outline, Root};
use crate::octree::{Domain, LinearOctree, MAX_DEPTH};

/// Most levels of a 64-tree.
const LEVELS: usize = (MAX_DEPTH as usize).div_ceil(2);

/// Words of a node above the lowest level: present, full, first child.
const UPPER_WORDS: usize = 3;

/// Zero words behind the last node, so that the `UPPER_WORDS` words from any node on
/// are in the buffer (`Tree64::node`).
const PAD: usize = UPPER_WORDS - 1;

/// One node of the 64-tree as the walk holds it: 4x4x4 children.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Node64 {
    /// Children that hold some solid (bit `x + 4 y + 16 z`).
    pub present: u64,
    /// Children that are wholly solid.
    pub full: u64,
    /// Word index of the first inner child (nothing on the lowest level).
    pub first: usize,
}

/// The 64-tree of one solid.
#[derive(Clone, Debug)]
pub struct Tree64 {
    outline: Outline,
    /// The build the walk runs (`lanes::Isa`).
    isa: Isa,
    /// Levels of 4x4x4 nodes: `ceil(depth / 2)`; the root's edge is `4^levels` voxels.
    levels: u32,
    /// The nodes (see the module doc) and `PAD` zero words, empty unless the root is
    /// inner.
    words: Vec<u64>,
    /// Word index of the root.
    root: usize,
    /// Number of nodes.
    nodes: usize,
}

impl Tree64 {
    /// Builds the 64-tree from a canonical linear octree.
    #[must_use]
    pub fn new(tree: &LinearOctree) -> Self {
        let outline = Outline::of(tree);
        let levels = u32::from(outline.domain.depth()).div_ceil(2);
        let (words, root, nodes) =
            if outline.root == Root::Inner { build::words(tree.keys(), levels) } else { (Vec::new(), 0, 0) };
        Tree64 { outline, isa: Isa::detect(), levels, words, root, nodes }
    }

    /// The node at word `i`, of a level above the lowest when `upper` is 1 (else 0).
    #[inline(always)]
    fn node(&self, i: usize, upper: usize) -> Node64 {
        let w = &self.words[i..][..UPPER_WORDS];
        Node64 { present: w[0], full: w[upper], first: w[2 * upper] as usize }
    }

    /// The domain.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        &self.outline.domain
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes
    }

    /// Bytes used: the struct plus the node buffer.
    #[must_use]
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.words.capacity() * std::mem::size_of::<u64>()
    }
}
