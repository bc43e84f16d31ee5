//! The distance from a voxel's centre to a solid's true surface near its nearest site,
//! from the site's Hermite data: the sub-voxel rule of an offset along the surface.
//!
//! The lattice rule ([`super::band`] without surface data) measures to the other
//! phase's voxel cubes, whose staircase lies up to half a voxel off a curved surface,
//! so a sphere's shell comes out half a voxel too thick. Here the surface is the one
//! the solid's crossings describe (Ju et al., *Dual Contouring of Hermite Data*, 2002:
//! a point and a normal a boundary face): for a voxel `p` of the phase a step spreads
//! into, its nearest site `s` (by the lattice transform, [`super::edt`], a feature
//! transform), and the tangent planes `n_i . (x - c_i) = 0` of `s`'s exposed faces
//! (the faces towards the other phase, each plane bounding the site's phase), the
//! distance is
//!
//! `d(p) = min(min_i |p - c_i|, max(dist(p, K), d_cube - 1/2))`,
//!
//! where `K` is the intersection of the half-spaces (the solid near `s` as its tangent
//! planes bound it: a face's plane, a sharp edge's wedge, a corner's cone) and `d_cube`
//! the lattice distance to `s`'s cube. `dist(p, K)` is the true distance for a flat
//! face, an edge or a corner, and for a smooth surface of radius `rho` it is off by
//! about `l^2 / (2 rho)` for a site `l` voxels to the side of `p`'s foot point; the
//! crossings bound it from above (each is a point of the surface), and `d_cube - 1/2`
//! from below (each crossing lies within half a voxel of `s`'s cube), so a degenerate
//! plane cannot carry it far. With no data a face's crossing is its centre with the
//! axis normal ([`FaceCrossings`] answering `None`).
//!
//! `d(p)` lies in `[d_cube - 1/2, d_cube + sqrt(3)/2]` (the crossing of `s`'s face
//! towards `p` is no farther than `s`'s centre), so only voxels with `d_cube` near the
//! step's radius need it.
//!
//! Where this departs from a true distance: the nearest site is the lattice's, not the
//! one nearest the true surface, and of equally near sites the transform's passes pick
//! one; the departure is second order in the voxel size for smooth surfaces.

use glam::DVec3;

/// Where a solid's surface crosses its boundary faces, as an offset reads it.
pub trait FaceCrossings: Sync {
    /// The crossing on the boundary face of the full voxel `voxel` (its Morton code)
    /// towards `direction` (`2 axis + 1` towards `+axis`, `2 axis` towards `-axis`):
    /// its place `t` from the full voxel's centre (`0..=1`, in voxels) and the surface's
    /// outward unit normal there; `None` for the face itself (`t = 1/2`, the axis).
    fn face_crossing(&self, voxel: u64, direction: u8) -> Option<(f32, [f32; 3])>;

    /// [`FaceCrossings::face_crossing`] of the full voxel `voxel` towards each
    /// direction set in `directions` (bit `d` for direction `d`), `None` for the others:
    /// one look-up for all where the crossings are stored by voxel.
    fn voxel_crossings(&self, voxel: u64, directions: u8) -> [Option<(f32, [f32; 3])>; 6] {
        std::array::from_fn(|d| if (directions >> d) & 1 == 1 { self.face_crossing(voxel, d as u8) } else { None })
    }
}

/// No surface data: every face is itself.
pub struct Staircase;

impl FaceCrossings for Staircase {
    fn face_crossing(&self, _voxel: u64, _direction: u8) -> Option<(f32, [f32; 3])> {
        None
    }
}

/// A crossing of the result of an offset along the surface, from its distance field:
/// the boundary face of the full voxel `voxel` (Morton code) towards `direction`, at
/// `t` from its centre, with the outward unit `normal`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewCrossing {
    /// Morton code of the result's full voxel.
    pub voxel: u64,
    /// The face's direction (`2 axis + 1` towards `+axis`).
    pub direction: u8,
    /// Place along the segment to the empty neighbour's centre, `0..=1`.
    pub t: f32,
    /// Outward unit normal of the result's surface there.
    pub normal: [f32; 3],
}

/// A tangent plane bounding a site's phase: `normal . (x - point) <= 0` on its side.
#[derive(Clone, Copy, Debug)]
pub(super) struct Plane {
    /// A point of the surface (the crossing), relative to the measured voxel's centre.
    pub point: DVec3,
    /// Unit normal pointing out of the site's phase.
    pub normal: DVec3,
}

