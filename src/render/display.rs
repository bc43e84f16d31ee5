//! Meagher's front-to-back octree display ("Geometric modeling using octree encoding",
//! 1982): full nodes visited nearest first, a node's faces that look at the viewer
//! drawn only into samples not yet covered, a subtree skipped when every sample of its
//! screen footprint is covered. No depth buffer within a solid.
//!
//! Steps, per screen strip of [`STRIP_ROWS`] sample rows (strips are independent rayon
//! tasks, each walking the octree culled to its rows, so the result does not depend on
//! the thread count):
//! 1. Walk the full nodes front to back ([`Traversal::front_to_back`]: in every inner
//!    node the child on the viewer's side of all three mid planes first). A node can
//!    only hide nodes visited after it.
//! 2. Footprint of a node: the box projected to the sample grid by one projective map
//!    (`column = X(p) / W(p)`, `row = Y(p) / W(p)`, `X, Y, W` affine in the voxel point
//!    `p`), bounded from its centre (see `Pass::footprint`: two divisions, no corners),
//!    widened by [`MARGIN`] samples; the whole strip when the box reaches behind the
//!    eye. A node whose footprint has no uncovered sample is skipped, an inner node
//!    with its subtree.
//! 3. Coverage is a bit a sample, kept in 8x8 tiles (one `u64` each, bit `8 row + col`),
//!    so a footprint test is one masked word test a tile it touches (one, mostly).
//! 4. A full node: each uncovered sample of its footprint makes its voxel ray once and
//!    tests the node's faces that look at the viewer, in axis order, by the exact face
//!    rule (`Face::enters`); the first face it enters covers the sample, with that
//!    face's [`VoxelRay::entry`] as the hit. (One ray a sample and node, not one a
//!    face: the ray, a square root and nine divisions, is the dear part of a test.)
//!
//! Tie-breaking: a sample takes the first face in visiting order (nodes front to back,
//! faces of a node by axis) whose exact test it passes. Since the footprints only ever
//! propose samples (the exact test decides), this is the rule of the plain version
//! that tests every sample of a widened footprint, and the hits are the ray walk's bits.
//!
//! Precision of the margin: the footprint and the exact test are two roundings of the
//! same geometry. The test's in-plane point is off by a few ulps of `t d` along the ray,
//! which moves it on screen only by the ulps of its depth coordinate; the projection's
//! own rounding is a few ulps of the sample coordinates. Both stay below 1e-6 samples
//! for any domain (depth <= 21) and image (<= 16384 a side), so [`MARGIN`] (1e-2
//! samples) only ever makes a footprint propose more samples, never fewer.

use std::cell::Cell;

use glam::DVec3;
use rayon::prelude::*;

use super::camera::{Projection, View};
use super::face::{Face, Viewer};
use super::raster::Samples;
use super::scene::{Scene, SceneHit};
use super::traverse::VoxelRay;
use crate::octree::Domain;

/// Sample rows a strip (one parallel task); a multiple of the tile height 8.
pub const STRIP_ROWS: usize = 64;

/// Samples by which a projected footprint is widened on every side.
const MARGIN: f64 = 1e-2;

/// Draws every solid of `scene` front to back into `seen` (row-major over the sample
/// grid, all `None` on entry); solids are merged by depth, ties to the earlier solid.
/// Returns the faces drawn: the visible faces of the full nodes with an uncovered
/// sample in their footprint (a node split between strips counts once a strip).
pub(crate) fn front_to_back(scene: &Scene, view: &View, samples: &Samples, seen: &mut [Option<SceneHit>]) -> u64 {
    let columns = samples.columns() as usize;
    seen.par_chunks_mut(STRIP_ROWS * columns)
        .enumerate()
        .map_init(
            || Strip::new(columns),
            |strip, (k, out)| {
                let row0 = k * STRIP_ROWS;
                let mut faces = 0;
                for (index, solid) in scene.solids.iter().enumerate() {
                    let domain = solid.traversal.domain();
                    let mut pass = Pass {
                        solid: index,
                        domain,
                        viewer: Viewer::new(view, domain),
                        projector: Projector::new(view, domain, samples),
                        samples,
                        view,
                        row0,
                        rows: out.len() / columns,
                        faces: 0,
                    };
                    strip.reset(pass.rows);
                    pass.draw(&solid.traversal, strip, out);
                    faces += pass.faces;
                }
                faces
            },
        )
        .sum()
}

/// A projective map from voxel units to the sample grid: `column = X / W`, `row = Y / W`,
/// with `X, Y, W` affine in the voxel point.
struct Projector {
    /// `X, Y, W` at the domain's origin (voxel `0, 0, 0`).
    base: DVec3,
    /// The change of `X, Y, W` a voxel along axis `a`, at `per_voxel[a]`.
    per_voxel: [DVec3; 3],
    /// The change of `X` a voxel along x, y, z.
    dx: DVec3,
    /// The change of `Y` a voxel along x, y, z.
    dy: DVec3,
    /// The change of `W` a voxel along x, y, z.
    dw: DVec3,
}

