//! Resampling: an octree moved by any affine map, voxelized into any domain.
//!
//! The source octree is viewed as a [`Shape`]: a target point is in the solid when its
//! preimage lies in a full source voxel; a target box maps (through the inverse) to a
//! source region whose bounding box is classified against the octree by
//! [`LinearOctree::classify_voxel_box`]. That view is conservative, so the ordinary
//! adaptive voxelizer does the rest with work proportional to the surface. Each target
//! voxel takes the value of the source voxel under its centre (nearest sampling).

use glam::{DAffine3, DVec3};

use super::domain::Domain;
use super::linear::LinearOctree;
use super::node::NodeKey;
use super::voxelize::{VoxelizeOptions, voxelize};
use crate::aabb::Aabb;
use crate::error::{Error, Result};
use crate::shape::{Class, Shape};

impl LinearOctree {
    /// The solid moved by the world-space affine map `transform` (finite, invertible)
    /// and voxelized into `target`.
    pub fn resample(&self, transform: DAffine3, target: Domain, options: &VoxelizeOptions) -> Result<LinearOctree> {
        let det = transform.matrix3.determinant();
        if !transform.is_finite() || !det.is_finite() || det.abs() < 1e-300 {
            return Err(Error::invalid("transform", format!("{transform:?} is not finite and invertible")));
        }
        let view = OctreeView { tree: self, to_source: transform.inverse(), to_target: transform };
        voxelize(&view, target, options)
    }

    /// The same solid in another domain or at another depth (nearest sampling).
    pub fn resample_to(&self, target: Domain, options: &VoxelizeOptions) -> Result<LinearOctree> {
        self.resample(DAffine3::IDENTITY, target, options)
    }

    /// Whether the voxels `[lo, hi)` (integer coordinates, per axis) are all full
    /// (`Inside`), all empty (`Outside`) or mixed (`Boundary`). An empty box is `Outside`.
    #[must_use]
    pub fn classify_voxel_box(&self, lo: [u32; 3], hi: [u32; 3]) -> Class {
        let n = self.domain().resolution();
        let hi = hi.map(|c| c.min(n));
        if (0..3).any(|a| lo[a] >= hi[a]) {
            return Class::Outside;
        }
        self.classify_in(NodeKey::new(0, u32::from(self.depth())), lo, hi)
    }

    /// [`Self::classify_voxel_box`] restricted to `node`, which meets the box.
    fn classify_in(&self, node: NodeKey, lo: [u32; 3], hi: [u32; 3]) -> Class {
        let keys = self.keys();
        let (s, e) = (node.start(), node.end());
        // Step 1: a key covering the whole node, or no key inside it at all.
        let first = keys.partition_point(|k| k.start() <= s);
        if first > 0 && keys[first - 1].end() >= e {
            return Class::Inside;
        }
        let starts_here = first > 0 && keys[first - 1].end() > s;
        let past = keys.partition_point(|k| k.start() < e);
        if !starts_here && past == first {
            return Class::Outside;
        }
        // Step 2: mixed; if the node lies inside the box, the box is mixed too.
        let min = crate::morton::decode(s);
        let size = 1u32 << node.k();
        if (0..3).all(|a| lo[a] <= min[a] && min[a] + size <= hi[a]) {
            return Class::Boundary;
        }
        // Step 3: the children that meet the box decide.
        let mut seen: Option<Class> = None;
        for i in 0..8 {
            let child = node.child(i).expect("a mixed node is not a voxel");
            let cmin = crate::morton::decode(child.start());
            let half = size / 2;
            if (0..3).any(|a| cmin[a] + half <= lo[a] || cmin[a] >= hi[a]) {
                continue;
            }
            let c = self.classify_in(child, lo, hi);
            match seen {
                _ if c == Class::Boundary => return Class::Boundary,
                Some(prev) if prev != c => return Class::Boundary,
                _ => seen = Some(c),
            }
        }
        seen.unwrap_or(Class::Outside)
    }
}

/// A source octree seen through an affine map, as a [`Shape`].
struct OctreeView<'a> {
    tree: &'a LinearOctree,
    to_source: DAffine3,
    to_target: DAffine3,
}

impl Shape for OctreeView<'_> {
    fn classify(&self, b: &Aabb) -> Class {
        let d = self.tree.domain();
        let region =
            Aabb::from_points((0..8).map(|i| self.to_source.transform_point3(b.corner(i)))).expect("eight corners");
        // Voxels the closed region touches, grown by a hair against rounding.
        let h = d.voxel_size();
        let pad = DVec3::splat(1e-9 * h);
        let t0 = (region.min - pad - d.min()) / h;
        let t1 = (region.max + pad - d.min()) / h;
        let n = f64::from(d.resolution());
        let outside_domain = t0.cmplt(DVec3::ZERO).any() || t1.cmpge(DVec3::splat(n)).any();
        if t1.cmplt(DVec3::ZERO).any() || t0.cmpge(DVec3::splat(n)).any() {
            return Class::Outside;
        }
        let lo = t0.max(DVec3::ZERO).floor().to_array().map(|c| c as u32);
        let hi = (t1.min(DVec3::splat(n - 1.0)).floor() + 1.0).to_array().map(|c| c as u32);
        match self.tree.classify_voxel_box(lo, hi) {
            // Points outside the source domain are empty, so the region is not all full.
            Class::Inside if outside_domain => Class::Boundary,
            c => c,
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        self.tree.contains_point(self.to_source.transform_point3(p))
    }

    fn bounds(&self) -> Option<Aabb> {
        let b = self.tree.bounds()?;
        Aabb::from_points((0..8).map(|i| self.to_target.transform_point3(b.corner(i))))
    }
}
