//! What part of a patch's rectangle its surface covers: the patch's triangles clipped
//! to the rectangle, as convex pieces in the rectangle's `(s, t)` coordinates.
//!
//! A patch of the true surface is a tile of its region's bounding rectangle
//! (`surface_patches`); where the region's outline does not follow the tiles (the
//! floor around a turned block's footprint, a curved cluster's ragged edge) only part
//! of the tile is surface. Areas and centroids of any sub-rectangle (an element, at any
//! level of subdivision) come from clipping the pieces to it (Sutherland and Hodgman
//! 1974, one axis-aligned edge at a time), exactly; a raster of
//! [`RASTER`]` x `[`RASTER`] cells (each set when its centre lies in a piece) answers
//! whether a sample point of the form factor's rays lies on the surface.
//!
//! A piece carries the ratio of its true area to its area in the rectangle's plane
//! (1 on a planar region; `1 / cos` of its tilt in a curved cluster), so areas are
//! the surface's, not its shadow's.

use glam::DVec2;
use smallvec::SmallVec;

/// Cells of the coverage raster along each side.
pub(crate) const RASTER: usize = 32;

/// A convex polygon in `(s, t)` and its area scale (true area over plane area).
#[derive(Clone, Debug)]
pub(crate) struct Piece {
    pub points: SmallVec<[DVec2; 8]>,
    pub scale: f64,
}

impl Piece {
    /// Its box, lowest and highest corner.
    fn bounds(&self) -> (DVec2, DVec2) {
        self.points
            .iter()
            .fold((DVec2::splat(f64::MAX), DVec2::splat(f64::MIN)), |(lo, hi), p| (lo.min(*p), hi.max(*p)))
    }
}

/// The covered part of a patch's rectangle (module doc).
#[derive(Clone, Debug)]
pub(crate) struct Cover {
    pieces: Vec<Piece>,
    /// Each piece's box.
    boxes: Vec<(DVec2, DVec2)>,
    /// The covered fraction of the rectangle in its plane (the pieces' own areas).
    plane_fraction: f64,
    /// The centroid of the covered part.
    centroid: DVec2,
    raster: [u64; RASTER * RASTER / 64],
}

/// The polygon `points` clipped to the half-plane `sign * (p[axis] - at) <= 0`.
fn clip(points: &[DVec2], axis: usize, at: f64, sign: f64) -> SmallVec<[DVec2; 8]> {
    let mut out = SmallVec::new();
    let inside = |p: DVec2| sign * (p[axis] - at) <= 0.0;
    for (i, &a) in points.iter().enumerate() {
        let b = points[(i + 1) % points.len()];
        if inside(a) {
            out.push(a);
        }
        if inside(a) != inside(b) {
            let f = (at - a[axis]) / (b[axis] - a[axis]);
            let mut p = a + (b - a) * f;
            p[axis] = at;
            out.push(p);
        }
    }
    out
}

/// The polygon `points` clipped to the rectangle `[s0, s1] x [t0, t1]`.
pub(crate) fn clip_to_rect(points: &[DVec2], s0: f64, s1: f64, t0: f64, t1: f64) -> SmallVec<[DVec2; 8]> {
    let p = clip(points, 0, s0, -1.0);
    let p = clip(&p, 0, s1, 1.0);
    let p = clip(&p, 1, t0, -1.0);
    clip(&p, 1, t1, 1.0)
}

/// A polygon's area (either orientation) and centroid; the area is 0 (centroid the
/// first point, or the origin) for fewer than three points.
pub(crate) fn area_and_centroid(points: &[DVec2]) -> (f64, DVec2) {
    if points.len() < 3 {
        return (0.0, points.first().copied().unwrap_or(DVec2::ZERO));
    }
    let (mut twice, mut c) = (0.0, DVec2::ZERO);
    let o = points[0];
    for i in 1..points.len() - 1 {
        let (a, b) = (points[i] - o, points[i + 1] - o);
        let cross = a.perp_dot(b);
        twice += cross;
        c += (a + b) * (cross / 3.0);
    }
    if twice.abs() <= 0.0 {
        return (0.0, o);
    }
    (0.5 * twice.abs(), o + c / twice)
}

/// Whether the convex polygon `points` (either orientation) holds `q`.
fn holds(points: &[DVec2], q: DVec2) -> bool {
    let (mut pos, mut neg) = (false, false);
    for (i, &a) in points.iter().enumerate() {
        let b = points[(i + 1) % points.len()];
        let side = (b - a).perp_dot(q - a);
        pos |= side > 0.0;
        neg |= side < 0.0;
    }
    !(pos && neg)
}

