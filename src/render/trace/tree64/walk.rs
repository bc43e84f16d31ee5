//! The exact first-hit walk through a [`Tree64`]: the traversal octree's walk
//! (`super::super::walk`) with the same hits, bit for bit, over 4x4x4 nodes.
//!
//! The walk (after dubiousconst282's 64-tree study and Amanatides and Woo's
//! 3D DDA, 1987): the ray is mirrored into the octant of positive directions, so that
//! in every node it only moves to higher cells; at each level it keeps its cell in the
//! mirrored lattice of that level's children and the time `tn[a]` it crosses the
//! cell's far plane on each axis. A step takes the least `tn` and moves every axis
//! whose `tn` is that time (edges and corners step together). Empty steps coalesce
//! off the masks: the ray in a node's child of mirrored coordinates `q` only reaches
//! the children at or past `q` on every axis (`Mirrored::ahead`, three table masks
//! ANDed), and of those only the ones its line can touch (`line_children`: per pair of
//! axes, the staircase of cells between its crossings of the two axes' inner planes,
//! worked out once a node is entered from the plane times the descent computes and
//! kept beside the node on the stack); when none of them is present the node is left
//! at once, taken as an empty cell of its parent (and so on up: to the deepest
//! ancestor with a present child on the line ahead of the one the ray is in, known
//! when the walk went down through it and kept as one bit a level, so found with one
//! leading-zero count), the exit time and
//! cell of stepping through it cell by cell (the cells skipped are empty, the planes
//! crossed the same); and an empty child whose 2x2x2 group holds no present child the
//! line touches is left at the group's far planes in one step. Leaving a node is found from the cells alone: the
//! highest bit of
//! `old ^ new` over the stepped axes says how many levels up the new cell's node is
//! (two bits a level), and the walk re-enters that ancestor off its stack (one
//! leading-zero count, no pop loop). A present child is the hit when full (at any
//! level: so a shadow ray ends on the largest full node it meets) or is entered.
//!
//! Lanes (`lanes`, as the octree's walk): the three axes' plane times are one lane
//! operation, `(p - o) * inv`, in the build `lanes::Isa::detect` picks (AVX2, SSE2,
//! scalar; the same bits). The cell's far planes `p` are kept as f64 in the original
//! frame, exact integers below `2^53`: a step adds the signed child edge in the lanes
//! that move, a descent takes the parent's far plane less 3, 2, 1 child edges, so no
//! integer is converted a step (only on re-entering an ancestor). The integer cell
//! (for the masks and `old ^ new`) follows from the lanes' compare bits, kept as one
//! word of a 16-bit field an axis (`Cell`): a descent or a step moves the three axes
//! with one add of the compare bits spread to the fields (`SPREAD`), and the child,
//! its 2x2x2 group and the children ahead of it are table rows of the child's index.
//! The ray's setup (its mirroring here, the root's and the full voxels' box's near
//! planes in `super::super::walk`) picks per axis by integer selects, not branches:
//! the signs of an incoherent ray's axes are coins to a branch predictor.
//!
//! Exactness (the rule of the traversal octree's walk, `super::super::walk`): the ray
//! is in the cell `[m, m + 1)` of an axis at time `t` when the computed times of the
//! cell's near and far planes satisfy `near <= t < far`, every plane's time is `(plane
//! - o) * inv` in the original frame (mirroring computes the plane, `E - x` for a
//! mirrored axis with `E` the root's edge, an exact integer, never `E - o`, which would
//! round), and a plane's time is monotone in the plane. So the cell a walk places the
//! ray in at a time is the same in both trees; a descent places it by counting its
//! child's three inner planes per axis whose time `<= t` (Revelles et al., 2000); the
//! first time the ray is in a full cell is a plane time both walks visit; and the
//! entered face (the lowest axis of a plane crossed at that time, or of the root's
//! entry plane when it is the root's entry time) is the lowest axis whose near plane
//! of the hit cell is crossed then (a nearer plane crossed at that time would put
//! that plane's time at it too, by monotony). Rays with infinite reciprocals are moved
//! off the lattice as in the octree's walk (`Lattice`). Where the hit node is finer
//! than the octree's (a full octree node at an odd level is 8 cells here), the voxel
//! and face worked out by `VoxelRay::entry` are the same: both follow plane times.
//!
//! Departure, tested: where the direction is subnormal on an axis (its reciprocal is
//! infinite), both walks keep the ray on the low side of a plane through its origin
//! (`off_lattice`), while `VoxelRay::entry` places the hit's voxel by the position,
//! clamped to the full node entered; when the octree's full node spans that plane and
//! the 64-tree's cell does not (an octree node at an odd level is 8 cells here), the
//! voxel differs on that axis by one (the time and face do not).
//!
//! Departure: two consecutive planes whose times round to the same value are crossed
//! in two steps here, in one by the octree's counting; that needs an origin more than
//! 2^50 voxels from the planes, which no ray the reach test lets through has.
//!
//! Measured and not kept (benchmark log, "descents off the ray's voxel"): the descent
//! of dubiousconst282's walk, the cell at every level below read off one integer voxel
//! (the mirrored position rounded down, checked by its near and far plane times,
//! placed by bisection where the check fails: the same hits), so going down several
//! levels costs no plane times. Without the line mask (which needs the inner plane
//! times) 4-7% fewer instructions on bounce and shadow rays but 16-26% more
//! mispredicts (primary rays: 3% more instructions, two thirds more mispredicts), 4-13% slower on
//! bounce, far-light shadow and primary rays, even on shadow rays to a near light;
//! with the line mask worked out for the node a descent ends in, 2-3% more
//! instructions, as many or more mispredicts and 14-27% slower (each descent waits on
//! the voxel's placement, a chain of rounding, conversion and two plane-time checks).

