//! The exact first-hit walk through a [`Traversal`], skipping empty space at every
//! level.
//!
//! The walk (after Revelles et al., "An efficient parametric algorithm for octree
//! traversal", 2000): a node's interval `[ta, tb]` along the ray is cut at the times the
//! ray crosses its three mid planes; each non-empty piece is one child, visited in ray
//! order; full children end the walk, empty ones are skipped, inner ones are entered.
//! The walk is one loop with an explicit stack of the inner nodes above (their record,
//! corner, mid-plane times and exit time), not recursion; the child at time `t` is read
//! off the mid-plane times (`tm <= t`, three lanes at once), so going back up needs no
//! saved child state.
//! Deviations from the paper: child times are computed from their planes,
//! `(plane - o) * inv` with `inv = 1 / d`, not averaged from the parent's, so every
//! plane's time is one formula and ties are decided the same way everywhere (and by
//! the tests' brute force); the entered face is worked out once, at the hit, from the
//! mid-plane times on the stack.
//!
//! Semantics: the hit is the first point (t >= 0) where the ray enters the interior of a
//! full voxel; a ray that only touches full voxels along an edge, a corner or a face it
//! grazes does not hit them. A ray parallel to an axis counts as inside the half-open
//! cells `[i, i + 1)` along that axis. The entered face is the axis of the plane crossed
//! there; when several voxel planes are crossed at once (an edge or corner), the
//! lowest axis.
//!
//! Precision: coordinates are in voxel units of the domain (`0..2^depth`), so every
//! plane is an integer below 2^21, exact in f64, at any depth.
//!
//! Speed: the per-axis arithmetic runs in three SIMD lanes (`lanes`), AVX2 where the
//! CPU has it (chosen at run time), SSE2 otherwise; the step on an empty child is a
//! compare, a mask, a select and a three-way minimum; the stack is left uninitialized
//! until written; any-hit queries skip the entered face. Against the array code before
//! it (small bunny at depth 10, one thread; callgrind, then CPU time): random rays
//! 2,860 to 2,436 instructions a ray, shadow rays 2,466 to 1,995, primary rays 1,976
//! to 1,698; in time shadow rays about 10% faster, random and primary rays and packets
//! the same. What bounds incoherent rays is branch prediction, not arithmetic: about
//! 33 mispredicted branches a random ray (about 30 steps), each child's kind (empty,
//! inner, full) a coin toss, the same before and after.
//!
//! Measured and not kept (docs/benchmark-log/2026-12.md, "Incoherent rays"): a stackless walk of four
//! rays at once in AVX2 lanes, lanes refilled from a stream, going up by parent
//! indices (a quarter of the mispredictions, a third more instructions, 1.6x slower on
//! random rays: each step waits on the last, four lanes give no parallelism to hide
//! it); starting shadow rays at the node holding their origin (the search down costs
//! more than the skipped levels: 2,629 to 3,972 instructions a shadow ray); a 64-ary
//! tree of 4x4x4 cells stepped by a DDA (1.49 against 4.85 MB at depth 10, but 4,235
//! instructions and 46.7 mispredictions a random ray against 3,374 and 32.7); the
//! first non-empty child of a node chosen without a branch a child, from the pieces
//! the ray's mid-plane crossings cut (a third fewer mispredictions, 1.6x the
//! instructions, 1.5x the time).
//! A full 64-tree with a mirrored DDA walk is kept as a contender (`tree64`, the same
//! hits): in lanes, with a node left at once when no child the ray can still reach in
//! it is present, 1.2-1.3x the instructions and half the mispredictions; 0.9x the time
//! on shadow rays from primary hits to a light, the same on bounce rays and shadow rays
//! to a near point light, 1.25x on primary rays (benchmark log); not routed.

use std::hint::select_unpredictable;
use std::mem::MaybeUninit;

#[cfg(target_arch = "x86_64")]
use super::lanes::{Avx2, Sse2};
use super::lanes::{Isa, Lanes, Scalar, earlier};
use super::traversal::{Inner, Outline, Root, Traversal};
use super::voxel_ray::{Entry, Hit, VoxelRay};
use crate::octree::MAX_DEPTH;
use crate::ray::{Ray, RayCast};

/// The walk through a traversal octree: the first full voxel a world-space ray
/// enters (`t` in the ray's own parameter: world units when `dir` is a unit vector).
impl RayCast for Traversal {
    type Hit = Hit;

