//! The band of a step over the cubes as a sparse set of small tiles: the exact squared
//! distance of every voxel near the surface, each pass of the separable transform run
//! once along whole lines of tiles, no halo recomputed.
//!
//! The transform is [`super::edt`]'s (Saito and Toriwaki 1994, Meijster et al. 2000,
//! Felzenszwalb and Huttenlocher 2012, the cost to the nearest cube of the other
//! phase), but its domain is not a brick with a halo: it is the set of tiles of `T =
//! 2^k` voxels a side (`T = 8`) the step can reach, and each pass (x, then y, then z)
//! walks the lines of that set along its axis, a run of consecutive tiles at a time,
//! so a voxel is computed once a pass (bricks of `B` voxels each read with a halo of
//! `R` voxels compute `(B + 2R)^3 / B^3` voxels a brick voxel: 3.6 at `R = 10`).
//!
//! Which tiles (`t = ceil(R / T)`, `R` the reach of the step, [`super::band`]):
//! a tile is *site* when all its voxels are of the phase the step spreads (full
//! growing, empty shrinking), *mixed*, or *free* (none of that phase). The tiles
//! computed are the mixed and free tiles within `t` tiles (Chebyshev) of a mixed tile
//! or within `max(t - 1, 1)` of a free tile touching a site tile (26 neighbours;
//! shrinking, the outside of the domain counts as site). Why that is enough: a voxel
//! that changes lies within `R` voxels on each axis of a site with a neighbour of the
//! other phase, and so do the two corners of the box between them the passes go
//! through (`(p_x, s_y, s_z)` and `(p_x, p_y, s_z)`); their tiles are within `t` of
//! that site's tile. For such a free tile `Y`, take the nearest tile holding a site
//! (at most `t` away): if it is mixed, `Y` is within `t` of it; if it is a site tile,
//! the tile before it on the way from `Y` is a free tile touching it, at most `t - 1`
//! from `Y`. The kinds are found in one walk of the keys in Morton order.
//!
//! Site tiles are never stored: every pass value in them is 0 (all sites are seeds
//! here, not only the boundary's, so a site's own value is 0), and along a line the
//! first voxel of the site tile beyond a run's end is nearer than any other site
//! beyond it, so a run carries at most one site or zero each end. Tiles that are none
//! of these hold no value under the cap. Shrinking, the voxel past a domain face is a
//! site. Every value the passes keep is the exact one over this reduced set, which is
//! the true one for every voxel that can change (by the argument above), so the result
//! is the exact offset (checked voxel for voxel against a dense brute force,
//! tests/offset.rs), the same voxels as the bricks with halos it replaced.
//!
//! The passes: the values start at 0 on the sites (read from the tree for the mixed
//! tiles only) and none elsewhere, and all three passes are the same one-dimensional
//! transform in place (the first, over 0 and none, gives the cost to the nearest site
//! along the row; a site's value stays 0 and every other voxel's is at least 1, so the
//! changed voxels are read from the values alone). Where the papers take the lower
//! envelope for any reach, a reach `R` of at most [`WINDOW_REACH`] takes the minimum
//! over the window `|o| <= R` directly ([`window_pass`]): `2R + 1` saturating adds and
//! minimums a value, but the eight lines of a tile side by side in 16-bit lanes, which
//! vectorize, where the envelope's stack branches on every value; the same values, as
//! no cost beyond `R` is under the cap. Over that reach the first pass, whose input is 0
//! or none, is the two sweeps to the nearest site along the row ([`row_pass`]), and the
//! envelope is kept for the other two.
//!
//! Memory follows the tiles: one array of values, 2 bytes a voxel (4 when the radius
//! is 128 voxels or more, the squared distances beyond 16 bits), which each pass
//! rewrites in place (a line is read whole before it is written, and a run reads and
//! writes only its own tiles); the tile lists. Radii over `2n + 2` (`n` the domain's
//! voxels a side) are taken as `2n + 2`, which reaches every voxel as they do ([`super::band`]).
//! Runs are transformed in parallel, each writing only its own tiles, and the changes
//! are gathered in Morton order, so the result does not depend on the number of
//! threads.

use std::sync::atomic::{AtomicU64, Ordering};

use rayon::prelude::*;

use super::edt::{FAR, lower_envelope, nearest_site_along_row};
use super::metric::Metric;
use super::step::Step;
use crate::morton;
use crate::octree::window::{keys_meeting, keys_meeting_near, range_meeting_near};
use crate::octree::{LinearOctree, NodeKey};
use crate::progress::Progress;

/// Tile edge, as a power of two (at most the domain's).
const TILE_K: u32 = 3;
/// Seeds a thread lists before it counts them against the cap ([`TileBand::of`]).
const COUNT_EVERY: u64 = 1 << 16;