impl Cover {
    /// The cover of the pieces (each already within `[0, 1]^2`).
    pub fn new(pieces: Vec<Piece>) -> Cover {
        let mut raster = [0u64; RASTER * RASTER / 64];
        let n = RASTER as f64;
        for piece in &pieces {
            if piece.points.len() < 3 {
                continue;
            }
            let (lo, hi) = piece.bounds();
            let cells = |a: f64, b: f64| {
                let first = ((a * n - 0.5).ceil().max(0.0)) as usize;
                let last = ((b * n - 0.5).floor().min(n - 1.0)) as i64;
                first..(last + 1).max(first as i64) as usize
            };
            for j in cells(lo.y, hi.y) {
                for i in cells(lo.x, hi.x) {
                    let q = DVec2::new((i as f64 + 0.5) / n, (j as f64 + 0.5) / n);
                    if holds(&piece.points, q) {
                        let bit = j * RASTER + i;
                        raster[bit / 64] |= 1 << (bit % 64);
                    }
                }
            }
        }
        let (mut plane_fraction, mut moment) = (0.0, DVec2::ZERO);
        for piece in &pieces {
            let (a, c) = area_and_centroid(&piece.points);
            plane_fraction += a;
            moment += c * a;
        }
        let centroid = if plane_fraction > 0.0 { moment / plane_fraction } else { DVec2::splat(0.5) };
        let boxes = pieces.iter().map(Piece::bounds).collect();
        Cover { pieces, boxes, plane_fraction, centroid, raster }
    }

    /// The covered fraction of the rectangle, in its plane.
    pub fn plane_fraction(&self) -> f64 {
        self.plane_fraction
    }

    /// The centroid `(s, t)` of the covered part.
    pub fn centroid(&self) -> DVec2 {
        self.centroid
    }

    /// Whether the raster cell holding `(s, t)` is covered.
    pub fn covers(&self, s: f64, t: f64) -> bool {
        let n = RASTER as f64;
        let i = ((s * n) as usize).min(RASTER - 1);
        let j = ((t * n) as usize).min(RASTER - 1);
        let bit = j * RASTER + i;
        self.raster[bit / 64] & (1 << (bit % 64)) != 0
    }

    /// The covered part of `[s0, s1] x [t0, t1]`: its true area as a fraction of the
    /// whole rectangle's (`[0, 1]^2`) and its centroid (the sub-rectangle's centre when
    /// nothing of it is covered).
    pub fn within(&self, s0: f64, s1: f64, t0: f64, t1: f64) -> (f64, DVec2) {
        let (mut area, mut moment, mut plane) = (0.0, DVec2::ZERO, 0.0);
        for (piece, &(lo, hi)) in self.pieces.iter().zip(&self.boxes) {
            if hi.x <= s0 || lo.x >= s1 || hi.y <= t0 || lo.y >= t1 {
                continue;
            }
            let inside = lo.x >= s0 && hi.x <= s1 && lo.y >= t0 && hi.y <= t1;
            let (a, c) = if inside {
                area_and_centroid(&piece.points)
            } else {
                area_and_centroid(&clip_to_rect(&piece.points, s0, s1, t0, t1))
            };
            area += a * piece.scale;
            moment += c * a;
            plane += a;
        }
        let centre = if plane > 0.0 { moment / plane } else { DVec2::new(0.5 * (s0 + s1), 0.5 * (t0 + t1)) };
        (area, centre)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_triangle_over_half_the_square_covers_half_and_clips_to_quarters() {
        let half = Piece {
            points: [DVec2::ZERO, DVec2::new(1.0, 0.0), DVec2::new(0.0, 1.0)].into_iter().collect(),
            scale: 1.0,
        };
        let cover = Cover::new(vec![half]);
        let (area, c) = cover.within(0.0, 1.0, 0.0, 1.0);
        assert!((area - 0.5).abs() < 1e-15 && (c - DVec2::splat(1.0 / 3.0)).length() < 1e-15);
        // The lower-left quarter is whole, the upper-right one empty, the others half.
        assert!((cover.within(0.0, 0.5, 0.0, 0.5).0 - 0.25).abs() < 1e-15);
        assert_eq!(cover.within(0.5, 1.0, 0.5, 1.0).0, 0.0);
        assert!((cover.within(0.5, 1.0, 0.0, 0.5).0 - 0.125).abs() < 1e-15);
        assert!(cover.covers(0.2, 0.2) && !cover.covers(0.8, 0.8) && cover.covers(0.6, 0.3));
    }
}