    fn hit(&self, ray: &Ray) -> Option<Hit> {
        if !self.outline.reach.may_meet(ray) {
            return None;
        }
        let r = VoxelRay::new(&self.outline.domain, ray);
        Some(r.entry(&self.first_full(&r, ray.t_max)?))
    }

    /// The walk of [`RayCast::hit`] without working out the voxel and face. Always
    /// inlined: called, it read the shadow ray its caller had just stored with loads
    /// that straddle those stores (a failed store forwarding: 30% of its own time, 1-2%
    /// of a Whitted render).
    #[inline(always)]
    fn occluded(&self, ray: &Ray) -> bool {
        if !self.outline.reach.may_meet(ray) {
            return false;
        }
        let r = VoxelRay::new(&self.outline.domain, ray);
        self.first_full_after::<false>(&r, ray.t_max, 0.0, Subtree::ROOT).is_some()
    }
}

impl Traversal {
    /// The first full node the ray enters before `t_max`: its corner, size, entry time
    /// and entered face (what [`VoxelRay::entry`] turns into a hit). A ray with a
    /// non-finite origin or direction hits nothing.
    fn first_full(&self, r: &VoxelRay, t_max: f64) -> Option<Entry> {
        self.first_full_after::<true>(r, t_max, 0.0, Subtree::ROOT)
    }

    /// [`Traversal::first_full`] with the walk started at `max(entry, start)` instead of
    /// `max(entry, 0)`, for a `start >= 0` at or before the ray's first hit (a beam's
    /// lower bound): the pieces skipped are empty, so the result is the same. When the
    /// ray enters the root by `start`, the walk begins in `from`, which must hold the
    /// ray at time `start` as the walk places it (see [`Subtree`]).
    /// `FACE` false skips working out the entered face (`Entry::face` is `None`), for
    /// any-hit queries.
    pub(super) fn first_full_after<const FACE: bool>(
        &self,
        r: &VoxelRay,
        t_max: f64,
        start: f64,
        from: Subtree,
    ) -> Option<Entry> {
        let Opening { span, t_max, enter } = match self.outline.opening(r, t_max, start) {
            Ok(opening) => opening,
            Err(full) => {
                let n = self.outline.domain.resolution();
                return full.map(|RootSpan { ta, face, .. }| Entry { min: [0, 0, 0], size: n, t: ta, face });
            }
        };
        let ray = Lattice::new(r);
        // Two builds of the walk: the one from the root (single rays) carries no
        // subtree logic; it starts where the ray enters the full voxels' box.
        if from.above.is_empty() {
            self.walk::<false, FACE>(&ray, t_max, span, start.max(enter), Subtree::ROOT)
        } else if span.ta > start {
            self.walk::<false, FACE>(&ray, t_max, span, start, Subtree::ROOT)
        } else {
            self.walk::<true, FACE>(&ray, t_max, span, start, from)
        }
    }
}

impl Outline {
    /// What a walk of `r` before `t_max`, started at `start >= 0`, has to do: walk the
    /// inner root (`Ok`), or not (`Err`): `Some` of where the ray crosses a full root
    /// it hits there, `None` for no hit. The tests every walk shares
    /// ([`Traversal::first_full_after`], the 64-tree's walk and their callers). (Not an enum
    /// of three: its match became an indirect jump, 1% of a primary ray's
    /// instructions.)
    #[inline(always)]
    pub(super) fn opening(&self, r: &VoxelRay, t_max: f64, start: f64) -> Result<Opening, Option<RootSpan>> {
        // No hit before a limit of 0 or less, or NaN (whatever the ray's axes).
        if self.root == Root::Empty || !(r.o.is_finite() && r.d.is_finite()) || t_max <= 0.0 || t_max.is_nan() {
            return Err(None);
        }
        let Some(span) = self.root_span(r) else { return Err(None) };
        let RootSpan { ta, tb, .. } = span;
        // The walk starts at max(ta, start) (start >= 0), which must be before tb.
        if ta >= tb || tb <= start || ta >= t_max {
            return Err(None);
        }
        if self.root == Root::Full {
            return Err((ta.max(0.0) < t_max).then_some(span));
        }
        let Some((enter, exit)) = self.occupied_span(r, t_max) else { return Err(None) };
        // No hit after the box's exit: the walk stops at the first non-empty node it
        // would enter from there on.
        Ok(Opening { span, t_max: t_max.min(exit), enter })
    }