use std::mem::MaybeUninit;

use super::{LEVELS, Node64, Tree64, UPPER_WORDS};
use crate::ray::{Ray, RayCast};
#[cfg(target_arch = "x86_64")]
use crate::render::trace::lanes::{Avx2, Sse2};
use crate::render::trace::lanes::{Isa, Lanes, Scalar};
use crate::render::trace::voxel_ray::{Entry, Hit, VoxelRay};
use crate::render::trace::walk::{Lattice, Opening, RootSpan, pick};

/// The walk through a 64-tree: the first full voxel a world-space ray enters, the
/// same hit as [`super::super::Traversal`]'s walk.
impl RayCast for Tree64 {
    type Hit = Hit;

    fn hit(&self, ray: &Ray) -> Option<Hit> {
        if !self.outline.reach.may_meet(ray) {
            return None;
        }
        let r = VoxelRay::new(&self.outline.domain, ray);
        Some(r.entry(&self.first_full::<true>(&r, ray.t_max)?))
    }

    /// The walk of [`RayCast::hit`] without working out the voxel and face.
    #[inline(always)]
    fn occluded(&self, ray: &Ray) -> bool {
        if !self.outline.reach.may_meet(ray) {
            return false;
        }
        let r = VoxelRay::new(&self.outline.domain, ray);
        self.first_full::<false>(&r, ray.t_max).is_some()
    }
}

/// The ray's cell on the three axes in one word, axis `a` in bits `FIELD a` up (the
/// cells of a level are below `4^6 + 2`, so no field carries into the next): a
/// descent, a step and the test of which node holds the new cell are a few integer
/// operations on all three axes at once.
type Cell = u64;

/// Bits of an axis' field in a `Cell`.
const FIELD: usize = 16;

/// 1 in every field of a `Cell`.
const ONES: Cell = 1 | 1 << FIELD | 1 << (2 * FIELD);

/// Axis `a`'s coordinate in `cell`.
#[inline(always)]
fn axis(cell: Cell, a: usize) -> u32 {
    (cell >> (FIELD * a)) as u32 & 0xffff
}

/// `cell` on the level `up` levels above (each field shifted down by two bits a level).
#[inline(always)]
fn ascend(cell: Cell, up: u32) -> Cell {
    (cell >> (2 * up)) & (ONES * (0xffff >> (2 * up)))
}

