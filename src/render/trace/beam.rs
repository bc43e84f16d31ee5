//! Beams: the first hits of a packet of coherent rays (a tile of primary rays), with
//! one conservative walk of the octree for the whole packet before the rays' own walks.
//!
//! The packet is bounded per axis by the range of its origins `[o-, o+]` and of its
//! reciprocal directions `[inv-, inv+]` (voxel units), all its directions having one
//! sign an axis. Every plane time of a ray of the packet, `(p - o) * inv` rounded as
//! the walk rounds it, lies between the same formula at the corners of those
//! intervals, because rounding is monotone. So a node `[min, min + size)` that some ray
//! of the packet enters has `lo < hi` for `lo` = the largest over axes of the earliest
//! time of its near plane and `hi` = the smallest over axes of the latest time of its
//! far plane, and every ray enters it at or after `lo`.
//!
//! The pre-pass finds `start` = the least `lo` over the full nodes the packet may
//! enter (best first, pruning subtrees whose `lo` is no better), then each ray walks
//! from `max(entry, start)`: the pieces it skips lie before its first hit, so they are
//! empty and the hit is bit for bit that of [`Traversal::hit`]. A packet that can enter
//! no full node hits nothing, without walking a ray. The walks begin in the deepest
//! inner node that holds every ray at `start` (for each mid plane above it the latest
//! crossing time is `<= start` or the earliest `> start`), not at the root: the walk
//! from the root would go straight down to it, so the steps skipped are that descent.
//!
//! After the multi-level ray tracing algorithm of Reshetov, Soupikov and Hurley (2005),
//! which finds the entry point of a beam deep in a kd-tree; deviation: the beam is
//! bounded by intervals of the rays' parameters, not by frustum planes, so the bounds
//! hold exactly in floating point.

use glam::DVec3;

use super::traversal::{Root, Traversal};
use super::voxel_ray::{Hit, VoxelRay};
use super::walk::Subtree;
use crate::octree::MAX_DEPTH;
use crate::ray::Ray;

/// Samples a side of the square tiles of primary rays the renderer walks as packets.
pub const TILE: usize = 8;

/// Rays a packet walks together at most (one tile); longer slices are cut into
/// packets of this many.
pub const PACKET: usize = TILE * TILE;

/// Bounds of a packet's plane times.
struct Beam {
    /// Per axis the origin bound giving the earliest time of a near plane.
    near_o: [f64; 3],
    /// Per axis the origin bound giving the latest time of a far plane.
    far_o: [f64; 3],
    /// Per axis the least and the greatest reciprocal direction.
    inv: [[f64; 2]; 3],
    /// Per axis whether the rays run to lower coordinates.
    mirror: [bool; 3],
}

impl Beam {
    /// The bounds of the world rays `rays` seen in voxel units (origin `(o - min) s`,
    /// direction `d s`, reciprocal `1 / (d s)`, as [`VoxelRay::scaled`] makes them),
    /// `None` when they are not a beam: a non-finite origin or reciprocal direction
    /// (axis-parallel rays), or directions of both signs on an axis.
    ///
    /// The bounds come from the world rays' least and greatest coordinates: subtracting
    /// `min`, scaling by `s > 0` and, on directions of one sign, the reciprocal are
    /// monotone with rounding, so the extremes map to the extremes and a packet that
    /// is culled never works out its rays' reciprocals.
    fn new(rays: &[Ray], min: DVec3, scale: f64) -> Option<Self> {
        // Per ray `[o, d]`: the least and greatest of each (plain compares, no NaN-aware
        // min and max), and the sums of each, finite only when every value is (a NaN or
        // an infinity carries through; an overflow only turns a beam down). Six sums,
        // not one: a single sum is a chain of dependent additions, the loop's bottleneck.
        let (mut lo, mut hi) = ([f64::INFINITY; 6], [f64::NEG_INFINITY; 6]);
        let mut sums = [0.0; 6];
        for Ray { origin: o, dir: d, .. } in rays {
            let v = [o.x, o.y, o.z, d.x, d.y, d.z];
            for k in 0..6 {
                sums[k] += v[k];
                lo[k] = if v[k] < lo[k] { v[k] } else { lo[k] };
                hi[k] = if v[k] > hi[k] { v[k] } else { hi[k] };
            }
        }
        if rays.is_empty() || !sums.iter().sum::<f64>().is_finite() {
            return None;
        }
        let o = |a: usize, x: f64| (x - min[a]) * scale;
        let mut beam = Beam { near_o: [0.0; 3], far_o: [0.0; 3], inv: [[0.0; 2]; 3], mirror: [false; 3] };
        for a in 0..3 {
            let (o_lo, o_hi) = (o(a, lo[a]), o(a, hi[a]));
            let (d_lo, d_hi) = (lo[a + 3] * scale, hi[a + 3] * scale);
            // 1 / d falls as d grows on either side of 0.
            let inv = [1.0 / d_hi, 1.0 / d_lo];
            let one_sign = d_lo > 0.0 || d_hi < 0.0;
            if !(one_sign && o_lo.is_finite() && o_hi.is_finite() && inv[0].is_finite() && inv[1].is_finite()) {
                return None;
            }
            let mirror = d_hi < 0.0;
            // (p - o) * inv falls as o grows when inv > 0 (the earliest near-plane time
            // is at o+, the latest far-plane time at o-), and rises when inv < 0.
            (beam.near_o[a], beam.far_o[a]) = if mirror { (o_lo, o_hi) } else { (o_hi, o_lo) };
            beam.inv[a] = inv;
            beam.mirror[a] = mirror;
        }
        Some(beam)
    }

