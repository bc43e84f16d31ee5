//! Resampling: an octree moved by any affine map, voxelized into any domain.
//!
//! Method: the source octree is viewed as a [`Shape`] through the inverse map. A
//! target point is in the solid when its preimage lies in a full source voxel
//! (nearest, i.e. point, sampling at target voxel centres). A target box is classified
//! by mapping its eight corners into the source frame, taking their bounding box (it
//! holds the affine image of the box), widening it by a rounding allowance, and asking
//! [`LinearOctree::classify_voxel_box`] about the source voxels that closed box touches.
//! That answer is conservative, so the ordinary adaptive voxelizer does the rest.
//!
//! Exactness: a target voxel is full iff the source voxel under the preimage of its
//! centre is full; there is no rounding beyond locating that one point. When the map
//! sends target voxel centres to source voxel centres (identity into the same domain,
//! refinement to a finer depth, translations by whole voxels, mirrors and quarter turns
//! about the domain centre) the result equals the exact transform
//! ([`LinearOctree::refine`], [`LinearOctree::translate`], [`LinearOctree::mirror`],
//! [`LinearOctree::rotate90`]). Otherwise it is a sampling: the surface moves by up to
//! about one voxel, so the volume error is of order (surface area) x (voxel size).
//! Source voxels outside the source domain count as empty, target voxels outside the
//! image are empty.
//!
//! Cost: the voxelizer visits target nodes near the image's surface (work proportional
//! to the target surface, not the volume); each visit maps eight corners and runs one
//! [`LinearOctree::classify_voxel_box`] query, a descent that stops at nodes that are
//! uniform or wholly inside the box, with two binary searches a visited node. Rotations
//! by other than quarter turns make the corner boxes looser (up to about 1.7 times per
//! axis), which only adds boundary nodes.

use std::borrow::Borrow;

use glam::{DAffine3, DVec3};

use crate::aabb::Aabb;
use crate::error::Result;
use crate::morton;
use crate::octree::domain::Domain;
use crate::octree::driver::VoxelizeOptions;
use crate::octree::linear::LinearOctree;
use crate::octree::node::NodeKey;
use crate::octree::voxelize::voxelize;
use crate::octree::window::keys_meeting;
use crate::shape::{Class, Shape};

impl LinearOctree {
    /// The solid moved by the world-space affine map `transform` (finite and
    /// invertible; a point `p` of the solid goes to `transform * p`), voxelized into
    /// `target`, which may differ from this octree's domain in place, size and depth.
    ///
    /// See the module doc for exactness and cost. Fails when `transform` is not finite
    /// and invertible, or when the voxelization exceeds `options.budget`.
    pub fn resample(&self, transform: DAffine3, target: Domain, options: &VoxelizeOptions) -> Result<LinearOctree> {
        voxelize(&OctreeShape::new(self, transform)?, target, options)
    }

    /// The same solid in another domain or at another depth, sampled at the target
    /// voxel centres: exact when the target's voxels nest in the source's (the same
    /// cube deeper, as [`LinearOctree::refine`]) or the target is the source's lattice
    /// shifted by whole voxels (as [`LinearOctree::translate`]).
    pub fn resample_to(&self, target: Domain, options: &VoxelizeOptions) -> Result<LinearOctree> {
        self.resample(DAffine3::IDENTITY, target, options)
    }

    /// Whether the voxels of the integer box `[lo, hi)` (exclusive `hi`, per axis) are
    /// all full (`Inside`), all empty (`Outside`) or mixed (`Boundary`).
    ///
    /// `hi` is clipped to the resolution; a box left empty is `Outside`. Cost: a
    /// descent of the implicit tree from the smallest aligned node holding the box,
    /// into the children that meet the box, stopping at nodes wholly covered by one
    /// key, holding no key, or lying wholly inside the box (then mixed); two binary
    /// searches over a shrinking run of keys a visited node.
    #[must_use]
    pub fn classify_voxel_box(&self, lo: [u32; 3], hi: [u32; 3]) -> Class {
        let n = self.domain().resolution();
        let hi = hi.map(|c| c.min(n));
        if (0..3).any(|a| lo[a] >= hi[a]) {
            return Class::Outside;
        }
        classify_in(self.keys(), enclosing_node(lo, hi), lo, hi)
    }
}

/// The smallest aligned node holding the non-empty integer box `[lo, hi)`.
pub(in crate::octree) fn enclosing_node(lo: [u32; 3], hi: [u32; 3]) -> NodeKey {
    // Levels above the voxels at which the lowest and highest voxel share a cube.
    let k = (0..3).map(|a| u32::BITS - (lo[a] ^ (hi[a] - 1)).leading_zeros()).max().unwrap_or(0);
    let c = lo.map(|c| c >> k << k);
    NodeKey::new(morton::encode(c[0], c[1], c[2]), k)
}