/// The ray as the walk reads it: origin and reciprocal direction in voxel units (off
/// the lattice where the reciprocal is infinite), and per axis the map from a mirrored
/// coordinate `q` to the plane `q ^ flip + add` (wrapping): `q`, or `E - q` mirrored.
struct Mirrored {
    o: [f64; 3],
    inv: [f64; 3],
    flip: [u32; 3],
    add: [u32; 3],
    /// 3 in the fields (`Cell`) of mirrored axes: a mirrored child coordinate `c` is
    /// `c ^ 3` in the node.
    child_flip: Cell,
    /// `ahead[i]`: the children whose mirrored coordinates are at least child `i`'s on
    /// every axis (the ray in child `i` only ever reaches these children of the node):
    /// `AHEAD` for this ray's mirroring.
    ahead: &'static [u64; 64],
    /// `line[a]`: the children the ray's line can touch, by the pair of axes `a`, `a + 1`
    /// (`LINE`, for this ray's mirroring of the two axes).
    line: [&'static [u64; 64]; 3],
}

impl Mirrored {
    /// Without a branch on the mirrored axes (a coin per axis for incoherent rays):
    /// the per-axis values are masks and table rows of the axis' mirror bit.
    fn new(ray: &Lattice, edge: u32) -> Self {
        let bit = |a: usize| (ray.mirror >> a & 1) as u32;
        // All ones on a mirrored axis.
        let flip: [u32; 3] = std::array::from_fn(|a| bit(a).wrapping_neg());
        // The walk never crosses the root's far planes (it ends at the root's exit),
        // but it would take one whose time is before the origin's as crossed: the
        // plane 0 under a ray running down from it with a subnormal direction (moved
        // off the lattice to -0.5, where the octree's walk, counting mid planes only,
        // keeps it in cell 0). Moved to 0.5, it crosses no plane and stays there.
        let o = std::array::from_fn(|a| pick((bit(a) == 1) & (ray.o[a] < 0.0), 0.5, ray.o[a]));
        Mirrored {
            o,
            inv: ray.inv,
            flip,
            add: flip.map(|f| edge.wrapping_add(1) & f),
            child_flip: (0..3).fold(0, |f, a| f | u64::from(3 * bit(a)) << (FIELD * a)),
            ahead: &AHEAD[ray.mirror & 7],
            line: std::array::from_fn(|a| &LINE[a][(bit(a) + 2 * bit((a + 1) % 3)) as usize]),
        }
    }

    /// The child (`x + 4 y + 16 z`, original frame) of the node the ray is in at its
    /// mirrored cell `cell` (the low two bits of each field).
    #[inline(always)]
    fn child(&self, cell: Cell) -> usize {
        let q = (cell ^ self.child_flip) & (3 * ONES);
        (q | q >> (FIELD - 2) | q >> (2 * FIELD - 4)) as usize & 63
    }

    /// The plane at mirrored coordinate `q` (voxels) on axis `a`, in the original frame.
    #[inline(always)]
    fn plane(&self, a: usize, q: u32) -> u32 {
        (q ^ self.flip[a]).wrapping_add(self.add[a])
    }

    /// The time the ray crosses the plane at mirrored coordinate `q` on axis `a`.
    #[inline(always)]
    fn time(&self, a: usize, q: u32) -> f64 {
        (f64::from(self.plane(a, q)) - self.o[a]) * self.inv[a]
    }
}

/// The ray in lanes (`lanes`), as the step reads it: origin and reciprocal direction
/// (the idle AVX2 lane at `-inf` and `+inf`: its times are `+inf`, never crossed), and
/// the sign of a mirrored coordinate's step in the original frame (-1 on mirrored axes).
#[derive(Clone, Copy)]
struct RayLanes<L> {
    o: L,
    inv: L,
    sign: L,
}

impl<L: Lanes> RayLanes<L> {
    #[inline(always)]
    fn new(m: &Mirrored) -> Self {
        RayLanes {
            o: L::new(m.o, f64::NEG_INFINITY),
            inv: L::new(m.inv, f64::INFINITY),
            sign: L::new(std::array::from_fn(|a| if m.flip[a] == 0 { 1.0 } else { -1.0 }), 1.0),
        }
    }

