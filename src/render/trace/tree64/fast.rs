//! The 64-tree's walk with descents off the ray's voxel (issue 41, item 1): the walk of
//! `walk` (mirrored cells, the step to the least far-plane time, ascent by the highest
//! bit of `old ^ new`, the node exit and 2x2x2 group skip off the masks, a full child
//! ending the walk at any level), but a descent reads the ray's cell at every level
//! below off one integer voxel instead of counting each level's inner planes.
//!
//! After dubiousconst282's 64-tree study: the ray is mirrored into the octant of
//! positive directions and its position kept as integer cell coordinates, so the
//! cell at every level is the high bits of the voxel (`v >> shift`): going down any
//! number of levels is a mask test, a popcount and a load a level, no plane time.
//!
//! Exactness (the rule of `walk` and the octree's walk): the ray at time `t` is in the
//! cell whose near plane's computed time is `<= t` and whose far plane's is `> t`, on
//! every axis. The voxel is first guessed from the position, `o + |d| t` in the
//! mirrored frame, rounded down (off by one at most near a plane) and clamped to the
//! cell the walk has placed the ray in by plane times (exact); then checked by the
//! times of its near and far planes (two lane operations), and where the check fails
//! (a position within rounding of a plane: rare) placed by bisection on the plane
//! times within the cell (the times are monotone in the plane). A cell holding a
//! voxel placed so holds the ray by the same rule at every level, so every descent
//! lands where the counting descent of `walk` lands, every step is the same, and the
//! hit (time, voxel, face) is the same bit for bit. Steps keep the cell's far planes
//! and times in lanes as `walk` does; after a descent they are read off the voxel.
//!
//! Departure from `walk`: no line mask (`line_children` needs the inner plane times
//! a descent no longer computes), so the node exit and group skip test the box ahead
//! of the ray's cell only.

use std::mem::MaybeUninit;

use super::walk::{GROUP_CELLS, LEVELS, Mirrored, RayLanes, SKIP, hit};
use super::{Node64, Tree64};
use crate::render::trace::lanes::Lanes;
use crate::render::trace::voxel_ray::Entry;
use crate::render::trace::walk::{Lattice, RootSpan};

/// `1.5 * 2^52`: a double between `-2^51` and `2^51` added to it is rounded to an
/// integer, the low 32 bits of the sum's representation being that integer (two's
/// complement).
const ROUND: f64 = 6_755_399_441_055_744.0;

/// The ray's position in the mirrored frame, `p + d t` (lanes): `p` the origin less half
/// a voxel (so rounding to nearest rounds the position down), `d = |1 / inv|`, 0 on the
/// axes moved off the lattice.
struct Position<L> {
    p: L,
    d: L,
}

impl<L: Lanes> Position<L> {
    #[inline(always)]
    fn new(m: &Mirrored, edge: u32) -> Self {
        let flipped = |a: usize| m.flip[a] != 0;
        let p = std::array::from_fn(|a| if flipped(a) { f64::from(edge) - m.o[a] } else { m.o[a] } - 0.5);
        let d = std::array::from_fn(|a| if m.inv[a].is_finite() { (1.0 / m.inv[a]).abs() } else { 0.0 });
        Position { p: L::new(p, 0.0), d: L::new(d, 0.0) }
    }
}

