//! Triangles as a rasterizer sees them: each corner projected by the camera to pixels
//! (x right, y down) with its view depth, the pixel centres a triangle's box covers,
//! screen-space barycentrics by edge functions (Pineda, "A parallel algorithm for
//! polygon rasterization", 1988), and depth interpolated perspective-correct
//! (`1/z = sum w_i / z_i`) or linearly under a parallel camera. Shared by the
//! scan-line and whole-image Z-buffers (`polygon`) and the depth sort (`depth_sort`).

use rayon::prelude::*;

use crate::mesh::TriangleMesh;
use crate::render::film::Camera;

/// What a pixel centre sees: the triangle and its screen-space barycentrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    /// Index of the triangle.
    pub triangle: usize,
    /// Screen-space barycentric coordinates of the pixel centre.
    pub weights: [f64; 3],
    /// View depth of the surface point (distance along the view axis).
    pub depth: f64,
}

/// A triangle as drawn: its projected corners in pixels and their view depths.
pub(super) struct Projected {
    /// The corners in pixels (x right, y down).
    pub(super) screen: [(f64, f64); 3],
    /// The corners' view depths (distance along the view axis).
    pub(super) depth: [f64; 3],
    /// Twice the signed screen area (edge function normalizer).
    pub(super) area: f64,
}

/// Every triangle projected to the `width x height` pixel grid (`None`: a corner behind
/// a perspective camera, or no screen area).
pub(super) fn project_triangles(
    mesh: &TriangleMesh,
    camera: &Camera,
    width: u32,
    height: u32,
) -> Vec<Option<Projected>> {
    let aspect = f64::from(width) / f64::from(height);
    let forward = (camera.target - camera.eye).normalize();
    mesh.triangles
        .par_iter()
        .map(|t| {
            let mut screen = [(0.0, 0.0); 3];
            let mut depth = [0.0; 3];
            for k in 0..3 {
                let p = mesh.vertices[t[k] as usize];
                screen[k] = to_pixels(camera.project(p, aspect)?, width, height);
                depth[k] = (p - camera.eye).dot(forward);
            }
            let [a, b, c] = screen;
            let area = (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0);
            (area != 0.0).then_some(Projected { screen, depth, area })
        })
        .collect()
}

/// A projected point (`[-1, 1]^2`, y up) in pixels of a `width x height` grid (y down).
pub(super) fn to_pixels((x, y): (f64, f64), width: u32, height: u32) -> (f64, f64) {
    ((x + 1.0) * 0.5 * f64::from(width), (1.0 - y) * 0.5 * f64::from(height))
}

impl Projected {
    /// The view depth at screen barycentrics `weights`: perspective-correct
    /// (`1/z = sum wi / zi`) under a perspective camera, linear under a parallel one.
    pub(super) fn depth_at(&self, weights: [f64; 3], perspective: bool) -> f64 {
        if perspective {
            1.0 / (0..3).map(|k| weights[k] / self.depth[k]).sum::<f64>()
        } else {
            (0..3).map(|k| weights[k] * self.depth[k]).sum()
        }
    }

    /// `visit(pixel, x, y)` for every pixel centre `(x, y)` of the triangle's bounding
    /// box within the grid.
    pub(super) fn for_each_pixel(&self, width: u32, height: u32, mut visit: impl FnMut(usize, f64, f64)) {
        let (xs, ys) = (self.screen.map(|s| s.0), self.screen.map(|s| s.1));
        let (c0, c1) = pixel_range(xs, width);
        let (r0, r1) = pixel_range(ys, height);
        for r in r0..r1 {
            for c in c0..c1 {
                visit(r * width as usize + c, c as f64 + 0.5, r as f64 + 0.5);
            }
        }
    }
}

/// The pixel indices `first..end` whose centres lie within the span of `coords`.
pub(super) fn pixel_range(coords: impl IntoIterator<Item = f64>, n: u32) -> (usize, usize) {
    let (lo, hi) = coords.into_iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let first = (lo - 0.5).ceil().max(0.0);
    let last = (hi - 0.5).floor().min(f64::from(n) - 1.0);
    if first > last { (0, 0) } else { (first as usize, last as usize + 1) }
}

/// Screen-space barycentrics of `(x, y)`, `None` outside the triangle.
pub(super) fn barycentric(p: &Projected, x: f64, y: f64) -> Option<[f64; 3]> {
    let edge = |a: (f64, f64), b: (f64, f64)| (b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0);
    let [a, b, c] = p.screen;
    let w = [edge(b, c) / p.area, edge(c, a) / p.area, edge(a, b) / p.area];
    w.iter().all(|&w| w >= 0.0).then_some(w)
}
