//! Form factors from a receiving element to a shooting patch, by rays through the
//! octree.
//!
//! The form factor from a differential area `dA` at `p` (unit normal `n`) to a patch
//! `A_j` is `F = int_Aj cos(theta) cos(theta_j) / (pi r^2) V dA_j`. Wallace, Elmquist
//! and Haines ("A ray tracing algorithm for progressive radiosity", 1989) sample it
//! at points `q_k` of the patch, each standing for a disc of area `A_j / m`:
//!
//! ```text
//! F ~ sum_k V(p, q_k) cos(theta_k) cos(theta_jk) (A_j / m) / (pi r_k^2 + A_j / m)
//! ```
//!
//! Departure: the disc sum is used only for the visibility, as the kernel-weighted
//! fraction `V = sum_k w_k V_k / sum_k w_k` of the sample rays that reach the patch,
//! and multiplies the exact unoccluded form factor of the rectangle (Lambert's contour
//! integral, `F = 1/(2 pi) sum_edges gamma_e n . (R_e x R_e+1) / |R_e x R_e+1|`, over
//! the rectangle clipped to the half-space in front of `n`; Baum, Rushmeier and Winget
//! 1989 pair analytic form factors and ray-cast visibility the same way). So an
//! unoccluded pair is exact even where the patch is near or large (where the disc sum
//! is far off), and the rays only decide the shadows.
//!
//! A tile of the true surface that its surface covers only in part (`cover`) takes
//! the same rectangle's form factor, its sample points off the surface counted as
//! occluded; a far one (one sample) takes the covered fraction of the rectangle's
//! form factor, seen or not from the covered part's centroid. Exact for full tiles,
//! the kernel-weighted estimate of the covered part for the rest.
//!
//! Samples: the centres of an `m = s x s` grid on the patch, `s = ceil(4 L / d)`
//! clamped to `1..=MAX_SAMPLES_A_SIDE`, `L` the patch's longer edge and `d` the
//! distance to its centre: one ray for a far patch, up to 64 for a near one. The
//! points sit a thousandth of a voxel off both faces; `RayCast::occluded` of the
//! scene (the traversal walk of each solid) answers each ray. The grid is fixed, so
//! the result does not depend on threads or on the order of shots.

use glam::DVec3;
use smallvec::SmallVec;

use super::patch::Patch;
use super::patches::Element;
use crate::ray::Ray;
use crate::render::scene::{Cast, Scene};

/// Most sample points along a patch edge.
pub(crate) const MAX_SAMPLES_A_SIDE: u32 = 8;

/// Samples a side per unit of `patch edge / distance`.
const SAMPLE_DENSITY: f64 = 4.0;

/// The unoccluded form factor from the differential area at `p` of unit normal `n`
/// to the polygon `corners` (either orientation): the contour integral over the part
/// in front of `p`'s plane.
pub(crate) fn point_to_polygon(p: DVec3, n: DVec3, corners: &[DVec3]) -> f64 {
    // Clip to n . (x - p) >= 0 (Sutherland-Hodgman, one plane).
    let mut clipped: SmallVec<[DVec3; 8]> = SmallVec::new();
    let height = |q: DVec3| n.dot(q - p);
    for (i, &a) in corners.iter().enumerate() {
        let b = corners[(i + 1) % corners.len()];
        let (ha, hb) = (height(a), height(b));
        if ha >= 0.0 {
            clipped.push(a);
        }
        if (ha >= 0.0) != (hb >= 0.0) {
            clipped.push(a + (b - a) * (ha / (ha - hb)));
        }
    }
    if clipped.len() < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for (i, &a) in clipped.iter().enumerate() {
        let (ra, rb) = (a - p, clipped[(i + 1) % clipped.len()] - p);
        let cross = ra.cross(rb);
        let len = cross.length();
        if len <= 1e-300 {
            continue;
        }
        let gamma = len.atan2(ra.dot(rb));
        sum += gamma * n.dot(cross) / len;
    }
    sum.abs() / (2.0 * std::f64::consts::PI)
}

