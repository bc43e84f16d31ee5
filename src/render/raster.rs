//! Primary visibility: which solid, voxel and face every sample sees, decided by ray
//! tracing or by drawing the solids' voxel faces in object order.
//!
//! Methods (all sample the same points and hand the same [`SceneHit`]s to the one
//! shading stage, so they give the same picture):
//! - [`Method::Trace`]: the octree ray walk.
//! - [`Method::FrontToBack`]: Meagher's octree display (module `display`): full nodes
//!   visited nearest first; a node's faces that look at the viewer are drawn only into
//!   samples not yet covered; a subtree whose screen footprint is already covered is
//!   skipped. No depth buffer within a solid.
//! - [`Method::Painter`]: the same faces drawn far to near (the reverse order), each
//!   overwriting what is under it.
//! - [`Method::ZBuffer`]: the faces in any order (here: the octree's, with children in
//!   storage order), kept where nearer than the depth stored for the sample.
//! - [`Method::ScanLine`]: the seed's scan-line Z-buffer: a polygon table of the faces
//!   looking at the viewer, an edge table of their projected edges bucketed by first
//!   sample row, and per row the active edge table and active polygon table giving each
//!   polygon's span; one row of depths. Deviation from the seed: the depth and coverage
//!   of a span's samples come from the exact ray-plane test, not the incremental
//!   `z -= a / c` (which would differ in the last bits and break the bit-exact
//!   agreement); the spans are widened by a sample so that they only ever propose.
//!
//! A face covers a sample when the sample's ray crosses the face's plane (at the time
//! `(plane - o) / d`, the formula of the ray walk) and then enters the node's interior
//! there; the hit is then computed by [`VoxelRay::entry`], as in the walk (module
//! `face`). Solids are drawn one at a time and merged per sample by depth
//! (ties: the earlier solid), so a scene of several solids needs one depth per sample
//! whatever the method.

use glam::DVec3;
use rayon::prelude::*;

use super::beam::TILE;
use super::camera::{Camera, View};
use super::display;
use super::face::{Face, Viewer};
use super::scene::{Scene, SceneHit};
use super::traverse::{Hit, Traversal, VoxelRay};

/// How primary visibility is decided.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Ray tracing through the octree.
    Trace,
    /// Meagher's front-to-back octree display.
    FrontToBack,
    /// Painter's algorithm: far to near, overwrite.
    Painter,
    /// Z-buffer.
    ZBuffer,
    /// Scan-line Z-buffer with polygon, edge, active polygon and active edge tables.
    ScanLine,
}

/// The sample grid: `spp x spp` samples a pixel, at the centres of their strata.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Samples {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples a pixel side.
    pub spp: u32,
}

impl Samples {
    /// Samples a row.
    #[must_use]
    pub fn columns(&self) -> u32 {
        self.width * self.spp
    }

    /// Sample rows.
    #[must_use]
    pub fn rows(&self) -> u32 {
        self.height * self.spp
    }

    /// Image aspect, width / height.
    #[must_use]
    pub fn aspect(&self) -> f64 {
        f64::from(self.width) / f64::from(self.height)
    }

    /// Image point of sample `(col, row)` of the sample grid, `[-1, 1]^2`, y up.
    #[must_use]
    pub fn point(&self, col: u32, row: u32) -> (f64, f64) {
        let x = (f64::from(col) + 0.5) / f64::from(self.columns());
        let y = (f64::from(row) + 0.5) / f64::from(self.rows());
        (2.0 * x - 1.0, 1.0 - 2.0 * y)
    }

    /// The sample column (continuous) of image x in `[-1, 1]`.
    fn column_of(&self, x: f64) -> f64 {
        (x + 1.0) * 0.5 * f64::from(self.columns()) - 0.5
    }

    /// The sample row (continuous) of image y in `[-1, 1]`.
    fn row_of(&self, y: f64) -> f64 {
        (1.0 - y) * 0.5 * f64::from(self.rows()) - 0.5
    }
}

/// What a visibility pass did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VisibilityStats {
    /// Voxel faces drawn (0 for the ray tracer): every face looking at the viewer for
    /// painter's, the Z-buffer and the scan-line Z-buffer; for the front-to-back
    /// display, the visible faces of the full nodes that had an uncovered sample in
    /// their footprint when reached (a node split between screen strips counts once a
    /// strip).
    pub faces_drawn: u64,
}

