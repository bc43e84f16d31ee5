//! Rays in the lattice of a domain ([`VoxelRay`]), where every voxel plane is an
//! integer and each plane's crossing time is `(plane - o) * inv`, and what a walk
//! returns ([`Hit`]): the entry time, the full voxel entered and the entered face.
//!
//! Semantics: the hit is the first point (t >= 0) where the ray enters the interior of a
//! full voxel; a ray that only touches full voxels along an edge, a corner or a face it
//! grazes does not hit them. A ray parallel to an axis counts as inside the half-open
//! cells `[i, i + 1)` along that axis. The entered face is the axis of the plane crossed
//! there; when several voxel planes are crossed at once (an edge or corner), the
//! lowest axis.
//!
//! Precision: coordinates are in voxel units of the domain (`0..2^depth`), so every
//! plane is an integer below 2^21, exact in f64, at any depth. A hit's voxel inside a
//! full node is placed by the same plane times as the walk (planes crossed by the entry
//! time lie behind it), not by the rounded entry point alone, so a ray whose rounded
//! position and plane times disagree by an ulp still gets the brute force's voxel.

use glam::DVec3;

use crate::octree::Domain;
use crate::ray::Ray;

/// A ray hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// Ray parameter of the entry point (0 when the origin is inside the solid).
    pub t: f64,
    /// The full voxel entered, in integer coordinates.
    pub voxel: [u32; 3],
    /// Axis of the entered face (0, 1, 2), `None` when the origin is inside. (A byte:
    /// a frame holds a hit a sample, so the record is kept to 24 bytes.)
    pub axis: Option<u8>,
}

impl Hit {
    /// The axis normal of the entered face, facing the ray (zero when inside).
    #[must_use]
    pub fn normal(&self, dir: DVec3) -> DVec3 {
        match self.axis {
            Some(a) => {
                let a = usize::from(a);
                let mut n = DVec3::ZERO;
                n[a] = -dir[a].signum();
                n
            }
            None => DVec3::ZERO,
        }
    }
}

/// Where a walk enters a full node: the node's corner and size (voxels), the entry
/// time and the entered face's axis (`None` when the ray starts inside).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Entry {
    /// Lowest voxel of the node.
    pub min: [u32; 3],
    /// Edge in voxels.
    pub size: u32,
    /// Entry time (`<= 0` when the origin is inside).
    pub t: f64,
    /// Axis of the entered face.
    pub face: Option<usize>,
}

/// A ray in voxel units of a domain: origin, direction and reciprocal direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VoxelRay {
    /// Origin in voxel units.
    pub o: DVec3,
    /// Direction in voxel units (same ray parameter as the world ray).
    pub d: DVec3,
    /// `1 / d` per axis (infinite where `d` is 0).
    pub inv: DVec3,
}

impl VoxelRay {
    /// The world ray `origin + t dir` seen in the lattice of `domain`: `o = (origin -
    /// min) s`, `d = dir s` with `s` = [`Domain::voxels_per_unit`], `inv = 1 / d`
    /// (the ray's `t_max` is not part of it: the walk is given its limit).
    #[must_use]
    pub fn new(domain: &Domain, ray: &Ray) -> Self {
        Self::scaled(domain.min(), domain.voxels_per_unit(), ray)
    }

    /// [`VoxelRay::new`] with the domain's corner and scale given (a packet's rays
    /// share them): three divisions a ray, not ten.
    #[inline]
    pub(crate) fn scaled(min: DVec3, scale: f64, ray: &Ray) -> Self {
        let d = ray.dir * scale;
        VoxelRay { o: (ray.origin - min) * scale, d, inv: DVec3::ONE / d }
    }

    /// The hit on entering the full cube at `min` of `size` voxels at time `ta` through
    /// `face`: the voxel just after the entry point, and the lowest axis among the
    /// voxel planes crossed at `ta` (`t = 0` and no face when `ta <= 0`).
    #[must_use]
    pub(crate) fn entry(&self, entry: &Entry) -> Hit {
        let Entry { min, size, t: ta, face } = *entry;
        let t = ta.max(0.0);
        let inside = ta <= 0.0;
        // A voxel node (most hits at a surface) is its own voxel: every rule below
        // clamps to it.
        let voxel: [u32; 3] =
            if size == 1 { min } else { std::array::from_fn(|a| self.voxel_in(min, size, a, t, inside, face)) };
        // A voxel plane inside the node crossed at the same time is entered too: the
        // face is the lowest axis among them (the axes below the face tested side by
        // side into a mask, the face's own bit set: a search's early exit mispredicts).
        let face = face.map(|f| {
            let mut crossed = 1u32 << f;
            for (a, &v) in voxel.iter().enumerate().take(2) {
                let plane = if self.d[a] > 0.0 { v } else { v + 1 };
                let same = (self.d[a] != 0.0) & ((f64::from(plane) - self.o[a]) * self.inv[a] == ta);
                crossed |= u32::from(same & (a < f)) << a;
            }
            crossed.trailing_zeros() as usize
        });
        Hit { t, voxel, axis: if inside { None } else { face.map(|a| a as u8) } }
    }

    /// The coordinate on axis `a` of the voxel of the node `[min, min + size)` the ray
    /// is in just after time `t` (see [`VoxelRay::entry`]).
    #[inline(always)]
    fn voxel_in(&self, min: [u32; 3], size: u32, a: usize, t: f64, inside: bool, face: Option<usize>) -> u32 {
        let lo = min[a];
        let hi = min[a] + size - 1;
        if self.d[a] > 0.0 && !inside && face == Some(a) {
            lo
        } else if self.d[a] < 0.0 && !inside && face == Some(a) {
            hi
        } else {
            let p = self.o[a] + self.d[a] * t;
            // The voxel is clamped to the node, so the position may be clamped to
            // a voxel beyond it first (NaN goes to the low end, as it would): then
            // its floor is a conversion to an integer and back, no library call.
            let q = p.max(f64::from(lo) - 1.0).min(f64::from(hi) + 1.0);
            let f = q as i64 as f64;
            let f = if f > q { f - 1.0 } else { f };
            // A position inside a voxel of the node, a millionth of a voxel or more
            // from its planes, is that voxel: the plane times and the position agree
            // to a few ulps of 2^22 (below 1e-9), whatever the depth.
            let frac = q - f;
            if frac > 1e-6 && frac < 1.0 - 1e-6 && f >= f64::from(lo) && f <= f64::from(hi) {
                return f as u32;
            }
            // Just inside along the ray: nudge by the direction's sign on ties.
            let c = if q == f && self.d[a] < 0.0 { f - 1.0 } else { f };
            let mut v = (c.max(f64::from(lo)).min(f64::from(hi))) as u32;
            // The position is rounded apart from the plane times: the voxel is
            // the one the plane times place the ray in at `t` (planes crossed by `t`
            // are behind it), as the walk places it in a node.
            let time = |p: u32| (f64::from(p) - self.o[a]) * self.inv[a];
            if self.d[a] > 0.0 && self.inv[a].is_finite() {
                while v < hi && time(v + 1) <= t {
                    v += 1;
                }
                while v > lo && time(v) > t {
                    v -= 1;
                }
            } else if self.d[a] < 0.0 && self.inv[a].is_finite() {
                while v > lo && time(v) <= t {
                    v -= 1;
                }
                while v < hi && time(v + 1) > t {
                    v += 1;
                }
            }
            v
        }
    }
}