    /// `(lo, hi)` for the node `[min, min + size)`: no ray of the beam enters it before
    /// `lo` or leaves it after `hi`.
    fn span(&self, min: [u32; 3], size: u32) -> (f64, f64) {
        let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
        for (a, &m) in min.iter().enumerate() {
            let (near, far) = if self.mirror[a] { (m + size, m) } else { (m, m + size) };
            lo = later(lo, self.plane_times(a, near).0);
            hi = earlier(hi, self.plane_times(a, far).1);
        }
        (lo, hi)
    }

    /// Per axis and child side (bit 0 low, 1 high) of the node `[min, min + size)`, the
    /// earliest time of the child's near plane and the latest of its far plane: the
    /// terms of [`Beam::span`] for its eight children, from the times of the node's
    /// three planes an axis (the same bits as `span` of each child).
    fn child_planes(&self, min: [u32; 3], size: u32) -> ([[f64; 2]; 3], [[f64; 2]; 3]) {
        let half = size / 2;
        let mut near = [[0.0; 2]; 3];
        let mut far = [[0.0; 2]; 3];
        for a in 0..3 {
            let planes = [min[a], min[a] + half, min[a] + size];
            let times = planes.map(|p| self.plane_times(a, p));
            for side in 0..2 {
                // Side `side` spans planes side and side + 1; a mirrored ray enters at the upper.
                let (n, f) = if self.mirror[a] { (side + 1, side) } else { (side, side + 1) };
                near[a][side] = times[n].0;
                far[a][side] = times[f].1;
            }
        }
        (near, far)
    }

    /// The earliest and the latest time at which a ray of the beam crosses the plane
    /// `p` of axis `a`.
    fn plane_times(&self, a: usize, p: u32) -> (f64, f64) {
        let [i0, i1] = self.inv[a];
        let x = f64::from(p) - self.near_o[a];
        let y = f64::from(p) - self.far_o[a];
        (earlier(x * i0, x * i1), later(y * i0, y * i1))
    }
}

/// The larger of two times that are not NaN.
fn later(x: f64, y: f64) -> f64 {
    if x > y { x } else { y }
}

/// The smaller of two times that are not NaN.
fn earlier(x: f64, y: f64) -> f64 {
    if x < y { x } else { y }
}

/// A node the pre-pass has still to look into.
#[derive(Clone, Copy)]
struct Pending {
    index: u32,
    min: [u32; 3],
    size: u32,
    lo: f64,
}

/// Most nodes the pre-pass holds at once: up to 7 siblings left a level, and the root.
const PENDING: usize = 7 * MAX_DEPTH as usize + 1;

impl Traversal {
    /// First hits of a packet of rays: `hits[i]` is `self.hit(&rays[i])`, bit for bit,
    /// found faster when the rays are coherent (a tile of primary rays; see the module
    /// doc).
    ///
    /// # Panics
    /// When the slices differ in length.
    pub fn hit_packet(&self, rays: &[Ray], hits: &mut [Option<Hit>]) {
        assert!(rays.len() == hits.len(), "a packet's slices differ in length");
        for (rays, hits) in rays.chunks(PACKET).zip(hits.chunks_mut(PACKET)) {
            let (min, scale) = (self.domain().min(), self.domain().voxels_per_unit());
            let limit = rays.iter().fold(f64::NEG_INFINITY, |m, r| m.max(r.t_max));
            let mut above = [0u32; MAX_DEPTH as usize];
            let (start, from) = match Beam::new(rays, min, scale) {
                Some(beam) => match self.nearest_full(&beam, limit) {
                    Some(lo) => {
                        let start = lo.max(0.0);
                        (start, self.start_node(&beam, start, &mut above))
                    }
                    None => {
                        hits.fill(None);
                        continue;
                    }
                },
                None => (0.0, Subtree::ROOT),
            };
            for (hit, ray) in hits.iter_mut().zip(rays) {
                let r = &VoxelRay::scaled(min, scale, ray);
                *hit = self.first_full_after::<true>(r, ray.t_max, start, from).map(|entry| r.entry(&entry));
            }
        }
    }

