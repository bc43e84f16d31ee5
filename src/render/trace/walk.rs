//! The exact first-hit walk through a [`Traversal`], skipping empty space at every
//! level.
//!
//! The walk (after Revelles et al., "An efficient parametric algorithm for octree
//! traversal", 2000): a node's interval `[ta, tb]` along the ray is cut at the times the
//! ray crosses its three mid planes; each non-empty piece is one child, visited in ray
//! order; full children end the walk, empty ones are skipped, inner ones are entered.
//! The walk is one loop with an explicit stack of the inner nodes above (their index,
//! mid-plane times and exit time), not recursion; the child at time `t` is read off
//! the mid-plane times (`tm <= t`, three lanes at once: `PlaneTimes`), so going back up
//! needs no saved child state.
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

use super::plane_times::{PlaneTimes, earlier};
use super::traversal::{Root, Traversal};
use super::voxel_ray::{Entry, Hit, VoxelRay};
use crate::octree::MAX_DEPTH;
use crate::ray::{Ray, RayCast};

/// The walk through a traversal octree: the first full voxel a world-space ray
/// enters (`t` in the ray's own parameter: world units when `dir` is a unit vector).
impl RayCast for Traversal {
    type Hit = Hit;

    fn hit(&self, ray: &Ray) -> Option<Hit> {
        let r = VoxelRay::new(&self.domain, ray);
        Some(r.entry(&self.first_full(&r, ray.t_max)?))
    }

    /// The walk of [`RayCast::hit`] without working out the voxel and face.
    fn occluded(&self, ray: &Ray) -> bool {
        let r = VoxelRay::new(&self.domain, ray);
        self.first_full(&r, ray.t_max).is_some()
    }
}

impl Traversal {
    /// [`RayCast::hit`] of a ray already in voxel units of the domain.
    #[must_use]
    pub fn hit_voxel_units(&self, ray: &Ray) -> Option<Hit> {
        let r = VoxelRay::in_voxel_units(ray);
        Some(r.entry(&self.first_full(&r, ray.t_max)?))
    }

    /// The first full node the ray enters before `t_max`: its corner, size, entry time
    /// and entered face (what [`VoxelRay::entry`] turns into a hit). A ray with a
    /// non-finite origin or direction hits nothing.
    fn first_full(&self, r: &VoxelRay, t_max: f64) -> Option<Entry> {
        self.first_full_after(r, t_max, 0.0, Subtree::ROOT)
    }