impl Tree64 {
    /// The walk from the root at `max(ta, start)` (see the module doc), its plane
    /// times three axes at once in lanes `L`.
    #[inline(always)]
    pub(super) fn walk_fast<L: Lanes, const FACE: bool>(
        &self,
        ray: &Lattice,
        t_max: f64,
        span: RootSpan,
        start: f64,
    ) -> Option<Entry> {
        let edge = 1u32 << (2 * self.levels);
        let m = Mirrored::new(ray, edge);
        // No hit at or after the ray's limit or the root's exit.
        let limit = if t_max < span.tb { t_max } else { span.tb };
        let mut t = span.ta.max(start);
        if t >= limit {
            return None;
        }
        let lanes = RayLanes::<L>::new(&m);
        let pos = Position::<L>::new(&m, edge);
        // The nodes above the current one, root first (left uninitialized until written).
        let mut stack = [const { MaybeUninit::<Node64>::uninit() }; LEVELS];
        let mut level = 0usize;
        let mut node = self.nodes[0];
        // log2 of the current level's child edge, the ray's cell there (mirrored, in
        // units of that edge), the cell's far planes (original frame, f64), their
        // times, and the child edge in lanes, signed as the mirrored coordinate runs.
        let mut shift = 2 * self.levels - 2;
        let v = voxel(&m, &lanes, &pos, t, [0; 3], shift + 2);
        let mut cell = v.map(|x| x >> shift);
        if self.down(&m, &mut stack, &mut level, &mut node, &mut shift, &mut cell, v) {
            return Some(hit::<FACE>(&m, cell, shift, t, span));
        }
        let (mut pn, mut tn, mut step) = far_planes(&lanes, &m, cell, shift);
        loop {
            // Here the child at `cell` is empty. When no child the ray can still reach
            // in this node is present, the node is left at once: it is taken as an
            // empty cell of its parent, and so on up (the same exit time and cell as
            // stepping through it).
            let mut c: [u32; 3] = std::array::from_fn(|a| (cell[a] & 3) ^ m.child_flip[a]);
            if node.present & m.ahead(cell) == 0 {
                loop {
                    if level == 0 {
                        return None;
                    }
                    level -= 1;
                    // SAFETY: the nodes `0..level` above were written on the way down.
                    node = unsafe { stack[level].assume_init() };
                    shift += 2;
                    for c in &mut cell {
                        *c >>= 2;
                    }
                    c = std::array::from_fn(|a| (cell[a] & 3) ^ m.child_flip[a]);
                    let left = c[0] + 4 * c[1] + 16 * c[2];
                    if node.present & m.ahead(cell) & !(1u64 << left) != 0 {
                        break;
                    }
                }
                (pn, tn, step) = far_planes(&lanes, &m, cell, shift);
            }
            // Step to the cell's far planes, or to its group's when no child of its
            // 2x2x2 group is present (`skip` on the axes where the cell is the group's
            // near one), without a branch on the axes that move.
            let group = GROUP_CELLS[((c[0] >> 1) + 2 * (c[1] >> 1) + 4 * (c[2] >> 1)) as usize];
            let empty_group = node.present & group == 0;
            let even = (!cell[0] & 1) | (!cell[1] & 1) << 1 | (!cell[2] & 1) << 2;
            let skip = L::new(SKIP[if empty_group { even as usize } else { 0 }], 0.0);
            let tt = lanes.time(pn.add(skip.and(step)));
            t = tt.min3();
            if t >= limit {
                return None;
            }
            // Past the target plane (the cell's or the group's far plane), or only
            // past the group's mid plane.
            let at = L::splat(t);
            let (mid, past) = (tn.le(at), tt.le(at).and(skip));
            let (mid_bits, past_bits) = (mid.bits() as u32, past.bits() as u32);
            let old = cell;
            for (a, c) in cell.iter_mut().enumerate() {
                *c += (mid_bits >> a & 1) + (past_bits >> a & 1);
            }
            let moved = (old[0] ^ cell[0]) | (old[1] ^ cell[1]) | (old[2] ^ cell[2]);
            if moved >= 4 {
                // The new cell is in another node: the ancestor `up` levels above holds it.
                let up = ((31 - moved.leading_zeros()) / 2) as usize;
                if up > level {
                    return None;
                }
                level -= up;
                // SAFETY: the nodes `0..level` above were written on the way down.
                node = unsafe { stack[level].assume_init() };
                shift += 2 * up as u32;
                for c in &mut cell {
                    *c >>= 2 * up;
                }
            } else {
                pn = pn.add(mid.and(step)).add(past.and(step));
                tn = lanes.time(pn);
            }
            let c: [u32; 3] = std::array::from_fn(|a| (cell[a] & 3) ^ m.child_flip[a]);
            let child = c[0] + 4 * c[1] + 16 * c[2];
            if node.present >> child & 1 == 1 {
                if node.full >> child & 1 == 1 {
                    return Some(hit::<FACE>(&m, cell, shift, t, span));
                }
                let v = voxel(&m, &lanes, &pos, t, cell, shift);
                if self.down(&m, &mut stack, &mut level, &mut node, &mut shift, &mut cell, v) {
                    return Some(hit::<FACE>(&m, cell, shift, t, span));
                }
                (pn, tn, step) = far_planes(&lanes, &m, cell, shift);
            } else if moved >= 4 {
                (pn, tn, step) = far_planes(&lanes, &m, cell, shift);
            }
        }
    }