/// What every sample sees, row-major over the sample grid, and what it took.
#[must_use]
pub fn visibility(
    scene: &Scene,
    camera: &Camera,
    samples: &Samples,
    method: Method,
) -> (Vec<Option<SceneHit>>, VisibilityStats) {
    let mut seen = Vec::new();
    let stats = visibility_into(scene, camera, samples, method, &mut seen);
    (seen, stats)
}

/// [`visibility`] into a frame buffer of the caller's, resized to the sample grid: a
/// viewer drawing frame after frame keeps one buffer (a fresh one costs a page fault
/// every 4 KiB of its first writes, a fifth of a front-to-back frame at 1024x1024).
pub fn visibility_into(
    scene: &Scene,
    camera: &Camera,
    samples: &Samples,
    method: Method,
    seen: &mut Vec<Option<SceneHit>>,
) -> VisibilityStats {
    let view = camera.view(samples.aspect());
    let count = (samples.rows() * samples.columns()) as usize;
    // Every sample None, on all threads (the first writes of a fresh buffer fault its pages in).
    seen.truncate(count);
    seen.par_iter_mut().for_each(|s| *s = None);
    let missing = count - seen.len();
    seen.par_extend(rayon::iter::repeat_n(None, missing));
    if method == Method::FrontToBack {
        let faces_drawn = display::front_to_back(scene, &view, samples, seen);
        return VisibilityStats { faces_drawn };
    }
    let columns = samples.columns() as usize;
    let rays: Vec<(DVec3, DVec3)> = (0..samples.rows() * samples.columns())
        .into_par_iter()
        .map(|i| {
            let (x, y) = samples.point(i % samples.columns(), i / samples.columns());
            view.ray(x, y)
        })
        .collect();
    if method == Method::Trace {
        // One packet a tile of TILE x TILE samples, a band of TILE rows a task.
        seen.par_chunks_mut(TILE * columns).zip(rays.par_chunks(TILE * columns)).for_each(|(seen, rays)| {
            let rows = rays.len() / columns;
            let mut tile = Vec::with_capacity(TILE * TILE);
            let mut hits = [None; TILE * TILE];
            for c0 in (0..columns).step_by(TILE) {
                let w = TILE.min(columns - c0);
                tile.clear();
                for r in 0..rows {
                    tile.extend_from_slice(&rays[r * columns + c0..][..w]);
                }
                let hits = &mut hits[..tile.len()];
                scene.hit_packet(&tile, hits);
                for (r, hits) in hits.chunks(w).enumerate() {
                    seen[r * columns + c0..][..w].copy_from_slice(hits);
                }
            }
        });
        return VisibilityStats::default();
    }
    let mut stats = VisibilityStats::default();
    for (index, solid) in scene.solids.iter().enumerate() {
        let domain = *solid.traversal.domain();
        let painter = Painter { view: &view, samples, rays: &rays, domain, viewer: Viewer::new(&view, &domain) };
        let (hits, faces) = painter.draw_solid(&solid.traversal, method);
        stats.faces_drawn += faces;
        // Merge by depth; on equal depth the earlier solid stays.
        for (s, h) in seen.iter_mut().zip(hits) {
            if let Some(hit) = h
                && s.is_none_or(|old| hit.t < old.hit.t)
            {
                *s = Some(SceneHit { solid: index, hit });
            }
        }
    }
    stats
}

/// Draws one solid's faces into a per-sample hit buffer (the baseline methods).
struct Painter<'a> {
    view: &'a View,
    samples: &'a Samples,
    rays: &'a [(DVec3, DVec3)],
    domain: crate::octree::Domain,
    viewer: Viewer,
}

