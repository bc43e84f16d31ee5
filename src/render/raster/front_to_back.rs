//! Meagher's front-to-back octree display ("Geometric modeling using octree encoding",
//! 1982): full nodes visited nearest first, a node's faces that look at the viewer
//! drawn only into samples not yet covered, a subtree skipped when every sample of its
//! screen footprint is covered. No depth buffer within a solid.
//!
//! Steps, per screen strip of [`strip_rows`] sample rows (strips are independent rayon
//! tasks, each walking the octree culled to its rows, so the hits do not depend on the
//! thread count or the strips; [`Display`] draws one strip, so that the render pipeline
//! can shade a strip as soon as it is drawn):
//! 1. Walk the traversal octree's nodes front to back (`Pass::inner`, recursive: in
//!    every inner node the child on the viewer's side of all three mid planes first,
//!    then those across one plane, two, three). A node can only hide nodes visited
//!    after it.
//! 2. Footprint of a node: the box projected to the sample grid by one projective map
//!    (`column = X(p) / W(p)`, `row = Y(p) / W(p)`, `X, Y, W` affine in the voxel point
//!    `p`), bounded from its centre (see `Pass::footprint`: two divisions, no corners),
//!    widened by [`MARGIN`] samples and cut to the parent's footprint (the child's box
//!    is in the parent's). The centre's bound grows without limit as the box nears the
//!    eye's plane: a box whose nearest point is less than half as far as its centre
//!    takes the rectangle of its eight projected corners instead (`Pass::near_footprint`);
//!    a box reaching behind the eye's plane has no bounded projection, and is dropped
//!    when it lies wholly behind the eye or outside one of the planes through the eye
//!    and the parent footprint's edges, else takes all of the parent's footprint
//!    (`Pass::across_eye_plane`: without it, every node of a floor reaching behind the
//!    eye was drawn against every sample of its strip, 95 faces a sample).
//!    A child's `X, Y, W` is its parent's plus a per-size offset (no products). A node
//!    whose footprint has no uncovered sample is skipped, an inner node with its
//!    subtree; the remaining children of a node whose footprint lies in one tile are
//!    skipped once it is covered.
//! 3. Coverage is a bit a sample, kept in 8x8 tiles (one `u64` each, bit `8 row + col`),
//!    so a footprint test is one masked word test a tile it touches (one to four for
//!    most, tested together without a branch: [`Tiles::any_uncovered`]).
//! 4. A full node with an uncovered sample in its footprint: its faces that look at
//!    the viewer, then each uncovered sample of the footprint makes its voxel ray once
//!    (the camera ray from per-column and per-row terms, [`RayGrid`]) and tests those
//!    faces in axis order by the exact face rule (`Face::enters`; all three axes side
//!    by side, the first passed taken from a mask: [`NodeFaces::first_entered`]); the
//!    first face it enters covers the sample, with that face's [`VoxelRay::entry`] as
//!    the hit. (One ray a sample and node, not one a face: the ray, a square root and
//!    ten divisions, is the dear part of a test. The rays of a tile's uncovered
//!    samples are made first, then tested: with no branch between them their square
//!    roots and divisions overlap; Whitted classic, uniform 3x3: 1.09-1.11 s to
//!    1.05-1.07 s, with the faces read in place rather than copied a sample.)
//!
//! A node's lowest voxel travels down the walk packed in one word ([`Corner`]), its
//! faces are made only for a full node with an uncovered sample; the bunny at depth
//! 10, 1024x1024: 13% fewer instructions and 41% fewer mispredicted branches
//! (callgrind) than with the corner as an array and the faces searched one by one.
//!
//! Tie-breaking: a sample takes the first face in visiting order (nodes front to back,
//! faces of a node by axis) whose exact test it passes. Since the footprints only ever
//! propose samples (the exact test decides), this is the rule of the plain version
//! that tests every sample of a widened footprint, and the hits are the ray walk's bits.
//!
//! Precision of the margin: the footprint and the exact test are two roundings of the
//! same geometry. The test's in-plane point is off by a few ulps of `t d` along the ray,
//! which moves it on screen only by the ulps of its depth coordinate; the projection's
//! own rounding (a centre summed from at most 21 offsets, the bound, the rounding of
//! the bound to whole samples) is a few dozen ulps of the sample coordinates. Both
//! stay below 1e-6 samples for any domain (depth <= 21) and image (<= 16384 a side),
//! so [`MARGIN`] (1e-2 samples) only ever makes a footprint propose more samples,
//! never fewer: a sample the rounding of a bound drops lies on the widened edge,
//! [`MARGIN`] away from the projection.

use glam::DVec3;
use rayon::prelude::*;

