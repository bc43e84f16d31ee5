//! Shadow rays of one point walked together: the any-hit walk of several rays that
//! start at the same place, sharing the way down from the root for as long as every
//! ray is in the same child: a hit's shadow rays to several lights, or an element's
//! rays to the samples of a patch.
//!
//! A ray whose walk starts at `t = 0` (its origin inside the root and inside the box
//! of the full voxels) goes down from the root, in each inner node, to the child that
//! holds it at `t = 0` (`tm <= 0` per axis, flipped by its mirror bits) while that
//! child is inner. Rays from one origin typically take the same children (not when
//! the origin lies on a mid plane their directions cross in opposite senses, or a
//! plane time underflows to 0 for a huge direction). So the joint walk goes
//! down once for the group: at every level it reads one node record, decides one
//! child and its kind (the walk's data-dependent branches), and works out each ray's
//! frame (its mid-plane times and exit time, which depend on its direction) in a
//! fixed loop without branches of its own. It stops where the rays' children differ,
//! or the child is empty; from there each ray goes on with the walk's own loop
//! (`Traversal::walk_on`) and its own stack. A full child there blocks every ray at
//! `t = 0`.
//!
//! Exact: each ray's frames are those its own walk would write on the same way down
//! (the same formulas, in the same order), and its walk goes on from the same place,
//! so every answer is [`crate::ray::RayCast::occluded`]'s (tested ray by ray on
//! every build, and against the brute force).
//! Rays that start elsewhere (outside the root or the box, or with an axis the walk
//! moves off the lattice) are walked alone, and so are all the rays of a group of
//! which at most one may meet the box at all.
//!
//! Measured (docs/benchmark-log/2026-12.md, "Incoherent rays", "Shadow rays of one hit
//! walked together"): the shadow rays of the bunny's 408,120 primary hits to two lights,
//! every pair of one hit walked together, 269.5 -> 249.9 ns a ray (-7%), 2,275 ->
//! 2,123 instructions and 22.1 -> 21.0 mispredictions a ray: each pair shares 8.6
//! levels of the way down. The sizes of a group are constants (`together::<L, N>`):
//! with a loop over a run-time count the same walk was 12% slower than the rays one
//! by one. The renderer does not call it: in the Whitted classic (two lights) and in
//! the Cornell box's form factors (rays from an element to a patch's samples) most
//! shadow rays are answered by the box tests before any walk, and a group's
//! bookkeeping cost more than the shared way down saved (1.05 -> 1.13 s and 2.57 ->
//! 2.67 s, the same pictures and solutions).

use std::mem::MaybeUninit;

#[cfg(target_arch = "x86_64")]
use super::lanes::{Avx2, Sse2};
use super::lanes::{Isa, Lanes, Scalar, earlier};
use super::traversal::Traversal;
use super::voxel_ray::VoxelRay;
use super::walk::{Course, Frame, INNER_BEFORE, Lattice, Opening, Place, RayLanes, RootSpan, STACK, Subtree};
use crate::ray::Ray;

/// Most rays walked as one group.
const TOGETHER: usize = 4;

/// A ray of a group: the walk's view of it, where it crosses the root, its limit
/// (clamped to the exit of the full voxels' box) and its place in the caller's slice.
struct Member {
    lattice: Lattice,
    span: RootSpan,
    t_max: f64,
    slot: usize,
}

impl Traversal {
    /// `blocked[i] = self.occluded(&rays[i])` for every ray, walked together four at
    /// a time (see the module doc). Exact for any rays; faster than one by one only
    /// for rays of one origin inside the box of the full voxels (a hit's shadow rays
    /// to several lights).
    ///
    /// # Panics
    /// When `rays` and `blocked` differ in length.
    pub fn occluded_each(&self, rays: &[Ray], blocked: &mut [bool]) {
        assert_eq!(rays.len(), blocked.len(), "rays and answers differ in length");
        for (rays, blocked) in rays.chunks(TOGETHER).zip(blocked.chunks_mut(TOGETHER)) {
            // Most rays of a scene miss most solids' boxes (the division-free test):
            // a group only when two or more may meet this one.
            // (A bit a ray, not an array of bools: counting those read them back as
            // one word and stalled on their byte stores.)
            let meeting =
                rays.iter().enumerate().fold(0u32, |m, (k, ray)| m | u32::from(self.reach.may_meet(ray)) << k);
            if meeting.count_ones() >= 2 {
                self.occluded_group(rays, blocked, meeting);
            } else {
                for (k, (ray, blocked)) in rays.iter().zip(blocked.iter_mut()).enumerate() {
                    *blocked = meeting >> k & 1 == 1 && {
                        let r = VoxelRay::new(&self.domain, ray);
                        self.first_full_after::<false>(&r, ray.t_max, 0.0, Subtree::ROOT).is_some()
                    };
                }
            }
        }
    }

