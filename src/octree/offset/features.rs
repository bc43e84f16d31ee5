//! A step along a surface on the sparse tiles: the feature transform (each voxel's
//! nearest site) carried through the tiles' separable passes, then the sub-voxel
//! distance to that site's tangent planes ([`super::subvoxel`]) and the result's
//! crossings from it.
//!
//! The band is [`super::tiles`]'s, taken with the reach `R = ceil(D) + 1`: a voxel the
//! sub-voxel rule reads (four times its squared lattice distance at most the cap
//! `(2D + 3)^2`: a voxel that changes, or a face's far end) lies within `R` voxels on
//! each axis of its nearest site, so the argument of [`super::tiles`] makes its value
//! exact. The passes are [`super::edt`]'s one-dimensional transforms along whole runs
//! of tiles, but a voxel stores its nearest site rather than its value (Maurer, Qi
//! and Raghavan 2003: the feature transform), as the offset from the voxel to the site,
//! and a pass's input value is recomputed from it (`sum_a c(o_a)`, the cost of
//! [`super::edt`]): pass one names the nearest site along the row, passes two and three
//! the line entry whose value wins, and the site it names moves by the entry's offset.
//! A site tile beyond a run's end is its first voxel (offset zero: a site is its own).
//!
//! Of equally near sites, the least in the order (z, y, x): each pass keeps the earlier
//! of two equal entries on its line, so pass three takes the least `z` among them,
//! pass two the least `y` of those, pass one the least `x` (checked against a brute
//! force below). The bricks with halos this replaced followed the same rule, and as
//! every site under the cap lies in the band, each pass sees the entries theirs saw
//! that can win, so the result is theirs byte for byte.
//!
//! The last pass leaves alone the voxels that cost under `S = (2D - 4)^2` after the
//! second (*settled*; `D > 2`: the lattice distance `d_cube` under `D - 2`). Each
//! voxel's own entry is on its line, so its final cost is under `S` as well: the
//! voxel flips (under `(2D - 2)^2`, the sub-voxel range's start below), and each of
//! its six neighbours lies within one voxel more (`d_cube` is 1-Lipschitz), under
//! `D - 1`, so it flips too or is a site: no face of the result ends at the voxel, and
//! nothing reads its site beyond its cost being under `S`, which the second pass's site
//! keeps. Along each line the pass transforms the stretches between voxels not settled
//! (settled gaps of at most twice the cap's reach `W` inside them, `W` the largest
//! `|o|` with `c(o)` at most the cap), each from the entries within `W` of it: an entry
//! farther costs more than the cap there, so the values it keeps under the cap, and
//! their sites, are the whole line's. A settled voxel left alone keeps a site under
//! `S`, not always the least nearest (for PR 6647's cube grown by 36.6 voxels, the
//! middles of the lines along z through the shell of its side faces).
//!
//! Where the cap's reach `W` is at most 64 voxels (tiles of 8^3), passes two and three
//! take each voxel's least cost by the window `|o| <= W` instead of the envelope
//! ([`super::window`]: a tile's eight lines side by side in 16-bit lanes, every tap in
//! turn, keeping the first tap that gives the least, so the envelope's entry among
//! equal ones), the same rule as the cubes' window passes ([`super::tiles`]) with the
//! entry carried. It gives every voxel its exact entry, so it leaves all settled voxels
//! alone (the envelope's stretches also transform those in short gaps) and skips the
//! window for the voxels of a tile's layer across the axis that are all settled; the
//! voxels not settled get the envelope's features.
//!
//! Then the tiles are measured in two sweeps, each in parallel. The first decides each
//! voxel's phase in the result (a bit a voxel, a mask a tile): a voxel whose lattice
//! distance `d_cube` lies within `[D - 1, D + 3/2]` is measured to its site's tangent
//! planes (its exposed faces' crossings; a neighbour's phase read from the tiles, or
//! beyond them from the band's site tiles), others take `d_cube` (under the range:
//! they flip) or `d_cube - 1/2` (over it: they do not, but a face's far end reads it).
//! A voxel of the range whose crossings and cube already bound its sub-voxel distance
//! at least `D` (the bound [`distance_to_site`] keeps) does not flip and is not
//! measured further. The second (tiles in Morton order) gathers the flipped voxels'
//! runs from the masks and finds the result's faces by comparing the masks of a tile
//! and of the six next to it (looked up once a tile; a tile of one phase among
//! neighbours of that phase has none), measuring only the faces' ends, each once a
//! tile, where the tiles' seams were measured twice before. The result's crossing on
//! a face between a full and an empty voxel of the result is where the distance,
//! linear between the two centres, meets `D` (a site's value: minus its old
//! crossing's distance along the normal); its normal is the direction from the foot
//! point of the end whose direction is nearer the face's own. Each face is measured
//! by the tile of its lower voxel, or of its upper one when the lower lies outside
//! the band, so once. Each part's crossings (64 tiles) are sorted in it, so the
//! step's come out sorted by face after a merge of the few keyed by a voxel beyond
//! the part's tiles, without a sort of them all.
//!
//! Memory: a feature a voxel of the band (4 bytes, 8 when the reach passes 510 voxels),
//! a byte a voxel of a mixed tile's occupancy, two bits a voxel of the masks, and the
//! crossings out.

use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;

use super::edt::{FAR, axis_cost, lower_envelope, nearest_site_along_row};
use super::step::{Changes, Step};
use super::subvoxel::{FaceCrossings, NewCrossing, Plane, distance_to_site};
use super::tiles::{Kind, Packed, Run, TileBand, encode, for_runs, pack, runs, unpack};
use super::window::{LANES, has_avx2, window_argmin};
use crate::morton;
use crate::octree::LinearOctree;
use crate::progress::Progress;

/// A voxel's nearest site, as the offset from the voxel to it, or none in reach.
trait Feature: Copy + PartialEq + Send + Sync {
    /// No site in reach.
    const NONE: Self;
    /// The largest offset on an axis it holds.
    const MAX_OFFSET: i64;
    /// The feature of the offset `o` (each axis within `MAX_OFFSET`).
    fn of(o: [i64; 3]) -> Self;
    /// The offset, `None` for [`Feature::NONE`].
    fn offset(self) -> Option<[i64; 3]>;
    /// The feature of this offset (not [`Feature::NONE`]) moved by `by` along `axis`, the
    /// result within `MAX_OFFSET`: `of(o + by e_axis)` without decoding (each axis is a
    /// biased field, so the sum carries into no other).
    fn moved(self, axis: usize, by: i64) -> Self;
    /// [`cost_of`] its offset, [`FAR`] for [`Feature::NONE`].
    fn cost(self) -> i64 {
        self.offset().map_or(FAR, cost_of)
    }
    /// [`Feature::cost`] in 16 bits: `u16::MAX` when over `cap` (under `u16::MAX`) or
    /// for [`Feature::NONE`].
    fn cost_under(self, cap: u16) -> u16 {
        let c = self.cost();
        if c <= i64::from(cap) { c as u16 } else { u16::MAX }
    }
}

/// [`axis_cost`] of each 10-bit field of a `u32` feature (the offset plus 512).
const FIELD_COSTS: [i64; 1024] = {
    let mut costs = [0; 1024];
    let mut i = 0;
    while i < 1024 {
        let o = i as i64 - 512;
        costs[i] = if o == 0 { 0 } else { (2 * o.abs() - 1) * (2 * o.abs() - 1) };
        i += 1;
    }
    costs
};

