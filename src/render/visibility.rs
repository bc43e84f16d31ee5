//! Primary visibility: which solid, voxel and face every sample sees, decided by ray
//! tracing or by drawing the solids' voxel faces in object order.
//!
//! Methods (all sample the same points and hand the same [`SceneHit`]s to the one
//! shading stage, so they give the same picture):
//! - [`Method::Trace`]: the octree ray walk.
//! - [`Method::FrontToBack`]: Meagher's octree display (`raster::front_to_back`): full nodes
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
//! there; the hit is then computed by [`VoxelRay::entry`], as in the walk (`raster::face`). Solids are drawn one at a time and merged per sample by depth
//! (ties: the earlier solid), so a scene of several solids needs one depth per sample
//! whatever the method.

use rayon::prelude::*;

use super::film::{Camera, SampleGrid};
use super::raster::{self, FaceDrawer};
use super::scene::{Scene, SceneHit};
use super::trace::TILE;
use crate::progress::{NoProgress, Progress};
use crate::ray::Ray;

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

impl Method {
    /// Every value, in the order `--help` lists them.
    pub const ALL: [Method; 5] =
        [Method::Trace, Method::FrontToBack, Method::Painter, Method::ZBuffer, Method::ScanLine];

    /// The value's one spelling (the command line's, a viewer query's, `Display`'s).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Method::Trace => "trace",
            Method::FrontToBack => "front-to-back",
            Method::Painter => "painter",
            Method::ZBuffer => "zbuffer",
            Method::ScanLine => "scanline",
        }
    }
}

crate::spelling::spelled!(Method);

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
    samples: &SampleGrid,
    method: Method,
) -> (Vec<Option<SceneHit>>, VisibilityStats) {
    visibility_or_stop(scene, camera, samples, method, &NoProgress)
}

/// [`visibility`], leaving the rest of the frame unseen once `stop` asks to stop (the
/// traced method between bands of rows, the others between solids; the caller
/// returns `Cancelled`).
pub(crate) fn visibility_or_stop(
    scene: &Scene,
    camera: &Camera,
    samples: &SampleGrid,
    method: Method,
    stop: &dyn Progress,
) -> (Vec<Option<SceneHit>>, VisibilityStats) {
    let mut seen = Vec::new();
    let stats = visibility_into_or_stop(scene, camera, samples, method, &mut seen, stop);
    (seen, stats)
}

/// [`visibility`] into a frame buffer of the caller's, resized to the sample grid: a
/// viewer drawing frame after frame keeps one buffer (a fresh one costs a page fault
/// every 4 KiB of its first writes, a fifth of a front-to-back frame at 1024x1024).
pub fn visibility_into(
    scene: &Scene,
    camera: &Camera,
    samples: &SampleGrid,
    method: Method,
    seen: &mut Vec<Option<SceneHit>>,
) -> VisibilityStats {
    visibility_into_or_stop(scene, camera, samples, method, seen, &NoProgress)
}

/// [`visibility_into`] with [`visibility_or_stop`]'s `stop`.
fn visibility_into_or_stop(
    scene: &Scene,
    camera: &Camera,
    samples: &SampleGrid,
    method: Method,
    seen: &mut Vec<Option<SceneHit>>,
    stop: &dyn Progress,
) -> VisibilityStats {
    let view = camera.view(samples.aspect());
    let count = (samples.rows() * samples.columns()) as usize;
    // Every sample None, on all threads (the first writes of a fresh buffer fault its pages in).
    seen.truncate(count);
    seen.par_iter_mut().for_each(|s| *s = None);
    let missing = count - seen.len();
    seen.par_extend(rayon::iter::repeat_n(None, missing));
    if method == Method::FrontToBack {
        let faces_drawn = raster::front_to_back(scene, &view, samples, seen);
        return VisibilityStats { faces_drawn };
    }
    let columns = samples.columns() as usize;
    let rays: Vec<Ray> = (0..samples.rows() * samples.columns())
        .into_par_iter()
        .map(|i| {
            let (x, y) = samples.point(i % samples.columns(), i / samples.columns());
            view.ray(x, y)
        })
        .collect();
    if method == Method::Trace {
        // One packet a tile of TILE x TILE samples, a band of TILE rows a task.
        seen.par_chunks_mut(TILE * columns).zip(rays.par_chunks(TILE * columns)).for_each(|(seen, rays)| {
            if stop.cancelled() {
                return;
            }
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
        if stop.cancelled() {
            break;
        }
        let domain = *solid.traversal.domain();
        let drawer = FaceDrawer::new(&view, samples, &rays, domain);
        let (hits, faces) = match method {
            Method::Painter => drawer.painter(&solid.traversal),
            Method::ScanLine => drawer.scan_lines(&solid.traversal),
            Method::ZBuffer | Method::Trace | Method::FrontToBack => drawer.z_buffer(&solid.traversal),
        };
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
