//! Whether a world-space ray can come near a box, without a division: the test a walk
//! makes first, so that the many rays of a scene that pass far from a solid (a floor's
//! reflected rays, shadow rays from elsewhere) cost a few multiplications, not the
//! three divisions of the conversion to the lattice ([`super::VoxelRay`]).
//!
//! The separating-axis test of a half-line `o + t d` (`t >= 0`) against a box of
//! centre `c` and half-extents `h` (Gottschalk et al., "OBBTree", 1996; Ericson,
//! "Real-Time Collision Detection", 5.3.3, for segments), with `w = o - c`:
//! - a face normal `e_i` separates them when the origin is outside the slab and the ray
//!   points away from it: `|w_i| > h_i` and `w_i d_i >= 0`;
//! - an axis `d x e_i` separates them when the line's distance from the centre along it
//!   exceeds the box's extent there: for `i = x`, `|d_z w_y - d_y w_z| > h_y |d_z| +
//!   h_z |d_y|`, and the same for `y` and `z` by cycling the axes.
//!
//! No other axis can separate a box from a line (the ray's own direction is parallel
//! to it), so a ray no axis separates meets the box.
//!
//! Conservative, not exact: the box is the full voxels' box grown by a margin `g`
//! larger than any rounding here or in the lattice conversion, so a ray the walk would
//! find a hit for always passes. A walk's hit means the ray as rounded into the lattice
//! enters the box; that ray is the world ray moved by at most a few ulps of `|o| +
//! |min| + |w| + diagonal` (the origin, the domain's corner, the distance travelled),
//! and each quantity compared here is off by a few ulps of `|d| (|w| + |h|)`. With
//! origins no farther than `far` (1024 box sizes; farther ones are not judged), `g =
//! 2^-40 (|c| + |min| + edge + far + |h|) + voxel / 4096` exceeds both a thousandfold
//! while staying below the thousandth of a voxel by which secondary rays leave a
//! face (`shade::whitted`): the rays a floor casts up from its top are told apart from
//! its box. The ray's `t_max` is not used: the walk itself ends a segment that stops
//! short.

use glam::DVec3;

use crate::octree::Domain;
use crate::ray::Ray;

/// A box in world space that no ray misses if it enters a full voxel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Reach {
    center: DVec3,
    half: DVec3,
    /// Origins farther than this from the centre on some axis are not judged (always
    /// may meet): the margin is sized for the rounding of nearer ones.
    far: f64,
}

impl Reach {
    /// The box of the voxels `[lo, hi)` of `domain`, grown by the margin `g` (see the
    /// module doc).
    pub(super) fn around(domain: &Domain, lo: [u32; 3], hi: [u32; 3]) -> Reach {
        let (min, max) = (domain.lattice_point(lo), domain.lattice_point(hi));
        let (center, half) = ((min + max) * 0.5, (max - min) * 0.5);
        let voxel = domain.voxel_size();
        let far = 1024.0 * half.max_element().max(voxel);
        let scale = center.abs().max_element() + domain.min().abs().max_element() + domain.edge() + far;
        let grow = (scale + half.max_element()) * 2f64.powi(-40) + voxel / 4096.0;
        Reach { center, half: half + DVec3::splat(grow), far }
    }

    /// Whether the ray may enter the box (`false` only when an axis separates them;
    /// `true` for a ray with a non-finite origin or direction, which the walk refuses).
    #[inline(always)]
    pub(super) fn may_meet(&self, ray: &Ray) -> bool {
        let (d, h) = (ray.dir, self.half);
        let w = ray.origin - self.center;
        if !w.is_finite() || w.abs().max_element() > self.far {
            return true;
        }
        let away = (w.abs().cmpgt(h) & (w * d).cmpge(DVec3::ZERO)).any();
        let distance = DVec3::new(d.z * w.y - d.y * w.z, d.x * w.z - d.z * w.x, d.y * w.x - d.x * w.y).abs();
        let a = d.abs();
        let extent = DVec3::new(h.y * a.z + h.z * a.y, h.x * a.z + h.z * a.x, h.x * a.y + h.y * a.x);
        !(away || distance.cmpgt(extent).any())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Against slabs clipped by divisions: a ray meets the box exactly when the
    /// interval of `t >= 0` inside all three slabs is not empty (the slabs with a
    /// margin below rounding either way are skipped).
    #[test]
    fn agrees_with_the_slab_test() {
        let domain = Domain::new(DVec3::new(-2.0, -1.0, 0.5), 4.0, 4).unwrap();
        let reach = Reach::around(&domain, [3, 5, 2], [7, 6, 12]);
        let (lo, hi) = (reach.center - reach.half, reach.center + reach.half);
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut unit = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut met, mut missed) = (0, 0);
        for _ in 0..200_000 {
            let o = reach.center + (DVec3::new(unit(), unit(), unit()) * 2.0 - DVec3::ONE) * 1.5;
            let mut d = DVec3::new(unit(), unit(), unit()) * 2.0 - DVec3::ONE;
            if unit() < 0.1 {
                d[(unit() * 3.0) as usize] = 0.0;
            }
            let (mut enter, mut exit) = (0.0f64, f64::INFINITY);
            let mut clear = true;
            for a in 0..3 {
                if d[a] == 0.0 {
                    clear &= (o[a] - lo[a]).abs() > 1e-9 && (o[a] - hi[a]).abs() > 1e-9;
                    if o[a] < lo[a] || o[a] > hi[a] {
                        exit = -1.0;
                    }
                    continue;
                }
                let (t0, t1) = ((lo[a] - o[a]) / d[a], (hi[a] - o[a]) / d[a]);
                enter = enter.max(t0.min(t1));
                exit = exit.min(t0.max(t1));
            }
            clear &= (exit - enter).abs() > 1e-9 && exit.abs() > 1e-9;
            if !clear {
                continue;
            }
            let want = enter <= exit;
            assert_eq!(reach.may_meet(&Ray::new(o, d)), want, "{o} {d}");
            if want { met += 1 } else { missed += 1 }
        }
        assert!(met > 10_000 && missed > 10_000, "{met} met, {missed} missed");
    }
}