    /// The times a ray enters and leaves the box of the full voxels
    /// ([`Outline::occupied`]), `None` when it cannot hit a full voxel there before
    /// `t_max` (it misses the box, leaves it before 0, or enters it at `t_max` or
    /// later); `(-inf, +inf)` for a ray with an infinite reciprocal on some axis (moved
    /// off the lattice by the walk: no test).
    ///
    /// Exact: the walk places the ray in the cell `[m, m + 1)` of an axis at time `t`
    /// when the computed times of the cell's near and far planes satisfy `near <= t <
    /// far` (`(plane - o) inv`, the same formula here), and a plane's computed time is
    /// monotone in the plane; a full voxel's cells lie within the box's planes, so a hit
    /// at `t` has `enter <= t < exit`, with `0 <= t < t_max`.
    #[inline(always)]
    fn occupied_span(&self, r: &VoxelRay, t_max: f64) -> Option<(f64, f64)> {
        if !r.inv.is_finite() {
            return Some((f64::NEG_INFINITY, f64::INFINITY));
        }
        let [low, high] = self.occupied;
        let (mut enter, mut exit) = (f64::NEG_INFINITY, f64::INFINITY);
        for a in 0..3 {
            // By a select, not a branch: the sign of an incoherent ray's axis is a coin.
            let up = r.d[a] > 0.0;
            let (near, far) = (pick(up, low[a], high[a]), pick(up, high[a], low[a]));
            enter = enter.max((near - r.o[a]) * r.inv[a]);
            exit = exit.min((far - r.o[a]) * r.inv[a]);
        }
        (enter < exit && exit > 0.0 && enter < t_max).then_some((enter, exit))
    }

    /// Entry and exit times of the root's slabs, with the lowest axis of the entry
    /// plane; an axis the ray is parallel to only says whether the origin is in
    /// (`None` when it is not).
    #[inline(always)]
    fn root_span(&self, r: &VoxelRay) -> Option<RootSpan> {
        let n = f64::from(self.domain.resolution());
        let (mut ta, mut tb, mut face) = (f64::NEG_INFINITY, f64::INFINITY, None);
        let mut outside = false;
        let mut slab = |a: usize| {
            let (o, d, inv) = (r.o[a], r.d[a], r.inv[a]);
            if d == 0.0 {
                outside |= o < 0.0 || o >= n;
                return;
            }
            // By a select, not a branch (as in `occupied_span`).
            let (near, far) = (pick(d > 0.0, 0.0, n), pick(d > 0.0, n, 0.0));
            let (t0, t1) = ((near - o) * inv, (far - o) * inv);
            if t0 > ta {
                ta = t0;
                face = Some(a);
            }
            tb = tb.min(t1);
        };
        slab(0);
        slab(1);
        slab(2);
        (!outside).then_some(RootSpan { ta, tb, face })
    }
}

/// `a` when `cond`, else `b`, chosen on the bits by an integer conditional move: a
/// select of two f64 is a branch on x86-64's baseline (no SSE4.1 blend), and the
/// conditions this takes (the signs of an incoherent ray's axes) are coins.
#[inline(always)]
pub(super) fn pick(cond: bool, a: f64, b: f64) -> f64 {
    f64::from_bits(select_unpredictable(cond, a.to_bits(), b.to_bits()))
}

/// A walk of the inner root to make (see [`Traversal::opening`]): the ray crosses
/// the root over `span`, enters the full voxels' box at `enter`, and is walked before
/// `t_max` (clamped to that box's exit).
pub(super) struct Opening {
    pub span: RootSpan,
    pub t_max: f64,
    pub enter: f64,
}

/// Where a ray crosses the root: entered at `ta` through `face`, left at `tb`.
#[derive(Clone, Copy)]
pub(super) struct RootSpan {
    pub ta: f64,
    pub tb: f64,
    pub face: Option<usize>,
}

/// The ray as the walk reads it: origin and reciprocal direction in voxel units (moved
/// off the lattice where the reciprocal is infinite, see `off_lattice`) and the mirror
/// bits (bit `a` set when the ray runs to lower coordinates on axis `a`).
pub(super) struct Lattice {
    pub o: [f64; 3],
    pub inv: [f64; 3],
    pub mirror: usize,
}