impl Projector {
    /// With `v = min + p h - eye` (world offset of voxel point `p`) and the image point of
    /// [`View::project`], `column = (x + 1) C / 2 - 1/2`, `row = (1 - y) R / 2 - 1/2`:
    /// perspective `X = v.(right C / (2 t a) + forward (C - 1) / 2)`,
    /// `Y = v.(-up R / (2 t) + forward (R - 1) / 2)`, `W = v.forward`;
    /// orthographic the same with `t` the half height and `W = 1`.
    fn new(view: &View, domain: &Domain, samples: &Samples) -> Self {
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
        Projector { base, per_voxel, dx, dy, dw }
    }

    /// `X, Y, W` at the centre of the cube `[min, min + size]`.
    #[inline]
    fn centre(&self, min: [u32; 3], size: u32) -> DVec3 {
        let half = 0.5 * f64::from(size);
        let [px, py, pz] = self.per_voxel;
        self.base + px * (f64::from(min[0]) + half) + py * (f64::from(min[1]) + half) + pz * (f64::from(min[2]) + half)
    }
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
    solid: usize,
    domain: &'a Domain,
    viewer: Viewer,
    projector: Projector,
    samples: &'a Samples,
    view: &'a View,
    /// First sample row of the strip.
    row0: usize,
    /// Sample rows in the strip.
    rows: usize,
    faces: u64,
}

impl Pass<'_> {
    fn draw(&mut self, traversal: &super::traverse::Traversal, strip: &mut Strip, out: &mut [Option<SceneHit>]) {
        let Strip { covered, tiles_x, .. } = strip;
        let tiles = Tiles { covered: Cell::from_mut(covered.as_mut_slice()).as_slice_of_cells(), tiles_x: *tiles_x };
        let viewer = self.viewer;
        let this = &*self;
        let columns = this.samples.columns() as usize;
        let mut faces = 0;
        traversal.front_to_back(
            &|axis, plane| viewer.is_high(axis, plane),
            &mut |min, size| {
                let centre = this.projector.centre(min, size);
                let half = DVec3::splat(0.5 * f64::from(size));
                this.footprint(centre, half).is_some_and(|rect| tiles.any_uncovered(rect))
            },
            &mut |min, size| {
                let centre = this.projector.centre(min, size);
                let half = DVec3::splat(0.5 * f64::from(size));
                let Some(rect) = this.footprint(centre, half) else { return };
                // Step 4: each uncovered sample of the footprint, its ray against the
                // visible faces in axis order.
                let mut visible = [None; 3];
                let mut count = 0;
                for face in Face::visible(&viewer, min, size) {
                    visible[count] = Some(face);
                    count += 1;
                }
                let mut drawn = false;
                tiles.for_each_uncovered(rect, |row, col| {
                    drawn = true;
                    let ray = this.voxel_ray(row, col);
                    let Some(hit) = visible.iter().flatten().find_map(|face| face.enters(&ray)) else { return false };
                    let i = row * columns + col;
                    if out[i].is_none_or(|old| hit.t < old.hit.t) {
                        out[i] = Some(SceneHit { solid: this.solid, hit });
                    }
                    true
                });
                if drawn {
                    faces += count as u64;
                }
            },
        );
        self.faces += faces;
    }

    /// The voxel ray of sample `(col, row0 + row)`: the tracer's primary ray.
    fn voxel_ray(&self, row: usize, col: usize) -> VoxelRay {
        let (x, y) = self.samples.point(col as u32, (self.row0 + row) as u32);
        let (o, d) = self.view.ray(x, y);
        VoxelRay::new(self.domain, o, d)
    }

    /// The strip rectangle holding the projection of the box of centre `centre` (its
    /// `X, Y, W`) and half extents `half` (voxels, per axis), widened by [`MARGIN`]; the
    /// whole strip when the box reaches behind the eye; `None` when empty.
    ///
    /// Bound: for a point `c + e` of the box, `x(c + e) - x(c) = ((dX - x(c) dW) . e) /
    /// (W(c) + dW . e)`, so `|x(c + e) - x(c)| <= sum |dX - x(c) dW| half / (W(c) - sum
    /// |dW| half)` when that denominator is positive; the same for rows.
    #[inline]
    fn footprint(&self, centre: DVec3, half: DVec3) -> Option<Rect> {
        let (columns, rows) = (i64::from(self.samples.columns()), self.rows as i64);
        let p = &self.projector;
        let nearest = centre.z - p.dw.abs().dot(half);
        if nearest <= 0.0 {
            return Some(Rect { c0: 0, c1: columns as usize - 1, r0: 0, r1: self.rows - 1 });
        }
        let (w, k) = (1.0 / centre.z, 1.0 / nearest);
        let y = centre.y * w;
        let ry = (p.dy - p.dw * y).abs().dot(half) * k + MARGIN;
        let row0 = self.row0 as f64;
        let r0 = ceil_within(y - ry - row0, rows).max(0);
        let r1 = floor_within(y + ry - row0, rows).min(rows - 1);
        if r0 > r1 {
            return None;
        }
        let x = centre.x * w;
        let rx = (p.dx - p.dw * x).abs().dot(half) * k + MARGIN;
        let c0 = ceil_within(x - rx, columns).max(0);
        let c1 = floor_within(x + rx, columns).min(columns - 1);
        if c0 > c1 {
            return None;
        }
        Some(Rect { c0: c0 as usize, c1: c1 as usize, r0: r0 as usize, r1: r1 as usize })
    }
}