/// A tile's phase as the step sees it.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub(super) enum Kind {
    /// Every voxel of the phase the step spreads.
    Site,
    /// Both phases.
    Mixed,
    /// No voxel of that phase.
    Free,
}

/// A tile position, packed `z << 42 | y << 21 | x` (sorting gives lines along x).
pub(super) type Packed = u64;

pub(super) fn pack(c: [u32; 3]) -> Packed {
    (u64::from(c[2]) << 42) | (u64::from(c[1]) << 21) | u64::from(c[0])
}

pub(super) fn unpack(p: Packed) -> [u32; 3] {
    [(p & 0x1f_ffff) as u32, ((p >> 21) & 0x1f_ffff) as u32, (p >> 42) as u32]
}

/// The tiles a step over the cubes transforms and the memory it is estimated to need.
pub(super) struct TileBand {
    /// Tile edge, as a power of two.
    pub(super) k: u32,
    /// Tiles a side of the domain.
    n: u32,
    /// Whether the step grows (the outside of the domain is no site).
    grow: bool,
    /// The tiles, sorted by packed position.
    pub(super) tiles: Vec<Packed>,
    /// Whether each tile is mixed (else free: no site).
    pub(super) mixed: Vec<bool>,
    /// The reach of the step, in voxels.
    reach: u32,
    /// The site tiles next to them (and others), sorted by packed position.
    pub(super) sites: Vec<Packed>,
    /// Estimated peak memory of the step, in bytes.
    pub estimate: u64,
}

/// What a step's tile classification reads: the tree's keys and the tile scale.
struct Tiles<'a> {
    keys: &'a [NodeKey],
    k: u32,
    /// Tiles a side of the domain.
    n: u32,
    grow: bool,
}

impl Tiles<'_> {
    /// The kind of the tile at `c` (outside the domain: site when shrinking, free else),
    /// the keys searched from index `hint` (a key near the tile in Morton order).
    fn kind_near(&self, c: [i64; 3], hint: usize) -> Kind {
        if c.iter().any(|&x| x < 0 || x >= i64::from(self.n)) {
            return if self.grow { Kind::Free } else { Kind::Site };
        }
        let code = morton::encode(c[0] as u32, c[1] as u32, c[2] as u32);
        let node = NodeKey::new(code << (3 * self.k), self.k);
        self.kind_of(keys_meeting_near(self.keys, hint, node))
    }

    /// The kind of a tile the keys `meeting` meet.
    fn kind_of(&self, meeting: &[NodeKey]) -> Kind {
        let full = match meeting {
            [] => Some(false),
            [key] if key.k() >= self.k => Some(true),
            _ => None,
        };
        match full {
            None => Kind::Mixed,
            Some(full) if full == self.grow => Kind::Site,
            Some(_) => Kind::Free,
        }
    }
}

impl TileBand {
    /// The tiles of `step` (reach `r` voxels, at least 1) on `tree` (see the module doc),
    /// or, when finding them would take more than `cap` bytes, `Err` with bytes the step
    /// needs at least (more than `cap`): the lists are counted as they grow, so a solid
    /// whose surface is far larger than its nodes (a coarse solid at a fine depth) is
    /// refused before they fill memory.
    pub(super) fn of(tree: &LinearOctree, step: Step, r: u32, cap: u64) -> Result<TileBand, u64> {
        let depth = u32::from(tree.depth());
        let k = TILE_K.min(depth);
        let n = tree.domain().resolution() >> k;
        let tiles = Tiles { keys: tree.keys(), k, n, grow: step.grow };
        let t = r.div_ceil(1 << k);
        if !step.grow {
            let least = least_shrinking_band(tree, k);
            if least > cap {
                return Err(least);
            }
        }
        let (mixed, free) = seeds(&tiles, cap)?;
        // Every seed is a tile of the band, which takes at least its values (2 bytes a
        // voxel) and its entries in the lists.
        let least = (mixed.len() + free.len()) as u64 * ((2 << (3 * k)) + 64);
        if least > cap {
            return Err(least);
        }
        // Free seeds by at least one: then every site tile next to a tile of the band
        // is in the dilated set (a free tile touching one is a seed).
        let mut dilated = dilate(mixed, t, n, cap)?;
        dilated.extend(dilate(free, (t - 1).max(1), n, cap)?);
        dilated.par_sort_unstable();
        dilated.dedup();
        let kinds = kinds_of(&tiles, &dilated);
        let (mut band, mut mixed, mut sites) = (Vec::new(), Vec::new(), Vec::new());
        for (p, kind) in dilated.into_iter().zip(kinds) {
            if kind == Kind::Site {
                sites.push(p);
            } else {
                band.push(p);
                mixed.push(kind == Kind::Mixed);
            }
        }
        let voxels = band.len() as u64 * (1u64 << (3 * k));
        // The passes' values (2 or 4 bytes a voxel), the tile lists, their orders and
        // runs (about 64 bytes a tile), the trees in and out.
        let value = if step.limit() < i64::from(u16::MAX) { 2 } else { 4 };
        let estimate = value * voxels + 64 * (band.len() + sites.len()) as u64 + 3 * tree.bytes() as u64;
        Ok(TileBand { k, n, grow: step.grow, tiles: band, mixed, reach: r, sites, estimate })
    }