    /// The times the ray crosses the planes `p` (original frame, exact integers).
    #[inline(always)]
    fn time(&self, p: L) -> L {
        p.sub(self.o).mul(self.inv)
    }
}

/// `AHEAD[f][i]`: the children `j` (`x + 4 y + 16 z`) of a node at or past child `i`
/// on every axis in mirrored coordinates (`c ^ 3` on the axes `a` of bit `a` of `f`).
const AHEAD: [[u64; 64]; 8] = {
    let mut masks = [[0u64; 64]; 8];
    let mut f = 0;
    while f < 8 {
        let mut i = 0;
        while i < 64 {
            let mut j = 0;
            while j < 64 {
                let mut ahead = true;
                let mut a = 0;
                while a < 3 {
                    let flip = if f >> a & 1 == 1 { 3 } else { 0 };
                    ahead &= (j >> (2 * a) & 3) ^ flip >= (i >> (2 * a) & 3) ^ flip;
                    a += 1;
                }
                if ahead {
                    masks[f][i] |= 1 << j;
                }
                j += 1;
            }
            i += 1;
        }
        f += 1;
    }
    masks
};

/// `LINE[a][f][c1 + 4 c2 + 16 c3]`: the children `x + 4 y + 16 z` of a node that a line
/// can touch whose cell on axis `b = a + 1 (mod 3)` is `ck` where it crosses axis `a`'s
/// inner plane `k` (`k` in `1..4`; coordinates mirrored on axis `a` when bit 0 of `f`
/// is set, on `b` when bit 1 is): in the slab `i` of axis `a` (`i` in `0..4`), the
/// cells `c_i..=c_{i+1}` of axis `b`, with `c_0 = 0` and `c_4 = 3`. A tuple that is not
/// non-decreasing (no line has one) gets every child.
const LINE: [[[u64; 64]; 4]; 3] = {
    let mut masks = [[[0u64; 64]; 4]; 3];
    let mut a = 0;
    while a < 3 {
        let b = (a + 1) % 3;
        let mut f = 0;
        while f < 4 {
            let mut idx = 0;
            while idx < 64 {
                let c = [0, idx & 3, idx >> 2 & 3, idx >> 4, 3];
                let monotone = c[1] <= c[2] && c[2] <= c[3];
                let mut child = 0;
                while child < 64 {
                    let ca = (child >> (2 * a) & 3) ^ if f & 1 == 1 { 3 } else { 0 };
                    let cb = (child >> (2 * b) & 3) ^ if f & 2 == 2 { 3 } else { 0 };
                    if !monotone || (c[ca] <= cb && cb <= c[ca + 1]) {
                        masks[a][f][idx] |= 1 << child;
                    }
                    child += 1;
                }
                idx += 1;
            }
            f += 1;
        }
        a += 1;
    }
    masks
};

/// `GROUP_OF[i]`: the cells of child `i`'s 2x2x2 group.
const GROUP_OF: [u64; 64] = {
    let mut masks = [0u64; 64];
    let mut i = 0;
    while i < 64 {
        let mut j = 0;
        while j < 64 {
            if (i ^ j) & 0b10_1010 == 0 {
                masks[i] |= 1 << j;
            }
            j += 1;
        }
        i += 1;
    }
    masks
};

/// `SPREAD[b]`: bit `a` of `b` moved to the low bit of axis `a`'s field (`Cell`).
const SPREAD: [Cell; 8] = {
    let mut spread = [0; 8];
    let mut b = 0;
    while b < 8 {
        spread[b] = (b as u64 & 1) | (b as u64 & 2) << (FIELD - 1) | (b as u64 & 4) << (2 * FIELD - 2);
        b += 1;
    }
    spread
};

/// `SKIP[s]`: all ones in the lanes of the axes set in `s` (bit `a`), zero elsewhere.
const SKIP: [[f64; 3]; 8] = {
    let mut masks = [[0.0; 3]; 8];
    let mut s = 0;
    while s < 8 {
        let mut a = 0;
        while a < 3 {
            if s >> a & 1 == 1 {
                masks[s][a] = f64::from_bits(u64::MAX);
            }
            a += 1;
        }
        s += 1;
    }
    masks
};

impl Tree64 {
    /// The first full node the ray enters before `t_max` (see `Traversal::first_full`):
    /// `FACE` false skips the entered face, for any-hit queries.
    fn first_full<const FACE: bool>(&self, r: &VoxelRay, t_max: f64) -> Option<Entry> {
        let Opening { span, t_max, enter } = match self.outline.opening(r, t_max, 0.0) {
            Ok(opening) => opening,
            Err(full) => {
                let n = self.outline.domain.resolution();
                return full.map(|RootSpan { ta, face, .. }| Entry { min: [0, 0, 0], size: n, t: ta, face });
            }
        };
        let start = 0.0f64.max(enter);
        let ray = Lattice::new(r);
        match self.isa {
            #[cfg(target_arch = "x86_64")]
            // SAFETY: `Isa::Avx2` is only chosen where the CPU has AVX2.
            Isa::Avx2 => unsafe { self.walk_avx2::<FACE>(&ray, t_max, span, start) },
            #[cfg(target_arch = "x86_64")]
            Isa::Sse2 => self.walk::<Sse2, FACE>(&ray, t_max, span, start),
            _ => self.walk::<Scalar, FACE>(&ray, t_max, span, start),
        }
    }

