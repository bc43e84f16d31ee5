//! [`LinearOctree`]: a solid as the sorted, canonical list of its full nodes.

use glam::DVec3;

use super::domain::Domain;
use super::node::{Node, NodeKey};
use super::ranges::{self, Runs};
use crate::aabb::Aabb;
use crate::error::{Error, Result};
use crate::morton;

/// A solid stored as the Morton-sorted list of its full ("black") nodes.
///
/// Invariants (checked by [`LinearOctree::validate`]):
/// - every key lies inside the domain (`end <= 8^depth`);
/// - keys are sorted by Morton start and pairwise disjoint;
/// - canonical: no eight full siblings (they would be their parent).
///
/// A solid has exactly one canonical form, so two octrees over the same domain hold
/// the same solid iff their key lists are equal (`==`). Memory: 8 bytes a node.
#[derive(Clone, Debug, PartialEq)]
pub struct LinearOctree {
    domain: Domain,
    keys: Vec<NodeKey>,
}

impl LinearOctree {
    /// The empty solid.
    #[must_use]
    pub fn empty(domain: Domain) -> Self {
        LinearOctree { domain, keys: Vec::new() }
    }

    /// The whole domain: one root node.
    #[must_use]
    pub fn full(domain: Domain) -> Self {
        LinearOctree { domain, keys: vec![NodeKey::new(0, u32::from(domain.depth()))] }
    }

    /// The solid made of the given voxels (any order, repeats allowed).
    ///
    /// Fails when a voxel lies outside the domain.
    pub fn from_voxels(domain: Domain, voxels: impl IntoIterator<Item = [u32; 3]>) -> Result<Self> {
        let n = domain.resolution();
        let mut codes = Vec::new();
        for v in voxels {
            if v.iter().any(|&c| c >= n) {
                return Err(Error::invalid("voxel", format!("{v:?} is outside 0..{n}")));
            }
            codes.push(morton::encode(v[0], v[1], v[2]));
        }
        codes.sort_unstable();
        Ok(Self::from_sorted_runs(domain, codes.into_iter().map(|c| (c, c + 1))))
    }

    /// The union of the given nodes (any order, may overlap), canonicalized.
    ///
    /// Fails when a node is not an aligned cube inside the domain.
    pub fn from_nodes(domain: Domain, nodes: impl IntoIterator<Item = Node>) -> Result<Self> {
        let mut keys = Vec::new();
        for node in nodes {
            let key = node
                .key()
                .filter(|_| {
                    node.min.iter().all(|&c| u64::from(c) + u64::from(node.size) <= u64::from(domain.resolution()))
                })
                .ok_or_else(|| Error::invalid("node", format!("{node:?} is not an aligned cube inside the domain")))?;
            keys.push(key);
        }
        Ok(Self::from_keys_unsorted(domain, keys))
    }

    /// Canonical octree from keys in any order that lie inside the domain.
    pub(crate) fn from_keys_unsorted(domain: Domain, mut keys: Vec<NodeKey>) -> Self {
        keys.sort_unstable_by_key(|k| k.start());
        Self::from_sorted_runs(domain, keys.iter().map(|k| (k.start(), k.end())))
    }

    /// Canonical octree from runs sorted by start (they may overlap or touch).
    pub(crate) fn from_sorted_runs(domain: Domain, runs: impl IntoIterator<Item = (u64, u64)>) -> Self {
        Self::from_canonical(domain, ranges::cut_runs(runs))
    }

    /// Wraps keys already known to be canonical (debug builds check), trimming spare capacity.
    pub(crate) fn from_canonical(domain: Domain, mut keys: Vec<NodeKey>) -> Self {
        keys.shrink_to_fit();
        let tree = LinearOctree { domain, keys };
        debug_assert!(tree.validate().is_ok(), "{:?}", tree.validate());
        tree
    }

    /// The same keys read in another domain (of at least this depth), without a copy:
    /// a key names a Morton start and a height above the voxels, so it describes the
    /// same cells of any domain with the same voxel lattice from its corner.
    pub(crate) fn reframed(self, domain: Domain) -> Self {
        LinearOctree::from_canonical(domain, self.keys)
    }