    /// The Morton runs of the voxels `step` changes (sorted), with its `limit` on four
    /// times the squared distance (under `u32::MAX`); progress in tiles, three passes
    /// each. Values are kept in 16 bits when the limit allows (radii under 128 voxels).
    pub(super) fn changed_runs(
        &self,
        tree: &LinearOctree,
        step: Step,
        limit: i64,
        progress: &dyn Progress,
    ) -> Vec<(u64, u64)> {
        if limit < i64::from(u16::MAX) {
            self.transform::<u16>(tree, step, limit, progress)
        } else {
            self.transform::<u32>(tree, step, limit, progress)
        }
    }

    /// [`TileBand::changed_runs`] with the passes' values stored as `V`.
    fn transform<V: Value>(
        &self,
        tree: &LinearOctree,
        step: Step,
        limit: i64,
        progress: &dyn Progress,
    ) -> Vec<(u64, u64)> {
        let (k, grow) = (self.k, step.grow);
        let t = 1usize << k;
        let v = t * t * t;
        progress.start(3 * self.tiles.len() as u64);
        // The index in a tile of each Morton offset.
        let at_morton: Vec<usize> = (0..v as u64)
            .map(|i| {
                let [x, y, z] = morton::decode(i).map(|c| c as usize);
                x + t * (y + t * z)
            })
            .collect();
        // The passes' input: 0 at each site (of a mixed tile, from the keys inside it;
        // a free tile has none), none elsewhere.
        let mut values = vec![V::NONE; self.tiles.len() * v];
        let keys = tree.keys();
        values.par_chunks_mut(v).zip(&self.tiles).zip(&self.mixed).filter(|(_, mixed)| **mixed).for_each(
            |((tile, &p), _)| {
                let base = encode(unpack(p)) << (3 * k);
                let (full, other) = if grow { (V::ZERO, V::NONE) } else { (V::NONE, V::ZERO) };
                tile.fill(other);
                for key in keys_meeting(keys, NodeKey::new(base, k)) {
                    let (start, end) = (key.start().max(base) - base, key.end().min(base + v as u64) - base);
                    for &at in &at_morton[start as usize..end as usize] {
                        tile[at] = full;
                    }
                }
            },
        );
        // Along x, then y, then z, in place: `values(x) <- min_i (axis_cost(x - i) +
        // values(i))` along each line; the first pass, over 0 and none, is the cost to
        // the nearest site along the row. Lanes are the tile's rows across the line.
        let strides = [[1, t, t * t], [t, 1, t * t], [t * t, 1, t]];
        for (axis, strides) in strides.into_iter().enumerate() {
            let runs = runs(&self.tiles, axis);
            if self.reach <= WINDOW_REACH || step.metric != Metric::Euclidean {
                window_pass(&runs, &mut values, v, t, strides, step.metric, self.reach, limit, self, progress);
            } else if axis == 0 {
                row_pass(&runs, &mut values, v, t, limit, self, progress);
            } else {
                envelope_pass(&runs, &mut values, v, t, strides, limit, self, progress);
            }
        }
        progress.finish();
        // The voxels that change: within the limit and not sites (a site's value is
        // 0, every other voxel's at least 1); in Morton order.
        let mut order: Vec<(u64, usize)> =
            self.tiles.iter().enumerate().map(|(s, &p)| (encode(unpack(p)), s)).collect();
        order.par_sort_unstable();
        let parts: Vec<Vec<(u64, u64)>> = order
            .par_chunks(1024)
            .map(|chunk| {
                let mut runs: Vec<(u64, u64)> = Vec::new();
                for &(code, s) in chunk {
                    let base = code << (3 * k);
                    let d = &values[s * v..(s + 1) * v];
                    for (i, &at) in (0..v as u64).zip(&at_morton) {
                        let cost = d[at].cost();
                        if cost <= limit && cost != 0 {
                            let code = base + i;
                            match runs.last_mut() {
                                Some(last) if last.1 == code => last.1 = code + 1,
                                _ => runs.push((code, code + 1)),
                            }
                        }
                    }
                }
                runs
            })
            .collect();
        let mut out: Vec<(u64, u64)> = Vec::new();
        for part in parts {
            for run in part {
                match out.last_mut() {
                    Some(last) if last.1 == run.0 => last.1 = run.1,
                    _ => out.push(run),
                }
            }
        }
        out
    }
}