use super::face::{NodeFaces, Viewer};
use crate::octree::{Domain, MAX_DEPTH};
use crate::render::film::ray_grid::RayGrid;
use crate::render::film::{Projection, SampleGrid, View};
use crate::render::scene::{Scene, SceneHit};
use crate::render::trace::{Inner, Traversal, VoxelRay};

/// Sample rows a strip (one parallel task) at least; a multiple of the tile height 8.
const STRIP_ROWS: usize = 64;

/// Sample rows a strip at `spp x spp` samples a pixel: the least multiple of both the
/// tile height 8 and `spp` (so that a strip is whole pixel rows, which the pipeline
/// shades at once) that is at least [`STRIP_ROWS`]: 64 for 1, 2, 4, 8 and 16, 72 for 3.
pub(crate) fn strip_rows(spp: u32) -> usize {
    let spp = spp.max(1) as usize;
    let (mut a, mut b) = (8, spp);
    while b != 0 {
        (a, b) = (b, a % b);
    }
    let lcm = 8 * spp / a;
    STRIP_ROWS.div_ceil(lcm) * lcm
}

/// SampleGrid by which a projected footprint is widened on every side.
const MARGIN: f64 = 1e-2;

/// Draws every solid of `scene` front to back into `seen` (row-major over the sample
/// grid, all `None` on entry); solids are merged by depth, ties to the earlier solid.
/// Returns the faces drawn: the visible faces of the full nodes with an uncovered
/// sample in their footprint (a node split between strips counts once a strip).
pub(crate) fn front_to_back(scene: &Scene, view: &View, samples: &SampleGrid, seen: &mut [Option<SceneHit>]) -> u64 {
    let display = Display::new(scene, view, samples);
    let columns = samples.columns() as usize;
    // A strip a task (rayon's default split leaves runs of several strips of unequal
    // work to one thread).
    seen.par_chunks_mut(display.strip_rows * columns)
        .enumerate()
        .with_max_len(1)
        .map_init(|| display.strip(), |strip, (k, out)| display.draw_strip(k, strip, out))
        .sum()
}

/// The display of a scene through a view, prepared once a frame; its strips are drawn
/// one at a time by [`Display::draw_strip`], on any thread, in any order (the
/// pipeline shades each strip's samples as soon as they are drawn).
pub(crate) struct Display<'a> {
    solids: Vec<Solid<'a>>,
    rays: RayGrid,
    columns: usize,
    /// Sample rows a strip ([`strip_rows`]).
    pub(crate) strip_rows: usize,
}

impl<'a> Display<'a> {
    pub(crate) fn new(scene: &'a Scene, view: &View, samples: &SampleGrid) -> Self {
        let solids = scene.solids.iter().map(|s| Solid::new(&s.traversal, view, samples)).collect();
        let (rays, columns, strip_rows) =
            (RayGrid::new(view, samples), samples.columns() as usize, strip_rows(samples.spp));
        Display { solids, rays, columns, strip_rows }
    }

    /// Coverage for this display's strips.
    pub(crate) fn strip(&self) -> Strip {
        Strip::new(self.columns, self.strip_rows)
    }

    /// Draws strip `k` (sample rows from `k strip_rows`) into `out`, its samples
    /// (row-major, all `None` on entry), with the coverage `strip` (any strip's: it is
    /// reset here); returns the faces drawn.
    pub(crate) fn draw_strip(&self, k: usize, strip: &mut Strip, out: &mut [Option<SceneHit>]) -> u64 {
        let columns = self.columns;
        let rows = out.len() / columns;
        let mut faces = 0;
        for (index, solid) in self.solids.iter().enumerate() {
            strip.reset(rows);
            let mut pass = Pass {
                solid,
                index,
                rays: &self.rays,
                row0: k * self.strip_rows,
                rows,
                columns,
                tiles: Tiles { covered: &mut strip.covered, tiles_x: strip.tiles_x },
                out: &mut *out,
                faces: 0,
            };
            pass.draw();
            faces += pass.faces;
        }
        faces
    }
}

/// A projective map from voxel units to the sample grid: `column = X / W`, `row = Y / W`,
/// with `X, Y, W` affine in the voxel point.
struct Projector {
    /// `X, Y, W` at the domain's origin (voxel `0, 0, 0`).
    base: DVec3,
    /// The change of `X, Y, W` a voxel along axis `a`, at `per_voxel[a]`.
    per_voxel: [DVec3; 3],
    /// The change of `Y` a voxel along x, y, z.
    dy: DVec3,
    /// The change of `X` a voxel along x, y, z.
    dx: DVec3,
    /// The change of `W` a voxel along x, y, z.
    dw: DVec3,
}