    /// [`Traversal::occluded_each`] of at most [`TOGETHER`] rays, those that may meet
    /// the full voxels' box (bit `k` of `meeting` for ray `k`): each walked from the
    /// root straight away, unless it starts at its origin; those walked together when
    /// there are two or more.
    fn occluded_group(&self, rays: &[Ray], blocked: &mut [bool], meeting: u32) {
        let mut members = [const { MaybeUninit::<Member>::uninit() }; TOGETHER];
        let mut count = 0;
        for (slot, (ray, blocked)) in rays.iter().zip(blocked.iter_mut()).enumerate() {
            *blocked = false;
            if meeting >> slot & 1 == 0 {
                continue;
            }
            let r = VoxelRay::new(&self.domain, ray);
            match self.opening(&r, ray.t_max, 0.0) {
                Err(full) => *blocked = full.is_some(),
                // At its origin (t = 0): it may join the group.
                Ok(Opening { span, t_max, enter }) if r.inv.is_finite() && span.ta <= 0.0 && enter <= 0.0 => {
                    members[count].write(Member { lattice: Lattice::new(&r), span, t_max, slot });
                    count += 1;
                }
                Ok(Opening { span, t_max, enter }) => {
                    let ray = Lattice::new(&r);
                    *blocked = self.walk::<false, false>(&ray, t_max, span, 0.0f64.max(enter), Subtree::ROOT).is_some();
                }
            }
        }
        // SAFETY: the first `count` members were written above.
        let members = unsafe { &*(std::ptr::from_ref(&members[..count]) as *const [Member]) };
        match members {
            [] => {}
            [m] => {
                blocked[m.slot] = self.walk::<false, false>(&m.lattice, m.t_max, m.span, 0.0, Subtree::ROOT).is_some()
            }
            _ => match self.isa {
                #[cfg(target_arch = "x86_64")]
                // SAFETY: `Isa::Avx2` is only chosen where the CPU has AVX2.
                Isa::Avx2 => unsafe { self.together_avx2(members, blocked) },
                #[cfg(target_arch = "x86_64")]
                Isa::Sse2 => self.together_apart::<Sse2>(members, blocked),
                _ => self.together_apart::<Scalar>(members, blocked),
            },
        }
    }

    /// [`Traversal::together`] in a build without AVX2, kept out of its caller (whose
    /// frame would otherwise hold the group's stacks).
    #[inline(never)]
    fn together_apart<L: Lanes>(&self, members: &[Member], blocked: &mut [bool]) {
        self.together_sized::<L>(members, blocked);
    }

    /// [`Traversal::together`] with the group's size a constant (its loops unrolled).
    #[inline(always)]
    fn together_sized<L: Lanes>(&self, members: &[Member], blocked: &mut [bool]) {
        match members.len() {
            2 => self.together::<L, 2>(members, blocked),
            3 => self.together::<L, 3>(members, blocked),
            _ => self.together::<L, 4>(members, blocked),
        }
    }