    /// Goes down from the present inner child at `cell` of `node` (level `level`,
    /// child edge `1 << shift`) along the voxel `v` the ray is in: each node entered
    /// is pushed, and the walk stops at the first child on the way that is empty
    /// (false) or full (true), `cell` and `shift` its.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)]
    fn down(
        &self,
        m: &Mirrored,
        stack: &mut [MaybeUninit<Node64>; LEVELS],
        level: &mut usize,
        node: &mut Node64,
        shift: &mut u32,
        cell: &mut [u32; 3],
        v: [u32; 3],
    ) -> bool {
        loop {
            let c: [u32; 3] = std::array::from_fn(|a| (cell[a] & 3) ^ m.child_flip[a]);
            let child = c[0] + 4 * c[1] + 16 * c[2];
            if node.present >> child & 1 == 0 {
                return false;
            }
            if node.full >> child & 1 == 1 {
                return true;
            }
            stack[*level].write(*node);
            *level += 1;
            let inner = node.present & !node.full;
            *node = self.nodes[(node.first + (inner & ((1u64 << child) - 1)).count_ones()) as usize];
            *shift -= 2;
            *cell = v.map(|x| x >> *shift);
        }
    }
}

/// The far planes of `cell` (mirrored, edge `1 << shift`) in the original frame, their
/// times and the cell's edge signed as the mirrored coordinate runs, in lanes.
#[inline(always)]
fn far_planes<L: Lanes>(lanes: &RayLanes<L>, m: &Mirrored, cell: [u32; 3], shift: u32) -> (L, L, L) {
    let pn = L::new(std::array::from_fn(|a| f64::from(m.plane(a, (cell[a] + 1) << shift))), 0.0);
    (pn, lanes.time(pn), lanes.sign.mul(L::splat(f64::from(1u32 << shift))))
}

/// The voxel (mirrored) the ray is in at time `t` by the walk's rule, in the cell
/// `cell` of edge `1 << shift` that holds it then (see the module doc).
#[inline(always)]
fn voxel<L: Lanes>(
    m: &Mirrored,
    lanes: &RayLanes<L>,
    pos: &Position<L>,
    t: f64,
    cell: [u32; 3],
    shift: u32,
) -> [u32; 3] {
    let at = L::splat(t);
    let guess = pos.p.add(pos.d.mul(at)).add(L::splat(ROUND)).to_array();
    let v: [u32; 3] = std::array::from_fn(|a| {
        let lo = (cell[a] << shift) as i32;
        let hi = lo + ((1i32 << shift) - 1);
        (guess[a].to_bits() as i32).clamp(lo, hi) as u32
    });
    let near = L::new(std::array::from_fn(|a| f64::from(m.plane(a, v[a]))), 0.0);
    let (tnear, tfar) = (lanes.time(near), lanes.time(near.add(lanes.sign)));
    if tnear.le(at).bits() == 7 && tfar.le(at).bits() == 0 {
        return v;
    }
    placed(m, t, cell, shift)
}

/// The voxel of [`voxel`] by bisection on the plane times: per axis the last voxel of
/// the cell whose near plane's time is `<= t` (the cell's own near plane's is).
#[cold]
#[inline(never)]
fn placed(m: &Mirrored, t: f64, cell: [u32; 3], shift: u32) -> [u32; 3] {
    std::array::from_fn(|a| {
        let (mut lo, mut hi) = (cell[a] << shift, (cell[a] + 1) << shift);
        while hi - lo > 1 {
            let mid = lo + (hi - lo) / 2;
            if m.time(a, mid) <= t {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    })
}