impl Projector {
    /// With `v = min + p h - eye` (world offset of voxel point `p`) and the image point of
    /// [`View::project`], `column = (x + 1) C / 2 - 1/2`, `row = (1 - y) R / 2 - 1/2`:
    /// perspective `X = v.(right C / (2 t a) + forward (C - 1) / 2)`,
    /// `Y = v.(-up R / (2 t) + forward (R - 1) / 2)`, `W = v.forward`;
    /// orthographic the same with `t` the half height and `W = 1`.
    fn new(view: &View, domain: &Domain, samples: &SampleGrid) -> Self {
        let (c, r) = (f64::from(samples.columns()), f64::from(samples.rows()));
        let t = view.half;
        let v0 = domain.min() - view.eye;
        let h = domain.voxel_size();
        let (kx, ky, kw, constant) = match view.projection {
            Projection::Perspective { .. } => (
                view.right * (c / (2.0 * t * view.aspect)) + view.forward * ((c - 1.0) * 0.5),
                -view.up * (r / (2.0 * t)) + view.forward * ((r - 1.0) * 0.5),
                view.forward,
                DVec3::ZERO,
            ),
            Projection::Orthographic { .. } => (
                view.right * (c / (2.0 * t * view.aspect)),
                -view.up * (r / (2.0 * t)),
                DVec3::ZERO,
                DVec3::new((c - 1.0) * 0.5, (r - 1.0) * 0.5, 1.0),
            ),
        };
        let base = DVec3::new(v0.dot(kx), v0.dot(ky), v0.dot(kw)) + constant;
        let (dx, dy, dw) = (kx * h, ky * h, kw * h);
        let per_voxel = [0, 1, 2].map(|a| DVec3::new(dx[a], dy[a], dw[a]));
        Projector { base, per_voxel, dy, dx, dw }
    }
}

/// What every node of one size shares: its half edge, how far its box reaches towards
/// the eye, and where its children's centres are.
#[derive(Clone, Copy, Debug, Default)]
struct Level {
    /// Half the edge, voxels.
    half: f64,
    /// `sum |dW| half`: the box's nearest point has `W >= W(centre) - reach`.
    reach: f64,
    /// `X, Y, W` of the centre of child `i` of a node twice this size minus the
    /// parent's: `sum_a (bit a of i ? +half : -half) per_voxel[a]`.
    to_child: [DVec3; 8],
}

/// One solid prepared once a frame for every strip.
struct Solid<'a> {
    /// The inner nodes, root first; `Some([])` when the root is full, `None` when empty.
    nodes: Option<&'a [Inner]>,
    domain: &'a Domain,
    /// The domain's [`Domain::voxels_per_unit`], divided out once (a sample's voxel
    /// ray is [`VoxelRay::scaled`] by it: [`VoxelRay::new`]'s bits).
    scale: f64,
    viewer: Viewer,
    /// [`Viewer::is_high`] as one comparison: the viewer is on the high side of the
    /// plane `axis = p` when `high[axis] >= p` (the eye for perspective, an infinity
    /// of the view direction's sign for orthographic).
    high: [f64; 3],
    projector: Projector,
    /// `X, Y, W` of the root's centre.
    root: DVec3,
    /// The largest `|X|, |Y|, |W|` of any term a node's centre is summed from (the
    /// root's centre, the offsets to children): the scale of their rounding.
    magnitude: DVec3,
    /// `levels[s]`: nodes of `2^s` voxels a side.
    levels: [Level; MAX_DEPTH as usize + 1],
}

impl<'a> Solid<'a> {
    fn new(traversal: &'a Traversal, view: &View, samples: &SampleGrid) -> Self {
        let domain = traversal.domain();
        let projector = Projector::new(view, domain, samples);
        let mut levels = [Level::default(); MAX_DEPTH as usize + 1];
        for (s, level) in levels.iter_mut().enumerate() {
            let half = 0.5 * f64::from(1u32 << s);
            let step = projector.per_voxel.map(|p| p * half);
            let to_child = std::array::from_fn(|i| {
                (0..3).fold(DVec3::ZERO, |sum, a| if i >> a & 1 == 1 { sum + step[a] } else { sum - step[a] })
            });
            *level = Level { half, reach: projector.dw.abs().element_sum() * half, to_child };
        }
        let half = 0.5 * f64::from(domain.resolution());
        let root = projector.per_voxel.iter().fold(projector.base, |sum, &p| sum + p * half);
        let magnitude = projector.per_voxel.iter().fold(root.abs(), |sum, &p| sum + p.abs() * half);
        let (nodes, viewer, scale) = (traversal.inner_nodes(), Viewer::new(view, domain), domain.voxels_per_unit());
        let high = std::array::from_fn(|a| match viewer {
            Viewer::At(e) => e[a],
            Viewer::Along(d) => {
                if d[a] < 0.0 {
                    f64::INFINITY
                } else {
                    f64::NEG_INFINITY
                }
            }
        });
        Solid { nodes, domain, scale, viewer, high, projector, root, magnitude, levels }
    }
}

