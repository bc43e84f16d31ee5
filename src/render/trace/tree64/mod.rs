//! The 64-tree: a traversal tree of 4x4x4 nodes built from the linear octree, for the
//! ray walk of `walk` (a contender beside the traversal octree, [`super::Traversal`]).
//!
//! After the sparse 64-trees of voxel engines (dubiousconst282's study of 64-tree
//! walks; Laine and Karras's octree for the comparison): a node is a cube of
//! 4x4x4 children, each empty, full or inner, with two 64-bit masks (present, full)
//! and the index of its first inner child. The
//! inner children of a node are stored together in child order, so child `i` (`i =
//! x + 4 y + 16 z`) is at `first + popcount(inner & ((1 << i) - 1))`, `inner =
//! present & !full`.
//!
//! Levels: a node spans two octree levels, so a domain of even depth `d` has `d / 2`
//! levels and the root is the domain. Departure for odd depth: the root is a virtual
//! 4x4x4 node of twice the domain's edge whose low 2x2x2 children are the domain's
//! octants (the rest absent); every level below it is whole. So the root's edge is
//! always `4^levels`, and the walk's arithmetic is the same at every level.
//!
//! Built by one recursive partition of the sorted keys, as the traversal octree is
//! (O(n * depth)); a full octree node at an odd level marks its 8 cells full.

mod walk;

use super::lanes::Isa;
use super::traversal::{Outline, Root};
use crate::octree::{Domain, LinearOctree, NodeKey};

/// One node of the 64-tree: 4x4x4 children.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub(crate) struct Node64 {
    /// Children that hold some solid (bit `x + 4 y + 16 z`).
    pub present: u64,
    /// Children that are wholly solid.
    pub full: u64,
    /// Index of the first inner child.
    pub first: u32,
    _pad: [u8; 4],
}

const _: () = assert!(std::mem::size_of::<Node64>() == 24);

const EMPTY: Node64 = Node64 { present: 0, full: 0, first: 0, _pad: [0; 4] };

/// The 64-tree of one solid.
#[derive(Clone, Debug)]
pub struct Tree64 {
    outline: Outline,
    /// The build the walk runs (`lanes::Isa`).
    isa: Isa,
    /// Levels of 4x4x4 nodes: `ceil(depth / 2)`; the root's edge is `4^levels` voxels.
    levels: u32,
    nodes: Vec<Node64>,
}

impl Tree64 {
    /// Builds the 64-tree from a canonical linear octree.
    #[must_use]
    pub fn new(tree: &LinearOctree) -> Self {
        let outline = Outline::of(tree);
        let depth = u32::from(outline.domain.depth());
        let levels = depth.div_ceil(2);
        let inner = outline.root == Root::Inner;
        let mut t = Tree64 { outline, isa: Isa::detect(), levels, nodes: Vec::new() };
        if inner {
            t.nodes.push(EMPTY);
            // An odd depth's root holds the domain's octants only (see the module doc).
            t.build(0, NodeKey::new(0, depth), tree.keys(), if depth % 2 == 1 { 1 } else { 2 });
        }
        t
    }

    /// Fills node `index` for `key`, whose solid is `keys`, splitting it `split` octree
    /// levels down (2, or 1 for an odd depth's root, whose children sit in cells 0..2).
    fn build(&mut self, index: usize, key: NodeKey, keys: &[NodeKey], split: u32) {
        // The inner children's keys and key ranges, by cell.
        let mut cells = [(key, 0u32, 0u32); 64];
        let (mut present, mut full) = (0u64, 0u64);
        let mut mark = |cell: usize, child: NodeKey, a: usize, b: usize, is_full: bool| {
            present |= 1 << cell;
            if is_full {
                full |= 1 << cell;
            } else {
                cells[cell] = (child, a as u32, b as u32);
            }
        };
        let mut pos = 0;
        for i in 0..8u64 {
            let child = key.child(i).expect("an inner node is not a voxel");
            let start = pos;
            while pos < keys.len() && keys[pos].start() < child.end() {
                pos += 1;
            }
            if pos == start {
                continue;
            }
            let bit = |a: u64| (i >> a & 1) as usize;
            let child_full = pos - start == 1 && keys[start] == child;
            if split == 1 {
                mark(bit(0) + 4 * bit(1) + 16 * bit(2), child, start, pos, child_full);
                continue;
            }
            let mut sub = start;
            for j in 0..8u64 {
                let cell = |a: u64| 2 * bit(a) + (j >> a & 1) as usize;
                let cell = cell(0) + 4 * cell(1) + 16 * cell(2);
                if child_full {
                    mark(cell, child, start, pos, true);
                    continue;
                }
                let grandchild = child.child(j).expect("an inner node is not a voxel");
                let from = sub;
                while sub < pos && keys[sub].start() < grandchild.end() {
                    sub += 1;
                }
                if sub > from {
                    mark(cell, grandchild, from, sub, sub - from == 1 && keys[from] == grandchild);
                }
            }
        }
        let inner = present & !full;
        let first = self.nodes.len();
        self.nodes[index] = Node64 { present, full, first: first as u32, _pad: [0; 4] };
        self.nodes.extend(std::iter::repeat_n(EMPTY, inner.count_ones() as usize));
        let (mut slot, mut bits) = (first, inner);
        while bits != 0 {
            let (child, a, b) = cells[bits.trailing_zeros() as usize];
            self.build(slot, child, &keys[a as usize..b as usize], 2);
            slot += 1;
            bits &= bits - 1;
        }
    }

    /// The domain.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        &self.outline.domain
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bytes used: the struct plus the node buffer.
    #[must_use]
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.nodes.capacity() * std::mem::size_of::<Node64>()
    }
}