impl TileBand {
    /// The kind of a tile next to the band, not in it: site or free (see [`TileBand::of`]).
    pub(super) fn beyond(&self, c: [i64; 3]) -> Kind {
        let n = i64::from(self.n);
        if c.iter().any(|&x| x < 0 || x >= n) {
            return if self.grow { Kind::Free } else { Kind::Site };
        }
        match self.sites.binary_search(&pack(c.map(|x| x as u32))) {
            Ok(_) => Kind::Site,
            Err(_) => Kind::Free,
        }
    }
}

/// The kinds of the tiles `set` (inside the domain), walked in Morton order so each
/// search of the keys starts from the last one's.
fn kinds_of(tiles: &Tiles, set: &[Packed]) -> Vec<Kind> {
    let mut order: Vec<(u64, usize)> = set.iter().enumerate().map(|(i, &p)| (encode(unpack(p)), i)).collect();
    order.par_sort_unstable();
    let found: Vec<(usize, Kind)> = order
        .par_chunks(4096)
        .flat_map_iter(|chunk| {
            let mut hint = 0;
            chunk.iter().map(move |&(code, i)| {
                let node = NodeKey::new(code << (3 * tiles.k), tiles.k);
                let range = range_meeting_near(tiles.keys, hint, node);
                hint = range.start.min(tiles.keys.len().saturating_sub(1));
                (i, tiles.kind_of(&tiles.keys[range]))
            })
        })
        .collect();
    let mut kinds = vec![Kind::Free; set.len()];
    for (i, kind) in found {
        kinds[i] = kind;
    }
    kinds
}

pub(super) fn encode(c: [u32; 3]) -> u64 {
    morton::encode(c[0], c[1], c[2])
}

/// A value of a pass as stored: four times a squared distance, at most the cap, or
/// none in reach.
trait Value: Copy + Ord + Send + Sync {
    /// No value in reach (the type's largest, so a saturating sum with it stays none).
    const NONE: Self;
    /// A site's value.
    const ZERO: Self;
    /// `cost` as stored: `NONE` when over `cap` (which is under `Self`'s largest).
    fn of(cost: i64, cap: i64) -> Self;
    /// The cost stored, [`FAR`] for `NONE`.
    fn cost(self) -> i64;
    /// The sum, `NONE` when it is more than the type holds.
    fn saturating_add(self, other: Self) -> Self;
}

/// [`Value`] for unsigned integer types.
macro_rules! unsigned_value {
    ($($t:ty),*) => {$(
        impl Value for $t {
            const NONE: Self = <$t>::MAX;
            const ZERO: Self = 0;
            fn of(cost: i64, cap: i64) -> Self {
                if cost > cap { Self::NONE } else { cost as $t }
            }
            fn cost(self) -> i64 {
                if self == Self::NONE { FAR } else { i64::from(self) }
            }
            fn saturating_add(self, other: Self) -> Self {
                <$t>::saturating_add(self, other)
            }
        }
    )*};
}

unsigned_value!(u16, u32);

/// A run of consecutive tiles along one axis and what lies just beyond each end.
pub(super) struct Run {
    /// The tiles' slots (indices into the band's tiles), in order along the axis.
    pub(super) slots: Vec<usize>,
    /// The first tile's position.
    first: [u32; 3],
    /// The axis.
    axis: usize,
    /// The kinds of the tiles just before and after the run (filled in by [`for_runs`]).
    pub(super) before: Kind,
    pub(super) after: Kind,
}

impl Run {
    pub(super) fn len(&self) -> usize {
        self.slots.len()
    }
}

/// The runs of consecutive tiles of `tiles` (sorted by packed position) along `axis`.
pub(super) fn runs(tiles: &[Packed], axis: usize) -> Vec<Run> {
    // Order by the other two coordinates, then this one.
    let key = |c: [u32; 3]| -> u64 {
        let (a, b) = match axis {
            0 => (c[2], c[1]),
            1 => (c[2], c[0]),
            _ => (c[1], c[0]),
        };
        (u64::from(a) << 42) | (u64::from(b) << 21) | u64::from(c[axis])
    };
    let mut order: Vec<(u64, usize)> = tiles.iter().enumerate().map(|(s, &p)| (key(unpack(p)), s)).collect();
    order.par_sort_unstable();
    let mut out: Vec<Run> = Vec::new();
    let mut last: Option<u64> = None;
    for (k, s) in order {
        match (last, out.last_mut()) {
            (Some(l), Some(run)) if k == l + 1 => run.slots.push(s),
            _ => out.push(Run { slots: vec![s], first: unpack(tiles[s]), axis, before: Kind::Free, after: Kind::Free }),
        }
        last = Some(k);
    }
    out
}

