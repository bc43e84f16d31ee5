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

/// The faces of one full node `[min, min + size)` that look at a viewer, for testing
/// many samples' rays against them: [`Face::enters`] for each in axis order, the first
/// entered, with the tests of all three axes made side by side and the first passed
/// picked from a mask (a sample's ray enters one face of a node's one to three, which
/// the branches of a face-by-face search mispredict).
#[derive(Clone, Copy, Debug)]
pub(crate) struct NodeFaces {
    lo: [f64; 3],
    hi: [f64; 3],
    min: [u32; 3],
    size: u32,
    /// The plane of the face on each axis (`lo` where none looks at the viewer).
    planes: [f64; 3],
    /// Whether the face on each axis is the box's low one (entered moving up).
    low: [bool; 3],
    /// Bit `a`: the face on axis `a` looks at the viewer.
    visible: u8,
}

impl NodeFaces {
    /// The faces of the full node `[min, min + size)` that look at `viewer`.
    #[inline]
    pub(crate) fn new(viewer: &Viewer, min: [u32; 3], size: u32) -> Self {
        let (lo, hi) = (min.map(f64::from), min.map(|c| f64::from(c + size)));
        let (mut planes, mut visible) = (lo, 0);
        for (axis, plane) in planes.iter_mut().enumerate() {
            if let Some(p) = viewer.visible_plane(axis, lo, hi) {
                *plane = p;
                visible |= 1 << axis;
            }
        }
        let low = std::array::from_fn(|a| planes[a] == lo[a]);
        NodeFaces { lo, hi, min, size, planes, low, visible }
    }

    /// How many faces look at the viewer.
    pub(crate) fn count(&self) -> u32 {
        self.visible.count_ones()
    }

    /// The hit of the first face in axis order that `ray` enters ([`Face::enters`]'s
    /// test and hit, bit for bit).
    #[inline]
    pub(crate) fn first_entered(&self, ray: &VoxelRay) -> Option<Hit> {
        if !ray.inv.is_finite() {
            return self.faces().find_map(|face| face.enters(ray));
        }
        let (o, d, inv) = (ray.o.to_array(), ray.d.to_array(), ray.inv.to_array());
        let t: [f64; 3] = std::array::from_fn(|a| (self.planes[a] - o[a]) * inv[a]);
        // `within` with a finite reciprocal, as a value: past the plane it enters by
        // at or before `t`, not yet past the other.
        let inside = |b: usize, t: f64| {
            let (t_lo, t_hi) = ((self.lo[b] - o[b]) * inv[b], (self.hi[b] - o[b]) * inv[b]);
            let (first, second) = if d[b] > 0.0 { (t_lo, t_hi) } else { (t_hi, t_lo) };
            (first <= t) & (t < second)
        };
        // `t > 0` for `Face::enters`'s `!(t <= 0)`: a NaN time is inside no slab.
        let enters = |a: usize, b: usize, c: usize| {
            let inward = if self.low[a] { d[a] > 0.0 } else { d[a] < 0.0 };
            u8::from(inward & (t[a] > 0.0) & inside(b, t[a]) & inside(c, t[a])) << a
        };
        let entered = (enters(0, 1, 2) | enters(1, 0, 2) | enters(2, 0, 1)) & self.visible;
        if entered == 0 {
            return None;
        }
        let axis = entered.trailing_zeros() as usize;
        Some(ray.entry(&Entry { min: self.min, size: self.size, t: t[axis], face: Some(axis) }))
    }

    /// The faces one by one, by axis.
    fn faces(&self) -> impl Iterator<Item = Face> + '_ {
        (0..3).filter(|&a| self.visible >> a & 1 == 1).map(|axis| Face {
            axis,
            plane: self.planes[axis],
            lo: self.lo,
            hi: self.hi,
            min: self.min,
            size: self.size,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A xorshift in `[0, 1)`, so every run tests the same rays.
    fn unit(state: &mut u64) -> f64 {
        *state ^= *state << 13;
        *state ^= *state >> 7;
        *state ^= *state << 17;
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn node_faces_find_the_face_by_face_searchs_hit() {
        let mut state = 0x2545_f491_4f6c_dd1d;
        let (min, size) = ([4, 6, 5], 4);
        let (mut hits, mut tested) = (0, 0);
        for _ in 0..40 {
            // Eyes around the box and on its planes' lattice (rays through edges and
            // corners), and views along directions for orthographic viewers.
            let mut coordinate = |c: u32| f64::from(c) + (16.0 * unit(&mut state) - 8.0).round() * 0.5;
            let eye = DVec3::new(coordinate(min[0]), coordinate(min[1]), coordinate(min[2]));
            let along = DVec3::new(unit(&mut state) - 0.5, unit(&mut state) - 0.5, unit(&mut state) - 0.5);
            let viewers = [Viewer::At(eye), Viewer::Along(along.normalize())];
            for viewer in viewers {
                let faces = NodeFaces::new(&viewer, min, size);
                for k in 0..200 {
                    let target = DVec3::new(
                        f64::from(min[0]) + 6.0 * unit(&mut state) - 1.0,
                        f64::from(min[1]) + 6.0 * unit(&mut state) - 1.0,
                        f64::from(min[2]) + 6.0 * unit(&mut state) - 1.0,
                    );
                    let (o, mut d) = match viewer {
                        Viewer::At(e) => (e, target - e),
                        Viewer::Along(d) => (target - d * 20.0, d),
                    };
                    // Some rays along a lattice direction, some with a zero or
                    // subnormal component, some aimed at corners.
                    match k % 10 {
                        0 => d.x = 0.0,
                        1 => d.y = f64::from_bits(3) * d.y.signum(),
                        2 => d = (DVec3::new(f64::from(min[0]), f64::from(min[1] + size), 7.0) - o).normalize(),
                        _ => {}
                    }
                    let ray = VoxelRay { o, d, inv: DVec3::ONE / d };
                    let want = Face::visible(&viewer, min, size).find_map(|face| face.enters(&ray));
                    let got = faces.first_entered(&ray);
                    let bits = |h: Option<Hit>| h.map(|h| (h.t.to_bits(), h.voxel, h.axis));
                    assert_eq!(bits(got), bits(want), "{viewer:?}, {ray:?}");
                    hits += usize::from(want.is_some());
                    tested += 1;
                }
            }
        }
        // Both outcomes are exercised.
        assert!(hits > tested / 10 && hits < tested * 9 / 10, "{hits} hits of {tested}");
    }
}