impl Lattice {
    pub(super) fn new(r: &VoxelRay) -> Self {
        let mirror = (0..3).fold(0usize, |m, a| m | usize::from(r.d[a] < 0.0) << a);
        let (mut o, mut inv) = (r.o.to_array(), r.inv.to_array());
        if !r.inv.is_finite() {
            off_lattice(r, &mut o, &mut inv);
        }
        Lattice { o, inv, mirror }
    }

    /// The time the ray leaves the node `[min, min + size)`: the least time of its far
    /// planes, `min over a of (far[a] - o[a]) * inv[a]`.
    fn exit_time(&self, min: [u32; 3], size: u32) -> f64 {
        let far = |a: usize| {
            let plane = if self.mirror >> a & 1 == 1 { min[a] } else { min[a] + size };
            (f64::from(plane) - self.o[a]) * self.inv[a]
        };
        earlier(earlier(far(0), far(1)), far(2))
    }

    /// The face through which a walk entered the node `[min, min + size)` at time `t`:
    /// the lowest axis whose near plane the ray crosses at `t`, `None` when there is
    /// none.
    ///
    /// The same axis as [`entered_face`] for a ray not parallel to any axis: the near
    /// planes of a node on the walk's path are mid planes of its ancestors or the
    /// root's entry planes, all crossed at or before `t`; a mid plane on the path
    /// crossed at `t` lies on the node's near side on its axis (a far-side one is
    /// crossed after `t`), so the node's near plane there is crossed at `t` too (plane
    /// times are monotone); and a root entry plane crossed at `t` means `t == ta`.
    fn near_face(&self, min: [u32; 3], size: u32, t: f64) -> Option<usize> {
        (0..3).find(|&a| {
            let plane = if self.mirror >> a & 1 == 1 { min[a] + size } else { min[a] };
            (f64::from(plane) - self.o[a]) * self.inv[a] == t
        })
    }
}

/// An inner node a walk may begin in, below the root: its index, corner and size, and
/// the indices of the inner nodes above it from the root down (empty for the root).
/// It must hold the ray at the walk's start time `t` as the walk's rule places it:
/// on each axis the time of its near plane `<= t` and of its far plane `> t` (then the
/// walk from the root would go down to it at `t` without a step across).
#[derive(Clone, Copy)]
pub(super) struct Subtree<'a> {
    pub index: u32,
    pub min: [u32; 3],
    pub size: u32,
    pub above: &'a [u32],
}

impl Subtree<'_> {
    /// The root (its size is read from the domain by the walk).
    pub const ROOT: Subtree<'static> = Subtree { index: 0, min: [0; 3], size: 0, above: &[] };
}

/// Most inner nodes a walk can be below: the root is at level 0 and the last inner
/// nodes at level `MAX_DEPTH - 1`.
const STACK: usize = MAX_DEPTH as usize;

/// An inner node the walk went down from: what it needs to go on there (its node
/// record, corner, mid-plane times and exit time).
#[derive(Clone, Copy)]
struct Frame<L> {
    pub tm: L,
    pub min: L,
    pub tb: f64,
    pub index: u32,
    pub node: Inner,
}

/// The ray in lanes, as the walk's step reads it: origin, reciprocal direction, the
/// mirror bits, and the lanes to flip (all ones where the ray runs to lower
/// coordinates).
///
/// No mid-plane time is NaN (see `off_lattice`), so "past the mid plane" is `tm <= t`
/// on every axis and the child is those bits flipped by the mirror bits. The idle lane
/// (AVX2) has `o = -1`, `inv = +inf` and corner 0: its time is `+inf`, never past,
/// never the next.
#[derive(Clone, Copy)]
struct RayLanes<L> {
    pub o: L,
    pub inv: L,
    pub mirror: usize,
    pub flip: L,
}

impl<L: Lanes> RayLanes<L> {
    #[inline(always)]
    fn new(ray: &Lattice) -> Self {
        let ones = f64::from_bits(u64::MAX);
        let flip = std::array::from_fn(|a| if ray.mirror >> a & 1 == 1 { ones } else { 0.0 });
        RayLanes {
            o: L::new(ray.o, -1.0),
            inv: L::new(ray.inv, f64::INFINITY),
            mirror: ray.mirror,
            flip: L::new(flip, 0.0),
        }
    }
}