/// Runs `f(run, its tiles' output slices)` over every run in parallel, each run's
/// tiles' values in `values` (`v` a tile) given to it alone; the kinds beyond the
/// run's ends filled in first.
pub(super) fn for_runs<V: Send, F>(
    runs: &[Run],
    values: &mut [V],
    v: usize,
    band: &TileBand,
    progress: &dyn Progress,
    f: F,
) where
    F: Fn(&Run, &mut [&mut [V]]) + Sync,
{
    let mut tiles: Vec<Option<&mut [V]>> = values.chunks_mut(v).map(Some).collect();
    let mut jobs: Vec<(Run, Vec<&mut [V]>)> = Vec::with_capacity(runs.len());
    for run in runs {
        let slots: Vec<&mut [V]> =
            run.slots.iter().map(|&s| tiles[s].take().expect("a tile in one run an axis")).collect();
        let mut before = run.first.map(i64::from);
        before[run.axis] -= 1;
        let mut after = run.first.map(i64::from);
        after[run.axis] += run.len() as i64;
        let run = Run {
            slots: run.slots.clone(),
            first: run.first,
            axis: run.axis,
            before: band.beyond(before),
            after: band.beyond(after),
        };
        jobs.push((run, slots));
    }
    jobs.par_iter_mut().for_each(|(run, slots)| {
        if progress.cancelled() {
            return; // The offset returns `Cancelled` after this pass.
        }
        f(run, slots);
        progress.advance(run.len() as u64);
    });
}

/// One envelope pass along `runs`' axis, in place: along each line (read whole before
/// it is written), `values(x) <- min_i (axis_cost(x - i) + values(i))`, a site tile
/// beyond a run's end giving 0 there; `strides` are the steps within a tile along the
/// axis and the two others. For any reach; [`window_pass`] gives the same values faster
/// for small ones.
#[allow(clippy::too_many_arguments)]
fn envelope_pass<V: Value>(
    runs: &[Run],
    values: &mut [V],
    v: usize,
    t: usize,
    strides: [usize; 3],
    cap: i64,
    band: &TileBand,
    progress: &dyn Progress,
) {
    for_runs(runs, values, v, band, progress, |run, slots| {
        let len = run.len() * t;
        let (before, after) = (run.before == Kind::Site, run.after == Kind::Site);
        let mut g = vec![FAR; len + 2];
        let mut out = vec![0i64; len];
        let (mut sites, mut starts) = (Vec::new(), Vec::new());
        for b in 0..t {
            for a in 0..t {
                let base = a * strides[1] + b * strides[2];
                g[0] = if before { 0 } else { FAR };
                g[len + 1] = if after { 0 } else { FAR };
                let mut any = before || after;
                for (j, tile) in slots.iter().enumerate() {
                    for i in 0..t {
                        let d = tile[base + i * strides[0]].cost();
                        any |= d <= cap;
                        g[1 + j * t + i] = d;
                    }
                }
                if !any {
                    continue;
                }
                lower_envelope(&g, 1, cap, &mut out, &mut sites, &mut starts, None);
                for (j, tile) in slots.iter_mut().enumerate() {
                    for i in 0..t {
                        tile[base + i * strides[0]] = V::of(out[j * t + i], cap);
                    }
                }
            }
        }
    });
}

/// The first pass along x for reaches over [`WINDOW_REACH`], in place: the values are 0
/// (a site) or none, so [`envelope_pass`]'s minimum is the cost to the nearest site
/// along the row, two sweeps ([`nearest_site_along_row`]) instead of an envelope; a site
/// tile beyond a run's end is a site there.
fn row_pass<V: Value>(
    runs: &[Run],
    values: &mut [V],
    v: usize,
    t: usize,
    cap: i64,
    band: &TileBand,
    progress: &dyn Progress,
) {
    for_runs(runs, values, v, band, progress, |run, slots| {
        let len = run.len() * t;
        let (before, after) = (run.before == Kind::Site, run.after == Kind::Site);
        let mut row = vec![false; len + 2];
        let mut costs = vec![0i64; len];
        for yz in 0..t * t {
            row[0] = before;
            row[len + 1] = after;
            let mut any = before || after;
            for (j, tile) in slots.iter().enumerate() {
                for (cell, &d) in row[1 + j * t..1 + (j + 1) * t].iter_mut().zip(&tile[t * yz..t * (yz + 1)]) {
                    *cell = d == V::ZERO;
                    any |= *cell;
                }
            }
            if !any {
                continue;
            }
            nearest_site_along_row(&row, 1, cap, &mut costs, None);
            for (j, tile) in slots.iter_mut().enumerate() {
                for (value, &c) in tile[t * yz..t * (yz + 1)].iter_mut().zip(&costs[j * t..(j + 1) * t]) {
                    *value = V::of(c, cap);
                }
            }
        }
    });
}

/// The largest reach [`window_pass`] is used for: it costs `2 R + 1` lane steps a value
/// where the envelope costs a few dozen instructions whatever the reach.
const WINDOW_REACH: u32 = 32;

/// Lanes of a window pass: the `t` (at most 8) lines of a tile side by side.
const LANES: usize = 8;