impl Feature for u32 {
    const NONE: Self = u32::MAX;
    const MAX_OFFSET: i64 = 511;
    fn of(o: [i64; 3]) -> Self {
        o.iter().enumerate().map(|(a, &c)| ((c + 512) as u32) << (10 * a)).sum()
    }
    fn offset(self) -> Option<[i64; 3]> {
        (self != Self::NONE).then(|| std::array::from_fn(|a| i64::from((self >> (10 * a)) & 0x3ff) - 512))
    }
    fn moved(self, axis: usize, by: i64) -> Self {
        self.wrapping_add((by << (10 * axis)) as u32)
    }
    /// Three look-ups, the fields not decoded.
    fn cost(self) -> i64 {
        if self == Self::NONE {
            return FAR;
        }
        let field = |a: u32| FIELD_COSTS[((self >> (10 * a)) & 0x3ff) as usize];
        field(0) + field(1) + field(2)
    }
    /// Without a branch or a table, so a tile's row of them vectorizes: each field's
    /// `max(2 |o| - 1, 0)^2` in 16 bits, its root held at 255 (so for caps under
    /// `255^2` a field over it is over the cap); [`Feature::NONE`]'s fields (511 each)
    /// are.
    fn cost_under(self, cap: u16) -> u16 {
        debug_assert!(cap < 255 * 255, "a cap beyond the 16-bit costs");
        let field = |a: u32| {
            let d = ((2 * ((self >> (10 * a)) & 0x3ff) as i32 - 1024).abs() - 1).clamp(0, 255) as u16;
            d * d
        };
        let c = field(0).saturating_add(field(1)).saturating_add(field(2));
        if c <= cap { c } else { u16::MAX }
    }
}

impl Feature for u64 {
    const NONE: Self = u64::MAX;
    const MAX_OFFSET: i64 = (1 << 20) - 1;
    fn of(o: [i64; 3]) -> Self {
        o.iter().enumerate().map(|(a, &c)| ((c + (1 << 20)) as u64) << (21 * a)).sum()
    }
    fn offset(self) -> Option<[i64; 3]> {
        (self != Self::NONE).then(|| std::array::from_fn(|a| ((self >> (21 * a)) & 0x1f_ffff) as i64 - (1 << 20)))
    }
    fn moved(self, axis: usize, by: i64) -> Self {
        self.wrapping_add((by << (21 * axis)) as u64)
    }
}

/// Four times the squared distance from a voxel to the cube `o` voxels away.
fn cost_of(o: [i64; 3]) -> i64 {
    o.iter().map(|&c| axis_cost(c)).sum()
}

/// The band of `step` along a surface on `tree` (see the module doc), `Ok(None)` when
/// the step reaches no voxel; `Err` as [`TileBand::of`] past `cap` bytes.
pub(super) fn band(tree: &LinearOctree, step: Step, cap: u64) -> Result<Option<TileBand>, u64> {
    match step.reach_along_surface() {
        0 => Ok(None),
        r => TileBand::of(tree, step, r + 1, cap).map(Some),
    }
}

/// Whether the features hold the offsets of `step`'s reach (and the one beyond).
pub(super) fn holds(step: Step) -> bool {
    i64::from(step.reach_along_surface()) + 2 <= u64::MAX_OFFSET
}

/// The memory a step along a surface on `band` is estimated to need: its features
/// and occupancy, the tile lists and trees [`TileBand`] counts, the crossings out (about
/// a face a voxel of a tile's face).
pub(super) fn estimate(band: &TileBand, step: Step) -> u64 {
    let t = 1u64 << band.k;
    let tiles = band.tiles.len() as u64;
    let value = if step.limit() < i64::from(u16::MAX) { 2 } else { 4 };
    let feature = if i64::from(step.reach_along_surface()) + 2 <= u32::MAX_OFFSET { 4 } else { 8 };
    // The cubes' values out, the features and a byte of occupancy a voxel in.
    band.estimate - value * tiles * t * t * t + (feature + 1) * tiles * t * t * t + 40 * tiles * t * t
}

/// The Morton runs of the voxels of `tree` that `step` changes along `surface` (sorted),
/// and the crossings of the result's faces in the band, on the tiles of `band`.
pub(super) fn changed_runs(
    tree: &LinearOctree,
    step: Step,
    band: &TileBand,
    surface: &dyn FaceCrossings,
    progress: &dyn Progress,
) -> Changes {
    if i64::from(step.reach_along_surface()) + 2 <= u32::MAX_OFFSET {
        transform::<u32>(tree, step, band, surface, progress)
    } else {
        transform::<u64>(tree, step, band, surface, progress)
    }
}

/// [`changed_runs`] with the features stored as `F`.
fn transform<F: Feature>(
    tree: &LinearOctree,
    step: Step,
    band: &TileBand,
    surface: &dyn FaceCrossings,
    progress: &dyn Progress,
) -> Changes {
    let (k, grow, radius) = (band.k, step.grow, step.radius);
    let t = 1usize << k;
    let v = t * t * t;
    progress.start(4 * band.tiles.len() as u64);
    let sites = tile_sites(tree, band, grow);
    // Values over this are never read: a voxel that flips lies under `radius + 1/2`
    // from its nearest cube, and a face's far end one voxel farther.
    let cap = (2.0 * radius + 3.0).powi(2).ceil().min(1e18) as i64;
    let features: Vec<F> = feature_transform(band, &sites, cap, settled(radius), progress);
    let measure = Measure::new(tree, band, &sites, &features, surface, step, cap);
    // Each tile's voxels of the phase the step spreads in the result (its sites and
    // the voxels that flip), a bit a voxel, x fastest.
    let mut spread = vec![(Mask::default(), Mask::default()); band.tiles.len()];
    spread.par_chunks_mut(64).enumerate().for_each_init(SiteCache::default, |cache, (c, masks)| {
        for (j, mask) in masks.iter_mut().enumerate() {
            if progress.cancelled() {
                return; // The offset returns `Cancelled` after this pass.
            }
            *mask = measure.spread(64 * c + j, cache);
            progress.advance(1);
        }
    });
    // The tiles in Morton order, each measured alone.
    let mut order: Vec<(u64, usize)> = band.tiles.iter().enumerate().map(|(s, &p)| (encode(unpack(p)), s)).collect();
    order.par_sort_unstable();
    let at_morton: Vec<usize> = (0..v as u64)
        .map(|i| {
            let [x, y, z] = morton::decode(i).map(|c| c as usize);
            x + t * (y + t * z)
        })
        .collect();
    // Each part's crossings sorted by face. The parts' spans of Morton codes (from its
    // first tile's to the next part's) cover the codes once, in order: the few
    // crossings of a part keyed by a voxel beyond its span (of a tile next to one of
    // its own) are sorted apart and merged into the part whose span holds them, and
    // the parts are then laid end to end.
    let span_start = |c: usize| if c == 0 { 0 } else { order[64 * c].0 << (3 * k) };
    let chunks = order.len().div_ceil(64);
    let parts: Vec<Part> = order
        .par_chunks(64)
        .enumerate()
        .map_init(
            || (vec![PENDING; v], SiteCache::default()),
            |(g, cache), (c, chunk)| {
                let (mut runs, mut faces): (Vec<(u64, u64)>, Vec<NewCrossing>) = (Vec::new(), Vec::new());
                for &(code, s) in chunk {
                    let flipped = spread[s].1;
                    if !flipped.is_empty() {
                        let base = code << (3 * k);
                        for (i, &at) in (0..v as u64).zip(&at_morton) {
                            if flipped.get(at) {
                                let code = base + i;
                                match runs.last_mut() {
                                    Some(last) if last.1 == code => last.1 = code + 1,
                                    _ => runs.push((code, code + 1)),
                                }
                            }
                        }
                    }
                    measure.faces(s, &spread, g, &mut faces, cache);
                }
                faces.sort_unstable_by_key(face_order);
                let span = span_start(c)..if c + 1 < chunks { span_start(c + 1) } else { u64::MAX };
                let (own, beyond): (Vec<NewCrossing>, Vec<NewCrossing>) =
                    faces.into_iter().partition(|f| span.contains(&f.voxel));
                (runs, own, beyond)
            },
        )
        .collect();
    progress.finish();
    let mut out: Vec<(u64, u64)> = Vec::new();
    let mut beyond = Vec::new();
    for (runs, _, b) in &parts {
        for &run in runs {
            match out.last_mut() {
                Some(last) if last.1 == run.0 => last.1 = run.1,
                _ => out.push(run),
            }
        }
        beyond.extend_from_slice(b);
    }
    beyond.par_sort_unstable_by_key(face_order);
    let lists: Vec<Vec<NewCrossing>> = parts
        .into_par_iter()
        .enumerate()
        .map(|(c, (_, own, _))| {
            let from = beyond.partition_point(|f| f.voxel < span_start(c));
            let to =
                if c + 1 < chunks { beyond.partition_point(|f| f.voxel < span_start(c + 1)) } else { beyond.len() };
            merged(own, &beyond[from..to])
        })
        .collect();
    let faces = end_to_end(&lists);
    debug_assert!(faces.windows(2).all(|w| face_order(&w[0]) < face_order(&w[1])), "a face measured twice");
    (out, faces)
}

