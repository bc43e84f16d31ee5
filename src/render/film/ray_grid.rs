//! The primary rays of a sample grid from per-column and per-row terms: the ray of
//! sample `(col, row)` is [`View::ray`] at [`SampleGrid::point`]`(col, row)`, bit for bit,
//! with the image point's divisions and products done once a column and once a row.

use glam::DVec3;

use super::camera::{Projection, View};
use super::sample_grid::SampleGrid;
use crate::ray::Ray;

/// Per-column and per-row terms of [`View::ray`] over a sample grid.
///
/// [`View::ray`] sums `base + right (x h aspect) + up (y h)` left to right (`base` the
/// forward direction for perspective, the eye for orthographic), so the sum of column
/// `col`'s `base + right (x h aspect)` and row `row`'s `up (y h)` is the same number;
/// perspective then normalizes it to the direction from the eye, orthographic takes it
/// as the origin of a ray along forward.
#[derive(Clone, Debug)]
pub(crate) struct RayGrid {
    /// `base + right (x h aspect)` for each sample column.
    columns: Vec<DVec3>,
    /// `up (y h)` for each sample row.
    rows: Vec<DVec3>,
    /// The eye for perspective (every ray's origin), `None` for orthographic.
    eye: Option<DVec3>,
    /// The direction of every orthographic ray.
    forward: DVec3,
}

impl RayGrid {
    /// The terms of `view`'s rays through the samples of `samples`.
    pub(crate) fn new(view: &View, samples: &SampleGrid) -> Self {
        let (base, eye) = match view.projection {
            Projection::Perspective { .. } => (view.forward, Some(view.eye)),
            Projection::Orthographic { .. } => (view.eye, None),
        };
        let h = view.half;
        let columns = (0..samples.columns()).map(|col| base + view.right * (samples.point(col, 0).0 * h * view.aspect));
        let rows = (0..samples.rows()).map(|row| view.up * (samples.point(0, row).1 * h));
        RayGrid { columns: columns.collect(), rows: rows.collect(), eye, forward: view.forward }
    }

    /// The ray of sample `(col, row)`, with a unit direction.
    #[inline]
    pub(crate) fn ray(&self, col: usize, row: usize) -> Ray {
        let sum = self.columns[col] + self.rows[row];
        match self.eye {
            Some(eye) => Ray::new(eye, sum.normalize()),
            None => Ray::new(sum, self.forward),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::film::Camera;

    #[test]
    fn rays_are_the_views_bit_for_bit() {
        let samples = SampleGrid { width: 13, height: 7, spp: 3 };
        let eye = DVec3::new(1.5, -2.25, 0.75);
        let target = DVec3::new(0.1, 0.3, -0.2);
        let up = DVec3::new(0.1, 0.2, 1.0);
        for projection in [Projection::Perspective { fov_y: 37.0 }, Projection::Orthographic { height: 2.5 }] {
            let view = Camera { eye, target, up, projection }.view(samples.aspect());
            let grid = RayGrid::new(&view, &samples);
            for row in 0..samples.rows() {
                for col in 0..samples.columns() {
                    let (x, y) = samples.point(col, row);
                    let want = view.ray(x, y);
                    let got = grid.ray(col as usize, row as usize);
                    let bits = |v: DVec3| v.to_array().map(f64::to_bits);
                    assert_eq!(
                        (bits(got.origin), bits(got.dir)),
                        (bits(want.origin), bits(want.dir)),
                        "{projection:?}, sample {col}, {row}"
                    );
                }
            }
        }
    }
}