    /// The deepest inner node that holds every ray of the beam at time `start` (each
    /// of its ancestors' mid planes is crossed by all rays at or before `start`, or by
    /// none), with the inner nodes above it recorded in `above`: the rays that enter
    /// the root by `start` begin their walks there instead of at the root.
    fn start_node<'a>(&self, beam: &Beam, start: f64, above: &'a mut [u32; MAX_DEPTH as usize]) -> Subtree<'a> {
        if self.outline.root != Root::Inner {
            return Subtree::ROOT;
        }
        let (mut index, mut min, mut size, mut depth) = (0u32, [0u32; 3], self.domain().resolution(), 0);
        'down: loop {
            let inner = self.nodes[index as usize];
            let half = size / 2;
            // The child all rays are in at `start`: per axis past the mid plane (its
            // latest time <= start) or not (its earliest time > start); else stop.
            let mut child = 0;
            for (a, &m) in min.iter().enumerate() {
                let (early, late) = beam.plane_times(a, m + half);
                if late <= start {
                    child |= 1 << a;
                } else if early <= start {
                    break 'down;
                }
                if beam.mirror[a] {
                    child ^= 1 << a;
                }
            }
            let inner_kids = inner.valid & !inner.full;
            if inner_kids >> child & 1 == 0 {
                break;
            }
            above[depth] = index;
            depth += 1;
            index = inner.first + (inner_kids & ((1u8 << child) - 1)).count_ones();
            min = std::array::from_fn(|a| min[a] + if child >> a & 1 == 1 { half } else { 0 });
            size = half;
        }
        Subtree { index, min, size, above: &above[..depth] }
    }

    /// The least `lo` (see [`Beam::span`]) over the full nodes the beam may enter before
    /// `limit`, best first; `None` when there is none.
    fn nearest_full(&self, beam: &Beam, limit: f64) -> Option<f64> {
        let n = self.domain().resolution();
        let enters = |(lo, hi): (f64, f64), best: f64| lo < hi && hi > 0.0 && lo < best;
        let root = beam.span([0; 3], n);
        match self.outline.root {
            Root::Empty => return None,
            Root::Full => return enters(root, limit).then_some(root.0),
            Root::Inner if !enters(root, limit) => return None,
            Root::Inner => {}
        }
        let mut best = limit;
        let mut found = false;
        let mut pending = [Pending { index: 0, min: [0; 3], size: n, lo: root.0 }; PENDING];
        let mut len = 1;
        while len > 0 {
            len -= 1;
            let node = pending[len];
            if node.lo >= best {
                continue;
            }
            let inner = self.nodes[node.index as usize];
            let half = node.size / 2;
            // Step 1: the children the beam may enter; full ones lower `best`.
            let mut kids = [(0.0f64, 0usize); 8];
            let mut count = 0;
            let (near, far) = beam.child_planes(node.min, node.size);
            for child in 0..8 {
                if inner.valid >> child & 1 == 0 {
                    continue;
                }
                let (x, y, z) = (child & 1, child >> 1 & 1, child >> 2);
                let lo = [near[0][x], near[1][y], near[2][z]].into_iter().fold(f64::NEG_INFINITY, later);
                let hi = [far[0][x], far[1][y], far[2][z]].into_iter().fold(f64::INFINITY, earlier);
                let span = (lo, hi);
                if !enters(span, best) {
                    continue;
                }
                if inner.full >> child & 1 == 1 {
                    best = span.0;
                    found = true;
                } else {
                    kids[count] = (span.0, child);
                    count += 1;
                }
            }
            // Step 2: the inner ones still better than `best`, the earliest on top.
            let kids = &mut kids[..count];
            kids.sort_unstable_by(|a, b| b.0.total_cmp(&a.0));
            for &(lo, child) in kids.iter() {
                if lo < best {
                    let cmin: [u32; 3] =
                        std::array::from_fn(|a| node.min[a] + if child >> a & 1 == 1 { half } else { 0 });
                    let before = inner.valid & !inner.full & ((1u8 << child) - 1);
                    pending[len] = Pending { index: inner.first + before.count_ones(), min: cmin, size: half, lo };
                    len += 1;
                }
            }
        }
        found.then_some(best)
    }
}