/// A part's flipped voxels' runs, its crossings within its span and those beyond it.
type Part = (Vec<(u64, u64)>, Vec<NewCrossing>, Vec<NewCrossing>);

/// The order of faces: by voxel, then direction.
fn face_order(c: &NewCrossing) -> (u64, u8) {
    (c.voxel, c.direction)
}

/// The crossings of `a` and `b`, each sorted by face, merged in that order.
fn merged(a: Vec<NewCrossing>, b: &[NewCrossing]) -> Vec<NewCrossing> {
    if b.is_empty() {
        return a;
    }
    let mut out = Vec::with_capacity(a.len() + b.len());
    let mut b = b.iter().copied().peekable();
    for c in a {
        while let Some(d) = b.next_if(|d| face_order(d) < face_order(&c)) {
            out.push(d);
        }
        out.push(c);
    }
    out.extend(b);
    out
}

/// The lists one after another, copied in parallel (the pages first touched by both
/// threads rather than one).
fn end_to_end(lists: &[Vec<NewCrossing>]) -> Vec<NewCrossing> {
    let none = NewCrossing { voxel: 0, direction: 0, t: 0.0, normal: [0.0; 3] };
    let mut out: Vec<NewCrossing> = rayon::iter::repeat_n(none, lists.iter().map(Vec::len).sum()).collect();
    let mut rest = &mut out[..];
    let mut pieces = Vec::with_capacity(lists.len());
    for list in lists {
        let (piece, tail) = rest.split_at_mut(list.len());
        pieces.push(piece);
        rest = tail;
    }
    pieces.into_par_iter().zip(lists).for_each(|(piece, list)| piece.copy_from_slice(list));
    out
}

/// Each tile's sites (none for a free tile, which the tree is not asked about), x
/// fastest.
fn tile_sites(tree: &LinearOctree, band: &TileBand, grow: bool) -> Vec<Option<Vec<bool>>> {
    let t = 1u32 << band.k;
    band.tiles
        .par_iter()
        .zip(&band.mixed)
        .map(|(&p, &mixed)| {
            if !mixed {
                return None;
            }
            let c = unpack(p).map(|x| i64::from(x) << band.k);
            let full = tree.occupancy(c, t);
            full.contains(&grow).then(|| full.into_iter().map(|f| f == grow).collect())
        })
        .collect()
}

/// The cost under which a voxel is settled by a step of `radius` (see the module doc):
/// `(2 radius - 4)^2` rounded up (a cost is an integer), 0 (none) for radii up to 2.
fn settled(radius: f64) -> i64 {
    if radius > 2.0 { (2.0 * radius - 4.0).powi(2).ceil().min(1e18) as i64 } else { 0 }
}

/// The nearest site of every voxel of `band`'s tiles (their `sites`) whose cost is at
/// most `cap`, else [`Feature::NONE`], `v` a tile in the tiles' order (see the module
/// doc), but for the voxels the last pass leaves alone, settled (under `settled` after
/// the second pass) and in no stretch: those keep the second pass's sites, each also
/// costing under `settled`; progress three a tile. Passes two and three by the window
/// where it applies ([`feature_window_pass`]), else by the envelope.
fn feature_transform<F: Feature>(
    band: &TileBand,
    sites: &[Option<Vec<bool>>],
    cap: i64,
    settled: i64,
    progress: &dyn Progress,
) -> Vec<F> {
    let window = 1 << band.k == LANES && cap_reach(cap) <= WINDOW_FEATURE_REACH;
    let pass: Pass<F> = if window { feature_window_pass } else { feature_pass };
    features_by(band, sites, (cap, settled), pass, progress)
}

/// A pass two or three of the feature transform, by the envelope or the window.
type Pass<F> = fn(&[Run], &mut [F], usize, [usize; 3], (i64, i64), &TileBand, &dyn Progress);

/// [`feature_transform`] with passes two and three by `pass`.
fn features_by<F: Feature>(
    band: &TileBand,
    sites: &[Option<Vec<bool>>],
    (cap, settled): (i64, i64),
    pass: Pass<F>,
    progress: &dyn Progress,
) -> Vec<F> {
    let t = 1usize << band.k;
    let v = t * t * t;
    // Filled in parallel: the first touch of the pages is most of the cost.
    let mut features: Vec<F> = rayon::iter::repeat_n(F::NONE, band.tiles.len() * v).collect();
    // Pass one, along x: the nearest site along each row.
    for_runs(&runs(&band.tiles, 0), &mut features, v, band, progress, |run, slots| {
        let (before, after) = (run.before == Kind::Site, run.after == Kind::Site);
        if !before && !after && run.slots.iter().all(|&s| sites[s].is_none()) {
            return;
        }
        let len = run.len() * t;
        let mut row = vec![false; len + 2];
        let (mut costs, mut nearest) = (vec![0i64; len], vec![0u32; len]);
        for yz in 0..t * t {
            row[0] = before;
            row[len + 1] = after;
            for (j, &s) in run.slots.iter().enumerate() {
                let cells = &mut row[1 + j * t..1 + (j + 1) * t];
                match &sites[s] {
                    Some(site) => cells.copy_from_slice(&site[t * yz..t * (yz + 1)]),
                    None => cells.fill(false),
                }
            }
            nearest_site_along_row(&row, 1, cap, &mut costs, Some((0, &mut nearest[..])));
            for (j, tile) in slots.iter_mut().enumerate() {
                for x in 0..t {
                    let at = j * t + x;
                    tile[x + t * yz] =
                        if costs[at] <= cap { F::of([i64::from(nearest[at]) - 1 - at as i64, 0, 0]) } else { F::NONE };
                }
            }
        }
    });
    pass(&runs(&band.tiles, 1), &mut features, 1, [t, 1, t * t], (cap, 0), band, progress);
    pass(&runs(&band.tiles, 2), &mut features, 2, [t * t, 1, t], (cap, settled), band, progress);
    features
}