    /// [`Traversal::together`] compiled with AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn together_avx2(&self, members: &[Member], blocked: &mut [bool]) {
        self.together_sized::<Avx2>(members, blocked);
    }

    /// The walk of a group: down together while every ray is in the same inner
    /// child at `t = 0`, then each ray on its own (see the module doc).
    #[inline(always)]
    fn together<L: Lanes, const N: usize>(&self, members: &[Member], blocked: &mut [bool]) {
        let members: &[Member; N] = members.try_into().expect("a group of N rays");
        let zero = L::splat(0.0);
        let infinity = L::splat(f64::INFINITY);
        let lanes: [RayLanes<L>; N] = std::array::from_fn(|k| RayLanes::new(&members[k].lattice));
        let mut stacks = [const { [const { MaybeUninit::<Frame<L>>::uninit() }; STACK] }; N];
        let (mut index, mut depth) = (0u32, 0usize);
        let mut node = self.nodes[0];
        let (mut min, mut half) = (L::splat(0.0), f64::from(self.domain.resolution() / 2));
        let mut tm: [L; N] = std::array::from_fn(|k| min.add(L::splat(half)).sub(lanes[k].o).mul(lanes[k].inv));
        let mut tb: [f64; N] = std::array::from_fn(|k| members[k].span.tb);
        loop {
            let past = tm[0].le(zero);
            let child = past.bits() ^ lanes[0].mirror;
            if (1..N).any(|k| tm[k].le(zero).bits() ^ lanes[k].mirror != child) || node.valid >> child & 1 == 0 {
                break;
            }
            if node.full >> child & 1 == 1 {
                // Every ray starts inside a full voxel, with 0 < t_max.
                for m in members {
                    blocked[m.slot] = true;
                }
                return;
            }
            for k in 0..N {
                let past = tm[k].le(zero);
                let next = L::select(past, infinity, tm[k]).min3();
                stacks[k][depth].write(Frame { tm: tm[k], min, tb: tb[k], index, node });
                tb[k] = earlier(next, tb[k]);
            }
            depth += 1;
            min = min.add(past.xor(lanes[0].flip).and(L::splat(half)));
            index = node.first + u32::from(INNER_BEFORE[usize::from(node.valid & !node.full)][child]);
            node = self.nodes[index as usize];
            half *= 0.5;
            for k in 0..N {
                tm[k] = min.add(L::splat(half)).sub(lanes[k].o).mul(lanes[k].inv);
            }
        }
        for (k, m) in members.iter().enumerate() {
            let place = Place { base: 0, depth, index, node, min, half, tb: tb[k], tm: tm[k], t: 0.0 };
            let course = Course { lattice: &m.lattice, lanes: lanes[k], span: m.span, t_max: m.t_max };
            let hit = self.walk_on::<L, false, false>(&mut stacks[k], place, &course, Subtree::ROOT);
            blocked[m.slot] = hit.is_some();
        }
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::octree::{Domain, LinearOctree};
    use crate::ray::RayCast;

    /// Every build of the joint walk (AVX2, SSE2 where the CPU has them) gives the
    /// scalar walk's answers, ray by ray, on groups of one to six rays from origins
    /// on and off the lattice.
    #[test]
    fn every_build_matches_the_scalar_walk() {
        let mut x = 0x2545_f491_4f6c_dd1du64;
        let mut next = move || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            x
        };
        let unit = |next: &mut dyn FnMut() -> u64| (next() >> 11) as f64 / (1u64 << 53) as f64;
        for depth in [2, 4, 6] {
            let d = Domain::new(DVec3::new(-0.3, 0.2, 0.1), 1.7, depth).unwrap();
            let n = d.resolution();
            let voxels: Vec<[u32; 3]> = (0..n * n).map(|_| [0; 3].map(|_| (next() % u64::from(n)) as u32)).collect();
            let tree = LinearOctree::from_voxels(d, voxels).unwrap();
            let mut scalar = Traversal::new(&tree);
            scalar.isa = Isa::Scalar;
            for isa in Isa::available() {
                let mut t = Traversal::new(&tree);
                t.isa = isa;
                for g in 0..2000 {
                    let mut o = DVec3::new(unit(&mut next), unit(&mut next), unit(&mut next)) * f64::from(n);
                    if g % 3 == 0 {
                        o = o.round();
                    }
                    let origin = d.min() + o * d.voxel_size();
                    let rays: Vec<Ray> = (0..1 + next() % 6)
                        .map(|k| {
                            let mut dir = DVec3::new(unit(&mut next), unit(&mut next), unit(&mut next)) * 2.0 - 1.0;
                            if k % 4 == 3 {
                                dir[(next() % 3) as usize] = 0.0;
                            }
                            let ray = Ray::new(origin, dir);
                            if k % 3 == 2 { ray.until(unit(&mut next) * 2.0) } else { ray }
                        })
                        .collect();
                    let mut blocked = vec![false; rays.len()];
                    t.occluded_each(&rays, &mut blocked);
                    for (ray, got) in rays.iter().zip(blocked) {
                        assert_eq!(got, scalar.occluded(ray), "{isa:?} {ray:?}");
                    }
                }
            }
        }
    }
}