/// A node's lowest voxel packed in one word: x in bits 0-20, y in 21-41, z in 42-62
/// (coordinates are below 2^21), so that a child's is its parent's or'ed with
/// [`CHILD_OFFSET`] shifted by the child's size (the three words of an array
/// built a coordinate at a time were stored apart and read as one, a stall).
type Corner = u64;

/// Bits of one coordinate of a [`Corner`].
const CORNER_BITS: u32 = MAX_DEPTH as u32;

/// `CHILD_OFFSET[i]`: the corner of child `i` of a node of edge 2 relative to the node's.
const CHILD_OFFSET: [Corner; 8] = {
    let mut t = [0; 8];
    let mut i = 0;
    while i < 8 {
        t[i] = (i as u64 & 1) | (i as u64 >> 1 & 1) << CORNER_BITS | (i as u64 >> 2 & 1) << (2 * CORNER_BITS);
        i += 1;
    }
    t
};

/// The coordinates of a [`Corner`].
#[inline]
fn unpack(corner: Corner) -> [u32; 3] {
    let mask = (1u64 << CORNER_BITS) - 1;
    std::array::from_fn(|a| (corner >> (CORNER_BITS * a as u32) & mask) as u32)
}

/// Front-to-back child order relative to the child `e` nearest the viewer: child
/// `e ^ ORDER[p]` comes `p`-th (across no mid plane, one, two, three); its own inverse.
const ORDER: [usize; 8] = [0, 1, 2, 4, 3, 5, 6, 7];

/// The byte whose bit `j` is bit `e ^ j` of `mask` (`e < 8`): a swap of bits, pairs,
/// nibbles for each bit of `e`.
#[inline]
fn xor_permuted(mask: u8, e: usize) -> u8 {
    let mut m = mask;
    if e & 1 != 0 {
        m = (m & 0x55) << 1 | (m & 0xAA) >> 1;
    }
    if e & 2 != 0 {
        m = (m & 0x33) << 2 | (m & 0xCC) >> 2;
    }
    if e & 4 != 0 {
        m = m.rotate_left(4);
    }
    m
}

/// `mask` with bits 3 and 4 swapped: bit `j` to bit `p` where `ORDER[p] = j`.
#[inline]
fn swap_bits_3_and_4(mask: u8) -> u8 {
    (mask & 0xE7) | (mask & 0x08) << 1 | (mask & 0x10) >> 1
}

/// An inclusive rectangle of samples: columns `c0..=c1`, rows `r0..=r1` (strip rows).
#[derive(Clone, Copy, Debug)]
struct Rect {
    c0: usize,
    c1: usize,
    r0: usize,
    r1: usize,
}

/// One solid drawn into one strip.
struct Pass<'a> {
    solid: &'a Solid<'a>,
    /// Index of the solid in the scene.
    index: usize,
    /// The primary rays.
    rays: &'a RayGrid,
    /// First sample row of the strip.
    row0: usize,
    /// Sample rows in the strip.
    rows: usize,
    /// Sample columns.
    columns: usize,
    tiles: Tiles<'a>,
    /// The strip's samples.
    out: &'a mut [Option<SceneHit>],
    faces: u64,
}