/// [`envelope_pass`]'s values by the window of the reach `r`: `values(x) <- min over
/// |o| <= r of (cost(o) + values(x + o))`, in saturating integers, `t` lines side by
/// side (those along `strides[1]`), `cost` the metric's ([`Metric::axis_cost`]).
/// Exact: Euclidean, beyond `r` voxels along an axis a cost is over the cap (`(2r +
/// 1)^2 >= 4 radius^2`), so the window holds every value the envelope could keep, and
/// a sum over the cap becomes none as there; by any metric no voxel beyond the reach
/// on some axis is within the radius (its gap on that axis alone is at least the
/// radius), so the values over the window decide the same voxels. The other metrics
/// take this pass for every reach (`2 r + 1` taps a value).
#[allow(clippy::too_many_arguments)]
fn window_pass<V: Value>(
    runs: &[Run],
    values: &mut [V],
    v: usize,
    t: usize,
    strides: [usize; 3],
    metric: Metric,
    reach: u32,
    cap: i64,
    band: &TileBand,
    progress: &dyn Progress,
) {
    let r = reach as usize;
    // costs[j]: the cost of the offset j - r, as stored.
    let costs: Vec<V> = (0..=2 * r).map(|j| V::of(metric.axis_cost(j as i64 - i64::from(reach)), cap)).collect();
    let top = V::of(cap, cap);
    for_runs(runs, values, v, band, progress, |run, slots| {
        let len = run.len() * t;
        let (before, after) = (run.before == Kind::Site, run.after == Kind::Site);
        // g[LANES (r + x) + a]: lane a's value at x; none beyond the run but for a site
        // tile's 0 just beyond each end.
        let mut g = vec![V::NONE; LANES * (len + 2 * r)];
        g[LANES * (r - 1)..LANES * r].fill(if before { V::ZERO } else { V::NONE });
        g[LANES * (r + len)..LANES * (r + len + 1)].fill(if after { V::ZERO } else { V::NONE });
        let mut out = vec![V::NONE; LANES * len];
        for b in 0..t {
            for (j, tile) in slots.iter().enumerate() {
                for i in 0..t {
                    let at = b * strides[2] + i * strides[0];
                    let lanes = &mut g[LANES * (r + j * t + i)..][..t];
                    if strides[1] == 1 {
                        lanes.copy_from_slice(&tile[at..at + t]);
                    } else {
                        for (a, lane) in lanes.iter_mut().enumerate() {
                            *lane = tile[at + a * strides[1]];
                        }
                    }
                }
            }
            if g.iter().all(|&d| d == V::NONE) {
                continue;
            }
            // One tap of the window at a time over the whole line (which vectorizes).
            out.fill(V::NONE);
            for (j, &c) in costs.iter().enumerate() {
                for (m, &d) in out.iter_mut().zip(&g[LANES * j..]) {
                    *m = (*m).min(d.saturating_add(c));
                }
            }
            for (j, tile) in slots.iter_mut().enumerate() {
                for i in 0..t {
                    let at = b * strides[2] + i * strides[0];
                    let lanes = out[LANES * (j * t + i)..][..t].iter().map(|&d| if d > top { V::NONE } else { d });
                    if strides[1] == 1 {
                        for (value, d) in tile[at..at + t].iter_mut().zip(lanes) {
                            *value = d;
                        }
                    } else {
                        for (a, d) in lanes.enumerate() {
                            tile[at + a * strides[1]] = d;
                        }
                    }
                }
            }
        }
    });
}