/// `ceil(v)`, exact for `v` in `[-1, n]`; values outside are moved to the nearer end.
#[inline]
fn ceil_within(v: f64, n: i64) -> i64 {
    let v = v.clamp(-1.0, n as f64);
    let t = v as i64; // truncation: ceil for v <= 0, floor for v >= 0
    if (t as f64) < v { t + 1 } else { t }
}

/// `floor(v)`, exact for `v` in `[-1, n]`; values outside are moved to the nearer end.
#[inline]
fn floor_within(v: f64, n: i64) -> i64 {
    let v = v.clamp(-1.0, n as f64);
    let t = v as i64;
    if (t as f64) > v { t - 1 } else { t }
}

/// A strip's coverage, reused for every solid and strip a task draws.
struct Strip {
    /// One 8x8 tile a `u64` (bit `8 row + col`), tiles row-major.
    covered: Vec<u64>,
    /// Tiles a row.
    tiles_x: usize,
    /// Sample columns.
    columns: usize,
}

impl Strip {
    fn new(columns: usize) -> Self {
        let tiles_x = columns.div_ceil(8);
        Strip { covered: vec![0; tiles_x * STRIP_ROWS / 8], tiles_x, columns }
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

/// The coverage tiles of a strip, shared by the walk's pruning test and drawing.
struct Tiles<'a> {
    covered: &'a [Cell<u64>],
    tiles_x: usize,
}

impl Tiles<'_> {
    /// Calls `each(tile, tile row, tile column, mask of the tile's samples in rect)` for
    /// the tiles `rect` touches, row by row; stops when `each` returns true.
    #[inline]
    fn find_tile(&self, rect: Rect, mut each: impl FnMut(usize, usize, usize, u64) -> bool) -> bool {
        let (ty0, ty1, tx0, tx1) = (rect.r0 / 8, rect.r1 / 8, rect.c0 / 8, rect.c1 / 8);
        for ty in ty0..ty1 + 1 {
            let rows = ROWS[if ty == ty0 { rect.r0 % 8 } else { 0 }][if ty == ty1 { rect.r1 % 8 } else { 7 }];
            for tx in tx0..tx1 + 1 {
                let cols =
                    columns_mask(if tx == tx0 { rect.c0 % 8 } else { 0 }, if tx == tx1 { rect.c1 % 8 } else { 7 });
                if each(ty * self.tiles_x + tx, ty, tx, rows & cols) {
                    return true;
                }
            }
        }
        false
    }

    /// Whether some sample of `rect` is not covered.
    #[inline]
    fn any_uncovered(&self, rect: Rect) -> bool {
        if let Some((t, mask)) = self.single_tile(rect) {
            return !self.covered[t].get() & mask != 0;
        }
        self.find_tile(rect, |t, _, _, mask| !self.covered[t].get() & mask != 0)
    }

    /// The tile and mask of a rectangle within one tile (the common case of small nodes).
    #[inline]
    fn single_tile(&self, rect: Rect) -> Option<(usize, u64)> {
        let (ty, tx) = (rect.r0 / 8, rect.c0 / 8);
        (ty == rect.r1 / 8 && tx == rect.c1 / 8).then(|| {
            let mask = ROWS[rect.r0 & 7][rect.r1 & 7] & columns_mask(rect.c0 & 7, rect.c1 & 7);
            (ty * self.tiles_x + tx, mask)
        })
    }

    /// Calls `test(row, col)` for each uncovered sample of `rect`; a sample becomes
    /// covered when `test` says so.
    #[inline]
    fn for_each_uncovered(&self, rect: Rect, mut test: impl FnMut(usize, usize) -> bool) {
        let mut tile = |t: usize, ty: usize, tx: usize, mask: u64| {
            let mut open = !self.covered[t].get() & mask;
            while open != 0 {
                let bit = open.trailing_zeros();
                open &= open - 1;
                if test(8 * ty + (bit / 8) as usize, 8 * tx + (bit % 8) as usize) {
                    self.covered[t].set(self.covered[t].get() | 1 << bit);
                }
            }
            false
        };
        match self.single_tile(rect) {
            Some((t, mask)) => {
                tile(t, rect.r0 / 8, rect.c0 / 8, mask);
            }
            None => {
                self.find_tile(rect, tile);
            }
        }
    }
}