    /// An octree from raw keys, checked against every invariant.
    pub fn from_keys(domain: Domain, keys: Vec<NodeKey>) -> Result<Self> {
        let tree = LinearOctree { domain, keys };
        tree.validate()?;
        Ok(tree)
    }

    /// An octree from keys a reader decoded in range, sorted and disjoint (its format
    /// gives them so by construction), checked to be canonical: the check of
    /// [`LinearOctree::from_keys`] without the parts the decoding made.
    pub(crate) fn from_ordered_keys(domain: Domain, keys: Vec<NodeKey>) -> Result<Self> {
        debug_assert!(keys.iter().all(|k| k.end() <= domain.voxel_total()), "a key outside the domain");
        debug_assert!(keys.windows(2).all(|w| w[0].end() <= w[1].start()), "keys out of order or overlapping");
        let max_k = u32::from(domain.depth());
        (0..keys.len()).try_for_each(|i| check_canonical(&keys, i, max_k))?;
        Ok(LinearOctree { domain, keys })
    }

    /// Checks every invariant: in range, sorted, disjoint, canonical.
    pub fn validate(&self) -> Result<()> {
        let total = self.domain.voxel_total();
        let max_k = u32::from(self.domain.depth());
        let bad = |index, reason: String| Err(Error::InvalidOctree { index, reason });
        for (i, key) in self.keys.iter().enumerate() {
            if key.k() > max_k || key.end() > total {
                return bad(i, format!("{key:?} lies outside the depth-{max_k} domain"));
            }
            if i > 0 && self.keys[i - 1].end() > key.start() {
                return bad(i, format!("{key:?} is out of order or overlaps the node before it"));
            }
            check_canonical(&self.keys, i, max_k)?;
        }
        Ok(())
    }

    /// The domain and depth.
    #[must_use]
    pub fn domain(&self) -> &Domain {
        &self.domain
    }

    /// Depth (levels below the root).
    #[must_use]
    pub fn depth(&self) -> u8 {
        self.domain.depth()
    }

    /// The sorted canonical keys.
    #[must_use]
    pub fn keys(&self) -> &[NodeKey] {
        &self.keys
    }

    /// The sorted canonical keys as their `u64` encodings (see [`NodeKey`]'s module
    /// doc), the same memory as [`LinearOctree::keys`]: what bindings hand out as an
    /// array without copying.
    #[must_use]
    pub fn key_bits(&self) -> &[u64] {
        // SAFETY: `NodeKey` is `#[repr(transparent)]` over a `u64`, so a slice of keys
        // is a slice of `u64`s of the same length, alignment and lifetime.
        unsafe { std::slice::from_raw_parts(self.keys.as_ptr().cast::<u64>(), self.keys.len()) }
    }

    /// The sorted, canonical node keys, taken out.
    #[must_use]
    pub fn into_keys(self) -> Vec<NodeKey> {
        self.keys
    }

    /// Number of nodes.
    #[must_use]
    pub fn node_count(&self) -> usize {
        self.keys.len()
    }

    /// Whether the solid is empty.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Bytes used in memory: the struct plus the key buffer's capacity.
    #[must_use]
    pub fn bytes(&self) -> usize {
        std::mem::size_of::<Self>() + self.keys.capacity() * std::mem::size_of::<NodeKey>()
    }

    /// Number of full voxels, exact at every depth (at most `8^21 = 2^63`).
    #[must_use]
    pub fn voxel_count(&self) -> u64 {
        self.keys.iter().map(|k| k.len()).sum()
    }