/// The form factor from element `e` to patch `shooter` with the visibility of the
/// scene's solids (see the module doc), and the rays cast.
pub(crate) fn element_to_patch(scene: &Scene, e: &Element, shooter: &Patch) -> (f64, u32) {
    // The shooter emits from its front side only.
    if shooter.normal.dot(e.center - shooter.corner) <= 0.0 {
        return (0.0, 0);
    }
    let unoccluded = point_to_polygon(e.center, e.normal, &shooter.corners());
    if unoccluded <= 0.0 {
        return (0.0, 0);
    }
    let edge = shooter.du.length().max(shooter.dv.length());
    let d = (shooter.center() - e.center).length();
    let side = (SAMPLE_DENSITY * edge / d.max(1e-300)).ceil().clamp(1.0, f64::from(MAX_SAMPLES_A_SIDE)) as u32;
    let cover = shooter.cover.as_deref();
    if side == 1
        && let Some(cover) = cover
    {
        // A far, partly covered tile: its covered fraction of the rectangle's form
        // factor, seen or not from its surface's centroid.
        let c = cover.centroid();
        let q = shooter.point(c.x, c.y) + shooter.normal * shooter.lift;
        let v = q - e.origin;
        let r = v.length();
        if r <= 0.0 || scene.occluded_as(&Ray::segment(e.origin, v / r, r), Cast::Bounce) {
            return (0.0, 1);
        }
        return (unoccluded * cover.plane_fraction(), 1);
    }
    let disc = shooter.area / f64::from(side * side);
    let (mut seen, mut total) = (0.0, 0.0);
    for j in 0..side {
        for i in 0..side {
            let (s, t) = ((f64::from(i) + 0.5) / f64::from(side), (f64::from(j) + 0.5) / f64::from(side));
            let q = shooter.point(s, t) + shooter.normal * shooter.lift;
            let v = q - e.origin;
            let r2 = v.length_squared();
            let r = r2.sqrt();
            let dir = v / r;
            let w =
                (e.normal.dot(dir).max(0.0) * (-shooter.normal.dot(dir)).max(0.0)) / (std::f64::consts::PI * r2 + disc);
            if w <= 0.0 {
                continue;
            }
            total += w;
            if cover.is_some_and(|c| !c.covers(s, t)) {
                continue;
            }
            if !scene.occluded_as(&Ray::segment(e.origin, dir, r), Cast::Bounce) {
                seen += w;
            }
        }
    }
    let rays = side * side;
    if total <= 0.0 {
        return (0.0, rays);
    }
    (unoccluded * seen / total, rays)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_under_a_disc_like_polygon_matches_the_closed_form() {
        // A differential area facing a coaxial disc of radius R at height H: R^2 / (H^2 + R^2).
        // The disc as a 256-gon (area-equal radius).
        let (radius, height) = (0.7, 1.3);
        let n = 256;
        let k = std::f64::consts::TAU / f64::from(n);
        let re = radius * (k / k.sin()).sqrt();
        let corners: Vec<DVec3> =
            (0..n).map(|i| DVec3::new(re * (k * f64::from(i)).cos(), re * (k * f64::from(i)).sin(), height)).collect();
        let f = point_to_polygon(DVec3::ZERO, DVec3::Z, &corners);
        let want = radius * radius / (height * height + radius * radius);
        assert!((f - want).abs() < 1e-4 * want, "{f} against {want}");
    }

    #[test]
    fn a_polygon_behind_the_plane_gives_nothing_and_half_behind_is_clipped() {
        let square = [
            DVec3::new(-1.0, -1.0, -1.0),
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(1.0, 1.0, -1.0),
            DVec3::new(-1.0, 1.0, -1.0),
        ];
        assert_eq!(point_to_polygon(DVec3::ZERO, DVec3::Z, &square), 0.0);
        // A wall x = 1 spanning z -1..1 seen from the origin with normal +z: only its upper half counts,
        // which is a quarter of what the normal +x sees of the whole wall... check symmetry instead:
        let wall = [
            DVec3::new(1.0, -1.0, -1.0),
            DVec3::new(1.0, 1.0, -1.0),
            DVec3::new(1.0, 1.0, 1.0),
            DVec3::new(1.0, -1.0, 1.0),
        ];
        let up = point_to_polygon(DVec3::ZERO, DVec3::Z, &wall);
        let down = point_to_polygon(DVec3::ZERO, -DVec3::Z, &wall);
        assert!(up > 0.0 && (up - down).abs() < 1e-12);
        // The six faces of a cube around the point sum to 1 for any normal.
        let n = DVec3::new(0.3, -0.5, 0.8).normalize();
        let mut sum = 0.0;
        for a in 0..3 {
            for sign in [-1.0, 1.0] {
                let (u, v) = ((a + 1) % 3, (a + 2) % 3);
                let corner = |x: f64, y: f64| {
                    let mut c = DVec3::ZERO;
                    c[a] = sign;
                    c[u] = x;
                    c[v] = y;
                    c
                };
                sum += point_to_polygon(
                    DVec3::ZERO,
                    n,
                    &[corner(-1.0, -1.0), corner(1.0, -1.0), corner(1.0, 1.0), corner(-1.0, 1.0)],
                );
            }
        }
        assert!((sum - 1.0).abs() < 1e-12, "{sum}");
    }
}