/// A ray as the walk's loop takes it: in the lattice and in lanes, where it crosses
/// the root, and its limit.
#[derive(Clone, Copy)]
struct Course<'a, L> {
    pub lattice: &'a Lattice,
    pub lanes: RayLanes<L>,
    pub span: RootSpan,
    pub t_max: f64,
}

/// Where a walk is: at time `t` in the inner node `index` (record `node`, corner
/// `min`, half its edge `half`, mid-plane times `tm`, left at `tb`), below the frames
/// `stack[..depth]` of its stack (those below `base` not filled yet, for a walk begun
/// below the root).
#[derive(Clone, Copy)]
struct Place<L> {
    pub base: usize,
    pub depth: usize,
    pub index: u32,
    pub node: Inner,
    pub min: L,
    pub half: f64,
    pub tb: f64,
    pub tm: L,
    pub t: f64,
}

impl Traversal {
    /// The walk through the inner root, entered at `ta` through `face` and left at `tb`
    /// (after Revelles et al., iterative, with an explicit stack), in the build this
    /// traversal was made for (`lanes::Isa`). `BELOW_ROOT` false builds the walk from
    /// the root alone (single rays), `FACE` false the walk that needs no entered face
    /// (any-hit queries).
    #[inline]
    fn walk<const BELOW_ROOT: bool, const FACE: bool>(
        &self,
        ray: &Lattice,
        t_max: f64,
        span: RootSpan,
        start: f64,
        from: Subtree,
    ) -> Option<Entry> {
        match self.isa {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Isa::Avx2` is only chosen where the CPU has AVX2.
            Isa::Avx2 => unsafe { self.walk_avx2::<BELOW_ROOT, FACE>(ray, t_max, span, start, from) },
            #[cfg(target_arch = "x86_64")]
            Isa::Sse2 => self.walk_lanes::<Sse2, BELOW_ROOT, FACE>(ray, t_max, span, start, from),
            _ => self.walk_lanes::<Scalar, BELOW_ROOT, FACE>(ray, t_max, span, start, from),
        }
    }

    /// [`Traversal::walk_lanes`] compiled with AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn walk_avx2<const BELOW_ROOT: bool, const FACE: bool>(
        &self,
        ray: &Lattice,
        t_max: f64,
        span: RootSpan,
        start: f64,
        from: Subtree,
    ) -> Option<Entry> {
        self.walk_lanes::<Avx2, BELOW_ROOT, FACE>(ray, t_max, span, start, from)
    }

    /// The walk, over three lanes of plane times.
    ///
    /// In an inner node `[min, min + size)` the mid-plane times `tm[a] = (min[a] +
    /// size / 2 - o[a]) * inv[a]` (`inv = 1 / d`) are computed once. At time `t` the
    /// ray is in the child whose bit `a` is high when `tm[a] <= t` (`d[a] > 0`) or
    /// `tm[a] > t` (`d[a] < 0`); that child's piece ends at the next mid-plane time
    /// `min {tm[a] : tm[a] > t}` or at the node's exit `tb`, whichever comes first, and
    /// crossings at one time are taken together (no zero-length pieces). The walk
    /// starts at `max(ta, start)`, with `0 <= start < tb`: pieces before the origin are
    /// never visited (a hit there is the origin's own voxel, whatever its entry time);
    /// nor, when `start > 0`, those before `start`.
    ///
    /// A node's corner lives in lanes as f64 (integers below `2^22`, exact), so a
    /// child's corner is `min + (high & half)` with `high` the lanes past the mid plane
    /// flipped by the mirror, and its mid planes `min + half / 2` are the integer sums
    /// the scalar formula converts: the same bits.
    ///
    /// A walk begun in a node `from` below the root leaves the frames of the nodes
    /// above it empty; they are filled only if the ray leaves `from` (a node's exit
    /// time is the least time of its far planes, the same bits as the `tb` the walk
    /// from the root carries down), and the face of a hit in `from` is read off the
    /// hit node's near planes (see [`Lattice::near_face`]).
    #[inline(always)]
    fn walk_lanes<L: Lanes, const BELOW_ROOT: bool, const FACE: bool>(
        &self,
        ray: &Lattice,
        t_max: f64,
        span: RootSpan,
        start: f64,
        from: Subtree,
    ) -> Option<Entry> {
        let lanes = RayLanes::new(ray);
        let t = span.ta.max(start);
        // Frames below `base` are not filled yet (a walk begun below the root).
        let base = if BELOW_ROOT { from.above.len() } else { 0 };
        let (index, min, half, tb) = if base == 0 {
            (0u32, L::splat(0.0), f64::from(self.outline.domain.resolution() / 2), span.tb)
        } else {
            if t >= t_max {
                return None;
            }
            let corner = L::new(from.min.map(f64::from), 0.0);
            (from.index, corner, f64::from(from.size / 2), ray.exit_time(from.min, from.size))
        };
        let node = self.nodes[index as usize];
        let tm = min.add(L::splat(half)).sub(lanes.o).mul(lanes.inv);
        let mut stack = [const { MaybeUninit::<Frame<L>>::uninit() }; STACK];
        let place = Place { base, depth: base, index, node, min, half, tb, tm, t };
        self.walk_on::<L, BELOW_ROOT, FACE>(&mut stack, place, &Course { lattice: ray, lanes, span, t_max }, from)
    }

    /// The walk's loop from `place` on (see [`Traversal::walk_lanes`]): the first full
    /// node the ray enters before its limit. `place` must be where the walk from the
    /// root (or from `from`, frames below `base` not filled) would be at the top of its
    /// loop at time `t`: frames `base..depth` written on the way down, `tb` the node's
    /// exit as carried down (`earlier` of the parent's and the next mid plane's), `tm`
    /// the node's mid-plane times by the same formula.
    #[inline(always)]
    fn walk_on<L: Lanes, const BELOW_ROOT: bool, const FACE: bool>(
        &self,
        stack: &mut [MaybeUninit<Frame<L>>; STACK],
        place: Place<L>,
        course: &Course<L>,
        from: Subtree,
    ) -> Option<Entry> {
        let Course { lattice: ray, lanes, span, t_max } = *course;
        let RootSpan { ta, tb: root_tb, face } = span;
        let RayLanes { o, inv, mirror, flip } = lanes;
        let infinity = L::splat(f64::INFINITY);
        let Place { mut base, mut depth, mut index, mut node, mut min, mut half, mut tb, mut tm, mut t } = place;
        loop {
            // Step 1: the child the ray is in just after t, and the next mid plane.
            let past = tm.le(L::splat(t));
            let child = past.bits() ^ mirror;
            let next = L::select(past, infinity, tm).min3();
            // Step 2: a non-empty child is the hit (full) or is walked (inner).
            if node.valid >> child & 1 == 1 {
                if t >= t_max {
                    return None;
                }
                let cmin = min.add(past.xor(flip).and(L::splat(half)));
                if node.full >> child & 1 == 1 {
                    let cmin = cmin.to_array().map(|m| m as u32);
                    let size = half as u32;
                    let face = if !FACE {
                        None
                    } else if !BELOW_ROOT || base == 0 {
                        // SAFETY: frames `0..depth` were written on the way down.
                        let path = stack[..depth].iter().map(|f| unsafe { f.assume_init_ref() }.tm.to_array());
                        entered_face(path.chain([tm.to_array()]), t, ta, face)
                    } else {
                        ray.near_face(cmin, size, t)
                    };
                    return Some(Entry { min: cmin, size, t, face });
                }
                stack[depth].write(Frame { tm, min, tb, index, node });
                depth += 1;
                index = node.first + u32::from(INNER_BEFORE[usize::from(node.valid & !node.full)][child]);
                node = self.nodes[index as usize];
                min = cmin;
                half *= 0.5;
                tb = earlier(next, tb);
                tm = min.add(L::splat(half)).sub(o).mul(inv);
                continue;
            }
            // Step 3: leave the child across mid planes of this node, or out of it
            // (and of every ancestor left at the same time).
            if next < tb {
                t = next;
                continue;
            }
            t = tb;
            loop {
                if depth == base {
                    if !BELOW_ROOT || base == 0 {
                        return None;
                    }
                    // Leaving the node the walk began in: fill the frames above it.
                    let corner = min.to_array().map(|m| m as u32);
                    self.fill_frames_above(&mut stack[..base], &from, (corner, (2.0 * half) as u32), root_tb, ray);
                    base = 0;
                }
                depth -= 1;
                // SAFETY: frames `0..depth` were written on the way down or filled above.
                let frame = unsafe { stack[depth].assume_init() };
                half *= 2.0;
                (tm, min, tb, index, node) = (frame.tm, frame.min, frame.tb, frame.index, frame.node);
                if t < tb {
                    break;
                }
            }
        }
    }

    /// The frames of the nodes above `from`, from the root down, for a walk that began
    /// in `from` and now leaves it: each the ancestor of the node `[min, min + size)` the
    /// walk is in, at its level, with its mid-plane times and exit time (the root's is
    /// `root_tb`).
    #[cold]
    fn fill_frames_above<L: Lanes>(
        &self,
        stack: &mut [MaybeUninit<Frame<L>>],
        from: &Subtree,
        (min, size): ([u32; 3], u32),
        root_tb: f64,
        ray: &Lattice,
    ) {
        let base = stack.len();
        let o = L::new(ray.o, -1.0);
        let inv = L::new(ray.inv, f64::INFINITY);
        for (level, (frame, &above)) in stack.iter_mut().zip(from.above).enumerate() {
            let up = size << (base - level);
            let umin = min.map(|m| m & !(up - 1));
            let utb = if level == 0 { root_tb } else { ray.exit_time(umin, up) };
            let corner = L::new(umin.map(f64::from), 0.0);
            let tm = corner.add(L::splat(f64::from(up / 2))).sub(o).mul(inv);
            frame.write(Frame { tm, min: corner, tb: utb, index: above, node: self.nodes[above as usize] });
        }
    }
}

/// Where the reciprocal direction is infinite (a ray parallel to the axis, or a
/// subnormal direction), moves the walk's origin off the lattice to `ceil(o) - 0.5`
/// (`floor(o) + 0.5` and a reciprocal of +inf when parallel), so that no mid-plane
/// time `(mid - o) * inv` is NaN and the infinite ones put the ray on the side the
/// plane formula gives everywhere else: the high side of a plane through a parallel
/// ray's origin (half-open cells), the low side for a subnormal direction (as a NaN
/// time compares). Rare, so out of the walk's way.
#[cold]
fn off_lattice(r: &VoxelRay, o: &mut [f64; 3], inv: &mut [f64; 3]) {
    for a in 0..3 {
        if r.d[a] == 0.0 {
            (o[a], inv[a]) = (r.o[a].floor() + 0.5, f64::INFINITY);
        } else if r.inv[a].is_infinite() {
            o[a] = r.o[a].ceil() - 0.5;
        }
    }
}

/// `INNER_BEFORE[mask][i]`: how many of the children in `mask` come before child `i`
/// (`popcount(mask & ((1 << i) - 1))`, a table lookup where the CPU has no popcount).
const INNER_BEFORE: [[u8; 8]; 256] = {
    let mut table = [[0u8; 8]; 256];
    let mut mask = 0;
    while mask < 256 {
        let mut i = 1;
        while i < 8 {
            table[mask][i] = table[mask][i - 1] + ((mask >> (i - 1)) & 1) as u8;
            i += 1;
        }
        mask += 1;
    }
    table
};

/// The face through which the walk entered a node at time `t`, given the mid-plane
/// times of the inner nodes on its path from the root, the root's entry time `ta`
/// and entered face `root_face`: the lowest axis of a mid plane on the path crossed
/// at `t`, or of the root's entry plane when `t == ta`.
///
/// This is the rule "the lowest axis among the planes crossed at once" restricted to
/// the planes the walk meets: a node entered at `t > ta` lies in an ancestor `Q`
/// entered before `t`, whose mid planes crossed at `t` are the crossing; no node
/// above `Q` has a mid plane at `t` (the child of such a node would be entered at
/// `t`, and `Q` inside it), and the nodes below `Q` are entered at `t` through it, so
/// their mid planes at `t` are entered at once too.
///
/// Always inlined: left as a call (as the compiler chose at 32c1845), the AVX2 store
/// of each frame's mid-plane times in its iterator becomes a call too, 9% of a
/// Whitted render.
#[inline(always)]
fn entered_face(path: impl Iterator<Item = [f64; 3]>, t: f64, ta: f64, root_face: Option<usize>) -> Option<usize> {
    let mut face = if t == ta { root_face } else { None };
    for tm in path {
        let limit = face.unwrap_or(3);
        if let Some(a) = (0..limit).find(|&a| tm[a] == t) {
            face = Some(a);
        }
    }
    face
}

#[cfg(test)]
pub(super) mod tests {
    use glam::DVec3;

    use super::*;
    use crate::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
    use crate::samples;
    use crate::test_util::Rng;

    /// Rays of every kind in world units of `domain`: through the box from outside,
    /// from inside, axis-parallel on and off the lattice, diagonals through lattice
    /// corners, grazing, and segments ending inside.
    pub(in crate::render::trace) fn rays(rng: &mut Rng, domain: &Domain, count: usize) -> Vec<Ray> {
        let (min, edge, h) = (domain.min(), domain.edge(), domain.voxel_size());
        let n = f64::from(domain.resolution());
        let lattice = |rng: &mut Rng| DVec3::new(rng.range(0.0, n), rng.range(0.0, n), rng.range(0.0, n)).floor();
        (0..count)
            .map(|i| {
                let (o, d) = match i % 6 {
                    0 => {
                        let o = DVec3::new(rng.range(-0.5, 1.5), rng.range(-0.5, 1.5), rng.range(-0.5, 1.5)) * n;
                        (o, DVec3::new(rng.unit(), rng.unit(), rng.unit()) * n - o)
                    }
                    1 => (
                        DVec3::new(rng.unit(), rng.unit(), rng.unit()) * n,
                        DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
                    ),
                    2 => {
                        let mut d = DVec3::ZERO;
                        d[i % 3] = if rng.next().is_multiple_of(2) { 1.0 } else { -1.0 };
                        (lattice(rng) + DVec3::splat(if rng.next().is_multiple_of(2) { 0.5 } else { 0.0 }), d)
                    }
                    3 => {
                        let d = DVec3::new(
                            1.0,
                            if rng.next().is_multiple_of(2) { 1.0 } else { -1.0 },
                            if rng.next().is_multiple_of(3) { 0.0 } else { -1.0 },
                        );
                        (lattice(rng) - d * (n + 2.0), d)
                    }
                    4 => {
                        let mut d = DVec3::new(rng.range(-1e-3, 1e-3), rng.range(-1e-3, 1e-3), rng.range(-1e-3, 1e-3));
                        d[i % 3] = 1.0;
                        let mut o = DVec3::new(rng.unit(), rng.unit(), rng.unit()) * n;
                        o[i % 3] = -1.0;
                        (o, d)
                    }
                    _ => (lattice(rng), DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), 0.5)),
                };
                let ray = Ray::new(min + o * h, d);
                if i % 7 == 0 { ray.until(rng.range(0.0, 2.0) * edge) } else { ray }
            })
            .collect()
    }

    /// The solids every build of a walk is checked on (`every_build_matches_the_scalar_walk`
    /// here and in `tree64`): the showcase at depths 1, 2, 5 and 6 (even and odd), 400
    /// random voxels at depth 7 in a domain off the origin, and that domain full.
    pub(in crate::render::trace) fn isa_trees(rng: &mut Rng) -> Vec<LinearOctree> {
        let mut trees = Vec::new();
        for depth in [1, 2, 5, 6] {
            let d = samples::showcase_domain(depth).unwrap();
            trees.push(voxelize(&samples::showcase(), d, &VoxelizeOptions::default()).unwrap());
        }
        let d = Domain::new(DVec3::new(-0.3, 0.2, 0.1), 1.7, 7).unwrap();
        let voxels: Vec<[u32; 3]> = (0..400).map(|_| [0; 3].map(|_| (rng.next() % 128) as u32)).collect();
        trees.push(LinearOctree::from_voxels(d, voxels).unwrap());
        trees.push(LinearOctree::full(d));
        trees
    }

    /// Every build of the walk (AVX2, SSE2 where the CPU has them) gives the scalar
    /// build's hits, bit for bit, and the same any-hit answers.
    #[test]
    fn every_build_matches_the_scalar_walk() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for tree in &isa_trees(&mut rng) {
            let mut scalar = Traversal::new(tree);
            scalar.isa = Isa::Scalar;
            for isa in Isa::available() {
                let mut t = Traversal::new(tree);
                t.isa = isa;
                for ray in rays(&mut rng, tree.domain(), 3000) {
                    assert_eq!(t.hit(&ray), scalar.hit(&ray), "{isa:?} {ray:?}");
                    assert_eq!(t.occluded(&ray), scalar.occluded(&ray), "{isa:?} {ray:?}");
                }
            }
        }
    }
}
