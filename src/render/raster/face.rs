//! The voxel-face rule shared by every raster visibility method: which faces of a full
//! node look at the viewer, and whether a face covers a sample.
//!
//! A face covers a sample when the sample's ray crosses the face's plane at the time
//! `t = (plane - o) * (1 / d)` (the ray walk's formula, voxel units), `t > 0`, moving
//! inwards, and is inside the face there as the walk decides it (by the times of the
//! face's edge planes, not by the position at `t`: see `within`); the hit is then
//! [`VoxelRay::entry`], as in the walk, so every method gives the walk's bits.

use glam::DVec3;

use crate::octree::Domain;
use crate::render::film::{Projection, View};
use crate::render::trace::{Entry, Hit, VoxelRay};

/// The viewer in voxel units of a domain: a point (perspective), or a direction of
/// view (orthographic).
#[derive(Clone, Copy, Debug)]
pub(crate) enum Viewer {
    /// The eye, `(eye - domain.min) / h`: the origin every primary ray has in voxel units.
    At(DVec3),
    /// The unit direction of view.
    Along(DVec3),
}

impl Viewer {
    /// The viewer of `view` in voxel units of `domain`.
    pub(crate) fn new(view: &View, domain: &Domain) -> Self {
        match view.projection {
            Projection::Perspective { .. } => Viewer::At((view.eye - domain.min()) * domain.voxels_per_unit()),
            Projection::Orthographic { .. } => Viewer::Along(view.forward),
        }
    }

    /// Whether the viewer is on the high side of the plane `axis = plane` (front-to-back
    /// child order: the viewer's side first).
    pub(crate) fn is_high(&self, axis: usize, plane: f64) -> bool {
        match *self {
            Viewer::At(e) => e[axis] >= plane,
            Viewer::Along(d) => d[axis] < 0.0,
        }
    }

    /// The plane of the box `[lo, hi]`'s face on `axis` that faces the viewer, if any
    /// (none when the viewer is between the two planes or looks along them).
    #[inline]
    pub(crate) fn visible_plane(&self, axis: usize, lo: [f64; 3], hi: [f64; 3]) -> Option<f64> {
        match *self {
            Viewer::At(e) if e[axis] < lo[axis] => Some(lo[axis]),
            Viewer::At(e) if e[axis] > hi[axis] => Some(hi[axis]),
            Viewer::Along(d) if d[axis] > 0.0 => Some(lo[axis]),
            Viewer::Along(d) if d[axis] < 0.0 => Some(hi[axis]),
            _ => None,
        }
    }
}

/// A face of the full node `[min, min + size)` (voxel units): the plane `axis = plane`
/// of the node's box `[lo, hi]`.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Face {
    pub(crate) axis: usize,
    pub(crate) plane: f64,
    pub(crate) lo: [f64; 3],
    pub(crate) hi: [f64; 3],
    pub(crate) min: [u32; 3],
    pub(crate) size: u32,
}

impl Face {
    /// The faces of the full node `[min, min + size)` that look at `viewer`, by axis
    /// (the viewer's tests made once a node).
    #[inline]
    pub(crate) fn visible(viewer: &Viewer, min: [u32; 3], size: u32) -> impl Iterator<Item = Face> {
        let (lo, hi) = (min.map(f64::from), min.map(|c| f64::from(c + size)));
        let planes: [Option<f64>; 3] = std::array::from_fn(|axis| viewer.visible_plane(axis, lo, hi));
        (0..3).filter_map(move |axis| planes[axis].map(|plane| Face { axis, plane, lo, hi, min, size }))
    }

    /// The hit when `ray` crosses the face's plane and enters the node's interior there
    /// (the walk's semantics: a ray parallel to an axis is inside the half-open interval).
    #[inline]
    pub(crate) fn enters(&self, ray: &VoxelRay) -> Option<Hit> {
        let (axis, lo, hi) = (self.axis, self.lo, self.hi);
        let d = ray.d[axis];
        let inward = if self.plane == lo[axis] { d > 0.0 } else { d < 0.0 };
        if !inward {
            return None;
        }
        let t = (self.plane - ray.o[axis]) * ray.inv[axis];
        if t <= 0.0 {
            return None;
        }
        for b in (0..3).filter(|&b| b != axis) {
            if !within(ray, b, lo[b], hi[b], t) {
                return None;
            }
        }
        Some(ray.entry(&Entry { min: self.min, size: self.size, t, face: Some(axis) }))
    }
}

/// Whether the ray is between the planes `lo` and `hi` of axis `b` at time `t` as the
/// walk places it: past a plane once its time `(plane - o) * inv` is at or before `t`,
/// so inside `[lo, hi)` moving up (`(lo, hi]` moving down) from the time it crosses
/// the plane it enters by until the time it crosses the other. Comparing times, not
/// the position `o + d t`, is what makes a ray through an edge or corner enter the
/// node the walk enters: the two are roundings of the same geometry that can fall on
/// either side of a plane crossed at `t`. A ray parallel to the axis (or with a
/// subnormal direction, whose reciprocal is infinite) is placed by its origin, moved
/// off the lattice as the walk moves it (`walk::off_lattice`): inside `[lo, hi)` when
/// parallel, `(lo, hi]` when subnormal.
#[inline]
fn within(ray: &VoxelRay, b: usize, lo: f64, hi: f64, t: f64) -> bool {
    let (o, d, inv) = (ray.o[b], ray.d[b], ray.inv[b]);
    if !inv.is_finite() {
        return if d == 0.0 { o >= lo && o < hi } else { o > lo && o <= hi };
    }
    let (t_lo, t_hi) = ((lo - o) * inv, (hi - o) * inv);
    if d > 0.0 { t_lo <= t && t < t_hi } else { t_hi <= t && t < t_lo }
}