/// A face's crossing as [`FaceCrossings`] gives it, or the face itself (`t = 1/2`, the
/// axis towards `direction`), in `f64`.
fn crossing_or_face(found: Option<(f32, [f32; 3])>, direction: u8) -> (f64, DVec3) {
    let (t, normal) = found.unwrap_or_else(|| {
        let mut axis = [0.0; 3];
        axis[usize::from(direction / 2)] = if direction & 1 == 1 { 1.0 } else { -1.0 };
        (0.5, axis)
    });
    (f64::from(t), DVec3::from(normal.map(f64::from)))
}

/// Whether a voxel at distance `g` (minus infinity: a site) flips.
fn flips(g: f64, radius: f64) -> bool {
    g > f64::NEG_INFINITY && g < radius
}

/// The distance of a voxel measured lazily that does not flip (the sub-voxel distance
/// bounded at least the radius), not yet measured: flips nothing (NaN compares false).
const PENDING: (f64, DVec3) = (f64::NAN, DVec3::ZERO);

/// Passes two and three of the feature transform along `runs`' axis, in place: along
/// each line (read whole before it is written), the entry minimizing `axis_cost(x - i)
/// + cost(i)` (the first of equal ones), a site tile beyond a run's end giving its first
/// voxel; `strides` are the steps within a tile along the axis and the two others.
///
/// Voxels whose entries cost under `settled` are left as they are (each voxel's own
/// entry is a candidate, so its result would cost under `settled` too) unless they lie
/// between others; the rest are transformed in stretches, each from the entries within
/// the reach of the cap of its ends (an entry farther costs more than the cap there).
fn feature_pass<F: Feature>(
    runs: &[Run],
    features: &mut [F],
    axis: usize,
    strides: [usize; 3],
    (cap, settled): (i64, i64),
    band: &TileBand,
    progress: &dyn Progress,
) {
    let t = 1usize << band.k;
    let v = t * t * t;
    for_runs(runs, features, v, band, progress, |run, slots| {
        let len = run.len() * t;
        let (before, after) = (run.before == Kind::Site, run.after == Kind::Site);
        let mut g = vec![FAR; len + 2];
        let mut line = vec![F::NONE; len + 2];
        let entries: Vec<u32> = (0..len as u32 + 2).collect();
        let (mut out, mut nearest) = (vec![0i64; len], vec![0u32; len]);
        let (mut sites, mut starts) = (Vec::new(), Vec::new());
        let own = F::of([0; 3]);
        let reach = cap_reach(cap);
        for b in 0..t {
            for a in 0..t {
                let base = a * strides[1] + b * strides[2];
                (g[0], line[0]) = if before { (0, own) } else { (FAR, F::NONE) };
                (g[len + 1], line[len + 1]) = if after { (0, own) } else { (FAR, F::NONE) };
                let mut any = before || after;
                for (j, tile) in slots.iter().enumerate() {
                    for i in 0..t {
                        let f = tile[base + i * strides[0]];
                        let d = f.cost();
                        any |= d <= cap;
                        (g[1 + j * t + i], line[1 + j * t + i]) = (d, f);
                    }
                }
                if !any {
                    continue;
                }
                // Each stretch from a voxel not settled to the last one before a gap of
                // more than `2 reach` settled ones, from the entries within `reach`.
                let mut x = 0;
                while x < len {
                    if g[1 + x] < settled {
                        x += 1;
                        continue;
                    }
                    let (lo, mut hi) = (x, x);
                    for y in x + 1..len {
                        if y > hi + 2 * reach {
                            break;
                        }
                        if g[1 + y] >= settled {
                            hi = y;
                        }
                    }
                    let (e0, e1) = ((1 + lo).saturating_sub(reach), (2 + hi + reach).min(len + 2));
                    lower_envelope(
                        &g[e0..e1],
                        1 + lo - e0,
                        cap,
                        &mut out[lo..=hi],
                        &mut sites,
                        &mut starts,
                        Some((&entries[e0..e1], &mut nearest[lo..=hi])),
                    );
                    for at in lo..=hi {
                        let from = nearest[at] as usize;
                        let f = line[from];
                        slots[at / t][base + (at % t) * strides[0]] = if f != F::NONE && out[at] <= cap {
                            f.moved(axis, from as i64 - 1 - at as i64)
                        } else {
                            F::NONE
                        };
                    }
                    x = hi + 1;
                }
            }
        }
    });
}

/// The farthest an entry under `cap` reaches along a line: `axis_cost(o) <= cap` only
/// for `|o|` under this (`(2 |o| - 1)^2 > cap` from `|o| = (isqrt(cap) + 1) / 2 + 1`
/// on, one more than needed, for safety).
fn cap_reach(cap: i64) -> usize {
    usize::try_from((cap.isqrt() + 1) / 2 + 1).unwrap_or(usize::MAX / 4)
}

/// The largest [`cap_reach`] [`feature_window_pass`] is used for: it costs `2 R + 1`
/// lane steps a voxel, where the envelope's cost does not grow with the reach; at 64
/// the costs stay within 15 bits. The window still won at a reach of 63 (PR 6647 at
/// depth 8 grown by 60.3 voxels: the whole offset in 41% fewer instructions); the
/// crossover lies beyond, not measured.
const WINDOW_FEATURE_REACH: usize = 64;

/// [`feature_pass`] by the window ([`window_argmin`]), for tiles of [`LANES`] voxels a
/// side where the cap's reach is at most [`WINDOW_FEATURE_REACH`] (so costs fit 15
/// bits): each voxel's least cost along the line and the first entry along it that
/// gives it (the envelope's choice among equal ones) from the window, the same
/// features for every voxel the pass must transform. The settled voxels are left
/// alone, all of them (the envelope transforms those in short gaps between others:
/// either way each keeps a site under `settled`, which is all that is read of it), and
/// the window skips blocks of them. The tiles' rows across the axis are the lanes
/// (`strides[1] == 1`). Compiled with AVX2 too, used where the CPU has it.
fn feature_window_pass<F: Feature>(
    runs: &[Run],
    features: &mut [F],
    axis: usize,
    strides: [usize; 3],
    (cap, settled): (i64, i64),
    band: &TileBand,
    progress: &dyn Progress,
) {
    assert!(1 << band.k == LANES && strides[1] == 1, "a window pass over rows of tiles of {LANES} voxels");
    let cap = i16::try_from(cap).ok().filter(|&c| c < i16::MAX).expect("a window pass's cap in 15 bits");
    let settled = i16::try_from(settled).expect("settled under the cap");
    // The taps `|o| <= w`: beyond, `axis_cost(o)` is over the cap.
    let w = (0..).take_while(|&o| axis_cost(o) <= i64::from(cap)).last().unwrap_or(0) as usize;
    let taps: Vec<i16> = (0..=2 * w).map(|j| axis_cost(j as i64 - w as i64) as i16).collect();
    let pass = WindowPass { axis, strides, cap, settled, w, taps, own: F::of([0; 3]) };
    let avx2 = has_avx2();
    for_runs(runs, features, LANES * LANES * LANES, band, progress, |run, slots| {
        #[cfg(target_arch = "x86_64")]
        if avx2 {
            // SAFETY: the CPU has AVX2 (checked at run time).
            return unsafe { pass.run_avx2(run, slots) };
        }
        pass.run(run, slots);
    });
}