impl Pass<'_> {
    /// Step 1: the walk from the root.
    fn draw(&mut self) {
        let solid = self.solid;
        let Some(nodes) = solid.nodes else { return };
        let shift = usize::from(solid.domain.depth());
        let strip = Rect { c0: 0, c1: self.columns - 1, r0: 0, r1: self.rows - 1 };
        if nodes.is_empty() {
            self.full(0, shift, solid.root, strip);
        } else if let Some(rect) = self.open(solid.root, shift, strip) {
            self.inner(nodes, 0, 0, shift, solid.root, rect);
        }
    }

    /// The footprint of the node of centre `centre` (its `X, Y, W`) and `2^shift`
    /// voxels a side within its parent's `within`, when it has an uncovered sample.
    #[inline]
    fn open(&self, centre: DVec3, shift: usize, within: Rect) -> Option<Rect> {
        self.footprint(centre, &self.solid.levels[shift], within).filter(|&rect| self.tiles.any_uncovered(rect))
    }

    /// The children of inner node `index` (`[min, min + 2^shift)`, footprint `rect`
    /// with an uncovered sample) front to back: the child on the viewer's side of all
    /// three mid planes first, then those across one plane, two, three; a child's
    /// centre is its parent's plus the level's offset, its footprint within `rect`
    /// (the child's box is within the parent's). When `rect` lies in one tile, the rest
    /// are skipped once it is covered.
    fn inner(&mut self, nodes: &[Inner], index: u32, min: Corner, shift: usize, centre: DVec3, rect: Rect) {
        let solid = self.solid;
        let node = nodes[index as usize];
        let half = 1u32 << (shift - 1);
        let (corner, high) = (unpack(min), solid.high);
        let e = (0..3).fold(0usize, |bits, a| bits | usize::from(high[a] >= f64::from(corner[a] + half)) << a);
        let level = &solid.levels[shift - 1];
        // Bit `p` of `todo`: child `e ^ ORDER[p]` is not empty.
        let mut todo = swap_bits_3_and_4(xor_permuted(node.valid, e));
        let rect_tile = self.tiles.single_tile(rect);
        while todo != 0 {
            let child = e ^ ORDER[todo.trailing_zeros() as usize];
            todo &= todo - 1;
            let cmin = min | CHILD_OFFSET[child] << (shift - 1);
            let c = centre + level.to_child[child];
            if node.full >> child & 1 == 1 {
                self.full(cmin, shift - 1, c, rect);
            } else if let Some(child_rect) = self.open(c, shift - 1, rect) {
                let slot = node.first + (node.valid & !node.full & ((1u8 << child) - 1)).count_ones();
                self.inner(nodes, slot, cmin, shift - 1, c, child_rect);
            } else {
                continue;
            }
            if todo != 0 && rect_tile.is_some_and(|(t, mask)| !self.tiles.covered[t] & mask == 0) {
                return;
            }
        }
    }

    /// Step 4: the full node `[min, min + 2^shift)` (centre `centre`, within the
    /// parent's footprint `within`): when its footprint has an uncovered sample, its
    /// visible faces, then each uncovered sample's ray against them in axis order.
    fn full(&mut self, min: Corner, shift: usize, centre: DVec3, within: Rect) {
        let Some(rect) = self.footprint(centre, &self.solid.levels[shift], within) else { return };
        if !self.tiles.any_uncovered(rect) {
            return;
        }
        let Pass { solid, index, rays, row0, columns, tiles, out, .. } = self;
        let (solid, index, rays, row0, columns) = (*solid, *index, *rays, *row0, *columns);
        // The faces once, read in place by each sample's test.
        let faces = NodeFaces::new(&solid.viewer, unpack(min), 1 << shift);
        self.faces += u64::from(faces.count());
        let mut batch = [const { std::mem::MaybeUninit::<VoxelRay>::uninit() }; 64];
        tiles.for_each_uncovered_tile(rect, |ty, tx, open| {
            // The rays of the tile's open samples first (no branch: their square roots
            // and divisions overlap), then the tests.
            let sample = |bit: usize| (8 * ty + bit / 8, 8 * tx + bit % 8);
            let mut bits = open;
            let mut n = 0;
            while bits != 0 {
                let bit = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let (row, col) = sample(bit);
                batch[n].write(VoxelRay::scaled(solid.domain.min(), solid.scale, &rays.ray(col, row0 + row)));
                n += 1;
            }
            let (mut bits, mut covered) = (open, 0);
            for ray in &batch[..n] {
                // SAFETY: the first `n` were written above.
                let ray = unsafe { ray.assume_init_ref() };
                let bit = bits.trailing_zeros() as usize;
                bits &= bits - 1;
                let (row, col) = sample(bit);
                let Some(hit) = faces.first_entered(ray) else { continue };
                let i = row * columns + col;
                // The first solid draws into samples that are all None (no load of what
                // is there: a cache miss a sample of the 32-byte-a-sample frame).
                if index == 0 || out[i].is_none_or(|old| hit.t < old.hit.t) {
                    out[i] = Some(SceneHit { solid: index, hit });
                }
                covered |= 1 << bit;
            }
            covered
        });
    }

    /// Step 2: the rectangle within `within` holding the projection of the box of
    /// centre `centre` (its `X, Y, W`) and half edge `level.half`, widened by
    /// [`MARGIN`]; for boxes near or across the eye's plane, [`Pass::near_footprint`]
    /// and [`Pass::across_eye_plane`]; `None` when empty.
    ///
    /// Bound: for a point `c + e` of the box, `x(c + e) - x(c) = ((dX - x(c) dW) . e) /
    /// (W(c) + dW . e)`, so `|x(c + e) - x(c)| <= sum |dX - x(c) dW| half / (W(c) - sum
    /// |dW| half)` when that denominator is positive; the same for rows (rows first:
    /// most nodes a strip meets lie above or below it).
    #[inline(always)]
    fn footprint(&self, centre: DVec3, level: &Level, within: Rect) -> Option<Rect> {
        let (columns, rows) = (self.columns as i64, self.rows as i64);
        let p = &self.solid.projector;
        let nearest = centre.z - level.reach;
        if nearest <= 0.0 {
            return self.across_eye_plane(centre, level, within);
        }
        if nearest < 0.5 * centre.z {
            return self.near_footprint(centre, level, within);
        }
        let (w, k) = (1.0 / centre.z, level.half / nearest);
        let y = centre.y * w;
        let ry = (p.dy - p.dw * y).abs().element_sum() * k + MARGIN;
        let row0 = self.row0 as f64;
        let r0 = first_at_or_after(y - ry - row0, rows).max(within.r0 as i64);
        let r1 = last_at_or_before(y + ry - row0, rows).min(within.r1 as i64);
        if r0 > r1 {
            return None;
        }
        let x = centre.x * w;
        let rx = (p.dx - p.dw * x).abs().element_sum() * k + MARGIN;
        let c0 = first_at_or_after(x - rx, columns).max(within.c0 as i64);
        let c1 = last_at_or_before(x + rx, columns).min(within.c1 as i64);
        if c0 > c1 {
            return None;
        }
        Some(Rect { c0: c0 as usize, c1: c1 as usize, r0: r0 as usize, r1: r1 as usize })
    }
}