/// The seeds (see the module doc): the mixed tiles, and the free tiles touching a site
/// tile, each sorted by packed position; `Err` with bytes the band needs at least once
/// those pass `cap` (the listings counted over all threads as they grow, so at most a
/// few thousand a thread past it).
fn seeds(tiles: &Tiles, cap: u64) -> Result<(Vec<Packed>, Vec<Packed>), u64> {
    let k = tiles.k;
    let n = i64::from(tiles.n);
    let listed = AtomicU64::new(0);
    // What a listing stands for: its entry, and a 26th of the least a seed takes in the
    // band (its values and list entries, as in `TileBand::of`), as a tile is listed at
    // most once by each of the 26 keys around it (growing; shrinking, once by its own
    // key; a mixed tile by at most the two chunks its keys may span). So the listing
    // stops well before its entries fill the cap.
    let per_listing = (std::mem::size_of::<Packed>() as u64).max(((2 << (3 * k)) + 64) / 26);
    let parts: Vec<(Vec<Packed>, Vec<Packed>)> = tiles
        .keys
        .par_chunks(4096)
        .enumerate()
        .map(|(c, chunk)| {
            let (mut mixed, mut out) = (Vec::new(), Vec::new());
            let mut last_mixed = u64::MAX;
            // Entries listed here and not yet added to `listed`; whether all threads'
            // lists, with them, are still within the cap. Added every `COUNT_EVERY`
            // entries, within a key too (a key of whole tiles may list billions), so the
            // shared count is written rarely; read every key.
            let mut uncounted = 0u64;
            let within = |uncounted: &mut u64| {
                let total = listed.fetch_add(*uncounted, Ordering::Relaxed) + *uncounted;
                *uncounted = 0;
                total * per_listing <= cap
            };
            for (j, key) in chunk.iter().enumerate() {
                if uncounted >= COUNT_EVERY {
                    within(&mut uncounted);
                }
                if listed.load(Ordering::Relaxed) * per_listing > cap {
                    break;
                }
                let hint = 4096 * c + j;
                if key.k() < k {
                    let tile = key.start() >> (3 * k);
                    if tile != last_mixed {
                        last_mixed = tile;
                        mixed.push(pack(morton::decode(tile)));
                        uncounted += 1;
                    }
                    continue;
                }
                // A key of whole tiles: growing, the tiles around it that are free;
                // shrinking, its own tiles touching an empty one or the outside.
                let min = morton::decode(key.start() >> (3 * k)).map(i64::from);
                let size = 1i64 << (key.k() - k);
                let inside = |c: [i64; 3]| (0..3).all(|a| c[a] >= min[a] && c[a] < min[a] + size);
                let mut list = |c: [i64; 3]| {
                    out.push(pack(c.map(|x| x as u32)));
                    uncounted += 1;
                    uncounted < COUNT_EVERY || within(&mut uncounted)
                };
                if tiles.grow {
                    for_shell(min.map(|c| c - 1), min.map(|c| c + size + 1), n, |c| {
                        inside(c) || tiles.kind_near(c, hint) != Kind::Free || list(c)
                    });
                } else {
                    for_shell(min, min.map(|c| c + size), n, |c| {
                        let touches = (0..27).filter(|&d| d != 13).any(|d| {
                            let e = [d % 3 - 1, d / 3 % 3 - 1, d / 9 - 1];
                            let nb: [i64; 3] = std::array::from_fn(|a| c[a] + e[a]);
                            !inside(nb) && tiles.kind_near(nb, hint) == Kind::Site
                        });
                        !touches || list(c)
                    });
                }
            }
            listed.fetch_add(uncounted, Ordering::Relaxed);
            (mixed, out)
        })
        .collect();
    let total = listed.load(Ordering::Relaxed) * per_listing;
    if total > cap {
        return Err(total);
    }
    let (mut mixed, mut free): (Vec<Packed>, Vec<Packed>) = (Vec::new(), Vec::new());
    for (m, f) in parts {
        mixed.extend(m);
        free.extend(f);
    }
    for set in [&mut mixed, &mut free] {
        set.par_sort_unstable();
        set.dedup();
    }
    Ok((mixed, free))
}

/// Bytes a shrinking step's band takes at least, from the solid's volume alone, without
/// listing a tile: a coarse solid at a fine depth (a sphere of 2,872 nodes at depth 21)
/// has a surface of trillions of tiles, and listing its seeds (visiting every tile of
/// its big nodes' faces) took 20 s before the cap stopped it.
///
/// The isoperimetric inequality bounds the voxel faces of a solid of `V` voxels (the
/// domain's outside counts as empty when shrinking) from below by `(36 pi)^(1/3)
/// V^(2/3)`. Each such face lies on a seed tile (a mixed tile, or a full one touching a
/// site tile: the face's inside voxel's tile or its outside voxel's), and a tile of `T`
/// voxels a side holds at most `3 T^2 (T + 1)` faces, inside it and on its sides. Every
/// seed takes at least its values and its list entries, as in [`TileBand::of`].
fn least_shrinking_band(tree: &LinearOctree, k: u32) -> u64 {
    let volume = tree.voxel_count() as f64;
    let faces = (36.0 * std::f64::consts::PI).cbrt() * volume.powf(2.0 / 3.0);
    let side = f64::from(1u32 << k);
    // (A hundredth off, for the rounding of the powers.)
    let seeds = (0.99 * faces / (3.0 * side * side * (side + 1.0))).floor();
    let bytes = seeds * ((2u64 << (3 * k)) + 64) as f64;
    if bytes < u64::MAX as f64 { bytes as u64 } else { u64::MAX }
}

/// Calls `f` for each tile of the box `[lo, hi)` on its boundary layer, clipped to the
/// domain (`0..n`), until it returns `false`; rows through the box's inside visit only
/// their two ends.
fn for_shell(lo: [i64; 3], hi: [i64; 3], n: i64, mut f: impl FnMut([i64; 3]) -> bool) {
    let inside = |x: i64| (0..n).contains(&x);
    for z in lo[2].max(0)..hi[2].min(n) {
        for y in lo[1].max(0)..hi[1].min(n) {
            if z == lo[2] || z == hi[2] - 1 || y == lo[1] || y == hi[1] - 1 {
                if !(lo[0].max(0)..hi[0].min(n)).all(|x| f([x, y, z])) {
                    return;
                }
                continue;
            }
            if inside(lo[0]) && !f([lo[0], y, z]) {
                return;
            }
            if hi[0] - 1 != lo[0] && inside(hi[0] - 1) && !f([hi[0] - 1, y, z]) {
                return;
            }
        }
    }
}