    /// [`Tree64::walk`] compiled with AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn walk_avx2<const FACE: bool>(&self, ray: &Lattice, t_max: f64, span: RootSpan, start: f64) -> Option<Entry> {
        self.walk::<Avx2, FACE>(ray, t_max, span, start)
    }

    /// The walk from the root at `max(ta, start)` (see the module doc), its plane
    /// times three axes at once in lanes `L`.
    #[inline(always)]
    fn walk<L: Lanes, const FACE: bool>(&self, ray: &Lattice, t_max: f64, span: RootSpan, start: f64) -> Option<Entry> {
        let edge = 1u32 << (2 * self.levels);
        let m = Mirrored::new(ray, edge);
        // No hit at or after the ray's limit or the root's exit.
        let limit = if t_max < span.tb { t_max } else { span.tb };
        let mut t = span.ta.max(start);
        if t >= limit {
            return None;
        }
        let lanes = RayLanes::<L>::new(&m);
        // The nodes above the current one, root first (left uninitialized until written).
        // Each beside the children of it the ray's line can touch (`line_children`).
        let mut stack = [const { MaybeUninit::<(Node64, u64)>::uninit() }; LEVELS];
        let mut level = 0usize;
        // Bit `j`: the node at level `j` above has a present child on the ray's line
        // ahead of the child the ray is in (written on the way down; the bits from
        // `level` on are stale).
        let mut alive = 0u32;
        // The lowest level, whose nodes are one word (see `Tree64`).
        let bottom = self.levels as usize - 1;
        let mut node = self.node(self.root, usize::from(bottom > 0));
        // log2 of the current level's child edge, the ray's cell there (mirrored, in
        // units of that edge), the cell's far planes (original frame, f64), their
        // times, and the child edge in lanes, signed as the mirrored coordinate runs.
        let mut shift = 2 * self.levels - 2;
        let mut cell: Cell = 0;
        let mut pn = L::new(std::array::from_fn(|a| f64::from(m.plane(a, edge))), 0.0);
        let mut tn = lanes.time(pn);
        let mut step = lanes.sign.mul(L::splat(f64::from(1u32 << shift)));
        let mut line = descend(&lanes, &m, &mut cell, &mut pn, &mut tn, step, t);
        loop {
            let mut child = m.child(cell);
            if node.present >> child & 1 == 1 {
                if node.full >> child & 1 == 1 {
                    return Some(hit::<FACE>(&m, cell, shift, t, span));
                }
                // Whether the ray, once it leaves this child, has a present child of
                // this node on its line ahead (the node exit's mask, this child out): the
                // node's cell stays this child until then, so the answer is known now.
                let more = node.present & line & m.ahead[child] & !(1u64 << child) != 0;
                alive = (alive & !(1 << level)) | u32::from(more) << level;
                stack[level].write((node, line));
                level += 1;
                let inner = node.present & !node.full;
                let upper = usize::from(level < bottom);
                let before = (inner & ((1u64 << child) - 1)).count_ones() as usize;
                node = self.node(node.first + before * (1 + (UPPER_WORDS - 1) * upper), upper);
                shift -= 2;
                step = step.mul(L::splat(0.25));
                line = descend(&lanes, &m, &mut cell, &mut pn, &mut tn, step, t);
                continue;
            }
            // An empty child. When no child the ray can still reach in this node is
            // present, the node is left at once: it is taken as an empty cell of its
            // parent, and so on up (the same exit time and cell as stepping through it).
            // The ancestor left to is the deepest one with a present child ahead, the
            // highest bit of `alive` below this level (none: the ray leaves the root).
            if node.present & line & m.ahead[child] == 0 {
                let below = alive & ((1u32 << level) - 1);
                if below == 0 {
                    return None;
                }
                let up = level - (31 - below.leading_zeros()) as usize;
                level -= up;
                // SAFETY: the nodes `0..level` above were written on the way down.
                (node, line) = unsafe { stack[level].assume_init() };
                shift += 2 * up as u32;
                cell = ascend(cell, up as u32);
                child = m.child(cell);
                pn = L::new(std::array::from_fn(|a| f64::from(m.plane(a, (axis(cell, a) + 1) << shift))), 0.0);
                tn = lanes.time(pn);
                step = lanes.sign.mul(L::splat(f64::from(1u32 << shift)));
            }
            // Step to the cell's far planes, or to its group's when no present child of
            // its 2x2x2 group is on the ray's line (`skip` on the axes where the cell is
            // the group's near one), without a branch on the axes that move.
            let empty_group = node.present & line & GROUP_OF[child] == 0;
            let low = !cell & ONES;
            let even = (low | low >> (FIELD - 1) | low >> (2 * FIELD - 2)) as usize & 7;
            let skip = L::new(SKIP[even & usize::from(empty_group).wrapping_neg()], 0.0);
            let tt = lanes.time(pn.add(skip.and(step)));
            t = tt.min3();
            if t >= limit {
                return None;
            }
            // Past the target plane (the cell's or the group's far plane), or only
            // past the group's mid plane.
            let at = L::splat(t);
            let (mid, past) = (tn.le(at), tt.le(at).and(skip));
            let old = cell;
            cell += SPREAD[mid.bits() & 7] + SPREAD[past.bits() & 7];
            pn = pn.add(mid.and(step)).add(past.and(step));
            tn = lanes.time(pn);
            let changed = old ^ cell;
            let moved = (changed | changed >> FIELD | changed >> (2 * FIELD)) as u32 & 0xffff;
            if moved >= 4 {
                // The new cell is in another node: the ancestor `up` levels above holds it.
                let up = ((31 - moved.leading_zeros()) / 2) as usize;
                if up > level {
                    return None;
                }
                level -= up;
                // SAFETY: the nodes `0..level` above were written on the way down.
                (node, line) = unsafe { stack[level].assume_init() };
                shift += 2 * up as u32;
                cell = ascend(cell, up as u32);
                pn = L::new(std::array::from_fn(|a| f64::from(m.plane(a, (axis(cell, a) + 1) << shift))), 0.0);
                tn = lanes.time(pn);
                step = lanes.sign.mul(L::splat(f64::from(1u32 << shift)));
            }
        }
    }
}