impl Pass<'_> {
    /// [`Pass::footprint`] of a box near the eye (its nearest point less than half as
    /// far as its centre, where the centre's bound grows without limit): the rectangle
    /// of its eight corners' projections, which bound the projection of the whole box
    /// (a box in front of the eye projects to the convex hull of its corners). A corner
    /// nearly on the eye's plane, where its projection is ill-conditioned, leaves the
    /// box to [`Pass::across_eye_plane`].
    #[inline(never)]
    fn near_footprint(&self, centre: DVec3, level: &Level, within: Rect) -> Option<Rect> {
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for offset in &level.to_child {
            let corner = centre + *offset;
            if corner.z <= 1e-6 * level.reach {
                return self.across_eye_plane(centre, level, within);
            }
            let w = 1.0 / corner.z;
            let (x, y) = (corner.x * w, corner.y * w);
            (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
        }
        let (columns, rows, row0) = (self.columns as i64, self.rows as i64, self.row0 as f64);
        let r0 = first_at_or_after(y0 - MARGIN - row0, rows).max(within.r0 as i64);
        let r1 = last_at_or_before(y1 + MARGIN - row0, rows).min(within.r1 as i64);
        let c0 = first_at_or_after(x0 - MARGIN, columns).max(within.c0 as i64);
        let c1 = last_at_or_before(x1 + MARGIN, columns).min(within.c1 as i64);
        (r0 <= r1 && c0 <= c1).then_some(Rect { c0: c0 as usize, c1: c1 as usize, r0: r0 as usize, r1: r1 as usize })
    }

    /// [`Pass::footprint`] of a box that reaches behind the eye's plane (`W <= 0`), whose
    /// projection has no bound: `None` when the box lies wholly behind the eye or wholly
    /// outside one of the four planes through the eye and the edges of `within` (widened
    /// by [`MARGIN`]), else all of `within`. A sample's hit point `p` has `W(p) > 0` and
    /// projects onto its sample, so for a sample of `within` every plane's function
    /// (`X - c W` for the left edge `c`, and so on) is positive at `p`: its maximum over
    /// the box, `value at the centre + sum |per voxel| half`, is too. The maxima are
    /// compared with a slack of `1e-9` of the magnitudes the centre was summed from,
    /// far above their rounding, so a box is dropped only when it is sure.
    #[inline(never)]
    fn across_eye_plane(&self, centre: DVec3, level: &Level, within: Rect) -> Option<Rect> {
        let solid = self.solid;
        let p = &solid.projector;
        let size = solid.magnitude;
        let slack = |a: f64, along: f64| 1e-9 * (along + a.abs() * size.z);
        if centre.z + level.reach < -slack(0.0, 0.0) {
            return None;
        }
        // The plane `U = sign (V - a W)` (`V` the column's `X` or the row's `Y`) leaves
        // the box outside when its maximum over the box is negative.
        let outside = |v: f64, dv: DVec3, a: f64, sign: f64, along: f64| {
            let most = sign * (v - a * centre.z) + (dv - p.dw * a).abs().element_sum() * level.half;
            most < -slack(a, along)
        };
        let (row0, c0, c1) = (self.row0 as f64, within.c0 as f64 - MARGIN, within.c1 as f64 + MARGIN);
        let (r0, r1) = (row0 + within.r0 as f64 - MARGIN, row0 + within.r1 as f64 + MARGIN);
        let dropped = outside(centre.y, p.dy, r0, 1.0, size.y)
            || outside(centre.y, p.dy, r1, -1.0, size.y)
            || outside(centre.x, p.dx, c0, 1.0, size.x)
            || outside(centre.x, p.dx, c1, -1.0, size.x);
        (!dropped).then_some(within)
    }
}