/// What a window pass reads (see [`feature_window_pass`]).
struct WindowPass<F> {
    axis: usize,
    strides: [usize; 3],
    cap: i16,
    settled: i16,
    /// The window's reach.
    w: usize,
    /// `axis_cost(j - w)`.
    taps: Vec<i16>,
    /// A site's own feature.
    own: F,
}

impl<F: Feature> WindowPass<F> {
    /// [`WindowPass::run`] compiled with AVX2.
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn run_avx2(&self, run: &Run, slots: &mut [&mut [F]]) {
        self.run(run, slots);
    }

    /// One run of tiles (`slots`), layer by layer across the axis.
    #[inline(always)]
    fn run(&self, run: &Run, slots: &mut [&mut [F]]) {
        const T: usize = LANES;
        let WindowPass { axis, strides, cap, settled, w, ref taps, own } = *self;
        let len = run.len() * T;
        let (before, after) = (run.before == Kind::Site, run.after == Kind::Site);
        // costs[w + e]: the lanes' costs of entry e (0 and len + 1 the site tiles
        // beyond the ends), none (i16::MAX) beyond; line[e]: their features; least[x]
        // and first[x]: voxel x's least cost and the tap giving it; need[x / T]: a
        // block of voxels not all settled.
        let mut costs = vec![[i16::MAX; T]; len + 2 + 2 * w];
        let mut line = vec![[F::NONE; T]; len + 2];
        let (mut least, mut first) = (vec![[i16::MAX; T]; len], vec![[0i16; T]; len]);
        let mut need = vec![false; run.len()];
        for (e, site) in [(0, before), (len + 1, after)] {
            if site {
                costs[w + e] = [0; T];
                line[e] = [own; T];
            }
        }
        for b in 0..T {
            let mut any = before || after;
            for (j, tile) in slots.iter().enumerate() {
                let mut open = false;
                for i in 0..T {
                    let at = b * strides[2] + i * strides[0];
                    let row: &[F; T] = tile[at..at + T].try_into().expect("a row of a tile");
                    let e = 1 + j * T + i;
                    line[e] = *row;
                    let c = lane_costs(row, cap);
                    any |= c != [i16::MAX; T];
                    open |= c.iter().any(|&c| c >= settled);
                    costs[w + e] = c;
                }
                need[j] = open;
            }
            if !any || !need.contains(&true) {
                continue;
            }
            window_argmin(costs[1..].as_flattened(), taps, least.as_flattened_mut(), first.as_flattened_mut(), &need);
            for (j, tile) in slots.iter_mut().enumerate().filter(|(j, _)| need[*j]) {
                for i in 0..T {
                    let at = b * strides[2] + i * strides[0];
                    let row: &mut [F; T] = (&mut tile[at..at + T]).try_into().expect("a row of a tile");
                    let x = j * T + i;
                    let (c, m, o) = (&costs[w + 1 + x], &least[x], &first[x]);
                    for a in 0..T {
                        if c[a] >= settled {
                            // The entry `x + 1 + o - w` of the tap `o`.
                            let o = o[a] as usize;
                            row[a] = if m[a] <= cap {
                                line[x + 1 + o - w][a].moved(axis, o as i64 - w as i64)
                            } else {
                                F::NONE
                            };
                        }
                    }
                }
            }
        }
    }
}

/// The costs of a tile's row of features (each [`Feature::cost_under`] `cap`), none
/// as `i16::MAX`.
#[inline(always)]
fn lane_costs<F: Feature>(row: &[F; LANES], cap: i16) -> [i16; LANES] {
    let mut out = [0; LANES];
    for (c, f) in out.iter_mut().zip(row) {
        *c = f.cost_under(cap as u16).min(i16::MAX as u16) as i16;
    }
    out
}

/// A bit a voxel of a tile, x fastest (tiles of at most 8^3 voxels).
#[derive(Clone, Copy, Default)]
struct Mask([u64; 8]);

impl Mask {
    fn get(&self, i: usize) -> bool {
        (self.0[i >> 6] >> (i & 63)) & 1 == 1
    }

    fn set(&mut self, i: usize) {
        self.0[i >> 6] |= 1 << (i & 63);
    }

    fn is_empty(&self) -> bool {
        self.0.iter().all(|&w| w == 0)
    }

    /// The first `v` bits set.
    fn first(v: usize) -> Mask {
        Mask(std::array::from_fn(|w| match v.saturating_sub(64 * w) {
            0 => 0,
            bits if bits >= 64 => u64::MAX,
            bits => (1 << bits) - 1,
        }))
    }

    /// The set bits, in increasing order.
    fn ones(self) -> impl Iterator<Item = usize> {
        self.0.into_iter().enumerate().flat_map(|(w, mut bits)| {
            std::iter::from_fn(move || {
                (bits != 0).then(|| {
                    let b = bits.trailing_zeros() as usize;
                    bits &= bits - 1;
                    64 * w + b
                })
            })
        })
    }

    /// Of a tile of 8^3 voxels (a word a z-layer, `x + 8 y` in it), the voxels whose
    /// bit differs from a neighbour's towards `+axis` (`next[axis][1]` beyond the tile)
    /// or, where `below[axis]`, towards `-axis` from `next[axis][0]` beyond it.
    fn faces_8(&self, next: &[[Mask; 2]; 3], below: [bool; 3]) -> Mask {
        const X0: u64 = 0x0101_0101_0101_0101;
        const X7: u64 = X0 << 7;
        const Y0: u64 = 0xff;
        const Y7: u64 = Y0 << 56;
        let w = &self.0;
        Mask(std::array::from_fn(|z| {
            let a = w[z];
            let mut d = ((a ^ (a >> 1)) & !X7) | ((a ^ (next[0][1].0[z] << 7)) & X7);
            d |= ((a ^ (a >> 8)) & !Y7) | ((a ^ (next[1][1].0[z] << 56)) & Y7);
            d |= a ^ if z < 7 { w[z + 1] } else { next[2][1].0[0] };
            if below[0] {
                d |= (a ^ (next[0][0].0[z] >> 7)) & X0;
            }
            if below[1] {
                d |= (a ^ (next[1][0].0[z] >> 56)) & Y0;
            }
            if below[2] && z == 0 {
                d |= a ^ next[2][0].0[7];
            }
            d
        }))
    }
}

/// Where a tile lies: in the band (its slot) or a site tile next to it.
#[derive(Clone, Copy)]
enum Place {
    Band(usize),
    Site,
}

/// The exposed faces' planes of sites measured lately, relative to the site's centre
/// (a direct-mapped cache of one thread: a site is the nearest of several voxels).
struct SiteCache {
    keys: Vec<u64>,
    planes: Vec<([Plane; 6], usize)>,
}

impl SiteCache {
    const SIZE: usize = 512;
}

impl Default for SiteCache {
    fn default() -> Self {
        let none = Plane { point: DVec3::ZERO, normal: DVec3::ZERO };
        SiteCache { keys: vec![u64::MAX; Self::SIZE], planes: vec![([none; 6], 0); Self::SIZE] }
    }
}