impl Painter<'_> {
    /// The solid's hit per sample and the faces drawn.
    fn draw_solid(&self, traversal: &Traversal, method: Method) -> (Vec<Option<Hit>>, u64) {
        let mut hits: Vec<Option<Hit>> = vec![None; self.rays.len()];
        let mut faces = 0;
        let viewer = self.viewer;
        match method {
            Method::Painter => {
                let mut nodes = Vec::new();
                let eye_high = |a, plane| viewer.is_high(a, plane);
                traversal.front_to_back(&eye_high, &mut |_, _| true, &mut |min, size| nodes.push((min, size)));
                for &(min, size) in nodes.iter().rev() {
                    faces += self.draw_node(min, size, &mut |i, hit| hits[i] = Some(hit));
                }
            }
            Method::ScanLine => return self.scan_lines(traversal),
            Method::ZBuffer | Method::Trace | Method::FrontToBack => {
                let mut nodes = Vec::new();
                traversal.front_to_back(&|_, _| false, &mut |_, _| true, &mut |min, size| nodes.push((min, size)));
                for (min, size) in nodes {
                    faces += self.draw_node(min, size, &mut |i, hit| {
                        if hits[i].is_none_or(|old| hit.t < old.t) {
                            hits[i] = Some(hit);
                        }
                    });
                }
            }
        }
        (hits, faces)
    }

    /// The scan-line Z-buffer (see the module doc).
    fn scan_lines(&self, traversal: &Traversal) -> (Vec<Option<Hit>>, u64) {
        let (columns, rows) = (self.samples.columns() as usize, self.samples.rows() as i64);
        let h = self.domain.voxel_size();
        // Step 1: polygon table (front faces) and edge table (projected edges by first row).
        let mut polygons: Vec<Polygon> = Vec::new();
        let mut edge_table: Vec<Vec<Edge>> = vec![Vec::new(); rows.max(1) as usize];
        let mut full_screen: Vec<usize> = Vec::new();
        let mut nodes = Vec::new();
        traversal.front_to_back(&|_, _| false, &mut |_, _| true, &mut |min, size| nodes.push((min, size)));
        for (min, size) in nodes {
            for face in Face::visible(&self.viewer, min, size) {
                let (a, plane, lo, hi) = (face.axis, face.plane, face.lo, face.hi);
                let id = polygons.len();
                polygons.push(face);
                // The face's corners in order around it, projected to the sample grid.
                let (u, v) = ((a + 1) % 3, (a + 2) % 3);
                let corners = [(lo[u], lo[v]), (hi[u], lo[v]), (hi[u], hi[v]), (lo[u], hi[v])].map(|(cu, cv)| {
                    let mut p = DVec3::ZERO;
                    p[a] = plane;
                    p[u] = cu;
                    p[v] = cv;
                    self.view
                        .project(self.domain.min() + p * h)
                        .map(|(x, y)| (self.samples.column_of(x), self.samples.row_of(y)))
                });
                let Some(corners) = corners.into_iter().collect::<Option<Vec<_>>>() else {
                    full_screen.push(id); // a corner behind the eye: every row, every column
                    continue;
                };
                for k in 0..4 {
                    let (p, q) = (corners[k], corners[(k + 1) % 4]);
                    let (top, bottom) = if p.1 <= q.1 { (p, q) } else { (q, p) };
                    let first = (top.1.floor() as i64 - 1).clamp(0, rows - 1);
                    let last = (bottom.1.ceil() as i64 + 1).clamp(0, rows - 1);
                    if top.1 > (rows + 1) as f64 || bottom.1 < -2.0 {
                        continue;
                    }
                    edge_table[first as usize].push(Edge { polygon: id, last, top, bottom });
                }
            }
        }
        // Step 2: rows top to bottom with the active edge and polygon tables.
        let mut hits: Vec<Option<Hit>> = vec![None; self.rays.len()];
        let mut active_edges: Vec<Edge> = Vec::new();
        let mut span: Vec<(f64, f64)> = vec![(f64::INFINITY, f64::NEG_INFINITY); polygons.len()];
        let mut active_polygons: Vec<usize> = Vec::new();
        for r in 0..rows {
            active_edges.append(&mut edge_table[r as usize]);
            active_edges.retain(|e| e.last >= r);
            // Active polygon table: each polygon's span on this row, from its edges'
            // x over the row band [r - 1, r + 1] (a superset of its samples).
            for e in &active_edges {
                let (y0, y1) = ((r - 1) as f64, (r + 1) as f64);
                let (t, b) = (e.top, e.bottom);
                for y in [y0.max(t.1), y1.min(b.1)] {
                    let x = if b.1 > t.1 {
                        t.0 + (b.0 - t.0) * ((y - t.1) / (b.1 - t.1)).clamp(0.0, 1.0)
                    } else {
                        t.0.min(b.0)
                    };
                    let x_other = if b.1 > t.1 { x } else { t.0.max(b.0) };
                    let s = &mut span[e.polygon];
                    if s.0 == f64::INFINITY {
                        active_polygons.push(e.polygon);
                    }
                    *s = (s.0.min(x.min(x_other)), s.1.max(x.max(x_other)));
                }
            }
            active_polygons.extend(full_screen.iter().copied());
            for &id in &full_screen {
                span[id] = (0.0, columns as f64);
            }
            // One row of depths: keep the nearest exact hit per sample.
            for &id in &active_polygons {
                let (x0, x1) = span[id];
                span[id] = (f64::INFINITY, f64::NEG_INFINITY);
                let c0 = (x0.floor() as i64 - 1).clamp(0, columns as i64 - 1) as usize;
                let c1 = (x1.ceil() as i64 + 1).clamp(0, columns as i64 - 1) as usize;
                let face = &polygons[id];
                for c in c0..=c1 {
                    let i = r as usize * columns + c;
                    let (o, d) = self.rays[i];
                    let ray = VoxelRay::new(&self.domain, o, d);
                    if let Some(hit) = face.enters(&ray)
                        && hits[i].is_none_or(|old| hit.t < old.t)
                    {
                        hits[i] = Some(hit);
                    }
                }
            }
            active_polygons.clear();
        }
        let faces = polygons.len() as u64;
        (hits, faces)
    }

    /// The sample-grid rectangle (inclusive) that the box `[min, min + size]` may cover.
    fn footprint(&self, lo: DVec3, hi: DVec3) -> (u32, u32, u32, u32) {
        let full = (0, self.samples.columns() - 1, 0, self.samples.rows() - 1);
        let (mut x0, mut x1, mut y0, mut y1) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..8 {
            let p = DVec3::new(
                if i & 1 == 0 { lo.x } else { hi.x },
                if i & 2 == 0 { lo.y } else { hi.y },
                if i & 4 == 0 { lo.z } else { hi.z },
            );
            let Some((x, y)) = self.view.project(p) else { return full };
            let (c, r) = (self.samples.column_of(x), self.samples.row_of(y));
            x0 = x0.min(c);
            x1 = x1.max(c);
            y0 = y0.min(r);
            y1 = y1.max(r);
        }
        let clamp = |v: f64, n: u32| (v.max(0.0) as u32).min(n - 1);
        if x1 < -1.0 || y1 < -1.0 || x0 > f64::from(self.samples.columns()) || y0 > f64::from(self.samples.rows()) {
            return (1, 0, 1, 0); // empty
        }
        (
            clamp(x0.floor() - 1.0, self.samples.columns()),
            clamp(x1.ceil() + 1.0, self.samples.columns()),
            clamp(y0.floor() - 1.0, self.samples.rows()),
            clamp(y1.ceil() + 1.0, self.samples.rows()),
        )
    }

    /// Draws the faces of the full node `[min, min + size)` that look at the viewer:
    /// `put(sample, hit)` for every sample whose ray enters the node through them.
    /// Returns the faces drawn.
    fn draw_node(&self, min: [u32; 3], size: u32, put: &mut impl FnMut(usize, Hit)) -> u64 {
        let mut faces = 0;
        for face in Face::visible(&self.viewer, min, size) {
            faces += 1;
            let (mut flo, mut fhi) = (DVec3::from_array(face.lo), DVec3::from_array(face.hi));
            flo[face.axis] = face.plane;
            fhi[face.axis] = face.plane;
            let h = self.domain.voxel_size();
            let (wlo, whi) = (self.domain.min() + flo * h, self.domain.min() + fhi * h);
            let (c0, c1, r0, r1) = self.footprint(wlo, whi);
            let columns = self.samples.columns() as usize;
            for r in r0..=r1 {
                for c in c0..=c1 {
                    let i = r as usize * columns + c as usize;
                    let (o, d) = self.rays[i];
                    let ray = VoxelRay::new(&self.domain, o, d);
                    if let Some(hit) = face.enters(&ray) {
                        put(i, hit);
                    }
                }
            }
        }
        faces
    }
}

/// A polygon of the scan-line polygon table: one face of a full node.
type Polygon = Face;

/// An edge of the scan-line edge table: its polygon, the last row it touches, and its
/// projected end points (sample-grid column, row), top first.
#[derive(Clone, Copy)]
struct Edge {
    polygon: usize,
    last: i64,
    top: (f64, f64),
    bottom: (f64, f64),
}
