//! The traversal octree: a compact pointer octree built from the linear octree, for
//! the ray walk (`walk`), the beam pre-pass of packets (`beam`) and the object-order
//! displays, which visit its full nodes front to back.
//!
//! Layout (a contract, 8 bytes an inner node): for each inner node the masks of its
//! non-empty and of its full children and the index of its first inner child; the inner
//! children of a node are stored together in child order, so child `i` is at
//! `first + popcount(inner & ((1 << i) - 1))`. Built by one recursive partition of the
//! sorted keys, O(n * depth).

use super::lanes::Isa;
use super::reach::Reach;
use crate::octree::{Domain, LinearOctree, NodeKey};

/// One inner node of the traversal octree.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(C)]
pub struct Inner {
    /// Index of the first inner child.
    pub first: u32,
    /// Children that hold some solid.
    pub valid: u8,
    /// Children that are wholly solid.
    pub full: u8,
    _pad: u16,
}

const _: () = assert!(std::mem::size_of::<Inner>() == 8);

/// What the root is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Root {
    Empty,
    Full,
    Inner,
}

/// What every walk of one solid reads before its tree: the domain, what the root is,
/// and the boxes of the full voxels (shared by the traversal octree and the 64-tree,
/// `tree64`).
#[derive(Clone, Debug)]
pub(super) struct Outline {
    pub domain: Domain,
    pub root: Root,
    /// The planes bounding the full voxels, `[low, high)` in voxel units (all 0 when
    /// empty): a walk meets no full voxel outside them (see `walk`).
    pub occupied: [[f64; 3]; 2],
    /// The full voxels' box in world space, grown by more than any rounding: a ray
    /// that cannot meet it is not walked.
    pub reach: Reach,
}

impl Outline {
    /// The outline of a canonical linear octree.
    pub fn of(tree: &LinearOctree) -> Self {
        let domain = *tree.domain();
        let keys = tree.keys();
        let root = match keys {
            [] => Root::Empty,
            [k] if *k == NodeKey::new(0, u32::from(domain.depth())) => Root::Full,
            _ => Root::Inner,
        };
        let bounds = tree.voxel_bounds().unwrap_or(([0; 3], [0; 3]));
        let occupied = [bounds.0.map(f64::from), bounds.1.map(f64::from)];
        let reach = Reach::around(&domain, bounds.0, bounds.1);
        Outline { domain, root, occupied, reach }
    }
}

/// The traversal octree of one solid.
#[derive(Clone, Debug)]
pub struct Traversal {
    pub(super) outline: Outline,
    /// The instruction set the walk runs on (the best this CPU has).
    pub(super) isa: Isa,
    pub(super) nodes: Vec<Inner>,
}

impl Traversal {
    /// Builds the pointer octree from a canonical linear octree.
    #[must_use]
    pub fn new(tree: &LinearOctree) -> Self {
        let outline = Outline::of(tree);
        let root_key = NodeKey::new(0, u32::from(outline.domain.depth()));
        let inner = outline.root == Root::Inner;
        let mut t = Traversal { outline, isa: Isa::detect(), nodes: Vec::new() };
        if inner {
            t.nodes.push(Inner { first: 0, valid: 0, full: 0, _pad: 0 });
            t.build(0, root_key, tree.keys());
        }
        t
    }

    /// Fills inner node `index` for `key`, whose solid is `keys`.
    fn build(&mut self, index: usize, key: NodeKey, keys: &[NodeKey]) {
        let mut ranges = [(0usize, 0usize); 8];
        let mut pos = 0;
        let (mut valid, mut full) = (0u8, 0u8);
        for (i, range) in ranges.iter_mut().enumerate() {
            let child = key.child(i as u64).expect("an inner node is not a voxel");
            let start = pos;
            while pos < keys.len() && keys[pos].start() < child.end() {
                pos += 1;
            }
            *range = (start, pos);
            if pos > start {
                valid |= 1 << i;
                if pos - start == 1 && keys[start] == child {
                    full |= 1 << i;
                }
            }
        }
        let inner = valid & !full;
        let first = self.nodes.len();
        self.nodes[index] = Inner { first: first as u32, valid, full, _pad: 0 };
        self.nodes
            .extend(std::iter::repeat_n(Inner { first: 0, valid: 0, full: 0, _pad: 0 }, inner.count_ones() as usize));
        let mut slot = first;
        for (i, &(a, b)) in ranges.iter().enumerate() {
            if inner >> i & 1 == 1 {
                self.build(slot, key.child(i as u64).expect("inner"), &keys[a..b]);
                slot += 1;
            }
        }
    }

    /// The domain.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        &self.outline.domain
    }

    /// Number of inner nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bytes used: the struct plus the node buffer.
    #[must_use]
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.nodes.capacity() * std::mem::size_of::<Inner>()
    }

    /// The root for walks of their own (the front-to-back display): `None` when empty,
    /// `Some([])` when wholly full, else the inner nodes with the root at index 0.
    pub(crate) fn inner_nodes(&self) -> Option<&[Inner]> {
        match self.outline.root {
            Root::Empty => None,
            Root::Full => Some(&[]),
            Root::Inner => Some(&self.nodes),
        }
    }

    /// Visits the full nodes front to back for a viewer (Meagher's octree display
    /// order): in every inner node, the child on the viewer's side of all three mid
    /// planes first, then those across one plane, two, three. A node can only hide
    /// nodes visited after it. `eye_high(axis, plane)` says whether the viewer is on
    /// the high side of `plane` (voxel units); `enter(min, size)` may prune a subtree;
    /// `full(min, size)` receives each full node.
    pub fn front_to_back(
        &self,
        eye_high: &impl Fn(usize, f64) -> bool,
        enter: &mut impl FnMut([u32; 3], u32) -> bool,
        full: &mut impl FnMut([u32; 3], u32),
    ) {
        let n = self.outline.domain.resolution();
        match self.outline.root {
            Root::Empty => {}
            Root::Full => full([0, 0, 0], n),
            Root::Inner => self.front_to_back_node(0, [0, 0, 0], n, eye_high, enter, full),
        }
    }

    fn front_to_back_node(
        &self,
        index: u32,
        min: [u32; 3],
        size: u32,
        eye_high: &impl Fn(usize, f64) -> bool,
        enter: &mut impl FnMut([u32; 3], u32) -> bool,
        full: &mut impl FnMut([u32; 3], u32),
    ) {
        if !enter(min, size) {
            return;
        }
        let inner = self.nodes[index as usize];
        let half = size / 2;
        let e = (0..3).fold(0usize, |bits, a| bits | usize::from(eye_high(a, f64::from(min[a] + half))) << a);
        for j in [0usize, 1, 2, 4, 3, 5, 6, 7] {
            let child = e ^ j;
            if inner.valid >> child & 1 == 0 {
                continue;
            }
            let cmin: [u32; 3] = std::array::from_fn(|a| min[a] + if child >> a & 1 == 1 { half } else { 0 });
            if inner.full >> child & 1 == 1 {
                full(cmin, half);
            } else {
                let slot = inner.first + (inner.valid & !inner.full & ((1u8 << child) - 1)).count_ones();
                self.front_to_back_node(slot, cmin, half, eye_high, enter, full);
            }
        }
    }
}