    /// Volume in world units: voxel count times `h^3`.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.voxel_count() as f64 * self.domain.voxel_size().powi(3)
    }

    /// Nodes in Morton order with their level and integer coordinates.
    pub fn nodes(&self) -> impl ExactSizeIterator<Item = Node> + '_ {
        let depth = self.depth();
        self.keys.iter().map(move |k| k.node(depth))
    }

    /// Maximal runs `[start, end)` of consecutive full voxel Morton codes.
    pub(crate) fn runs(&self) -> Runs<'_> {
        Runs::new(&self.keys)
    }

    /// Index of the node holding voxel Morton code `code`, if any.
    #[must_use]
    pub fn find_code(&self, code: u64) -> Option<usize> {
        // Last key starting at or before `code`.
        let i = self.keys.partition_point(|k| k.start() <= code).checked_sub(1)?;
        (code < self.keys[i].end()).then_some(i)
    }

    /// The node holding voxel `v`, if the voxel is full.
    #[must_use]
    pub fn node_at(&self, v: [u32; 3]) -> Option<Node> {
        if v.iter().any(|&c| c >= self.domain.resolution()) {
            return None;
        }
        let i = self.find_code(morton::encode(v[0], v[1], v[2]))?;
        Some(self.keys[i].node(self.depth()))
    }

    /// Whether voxel `v` is full.
    #[must_use]
    pub fn contains_voxel(&self, v: [u32; 3]) -> bool {
        self.node_at(v).is_some()
    }

    /// Whether the world point `p` lies in a full voxel (points outside the domain do not).
    #[must_use]
    pub fn contains_point(&self, p: DVec3) -> bool {
        self.domain.voxel_of(p).is_some_and(|v| self.contains_voxel(v))
    }

    /// Integer bounds `[min, max)` of the full voxels, `None` when empty.
    ///
    /// Without decoding a key: a coordinate is the Morton code's bits of its axis
    /// (`code & mask`) moved together, which keeps their order, so the least `x` of
    /// the nodes' first voxels is the `x` of the least `first & mask_x`, and the
    /// greatest `x + 1` of their last voxels that of the greatest `last & mask_x`.
    #[must_use]
    pub fn voxel_bounds(&self) -> Option<([u32; 3], [u32; 3])> {
        if self.keys.is_empty() {
            return None;
        }
        const X: u64 = 0x1249_2492_4924_9249; // bits 0, 3, 6, ...
        let masks = [X, X << 1, X << 2];
        let (mut lo, mut hi) = ([u64::MAX; 3], [0u64; 3]);
        for k in &self.keys {
            let (first, last) = (k.start(), k.last());
            for a in 0..3 {
                lo[a] = lo[a].min(first & masks[a]);
                hi[a] = hi[a].max(last & masks[a]);
            }
        }
        Some((
            std::array::from_fn(|a| morton::compact(lo[a] >> a)),
            std::array::from_fn(|a| morton::compact(hi[a] >> a) + 1),
        ))
    }

    /// World bounding box of the full voxels, `None` when empty.
    #[must_use]
    pub fn bounds(&self) -> Option<Aabb> {
        let (lo, hi) = self.voxel_bounds()?;
        Some(Aabb { min: self.domain.lattice_point(lo), max: self.domain.lattice_point(hi) })
    }

    /// Fails unless `other` has the same domain and depth.
    pub(crate) fn check_same_domain(&self, other: &LinearOctree) -> Result<()> {
        if self.domain == other.domain {
            Ok(())
        } else {
            Err(Error::DomainMismatch { left: self.domain.to_string(), right: other.domain.to_string() })
        }
    }
}

/// Checks that `keys[i]` (sorted, disjoint, at most `max_k` levels) does not complete
/// eight full siblings that should be their parent: a key that is its parent's last
/// child, the seven before it whole siblings.
#[inline]
fn check_canonical(keys: &[NodeKey], i: usize, max_k: u32) -> Result<()> {
    let key = keys[i];
    // Most keys are not a last child (their child number, the three bits above their
    // size in the start, is not 7): out at once.
    if key.k() < max_k && i >= 7 && (key.start() >> (3 * key.k())) & 7 == 7 {
        let parent = key.parent();
        if key.end() == parent.end() && keys[i - 7] == parent.child(0).unwrap_or(key) {
            let siblings = &keys[i - 7..=i];
            if siblings.iter().all(|s| s.k() == key.k()) {
                let reason = format!("eight full siblings should be their parent {parent:?}");
                return Err(Error::InvalidOctree { index: i, reason });
            }
        }
    }
    Ok(())
}