/// The class of the voxels of the box `[lo, hi)` that lie in `node` (a node meeting
/// the box); `keys` is any sorted run of the canonical key list that holds every key
/// meeting that part of the box (the whole list will do).
pub(super) fn classify_in(keys: &[NodeKey], node: NodeKey, lo: [u32; 3], hi: [u32; 3]) -> Class {
    // Step 1: the keys meeting the node: none, one covering it, or a part.
    let window = match keys_meeting(keys, node) {
        [] => return Class::Outside,
        [key] if key.k() >= node.k() => return Class::Inside,
        window => window,
    };
    // Step 2: partly full (a canonical list has no set of keys that fills a node
    // without a key covering it), so if the node lies in the box, the box is mixed.
    let min = morton::decode(node.start());
    let size = 1u32 << node.k();
    if (0..3).all(|a| lo[a] <= min[a] && min[a] + size <= hi[a]) {
        return Class::Boundary;
    }
    // Step 3: the children that meet the box decide.
    let half = size / 2;
    let mut seen: Option<Class> = None;
    for i in 0..8 {
        let child = node.child(i).expect("a partly full node is not a voxel");
        let cmin = morton::decode(child.start());
        if (0..3).any(|a| cmin[a] + half <= lo[a] || cmin[a] >= hi[a]) {
            continue;
        }
        match (seen, classify_in(window, child, lo, hi)) {
            (_, Class::Boundary) => return Class::Boundary,
            (Some(prev), c) if prev != c => return Class::Boundary,
            (_, c) => seen = Some(c),
        }
    }
    seen.unwrap_or(Class::Outside)
}

/// An octree moved by an affine map, as a [`Shape`]: what [`LinearOctree::resample`]
/// voxelizes, and how an octree takes part in shape CSG (a scene's `oct` leaves). `T`
/// holds the octree: a reference, or an `Arc` for a shape that owns it. See the module
/// doc for the point rule (nearest source voxel) and the conservative box rule.
#[derive(Clone, Debug)]
pub struct OctreeShape<T> {
    tree: T,
    /// Target (world) frame to source (world) frame: the inverse of the transform.
    to_source: DAffine3,
    /// Source frame to target frame: the transform.
    to_target: DAffine3,
}

impl<T: Borrow<LinearOctree>> OctreeShape<T> {
    /// The solid of `tree` moved by `transform` (a point `p` of it goes to
    /// `transform * p`), which must be finite and invertible.
    pub fn new(tree: T, transform: DAffine3) -> Result<Self> {
        crate::shape::check_invertible(&transform)?;
        Ok(OctreeShape { tree, to_source: transform.inverse(), to_target: transform })
    }

    /// The octree seen.
    #[must_use]
    pub fn tree(&self) -> &LinearOctree {
        self.tree.borrow()
    }

    /// World-space allowance for rounding when the points of `b` are mapped and
    /// located in the source grid: many ulps of the largest magnitude involved (the
    /// terms of the mapped coordinates and the domain's corner and edge).
    fn slack(&self, b: &Aabb) -> f64 {
        let m = self.to_source.matrix3.abs();
        let t = self.to_source.translation.abs();
        let d = self.tree().domain();
        let terms = (0..8).map(|i| (m * b.corner(i).abs() + t).max_element()).fold(0.0, f64::max);
        let magnitude = terms + d.min().abs().max_element() + d.edge();
        1e-12 * magnitude + 1e-9 * d.voxel_size()
    }
}

impl<T: Borrow<LinearOctree> + Send + Sync> Shape for OctreeShape<T> {
    fn classify(&self, b: &Aabb) -> Class {
        let d = self.tree().domain();
        let region =
            Aabb::from_points((0..8).map(|i| self.to_source.transform_point3(b.corner(i)))).expect("eight corners");
        // Step 1: the padded region in source voxel units.
        let h = d.voxel_size();
        let pad = DVec3::splat(self.slack(b));
        let t0 = (region.min - pad - d.min()) / h;
        let t1 = (region.max + pad - d.min()) / h;
        let n = f64::from(d.resolution());
        if t1.cmplt(DVec3::ZERO).any() || t0.cmpge(DVec3::splat(n)).any() {
            return Class::Outside;
        }
        // Points outside the source domain (upper faces included) are empty.
        let leaves_domain = t0.cmplt(DVec3::ZERO).any() || t1.cmpge(DVec3::splat(n)).any();
        // Step 2: the source voxels the closed region touches, clamped to the domain.
        let lo = t0.max(DVec3::ZERO).floor().to_array().map(|c| c as u32);
        let hi = (t1.min(DVec3::splat(n - 1.0)).floor() + 1.0).to_array().map(|c| c as u32);
        match self.tree().classify_voxel_box(lo, hi) {
            Class::Inside if leaves_domain => Class::Boundary,
            c => c,
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        self.tree().contains_point(self.to_source.transform_point3(p))
    }

    fn bounds(&self) -> Option<Aabb> {
        let b = self.tree().bounds()?;
        Aabb::from_points((0..8).map(|i| self.to_target.transform_point3(b.corner(i))))
    }
}