/// The first integer at or after `v` (`ceil`), moved into `[-1, n]` (NaN: -1). Rounds
/// `v + 1/2` to nearest, so an integer `v` (give or take its rounding) may give
/// `v + 1`: a footprint loses at most the samples on its widened edge, [`MARGIN`] away
/// from the projection.
#[inline]
fn first_at_or_after(v: f64, n: i64) -> i64 {
    round_to_integer(v.max(-1.0).min(n as f64) + 0.5)
}

/// The last integer at or before `v` (`floor`), moved into `[-1, n]` (NaN: `n`); the
/// mirror of [`first_at_or_after`].
#[inline]
fn last_at_or_before(v: f64, n: i64) -> i64 {
    round_to_integer(v.min(n as f64).max(-1.0) - 0.5)
}

/// `v` rounded to the nearest integer (ties to even) for `|v| < 2^51`: added to
/// `1.5 * 2^52`, the sum's last mantissa bits are that integer.
#[inline]
fn round_to_integer(v: f64) -> i64 {
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    (v + SHIFT).to_bits() as i64 - SHIFT.to_bits() as i64
}

/// A strip's coverage, reused for every solid and strip a task draws.
pub(crate) struct Strip {
    /// One 8x8 tile a `u64` (bit `8 row + col`), tiles row-major.
    covered: Vec<u64>,
    /// Tiles a row.
    tiles_x: usize,
    /// Sample columns.
    columns: usize,
}

impl Strip {
    /// Coverage for strips of `columns` sample columns and `rows` rows (a multiple of 8).
    fn new(columns: usize, rows: usize) -> Self {
        let tiles_x = columns.div_ceil(8);
        Strip { covered: vec![0; tiles_x * rows / 8], tiles_x, columns }
    }

    /// Nothing covered; samples outside the strip's `rows` and the
    /// image's columns count as covered, so they never look uncovered.
    fn reset(&mut self, rows: usize) {
        let columns_in_last = self.columns - (self.tiles_x - 1) * 8;
        for (t, c) in self.covered.iter_mut().enumerate() {
            let (ty, tx) = (t / self.tiles_x, t % self.tiles_x);
            let cols = if tx + 1 == self.tiles_x { columns_in_last } else { 8 };
            let live_rows = rows.saturating_sub(ty * 8).min(8);
            *c = if live_rows == 0 { u64::MAX } else { !(ROWS[0][live_rows - 1] & columns_mask(0, cols - 1)) };
        }
    }
}

/// `SPAN[lo][hi]`: bits `lo..=hi` of a byte (0 when `hi < lo`).
const SPAN: [[u64; 8]; 8] = {
    let mut t = [[0; 8]; 8];
    let mut lo = 0;
    while lo < 8 {
        let mut hi = lo;
        while hi < 8 {
            t[lo][hi] = (0xFF >> (7 - hi)) & (0xFF << lo) & 0xFF;
            hi += 1;
        }
        lo += 1;
    }
    t
};

/// Bits of columns `lo..=hi` in every row of a tile.
#[inline]
fn columns_mask(lo: usize, hi: usize) -> u64 {
    SPAN[lo][hi] * 0x0101_0101_0101_0101
}

/// `ROWS[lo][hi]`: [`rows_mask`] as a table.
const ROWS: [[u64; 8]; 8] = {
    let mut t = [[0; 8]; 8];
    let mut lo = 0;
    while lo < 8 {
        let mut hi = lo;
        while hi < 8 {
            t[lo][hi] = (u64::MAX >> (8 * (7 - hi))) & (u64::MAX << (8 * lo));
            hi += 1;
        }
        lo += 1;
    }
    t
};

/// The coverage tiles of a strip.
struct Tiles<'a> {
    covered: &'a mut [u64],
    tiles_x: usize,
}