/// Places the ray at time `t` in the node at the current cell, whose far planes are
/// `pn` at times `tn` (bits as carried down): the child cell per axis is the count of
/// the node's three inner planes crossed by `t` (`step` apart, signed: the child edge),
/// and `pn`, `tn` become that child's far planes and their times (the node's far plane
/// keeps its time, the same bits). Returns the children of the node the ray's line can
/// touch (`line_children`).
#[inline(always)]
fn descend<L: Lanes>(
    lanes: &RayLanes<L>,
    m: &Mirrored,
    cell: &mut Cell,
    pn: &mut L,
    tn: &mut L,
    step: L,
    t: f64,
) -> u64 {
    let p1 = pn.sub(step.mul(L::splat(3.0)));
    let p2 = p1.add(step);
    let p3 = p2.add(step);
    let (t1, t2, t3) = (lanes.time(p1), lanes.time(p2), lanes.time(p3));
    let at = L::splat(t);
    let (m1, m2, m3) = (t1.le(at), t2.le(at), t3.le(at));
    *cell = *cell * 4 + SPREAD[m1.bits() & 7] + SPREAD[m2.bits() & 7] + SPREAD[m3.bits() & 7];
    // The times are monotone in the plane, so the crossed planes are the first ones.
    *tn = L::select(m1, L::select(m2, L::select(m3, *tn, t3), t2), t1);
    *pn = L::select(m1, L::select(m2, L::select(m3, *pn, p3), p2), p1);
    line_children(m, [t1, t2, t3])
}