/// What measuring a tile's voxels reads.
struct Measure<'a, F> {
    tree: &'a LinearOctree,
    band: &'a TileBand,
    /// The band's tiles and the site tiles next to them, by packed position.
    places: FxHashMap<Packed, Place>,
    sites: &'a [Option<Vec<bool>>],
    features: &'a [F],
    surface: &'a dyn FaceCrossings,
    step: Step,
    cap: i64,
}

impl<'a, F: Feature> Measure<'a, F> {
    fn new(
        tree: &'a LinearOctree,
        band: &'a TileBand,
        sites: &'a [Option<Vec<bool>>],
        features: &'a [F],
        surface: &'a dyn FaceCrossings,
        step: Step,
        cap: i64,
    ) -> Self {
        let mut places = FxHashMap::default();
        places.reserve(band.tiles.len() + band.sites.len());
        places.extend(band.tiles.iter().enumerate().map(|(s, &p)| (p, Place::Band(s))));
        places.extend(band.sites.iter().map(|&p| (p, Place::Site)));
        Measure { tree, band, places, sites, features, surface, step, cap }
    }

    /// Where the tile of voxel `p` (inside the domain) lies, `None` for a free tile
    /// beyond the band.
    fn place(&self, p: [i64; 3]) -> Option<Place> {
        self.places.get(&pack(p.map(|c| (c >> self.band.k) as u32))).copied()
    }

    /// The index of voxel `p` in its tile.
    fn index(&self, p: [i64; 3]) -> usize {
        let t = 1i64 << self.band.k;
        let l = p.map(|c| (c & (t - 1)) as usize);
        l[0] + (t as usize) * (l[1] + (t as usize) * l[2])
    }

    /// Whether voxel `p` is of the phase the step spreads (outside the domain: when
    /// shrinking).
    fn is_site(&self, p: [i64; 3]) -> bool {
        let n = i64::from(self.tree.domain().resolution());
        if p.iter().any(|&c| c < 0 || c >= n) {
            return !self.step.grow;
        }
        self.is_site_in(p, self.place(p))
    }

    /// [`Measure::is_site`] of voxel `p` inside the domain, its tile at `place`.
    fn is_site_in(&self, p: [i64; 3], place: Option<Place>) -> bool {
        match place {
            Some(Place::Band(s)) => self.sites[s].as_ref().is_some_and(|site| site[self.index(p)]),
            Some(Place::Site) => true,
            None => false,
        }
    }

    /// The crossing of the face of the full voxel `voxel` towards `direction`, or the
    /// face itself.
    fn crossing(&self, voxel: [i64; 3], direction: u8) -> (f64, DVec3) {
        let code = morton::encode(voxel[0] as u32, voxel[1] as u32, voxel[2] as u32);
        crossing_or_face(self.surface.face_crossing(code, direction), direction)
    }

    /// The distance of voxel `p` (inside the domain, in the tile at `place`) and the
    /// direction from its foot point on the surface (see the module doc): minus infinity
    /// for a site, infinity beyond the cap; [`PENDING`] when `lazy` and the voxel is
    /// known not to flip ([`Measure::distance_in`]).
    fn distance_at(&self, p: [i64; 3], place: Option<Place>, lazy: bool, cache: &mut SiteCache) -> (f64, DVec3) {
        match place {
            Some(Place::Band(s)) => self.distance_in(p, s, self.index(p), lazy, cache),
            Some(Place::Site) => (f64::NEG_INFINITY, DVec3::ZERO),
            None => (f64::INFINITY, DVec3::ZERO),
        }
    }

    /// [`Measure::distance_at`] of voxel `p`, the `i`th of tile `s`. When `lazy`, a
    /// voxel whose sub-voxel distance is needed but bounded at least the radius by its
    /// crossings and its cube (`d >= min(d_cube - 1/2, min_i |p - c_i|)`, as
    /// [`distance_to_site`] computes it) gives [`PENDING`]: it does not flip, and its
    /// distance is measured only when a face of the result needs it.
    fn distance_in(&self, p: [i64; 3], s: usize, i: usize, lazy: bool, cache: &mut SiteCache) -> (f64, DVec3) {
        if self.sites[s].as_ref().is_some_and(|site| site[i]) {
            return (f64::NEG_INFINITY, DVec3::ZERO);
        }
        let v = 1usize << (3 * self.band.k);
        let Some(o) = self.features[s * v + i].offset() else {
            return (f64::INFINITY, DVec3::ZERO);
        };
        let cost = cost_of(o);
        if cost > self.cap {
            return (f64::INFINITY, DVec3::ZERO);
        }
        let radius = self.step.radius;
        let (exact_lo, exact_hi) = self.exact_range();
        let c = cost as f64;
        let d_cube = c.sqrt() / 2.0;
        if c >= exact_hi {
            return (d_cube - 0.5, DVec3::ZERO);
        }
        if c < exact_lo {
            return (d_cube, DVec3::ZERO);
        }
        // Each crossing lies on a segment from the site's centre to a neighbour's (`t`
        // in `0..=1`), so at least `max(|o_a| - 1, 0)` from `p` on each axis: a bound
        // that spares looking the planes up (with a margin for the rounding of theirs).
        if lazy && d_cube - 0.5 >= radius {
            let near = o.iter().map(|&c| ((c.abs() - 1).max(0) as f64).powi(2)).sum::<f64>().sqrt();
            if near >= radius + 1e-9 {
                return PENDING;
            }
        }
        let site: [i64; 3] = std::array::from_fn(|a| p[a] + o[a]);
        let (own, count) = self.site_planes(site, cache);
        let rel = DVec3::new(o[0] as f64, o[1] as f64, o[2] as f64);
        let mut planes = own;
        for plane in &mut planes[..count] {
            plane.point = rel + plane.point;
        }
        if lazy && d_cube - 0.5 >= radius && planes[..count].iter().all(|plane| plane.point.length() >= radius) {
            return PENDING;
        }
        let (d, foot) = distance_to_site(&planes[..count], d_cube);
        (d, -foot)
    }

    /// The tangent planes of site `site`'s exposed faces, their points relative to its
    /// centre (through `cache`).
    fn site_planes(&self, site: [i64; 3], cache: &mut SiteCache) -> ([Plane; 6], usize) {
        let key = pack(site.map(|c| (c + 1) as u32));
        let slot = (key.wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 55) as usize;
        if cache.keys[slot] == key {
            return cache.planes[slot];
        }
        // The exposed directions; a neighbour in the site's own tile is read from the
        // place looked up once.
        let n = i64::from(self.tree.domain().resolution());
        let own = site.iter().all(|&c| (0..n).contains(&c)).then(|| self.place(site));
        let mut exposed = 0u8;
        for direction in 0..6u8 {
            let (axis, positive) = (usize::from(direction / 2), direction & 1 == 1);
            let mut next = site;
            next[axis] += if positive { 1 } else { -1 };
            let is_site = match own {
                Some(place) if next[axis] >> self.band.k == site[axis] >> self.band.k => self.is_site_in(next, place),
                _ => self.is_site(next),
            };
            if !is_site {
                exposed |= 1 << direction;
            }
        }
        // Growing, the faces are the site's own: found together.
        let own_faces = if self.step.grow {
            let code = morton::encode(site[0] as u32, site[1] as u32, site[2] as u32);
            self.surface.voxel_crossings(code, exposed)
        } else {
            [None; 6]
        };
        let mut planes = [Plane { point: DVec3::ZERO, normal: DVec3::ZERO }; 6];
        let mut count = 0;
        for direction in (0..6u8).filter(|d| (exposed >> d) & 1 == 1) {
            let (axis, positive) = (usize::from(direction / 2), direction & 1 == 1);
            let mut e = DVec3::ZERO;
            e[axis] = if positive { 1.0 } else { -1.0 };
            planes[count] = if self.step.grow {
                let (t, normal) = crossing_or_face(own_faces[usize::from(direction)], direction);
                Plane { point: e * t, normal }
            } else {
                // The face belongs to the full neighbour, seen from its side.
                let mut next = site;
                next[axis] += if positive { 1 } else { -1 };
                let (t, normal) = self.crossing(next, direction ^ 1);
                Plane { point: e * (1.0 - t), normal: -normal }
            };
            count += 1;
        }
        cache.keys[slot] = key;
        cache.planes[slot] = (planes, count);
        (planes, count)
    }