impl Tiles<'_> {
    /// Whether some sample of `rect` is not covered. A rectangle of at most 8 samples
    /// a side (most nodes) lies in at most 2x2 tiles: the four tiles' masked words are
    /// tested together, with no branch on how many tiles it touches (whether a
    /// footprint crosses a tile edge is a coin toss the predictor missed). The masks
    /// of a tile it does not reach are zero (its second row or column of tiles is then
    /// its first).
    #[inline(always)]
    fn any_uncovered(&self, rect: Rect) -> bool {
        if (rect.r1 - rect.r0 >= 8) | (rect.c1 - rect.c0 >= 8) {
            return self.any_uncovered_in_tiles(rect);
        }
        let (ty0, ty1, tx0, tx1) = (rect.r0 / 8, rect.r1 / 8, rect.c0 / 8, rect.c1 / 8);
        // All ones when the rectangle stays in one row (column) of tiles.
        let one_row = 0u64.wrapping_sub(u64::from(ty0 == ty1));
        let one_column = 0u64.wrapping_sub(u64::from(tx0 == tx1));
        let (from_row, to_row) = (u64::MAX << (8 * (rect.r0 & 7)), u64::MAX >> (8 * (7 - (rect.r1 & 7))));
        let (from_column, to_column) = (columns_mask(rect.c0 & 7, 7), columns_mask(0, rect.c1 & 7));
        let (top, bottom) = (from_row & (to_row | !one_row), to_row & !one_row);
        let (left, right) = (from_column & (to_column | !one_column), to_column & !one_column);
        let c = &self.covered;
        let (row0, row1) = (ty0 * self.tiles_x, ty1 * self.tiles_x);
        let open = (!c[row0 + tx0] & top & left)
            | (!c[row0 + tx1] & top & right)
            | (!c[row1 + tx0] & bottom & left)
            | (!c[row1 + tx1] & bottom & right);
        open != 0
    }

    /// [`Tiles::any_uncovered`] for a rectangle over several tiles.
    #[inline(never)]
    fn any_uncovered_in_tiles(&self, rect: Rect) -> bool {
        let mut any = false;
        Self::for_each_tile(rect, self.tiles_x, |t, _, _, mask| {
            any = !self.covered[t] & mask != 0;
            any
        });
        any
    }

    /// Calls `each(tile, tile row, tile column, mask of the tile's samples in rect)` for
    /// the tiles `rect` touches (`tiles_x` tiles a row), row by row, until `each`
    /// returns true.
    #[inline]
    fn for_each_tile(rect: Rect, tiles_x: usize, mut each: impl FnMut(usize, usize, usize, u64) -> bool) {
        let (ty0, ty1, tx0, tx1) = (rect.r0 / 8, rect.r1 / 8, rect.c0 / 8, rect.c1 / 8);
        for ty in ty0..=ty1 {
            let rows = ROWS[if ty == ty0 { rect.r0 % 8 } else { 0 }][if ty == ty1 { rect.r1 % 8 } else { 7 }];
            for tx in tx0..=tx1 {
                let cols =
                    columns_mask(if tx == tx0 { rect.c0 % 8 } else { 0 }, if tx == tx1 { rect.c1 % 8 } else { 7 });
                if each(ty * tiles_x + tx, ty, tx, rows & cols) {
                    return;
                }
            }
        }
    }

    /// The tile and mask of a rectangle within one tile (the common case of small nodes).
    #[inline(always)]
    fn single_tile(&self, rect: Rect) -> Option<(usize, u64)> {
        let (ty, tx) = (rect.r0 / 8, rect.c0 / 8);
        (ty == rect.r1 / 8 && tx == rect.c1 / 8).then(|| {
            let mask = ROWS[rect.r0 & 7][rect.r1 & 7] & columns_mask(rect.c0 & 7, rect.c1 & 7);
            (ty * self.tiles_x + tx, mask)
        })
    }

    /// Calls `each(tile row, tile column, uncovered samples of rect in the tile)` for
    /// the tiles `rect` touches, and covers the samples it returns.
    #[inline]
    fn for_each_uncovered_tile(&mut self, rect: Rect, mut each: impl FnMut(usize, usize, u64) -> u64) {
        let mut tile = |covered: &mut u64, ty: usize, tx: usize, mask: u64| {
            let open = !*covered & mask;
            if open != 0 {
                *covered |= each(ty, tx, open);
            }
        };
        if let Some((t, mask)) = self.single_tile(rect) {
            tile(&mut self.covered[t], rect.r0 / 8, rect.c0 / 8, mask);
            return;
        }
        let covered = &mut *self.covered;
        Self::for_each_tile(rect, self.tiles_x, |t, ty, tx, mask| {
            tile(&mut covered[t], ty, tx, mask);
            false
        });
    }
}