/// The children of a node the ray's line can touch, from the times `t[k - 1]` it
/// crosses the node's inner planes `k` (mirrored order; lane `a`: axis `a`): a superset
/// of the cells it passes through, so a child outside it is never visited. A cell is
/// passed through when its three time spans `[near, far)` meet, that is when they meet
/// two by two (intervals on a line: Helly); per pair of axes `a`, `b = a + 1` that is
/// the staircase `LINE[a]` of the cell on `b` at each crossing of `a`'s inner planes,
/// `ck = #{j : t_b,j <= t_a,k}` (counted with `<=`, so a tie keeps both cells: the
/// superset). The three counts per pair are taken in lanes, `a` in lane `a`, against
/// the times turned one lane (`Lanes::rotate`), as one weighted sum `c1 + 4 c2 + 16 c3`.
/// Every lane operation is exact (small integers), so every build gives the same mask.
#[inline(always)]
fn line_children<L: Lanes>(m: &Mirrored, t: [L; 3]) -> u64 {
    let turned = t.map(Lanes::rotate);
    // Started at 2^52, so the sum's low mantissa bits are the index (no conversion).
    let mut sum = L::splat(4_503_599_627_370_496.0);
    for (tk, weight) in t.into_iter().zip([1.0, 4.0, 16.0]) {
        let w = L::splat(weight);
        for tj in turned {
            sum = sum.add(tj.le(tk).and(w));
        }
    }
    let i = sum.to_array().map(|x| x.to_bits() as usize & 63);
    m.line[0][i[0]] & m.line[1][i[1]] & m.line[2][i[2]]
}

/// The hit on entering the full cell `cell` (mirrored, edge `1 << shift`) at `t`: its
/// corner in the original frame, and the entered face when `FACE` (see the module doc).
#[inline(always)]
fn hit<const FACE: bool>(m: &Mirrored, cell: Cell, shift: u32, t: f64, span: RootSpan) -> Entry {
    let cell: [u32; 3] = std::array::from_fn(|a| axis(cell, a));
    let size = 1u32 << shift;
    let min =
        std::array::from_fn(|a| if m.flip[a] == 0 { cell[a] << shift } else { m.plane(a, (cell[a] + 1) << shift) });
    let face = if FACE {
        let near = (0..3).find(|&a| m.time(a, cell[a] << shift) == t);
        let root = if t == span.ta { span.face } else { None };
        match (near, root) {
            (Some(x), Some(y)) => Some(x.min(y)),
            (x, y) => x.or(y),
        }
    } else {
        None
    };
    Entry { min, size, t, face }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::trace::walk::tests::{isa_trees, rays};
    use crate::test_util::Rng;

    /// Every build of the 64-tree's walk (AVX2, SSE2 where the CPU has them) gives the
    /// scalar build's hits, bit for bit, and the same any-hit answers, at even and odd
    /// depths, on the octree walk's solids (the tests in `tests/traverse.rs` run the
    /// detected build only).
    #[test]
    fn every_build_matches_the_scalar_walk() {
        let mut rng = Rng(0x2545_f491_4f6c_dd1d);
        for tree in &isa_trees(&mut rng) {
            let mut scalar = Tree64::new(tree);
            scalar.isa = Isa::Scalar;
            for isa in Isa::available() {
                let mut t = Tree64::new(tree);
                t.isa = isa;
                for ray in rays(&mut rng, tree.domain(), 3000) {
                    assert_eq!(t.hit(&ray), scalar.hit(&ray), "{isa:?} {ray:?}");
                    assert_eq!(t.occluded(&ray), scalar.occluded(&ray), "{isa:?} {ray:?}");
                }
            }
        }
    }
}