    /// The voxels of tile `s` of the phase the step spreads in the result (its sites
    /// and the voxels that flip), and of those the ones that flip, x fastest.
    fn spread(&self, s: usize, cache: &mut SiteCache) -> (Mask, Mask) {
        let k = self.band.k;
        let t = 1usize << k;
        let min = unpack(self.band.tiles[s]).map(|c| i64::from(c) << k);
        let v = t * t * t;
        let (site, features) = (self.sites[s].as_deref(), &self.features[s * v..(s + 1) * v]);
        let (exact_lo, exact_hi) = self.exact_range();
        let (mut spread, mut flipped) = (Mask::default(), Mask::default());
        for (i, f) in features.iter().enumerate() {
            if site.is_some_and(|site| site[i]) {
                spread.set(i);
                continue;
            }
            // As [`Measure::distance_in`] decides, without the distance where the cost
            // alone does.
            let c = f.cost();
            if c > self.cap || c as f64 >= exact_hi {
                continue;
            }
            let flip = (c as f64) < exact_lo || {
                let p = [min[0] + (i % t) as i64, min[1] + (i / t % t) as i64, min[2] + (i / (t * t)) as i64];
                flips(self.distance_in(p, s, i, true, cache).0, self.step.radius)
            };
            if flip {
                spread.set(i);
                flipped.set(i);
            }
        }
        (spread, flipped)
    }

    /// The range of four times the squared lattice distance where the sub-voxel
    /// distance is needed: it lies within `[d_cube - 1/2, d_cube + sqrt 3 / 2]`, and a
    /// face's far end is a voxel farther. Under it a voxel flips, from its end on not.
    fn exact_range(&self) -> (f64, f64) {
        let radius = self.step.radius;
        let exact_lo = if radius > 1.0 { (2.0 * radius - 2.0).powi(2) } else { 0.0 };
        (exact_lo, (2.0 * radius + 3.0).powi(2))
    }

    /// The distance of voxel `p`, the `i`th of tile `s`, measured once a tile: kept in
    /// `g` where `known` marks it.
    fn measured(
        &self,
        p: [i64; 3],
        s: usize,
        i: usize,
        (g, known): (&mut [(f64, DVec3)], &mut Mask),
        cache: &mut SiteCache,
    ) -> (f64, DVec3) {
        if !known.get(i) {
            g[i] = self.distance_in(p, s, i, false, cache);
            known.set(i);
        }
        g[i]
    }

    /// Pushes the crossings of the result's faces tile `s` measures, from the result's
    /// phases (`spread`, a tile's [`Measure::spread`] by slot) and the distances of the
    /// faces' ends, measured here (in `g`, a tile's): each voxel's faces towards
    /// `+axis`, and towards `-axis` where that neighbour lies outside the band; both
    /// ends inside the domain. The places of the six tiles next to it are looked up
    /// once; a tile of one phase whose neighbours are all of it has no face.
    fn faces(
        &self,
        s: usize,
        spread: &[(Mask, Mask)],
        g: &mut [(f64, DVec3)],
        out: &mut Vec<NewCrossing>,
        cache: &mut SiteCache,
    ) {
        let k = self.band.k;
        let t = 1usize << k;
        let v = t * t * t;
        let grow = self.step.grow;
        let n = i64::from(self.tree.domain().resolution());
        let tile = unpack(self.band.tiles[s]).map(i64::from);
        let min = tile.map(|c| c << k);
        let next: [[Option<Place>; 2]; 3] = std::array::from_fn(|axis| {
            [-1, 1].map(|e| {
                let mut c = tile;
                c[axis] += e;
                if c.iter().any(|&x| x < 0) {
                    return None;
                }
                self.places.get(&pack(c.map(|x| x as u32))).copied()
            })
        });
        let own = spread[s].0;
        // Whether the `i`th voxel of the tile at `place` is of the spreading phase.
        let spreads = |place: Option<Place>, i: usize| match place {
            Some(Place::Band(b)) => spread[b].0.get(i),
            Some(Place::Site) => true,
            None => false,
        };
        let masks = next.map(|pair| {
            pair.map(|place| match place {
                Some(Place::Band(b)) => spread[b].0,
                Some(Place::Site) => Mask([u64::MAX; 8]),
                None => Mask::default(),
            })
        });
        // A face towards `-axis` is this tile's only where that neighbour is not in the band.
        let below = next.map(|pair| !matches!(pair[0], Some(Place::Band(_))));
        let candidates = if t == 8 { own.faces_8(&masks, below) } else { Mask::first(v) };
        let mut known = Mask::default();
        for i in candidates.ones() {
            let l = [i % t, i / t % t, i / (t * t)];
            let p: [i64; 3] = std::array::from_fn(|a| min[a] + l[a] as i64);
            let fi = own.get(i) == grow;
            for axis in 0..3 {
                let stride = [1, t, t * t][axis];
                let mut q = p;
                q[axis] += 1;
                if q[axis] < n {
                    let inside = l[axis] + 1 < t;
                    let fq = grow == if inside { own.get(i + stride) } else { spreads(next[axis][1], self.index(q)) };
                    if fi != fq {
                        let gi = self.measured(p, s, i, (&mut *g, &mut known), cache);
                        let gq = if inside {
                            self.measured(q, s, i + stride, (&mut *g, &mut known), cache)
                        } else {
                            self.distance_at(q, next[axis][1], false, cache)
                        };
                        self.face(p, gi, gq, axis, out);
                    }
                }
                let mut q = p;
                q[axis] -= 1;
                if l[axis] == 0 && q[axis] >= 0 && below[axis] {
                    let fq = grow == spreads(next[axis][0], 0);
                    if fq != fi {
                        let gq = self.distance_at(q, next[axis][0], false, cache);
                        let gi = self.measured(p, s, i, (&mut *g, &mut known), cache);
                        self.face(q, gq, gi, axis, out);
                    }
                }
            }
        }
    }

    /// Whether a voxel at distance `g` is full in the result (a site: of the phase the
    /// step spreads; [`PENDING`]: one that does not flip).
    fn result_full(&self, g: f64) -> bool {
        let grow = self.step.grow;
        if g == f64::NEG_INFINITY { grow } else { flips(g, self.step.radius) == grow }
    }