/// The tiles within `t` (Chebyshev) of `set`, inside the domain of `n` tiles a side,
/// sorted by packed position: one axis at a time; `Err` with the bytes a pass would
/// list when they pass `cap`.
fn dilate(mut set: Vec<Packed>, t: u32, n: u32, cap: u64) -> Result<Vec<Packed>, u64> {
    for axis in 0..3 {
        // A pass lists up to `2t + 1` tiles a tile before they are deduplicated.
        let listed = set.len() as u64 * u64::from(2 * t + 1) * std::mem::size_of::<Packed>() as u64;
        if listed > cap {
            return Err(listed);
        }
        let mut next: Vec<Packed> = set
            .par_iter()
            .flat_map_iter(|&p| {
                let c = unpack(p);
                let (lo, hi) = (c[axis].saturating_sub(t), (c[axis] + t).min(n - 1));
                (lo..=hi).map(move |x| {
                    let mut d = c;
                    d[axis] = x;
                    pack(d)
                })
            })
            .collect();
        next.par_sort_unstable();
        next.dedup();
        set = next;
    }
    Ok(set)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::Domain;
    use crate::test_util::{BoxesAndNoise, Rng, boxes_and_noise};

    /// The exposed voxel faces of a solid at depth 5 (the domain's outside empty), by
    /// brute force.
    fn exposed_faces(tree: &LinearOctree) -> u64 {
        let full = tree.occupancy([0; 3], 32);
        let at =
            |p: [i64; 3]| p.iter().all(|&c| (0..32).contains(&c)) && full[(p[0] + 32 * (p[1] + 32 * p[2])) as usize];
        let mut faces = 0;
        for z in 0..32 {
            for y in 0..32 {
                for x in 0..32 {
                    if at([x, y, z]) {
                        faces += [[1, 0, 0], [0, 1, 0], [0, 0, 1]]
                            .iter()
                            .flat_map(|e| [1, -1].map(|s| [x + s * e[0], y + s * e[1], z + s * e[2]]))
                            .filter(|&q| !at(q))
                            .count() as u64;
                    }
                }
            }
        }
        faces
    }

    #[test]
    fn the_shrinking_bound_is_under_the_seeds_it_stands_for() {
        let mut rng = Rng(0x21_5e_ed);
        let mut solids: Vec<LinearOctree> = (0..40)
            .map(|i| {
                let how = BoxesAndNoise {
                    fewest: 1,
                    more: 6,
                    against_face: 3,
                    shortest: 1,
                    noise: [1_000_000, 40, 400][i % 3],
                };
                boxes_and_noise(&mut rng, &how)
            })
            .collect();
        let domain = Domain::new(glam::DVec3::ZERO, 1.0, 5).unwrap();
        solids.push(LinearOctree::full(domain));
        solids.push(LinearOctree::from_voxels(domain, vec![[7, 9, 30]]).unwrap());
        // The most faces a tile: a checkerboard.
        let checkers =
            (0..32u32 * 32 * 32).map(|i| [i % 32, i / 32 % 32, i / 1024]).filter(|p| p.iter().sum::<u32>() % 2 == 0);
        solids.push(LinearOctree::from_voxels(domain, checkers.collect::<Vec<_>>()).unwrap());
        for (i, tree) in solids.iter().enumerate() {
            // The isoperimetric inequality on the voxel staircase, as the bound uses it.
            let volume = tree.voxel_count() as f64;
            let faces = exposed_faces(tree) as f64;
            assert!(faces >= (36.0 * std::f64::consts::PI).cbrt() * volume.powf(2.0 / 3.0), "solid {i}");
            for k in 1..=TILE_K {
                let tiles = Tiles { keys: tree.keys(), k, n: 32 >> k, grow: false };
                let (mixed, free) = seeds(&tiles, u64::MAX).unwrap();
                // Every face lies on a seed tile, at most 3 T^2 (T + 1) a tile.
                let side = 1u64 << k;
                let most = (mixed.len() + free.len()) as u64 * 3 * side * side * (side + 1);
                assert!(faces as u64 <= most, "solid {i}, k {k}: {faces} faces on seeds holding at most {most}");
                let listed = (mixed.len() + free.len()) as u64 * ((2 << (3 * k)) + 64);
                let least = least_shrinking_band(tree, k);
                assert!(least <= listed, "solid {i}, k {k}: bound {least} over the seeds' {listed} bytes");
            }
        }
    }
}