/// The distance from the origin (a voxel's centre) to the surface near a site
/// bounded by `planes` (see the module doc), and the surface point it is measured to.
/// `d_cube` is the lattice distance to the site's cube.
pub(super) fn distance_to_site(planes: &[Plane], d_cube: f64) -> (f64, DVec3) {
    let (mut best, mut foot) = (f64::INFINITY, DVec3::ZERO);
    for plane in planes {
        let d = plane.point.length();
        if d < best {
            (best, foot) = (d, plane.point);
        }
    }
    // No point of K found: the crossings alone.
    let (cone, x) = distance_to_cone(planes).unwrap_or((best, foot));
    let lifted = cone.max(d_cube - 0.5);
    if lifted < best { (lifted, x) } else { (best, foot) }
}

/// The distance from the origin to `K`, the intersection of the planes' half-spaces,
/// and its nearest point: the nearest of the origin's projections onto the flats of one,
/// two or three of the planes that lie in `K` (the true projection is one of them);
/// `None` when none does (no point of `K` found, the normals contradicting).
fn distance_to_cone(planes: &[Plane]) -> Option<(f64, DVec3)> {
    // Normals are unit to a float's precision: a projection's own plane holds it to
    // about 1e-16, a neighbour's within this.
    const SLACK: f64 = 1e-9;
    // At most six planes (a voxel's faces), so the offsets live on the stack.
    let mut offsets = [0.0; 6];
    for (b, p) in offsets.iter_mut().zip(planes) {
        *b = p.normal.dot(p.point);
    }
    let inside = |x: DVec3| planes.iter().zip(&offsets).all(|(p, &b)| p.normal.dot(x) <= b + SLACK);
    if inside(DVec3::ZERO) {
        return Some((0.0, DVec3::ZERO));
    }
    let mut best: Option<(f64, DVec3)> = None;
    let mut consider = |x: DVec3| {
        if x.is_finite() && inside(x) {
            let d = x.length();
            if best.is_none_or(|(b, _)| d < b) {
                best = Some((d, x));
            }
        }
    };
    let n = planes.len();
    for i in 0..n {
        let (a, b) = (planes[i].normal, offsets[i]);
        consider(a * (b / a.dot(a)));
        for j in i + 1..n {
            let (c, e) = (planes[j].normal, offsets[j]);
            // x = l a + m c with a.x = b, c.x = e.
            let (aa, ac, cc) = (a.dot(a), a.dot(c), c.dot(c));
            let det = aa * cc - ac * ac;
            if det.abs() > 1e-12 {
                let l = (b * cc - e * ac) / det;
                let m = (e * aa - b * ac) / det;
                consider(a * l + c * m);
            }
            for k in j + 1..n {
                let (f, g) = (planes[k].normal, offsets[k]);
                let det = a.dot(c.cross(f));
                if det.abs() > 1e-12 {
                    // The point where the three planes meet (Cramer's rule).
                    consider((c.cross(f) * b + f.cross(a) * e + a.cross(c) * g) / det);
                }
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plane(point: [f64; 3], normal: [f64; 3]) -> Plane {
        Plane { point: DVec3::from(point), normal: DVec3::from(normal).normalize() }
    }

    #[test]
    fn a_face_an_edge_and_a_corner_give_their_true_distances() {
        // The site's phase x <= -2 (and y <= -3, z <= -1), the origin outside it; each
        // crossing on the boundary of the phase.
        let x = plane([-2.0, 0.5, 0.0], [1.0, 0.0, 0.0]);
        let (d, foot) = distance_to_site(&[x], 2.0);
        assert!((d - 2.0).abs() < 1e-12 && (foot.x + 2.0).abs() < 1e-12);
        let x = plane([-2.0, -3.25, -1.25], [1.0, 0.0, 0.0]);
        let y = plane([-2.25, -3.0, -1.25], [0.0, 1.0, 0.0]);
        let (d, _) = distance_to_site(&[x, y], 3.6);
        assert!((d - 13f64.sqrt()).abs() < 1e-12, "{d}");
        let z = plane([-2.25, -3.25, -1.0], [0.0, 0.0, 1.0]);
        let (d, _) = distance_to_site(&[x, y, z], 3.8);
        assert!((d - 14f64.sqrt()).abs() < 1e-12, "{d}");
    }

    #[test]
    fn a_tilted_plane_is_measured_along_its_normal_and_bounded_by_its_crossing() {
        let n = DVec3::new(1.0, 1.0, 0.0).normalize();
        let p = Plane { point: DVec3::new(-3.0, 0.0, 0.0), normal: n };
        // The plane through (-3, 0, 0) at 45 degrees: the origin lies 3 / sqrt 2 away.
        let (d, _) = distance_to_site(&[p], 2.5);
        assert!((d - 3.0 / 2f64.sqrt()).abs() < 1e-12, "{d}");
        // A lattice distance that rules the plane too near: held at d_cube - 1/2.
        let (d, _) = distance_to_site(&[p], 2.9);
        assert!((d - 2.4).abs() < 1e-12, "{d}");
    }
}