    /// Pushes the result's crossing on the face between voxel `p` (distance and
    /// direction `gi`) and `p + e_axis` (`gj`), when the result has one there.
    fn face(
        &self,
        p: [i64; 3],
        (gi, ai): (f64, DVec3),
        (gj, aj): (f64, DVec3),
        axis: usize,
        out: &mut Vec<NewCrossing>,
    ) {
        let (grow, radius) = (self.step.grow, self.step.radius);
        let (fi, fj) = (self.result_full(gi), self.result_full(gj));
        if fi == fj {
            return;
        }
        let ((gf, af), (ge, ae), direction) =
            if fi { ((gi, ai), (gj, aj), 2 * axis as u8 + 1) } else { ((gj, aj), (gi, ai), 2 * axis as u8) };
        let mut fv = p;
        if !fi {
            fv[axis] += 1;
        }
        // A site's value: minus its distance to the original crossing between the
        // two, along the normal.
        let value = |g: f64, full_end: bool| {
            if g > f64::NEG_INFINITY {
                return g;
            }
            let (t, normal) = self.crossing(fv, direction);
            let along = if full_end { t } else { 1.0 - t };
            -along * normal[axis].abs()
        };
        let (gf, ge) = (value(gf, true), value(ge, false));
        let t = if grow { (radius - gf) / (ge - gf) } else { (gf - radius) / (gf - ge) };
        let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.5 };
        // The normal: the direction from the foot point (to the voxel growing, from it
        // shrinking), the two ends' interpolated at the crossing (the distance's
        // gradient there) when they are within 45 degrees of each other (one surface
        // nearest both, as on a grown edge's round); else the end's whose direction is
        // the nearer the face's own (two surfaces nearest, as at an edge voxel with two
        // faces equally near: a crease, not to be blurred).
        let mut axis_normal = DVec3::ZERO;
        axis_normal[axis] = if fi { 1.0 } else { -1.0 };
        let sign = if grow { 1.0 } else { -1.0 };
        let unit = |a: DVec3| (a.length_squared() > 1e-18).then(|| (a * sign).normalize());
        let normal = match (unit(af), unit(ae)) {
            (Some(f), Some(e)) if f.dot(e) > std::f64::consts::FRAC_1_SQRT_2 => f.lerp(e, t).normalize(),
            (Some(f), Some(e)) => {
                if e.dot(axis_normal) >= f.dot(axis_normal) {
                    e
                } else {
                    f
                }
            }
            (Some(a), None) | (None, Some(a)) => a,
            (None, None) => axis_normal,
        }
        .as_vec3()
        .to_array();
        let voxel = morton::encode(fv[0] as u32, fv[1] as u32, fv[2] as u32);
        out.push(NewCrossing { voxel, direction, t: t as f32, normal });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::progress::NoProgress;
    use crate::test_util::{BoxesAndNoise, Rng, boxes_and_noise};

    /// A solid at depth 5 of a few random boxes and scattered voxels: site, mixed and
    /// free tiles, and ties between equally near sites.
    fn random_solid(rng: &mut Rng) -> LinearOctree {
        boxes_and_noise(rng, &BoxesAndNoise { fewest: 1, more: 4, against_face: 0, shortest: 1, noise: 60 })
    }

    #[test]
    fn features_name_the_least_nearest_site_in_z_y_x_order_by_brute_force() {
        // Passes two and three by the envelope and by the window, each against the
        // brute force.
        for pass in [feature_pass as Pass<u32>, feature_window_pass] {
            features_are_the_brute_force_ones(pass);
        }
    }

    fn features_are_the_brute_force_ones(pass: Pass<u32>) {
        let mut rng = Rng(0x39_f7a3);
        let mut kept = 0;
        for round in 0..4 {
            let tree = random_solid(&mut rng);
            let full = tree.occupancy([0; 3], 32);
            for (radius, grow) in [(0.7, true), (2.3, false), (4.6, true), (4.6, false), (7.2, true), (7.2, false)] {
                let step = Step { radius, grow, metric: crate::octree::Metric::Euclidean };
                let band = band(&tree, step, u64::MAX).unwrap().unwrap();
                let sites = tile_sites(&tree, &band, grow);
                let cap = (2.0 * radius + 3.0).powi(2).ceil() as i64;
                let settled = settled(radius);
                let features: Vec<u32> = features_by(&band, &sites, (cap, settled), pass, &NoProgress);
                let is_site = |p: [i64; 3]| {
                    if p.iter().any(|&c| !(0..32).contains(&c)) {
                        return !grow;
                    }
                    full[(p[0] + 32 * (p[1] + 32 * p[2])) as usize] == grow
                };
                let w = i64::from(step.reach_along_surface()) + 2;
                let t = 1usize << band.k;
                let v = t * t * t;
                let mut named = 0;
                for (s, &tile) in band.tiles.iter().enumerate() {
                    let min = unpack(tile).map(|c| i64::from(c) << band.k);
                    for i in 0..v {
                        let p = [min[0] + (i % t) as i64, min[1] + (i / t % t) as i64, min[2] + (i / (t * t)) as i64];
                        if is_site(p) {
                            continue;
                        }
                        // The least (cost, z, y, x) of the sites in reach.
                        let mut best: Option<(i64, [i64; 3])> = None;
                        for oz in -w..=w {
                            for oy in -w..=w {
                                for ox in -w..=w {
                                    let o = [ox, oy, oz];
                                    if !is_site(std::array::from_fn(|a| p[a] + o[a])) {
                                        continue;
                                    }
                                    let key = (cost_of(o), [oz, oy, ox]);
                                    if best.is_none_or(|b| key < b) {
                                        best = Some(key);
                                    }
                                }
                            }
                        }
                        let want = best.filter(|b| b.0 <= cap).map(|(_, [z, y, x])| [x, y, z]);
                        let got = features[s * v + i].offset();
                        named += usize::from(want.is_some());
                        // A settled voxel may keep another site, itself under the bound.
                        if best.is_some_and(|b| b.0 < settled) && got != want {
                            let o = got.expect("a settled voxel names a site");
                            assert!(is_site(std::array::from_fn(|a| p[a] + o[a])) && cost_of(o) < settled);
                            kept += 1;
                            continue;
                        }
                        assert_eq!(got, want, "round {round} step {step:?} voxel {p:?}");
                    }
                }
                assert!(named > 100, "round {round} step {step:?}: {named} voxels named a site");
            }
        }
        assert!(kept > 0, "no settled line was left alone");
    }

    #[test]
    fn features_hold_every_offset_in_their_range() {
        for o in [[0, 0, 0], [-511, 511, 3], [511, -512 + 1, -7]] {
            assert_eq!(<u32 as Feature>::of(o).offset(), Some(o));
        }
        let big = (1 << 20) - 1;
        for o in [[0, 0, 0], [-big, big, 3], [big, -big, -7]] {
            assert_eq!(<u64 as Feature>::of(o).offset(), Some(o));
        }
        // Moved along an axis in place, as decoded, moved and encoded again.
        for (o, axis, by) in
            [([3, -5, 7], 0, -9), ([-511, 0, 511], 2, -1022), ([0, 40, -40], 1, -80), ([9, 9, 9], 1, 500)]
        {
            let mut m = o;
            m[axis] += by;
            assert_eq!(<u32 as Feature>::of(o).moved(axis, by), <u32 as Feature>::of(m));
            assert_eq!(<u64 as Feature>::of(o).moved(axis, by), <u64 as Feature>::of(m));
        }
        for o in [[0, 0, 0], [-511, 511, 3], [511, -511, -7], [1, -1, 0]] {
            assert_eq!(<u32 as Feature>::of(o).cost(), cost_of(o));
        }
        assert_eq!(<u32 as Feature>::NONE.cost(), FAR);
        assert_eq!(<u32 as Feature>::NONE.offset(), None);
        assert_eq!(<u64 as Feature>::NONE.offset(), None);
    }
}
