//! Inside by ray parity: count the triangles a ray from `p` along `+x` crosses.
//!
//! The triangles are binned by their projection on the `yz` plane into a uniform grid,
//! so a query tests only the triangles of one cell. A ray that passes exactly through
//! a shared edge or vertex is counted once: the 2-D point-in-triangle test uses the
//! top-left rule (an edge on the point counts only for the triangle that owns it, and
//! of two triangles that share an edge and lie on opposite sides, exactly one owns it),
//! with exact orientation signs.

use glam::{DVec2, DVec3};

use super::TriangleMesh;
use super::predicates::orient2d;

/// A `yz` grid of triangle lists for `+x` ray casting.
#[derive(Clone, Debug)]
pub struct ParityGrid {
    corners: Vec<[DVec3; 3]>,
    min: DVec2,
    cell: DVec2,
    cells: usize,
    /// Cell `i` holds `items[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<u32>,
    items: Vec<u32>,
}

/// Most cells a side of the grid.
const MAX_CELLS: usize = 1024;

/// The grid holds at most this many list entries a triangle (plus [`SPARE_ENTRIES`]):
/// where large triangles would cover more cells than that, the grid is made coarser
/// until they fit, so its memory is linear in the triangles whatever their shape.
const ENTRIES_PER_TRIANGLE: u64 = 16;

/// List entries allowed beyond [`ENTRIES_PER_TRIANGLE`] a triangle.
const SPARE_ENTRIES: u64 = 1024;

impl ParityGrid {
    /// Bins every triangle into the cells its `yz` bounding box overlaps.
    ///
    /// The grid has about `sqrt(triangles)` cells a side (at most 1024),
    /// halved until the lists hold at most 16 entries a triangle,
    /// so its bytes are at most [`ParityGrid::max_bytes`].
    #[must_use]
    pub fn new(mesh: &TriangleMesh) -> Self {
        let corners: Vec<[DVec3; 3]> = (0..mesh.triangles.len()).map(|t| mesh.corners(t)).collect();
        let b = mesh.bounds();
        let min = DVec2::new(b.min.y, b.min.z);
        let extent = (DVec2::new(b.max.y, b.max.z) - min).max(DVec2::splat(1e-300));
        let limit = (ENTRIES_PER_TRIANGLE * corners.len() as u64 + SPARE_ENTRIES).min(u64::from(u32::MAX));
        let mut cells = ((corners.len() as f64).sqrt() as usize).clamp(1, MAX_CELLS);
        while cells > 1 && entries(&corners, min, extent / cells as f64, cells) > limit {
            cells /= 2;
        }
        let cell = extent / cells as f64;
        // Counting sort into cells: count, prefix sum, fill.
        let mut offsets = vec![0u32; cells * cells + 1];
        for t in &corners {
            let (y0, y1, z0, z1) = span(t, min, cell, cells);
            for z in z0..=z1 {
                for y in y0..=y1 {
                    offsets[z * cells + y + 1] += 1;
                }
            }
        }
        for i in 1..offsets.len() {
            offsets[i] += offsets[i - 1];
        }
        let mut fill = offsets.clone();
        let mut items = vec![0u32; offsets[cells * cells] as usize];
        for (i, t) in corners.iter().enumerate() {
            let (y0, y1, z0, z1) = span(t, min, cell, cells);
            for z in z0..=z1 {
                for y in y0..=y1 {
                    let c = z * cells + y;
                    items[fill[c] as usize] = i as u32;
                    fill[c] += 1;
                }
            }
        }
        ParityGrid { corners, min, cell, cells, offsets, items }
    }

    /// Bytes the grid holds: corners, offsets and lists.
    #[must_use]
    pub fn bytes(&self) -> u64 {
        (72 * self.corners.len() + 4 * self.offsets.len() + 4 * self.items.len()) as u64
    }

    /// Most bytes the grid of a mesh of `triangles` triangles takes at its peak: the
    /// corners (72 bytes a triangle), two offset tables of `MAX_CELLS^2` cells and the
    /// lists.
    #[must_use]
    pub fn max_bytes(triangles: usize) -> u64 {
        let cells = (MAX_CELLS * MAX_CELLS + 1) as u64;
        let entries = ENTRIES_PER_TRIANGLE * triangles as u64 + SPARE_ENTRIES;
        72 * triangles as u64 + 2 * 4 * cells + 4 * entries
    }

    /// Number of triangles the ray from `p` along `+x` crosses.
    #[must_use]
    pub fn crossings(&self, p: DVec3) -> u32 {
        let q = DVec2::new(p.y, p.z);
        let c = ((q - self.min) / self.cell).floor();
        if c.x < 0.0 || c.y < 0.0 || c.x >= self.cells as f64 || c.y >= self.cells as f64 {
            return 0;
        }
        let cell = c.y as usize * self.cells + c.x as usize;
        let items = &self.items[self.offsets[cell] as usize..self.offsets[cell + 1] as usize];
        items.iter().filter(|&&t| crosses(&self.corners[t as usize], p, q)).count() as u32
    }
}

/// The cells (first and last column, first and last row) the `yz` bounding box of
/// triangle `t` overlaps in a grid of `cells` cells a side of size `cell` from `min`.
fn span(t: &[DVec3; 3], min: DVec2, cell: DVec2, cells: usize) -> (usize, usize, usize, usize) {
    let yz = t.map(|v| DVec2::new(v.y, v.z));
    let lo = ((yz[0].min(yz[1]).min(yz[2]) - min) / cell).floor();
    let hi = ((yz[0].max(yz[1]).max(yz[2]) - min) / cell).floor();
    let clamp = |v: f64| (v.max(0.0) as usize).min(cells - 1);
    (clamp(lo.x), clamp(hi.x), clamp(lo.y), clamp(hi.y))
}

/// List entries a grid of `cells` cells a side would hold (saturating).
fn entries(corners: &[[DVec3; 3]], min: DVec2, cell: DVec2, cells: usize) -> u64 {
    corners.iter().fold(0u64, |sum, t| {
        let (y0, y1, z0, z1) = span(t, min, cell, cells);
        sum.saturating_add(((y1 - y0 + 1) * (z1 - z0 + 1)) as u64)
    })
}

/// Whether the `+x` ray from `p` (with `q = (p.y, p.z)`) crosses triangle `t`.
#[inline]
fn crosses(t: &[DVec3; 3], p: DVec3, q: DVec2) -> bool {
    let v = t.map(|v| DVec2::new(v.y, v.z));
    let area = orient2d(v[0], v[1], v[2]);
    if area == 0.0 {
        return false; // seen edge-on: the ray grazes it
    }
    let s = area.signum();
    for k in 0..3 {
        let (a, b) = (v[k], v[(k + 1) % 3]);
        let e = s * orient2d(a, b, q);
        // Top-left rule: an edge through q counts when its direction (in the
        // triangle's counter-clockwise order) is negative in lexicographic order.
        let d = (b - a) * s;
        if e < 0.0 || (e == 0.0 && !(d.x < 0.0 || (d.x == 0.0 && d.y < 0.0))) {
            return false;
        }
    }
    // x of the triangle's plane at (y, z), by barycentric interpolation.
    let w1 = (q - v[0]).perp_dot(v[2] - v[0]) / (v[1] - v[0]).perp_dot(v[2] - v[0]);
    let w2 = (v[1] - v[0]).perp_dot(q - v[0]) / (v[1] - v[0]).perp_dot(v[2] - v[0]);
    let x = t[0].x + w1 * (t[1].x - t[0].x) + w2 * (t[2].x - t[0].x);
    x > p.x
}
