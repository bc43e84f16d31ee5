//! The seed's scan-line Z-buffer over a solid's voxel faces: a polygon table of the
//! faces looking at the viewer, an edge table of their projected edges bucketed by
//! first sample row, and per row the active edge table and active polygon table giving
//! each polygon's span; one row of depths.
//!
//! Deviation from the seed: the depth and coverage of a span's samples come from the
//! exact ray-plane test, not the incremental `z -= a / c` (which would differ in the
//! last bits and break the bit-exact agreement with the other methods); the spans are
//! widened by a sample so that they only ever propose.

use glam::DVec3;

use super::FaceDrawer;
use super::face::Face;
use crate::render::trace::{Hit, Traversal, VoxelRay};

impl FaceDrawer<'_> {
    /// The scan-line Z-buffer (see the module doc).
    pub(crate) fn scan_lines(&self, traversal: &Traversal) -> (Vec<Option<Hit>>, u64) {
        let (columns, rows) = (self.samples.columns() as usize, self.samples.rows() as i64);
        // Step 1: polygon table (front faces) and edge table (projected edges by first row).
        let Tables { polygons, mut edge_table, full_screen } = self.tables(traversal);
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
                let c0 = (x0.floor() as i64).saturating_sub(1).clamp(0, columns as i64 - 1) as usize;
                let c1 = (x1.ceil() as i64).saturating_add(1).clamp(0, columns as i64 - 1) as usize;
                let face = &polygons[id];
                for c in c0..=c1 {
                    let i = r as usize * columns + c;
                    let ray = VoxelRay::new(&self.domain, &self.rays[i]);
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

    /// The polygon table (the faces looking at the viewer), the edge table (their
    /// projected edges, bucketed by first sample row) and the polygons with a corner
    /// behind the eye (they may cover every sample).
    fn tables(&self, traversal: &Traversal) -> Tables {
        let rows = self.samples.rows() as i64;
        let h = self.domain.voxel_size();
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
        Tables { polygons, edge_table, full_screen }
    }
}

/// The scan-line algorithm's tables (see [`FaceDrawer::tables`]).
struct Tables {
    polygons: Vec<Polygon>,
    edge_table: Vec<Vec<Edge>>,
    full_screen: Vec<usize>,
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