    /// [`Traversal::first_full`] with the walk started at `max(entry, start)` instead of
    /// `max(entry, 0)`, for a `start >= 0` at or before the ray's first hit (a beam's
    /// lower bound): the pieces skipped are empty, so the result is the same. When the
    /// ray enters the root by `start`, the walk begins in `from`, which must hold the
    /// ray at time `start` as the walk places it (see [`Subtree`]).
    pub(super) fn first_full_after(&self, r: &VoxelRay, t_max: f64, start: f64, from: Subtree) -> Option<Entry> {
        if self.root == Root::Empty || !(r.o.is_finite() && r.d.is_finite()) {
            return None;
        }
        let span = self.root_span(r)?;
        let RootSpan { ta, tb, face } = span;
        // The walk starts at max(ta, start) (start >= 0), which must be before tb.
        if ta >= tb || tb <= start || ta >= t_max {
            return None;
        }
        if self.root == Root::Full {
            let n = self.domain.resolution();
            return (ta.max(0.0) < t_max).then_some(Entry { min: [0, 0, 0], size: n, t: ta, face });
        }
        // Two builds of the walk: the one from the root (single rays) carries no
        // subtree logic.
        if from.above.is_empty() || ta > start {
            self.walk::<false>(r, t_max, span, start, Subtree::ROOT)
        } else {
            self.walk::<true>(r, t_max, span, start, from)
        }
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
            let (near, far) = if d > 0.0 { (0.0, n) } else { (n, 0.0) };
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

/// Where a ray crosses the root: entered at `ta` through `face`, left at `tb`.
#[derive(Clone, Copy)]
struct RootSpan {
    ta: f64,
    tb: f64,
    face: Option<usize>,
}

/// The ray as the walk reads it: origin and reciprocal direction in voxel units (moved
/// off the lattice where the reciprocal is infinite, see `off_lattice`) and the mirror
/// bits (bit `a` set when the ray runs to lower coordinates on axis `a`).
struct Lattice {
    o: [f64; 3],
    inv: [f64; 3],
    mirror: usize,
}

impl Lattice {
    fn new(r: &VoxelRay) -> Self {
        let mirror = (0..3).fold(0usize, |m, a| m | usize::from(r.d[a] < 0.0) << a);
        let (mut o, mut inv) = (r.o.to_array(), r.inv.to_array());
        if !r.inv.is_finite() {
            off_lattice(r, &mut o, &mut inv);
        }
        Lattice { o, inv, mirror }
    }

    /// The times of the mid planes `min + half` of a node: `(min[a] + half - o[a]) * inv[a]`.
    #[inline(always)]
    fn mid_times(&self, min: [u32; 3], half: u32) -> PlaneTimes {
        PlaneTimes::new(std::array::from_fn(|a| (f64::from(min[a] + half) - self.o[a]) * self.inv[a]))
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

/// An inner node the walk went down from: what it needs to go on there.
#[derive(Clone, Copy)]
struct Frame {
    index: u32,
    tm: PlaneTimes,
    tb: f64,
}

impl Traversal {
    /// The walk through the inner root, entered at `ta` through `face` and left at `tb`
    /// (after Revelles et al., iterative, with an explicit stack).
    ///
    /// In an inner node `[min, min + size)` the mid-plane times `tm[a] = (min[a] +
    /// size / 2 - o[a]) * inv[a]` (`inv = 1 / d`) are computed once. At time `t` the
    /// ray is in the child whose bit `a` is high when `tm[a] <= t` (`d[a] > 0`) or
    /// `tm[a] > t` (`d[a] < 0`); that child's piece ends at the next mid-plane time
    /// `min {tm[a] : tm[a] > t}` or at the node's exit `tb`, whichever comes first, and
    /// crossings at one time are taken together (no zero-length pieces). The walk starts at `max(ta, start)`, with
    /// `0 <= start < tb`: pieces before the origin are never visited (a hit there is the
    /// origin's own voxel, whatever its entry time); nor, when `start > 0`, those before
    /// `start`.
    ///
    /// A walk begun in a node `from` below the root leaves the frames of the nodes
    /// above it empty; they are filled only if the ray leaves `from` (a node's exit
    /// time is the least time of its far planes, the same bits as the `tb` the walk
    /// from the root carries down), and the face of a hit in `from` is read off the
    /// hit node's near planes (see [`Lattice::near_face`]). `BELOW_ROOT` false builds the walk from
    /// the root alone, without that logic (single rays).
    fn walk<const BELOW_ROOT: bool>(
        &self,
        r: &VoxelRay,
        t_max: f64,
        span: RootSpan,
        start: f64,
        from: Subtree,
    ) -> Option<Entry> {
        // No mid-plane time is NaN (see `off_lattice`), so "past the mid plane" is
        // `tm <= t` on every axis and the child is those bits flipped by the mirror bits.
        let RootSpan { ta, tb, face } = span;
        let ray = Lattice::new(r);
        let mirror = ray.mirror;
        let mut stack = [Frame { index: 0, tm: PlaneTimes::new([0.0; 3]), tb: 0.0 }; STACK];
        let root_tb = tb;
        let mut t = ta.max(start);
        // Frames below `base` are not filled yet (a walk begun below the root).
        let mut base = if BELOW_ROOT { from.above.len() } else { 0 };
        let mut depth = base;
        let (mut index, mut min, mut size, mut tb) = if base == 0 {
            (0u32, [0u32; 3], self.domain.resolution(), tb)
        } else {
            if t >= t_max {
                return None;
            }
            (from.index, from.min, from.size, ray.exit_time(from.min, from.size))
        };
        let mut tm = ray.mid_times(min, size / 2);
        loop {
            let inner = self.nodes[index as usize];
            let half = size / 2;
            // Step 1: the child the ray is in just after t, and the next mid plane.
            let (past, next) = tm.split(t);
            let child = past ^ mirror;
            // Step 2: a non-empty child is the hit (full) or is walked (inner).
            if inner.valid >> child & 1 == 1 {
                if t >= t_max {
                    return None;
                }
                let cmin: [u32; 3] = std::array::from_fn(|a| min[a] + if child >> a & 1 == 1 { half } else { 0 });
                if inner.full >> child & 1 == 1 {
                    let face = if !BELOW_ROOT || base == 0 {
                        let path = stack[..depth].iter().map(|f| f.tm.to_array()).chain([tm.to_array()]);
                        entered_face(path, t, ta, face)
                    } else {
                        ray.near_face(cmin, half, t)
                    };
                    return Some(Entry { min: cmin, size: half, t, face });
                }
                stack[depth] = Frame { index, tm, tb };
                depth += 1;
                index = inner.first + u32::from(INNER_BEFORE[usize::from(inner.valid & !inner.full)][child]);
                min = cmin;
                size = half;
                tb = earlier(next, tb);
                tm = ray.mid_times(min, size / 2);
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
                    fill_frames_above(&mut stack[..base], &from, (min, size), root_tb, &ray);
                    base = 0;
                }
                depth -= 1;
                let frame = stack[depth];
                size *= 2;
                for m in &mut min {
                    *m &= !(size - 1);
                }
                (index, tm, tb) = (frame.index, frame.tm, frame.tb);
                if t < tb {
                    break;
                }
            }
        }
    }
}

/// The frames of the nodes above `from`, from the root down, for a walk that began in
/// `from` and now leaves it: each the ancestor of the node `[min, min + size)` the walk
/// is in, at its level, with its mid-plane times and exit time (the root's is `root_tb`).
#[cold]
fn fill_frames_above(stack: &mut [Frame], from: &Subtree, (min, size): ([u32; 3], u32), root_tb: f64, ray: &Lattice) {
    let base = stack.len();
    for (level, (frame, &above)) in stack.iter_mut().zip(from.above).enumerate() {
        let up = size << (base - level);
        let umin = min.map(|m| m & !(up - 1));
        let utb = if level == 0 { root_tb } else { ray.exit_time(umin, up) };
        *frame = Frame { index: above, tm: ray.mid_times(umin, up / 2), tb: utb };
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
