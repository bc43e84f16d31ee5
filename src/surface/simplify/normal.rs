//! A true bound on how far each face's normal turns from the input's normals under it,
//! carried through the collapses like the distance bound (module `gap`).
//!
//! Every face `f` carries a cone of directions `C(f)` (an axis and a half-angle;
//! input faces: their own normal, half-angle 0) holding the normal of every input face
//! related to a point of `f` (the relation of module `gap`: the vertical line of each
//! collapse, composed over the collapses). `f`'s normal is then within
//! `d(f) = angle(n_f, axis) + half-angle` of every input normal under it. A collapse
//! pairs each point of a new face `t` with the point of the old patch on its vertical
//! line; that point lies in some old face `s` whose projection overlaps `t`'s (a point
//! of `t` on the rim of an `s` that only touches `t` also lies in the closure of one
//! that overlaps it), so
//!
//! ```text
//! C(t) = the least cone holding C(s) for every old face s overlapping t in the projection
//! ```
//!
//! keeps the invariant, and refusing the collapse when some `d(t)` passes the limit
//! keeps every output face within the limit of the input's normals it stands for. The
//! cones are the cones of normals of Shirman and Abi-Ezzi ("The cone of normals
//! technique for fast processing of curved patches", 1993), carried over the collapses'
//! mapping as Cohen, Manocha and Olano carry their bounds ("Simplifying polygonal models
//! using successive mappings", 1997): unlike a sum of each collapse's turn (which grows
//! with every generation of collapses), a cone grows only with the normals it holds, so
//! on a cylinder a strip's cone is the strip's own turn. Unlike a normal term in the
//! cost (Hoppe 1999's attribute quadrics), it is a guarantee, and it spends triangles
//! where the surface turns: a strip on a cylinder may run along the axis but is only as
//! wide as the angle allows.
//!
//! Two cones are joined by the least cone holding both (the great-circle arc through
//! both axes carries the new axis); a fan face over several old faces joins them in the
//! region's order, which can only overestimate.
//!
//! Overlap is tested on the projected triangles (counter-clockwise, since the distance
//! bound already required every face to face the projection direction) by separating
//! edges: two triangles are apart when the three corners of one lie on or beyond an
//! edge line of the other. Shared edges and corners give exact zeros, so neighbours that
//! only touch are not counted; rounding elsewhere can only count more pairs, never fewer.

use glam::{DVec2, DVec3};
use smallvec::SmallVec;

/// Rounding allowance added to angles, in radians.
const SLACK: f64 = 1e-12;

/// The angle between two vectors, accurate at small angles.
fn angle(a: DVec3, b: DVec3) -> f64 {
    a.cross(b).length().atan2(a.dot(b))
}

/// A cone of directions: every unit vector within `half` of `axis` (unit). An empty
/// cone (a face without area) has a negative `half`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Cone {
    axis: DVec3,
    half: f64,
}

impl Default for Cone {
    fn default() -> Self {
        Cone::EMPTY
    }
}

impl Cone {
    const EMPTY: Cone = Cone { axis: DVec3::Z, half: -1.0 };

    /// The cone of one face's normal, `(b - a) x (c - a)` (empty without area).
    pub(crate) fn of_face(t: &[DVec3; 3]) -> Self {
        match (t[1] - t[0]).cross(t[2] - t[0]).try_normalize() {
            Some(axis) => Cone { axis, half: 0.0 },
            None => Cone::EMPTY,
        }
    }

    /// The largest angle between `normal` and a direction of the cone (0 when empty).
    pub(crate) fn deviation(&self, normal: DVec3) -> f64 {
        if self.half < 0.0 { 0.0 } else { angle(normal, self.axis) + self.half }
    }

    /// The least cone holding both.
    #[must_use]
    pub(crate) fn join(self, other: Cone) -> Cone {
        if other.half < 0.0 {
            return self;
        }
        if self.half < 0.0 {
            return other;
        }
        let between = angle(self.axis, other.axis);
        if between + other.half <= self.half {
            return self;
        }
        if between + self.half <= other.half {
            return other;
        }
        let half = (between + self.half + other.half) / 2.0;
        if half >= std::f64::consts::PI {
            return Cone { axis: self.axis, half: std::f64::consts::PI };
        }
        // Turn self's axis towards other's by half - self.half along their great circle.
        let Some(across) = (other.axis - self.axis * self.axis.dot(other.axis)).try_normalize() else {
            // Opposite axes: any great circle will do.
            return Cone { axis: self.axis, half: std::f64::consts::PI };
        };
        let turn = half - self.half;
        let axis = (self.axis * turn.cos() + across * turn.sin()).normalize();
        Cone { axis, half: half + SLACK }
    }
}

/// The cone `C(t)` of every face `t` of `new` (module doc) from the faces of `old` and
/// their cones, projected along `direction`; `None` when a face's deviation from its
/// cone passes `limit` (the rest are then not worked out).
pub(crate) fn fan_cones(
    old: &[[DVec3; 3]],
    old_cones: &[Cone],
    new: &[[DVec3; 3]],
    direction: DVec3,
    limit: f64,
) -> Option<SmallVec<[Cone; 24]>> {
    let u = direction.any_orthonormal_vector();
    let w = direction.cross(u);
    let flat = |t: &[DVec3; 3]| t.map(|x| DVec2::new(x.dot(u), x.dot(w)));
    let old_flat: SmallVec<[[DVec2; 3]; 24]> = old.iter().map(flat).collect();
    let mut cones = SmallVec::new();
    for t in new {
        let tf = flat(t);
        let mut cone = Cone::EMPTY;
        for (sf, &c) in old_flat.iter().zip(old_cones) {
            if overlap(&tf, sf) {
                cone = cone.join(c);
            }
        }
        let normal = (t[1] - t[0]).cross(t[2] - t[0]);
        if cone.deviation(normal) + SLACK > limit {
            return None;
        }
        cones.push(cone);
    }
    Some(cones)
}

/// Whether two counter-clockwise triangles' interiors meet (module doc).
fn overlap(a: &[DVec2; 3], b: &[DVec2; 3]) -> bool {
    let apart = |p: &[DVec2; 3], q: &[DVec2; 3]| {
        (0..3).any(|k| {
            let (s, e) = (p[k], p[(k + 1) % 3]);
            q.iter().all(|&x| (e - s).perp_dot(x - s) <= 0.0)
        })
    };
    !apart(a, b) && !apart(b, a)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlap_counts_interiors_only() {
        let o = DVec2::ZERO;
        let t = [o, DVec2::X, DVec2::Y];
        // Sharing an edge, on the other side: apart.
        assert!(!overlap(&t, &[DVec2::X, DVec2::ONE, DVec2::Y]));
        // Sharing a corner only: apart.
        assert!(!overlap(&t, &[DVec2::X, DVec2::new(2.0, 0.0), DVec2::new(2.0, 1.0)]));
        // Crossing: overlapping, both ways.
        let c = [DVec2::new(0.2, 0.2), DVec2::new(1.0, 0.2), DVec2::new(0.2, 1.0)];
        assert!(overlap(&t, &c) && overlap(&c, &t));
        // One inside the other.
        let small = [DVec2::new(0.1, 0.1), DVec2::new(0.2, 0.1), DVec2::new(0.1, 0.2)];
        assert!(overlap(&t, &small) && overlap(&small, &t));
    }

    #[test]
    fn joined_cones_hold_both_and_no_more() {
        let tilt = |deg: f64| DVec3::new(deg.to_radians().sin(), 0.0, deg.to_radians().cos());
        let a = Cone { axis: tilt(0.0), half: 0.0 };
        let b = Cone { axis: tilt(10.0), half: 2f64.to_radians() };
        let j = a.join(b);
        // The least cone: from 0 to 12 degrees, axis at 6, half 6.
        assert!((j.half - 6f64.to_radians()).abs() < 1e-9 && angle(j.axis, tilt(6.0)) < 1e-9, "{j:?}");
        assert_eq!(a.join(Cone::EMPTY), a);
        assert_eq!(Cone::EMPTY.join(b), b);
        // One inside the other.
        let wide = Cone { axis: tilt(1.0), half: 20f64.to_radians() };
        assert_eq!(wide.join(b), wide);
        // Random joins hold every direction of both (checked at their rims).
        let mut rng = crate::test_util::Rng(11);
        for _ in 0..500 {
            let c = [0, 1].map(|_| Cone { axis: rng.vec(-1.0, 1.0).normalize(), half: rng.range(0.0, 0.5) });
            let j = c[0].join(c[1]);
            for cone in c {
                let u = cone.axis.any_orthonormal_vector();
                let v = cone.axis.cross(u);
                for k in 0..16 {
                    let phi = k as f64 * std::f64::consts::TAU / 16.0;
                    let rim = cone.axis * cone.half.cos() + (u * phi.cos() + v * phi.sin()) * cone.half.sin();
                    assert!(angle(rim, j.axis) <= j.half + 1e-9, "{c:?} {j:?}");
                }
            }
        }
    }

    #[test]
    fn a_flat_fan_over_a_bent_patch_takes_the_cone_of_both_faces() {
        // Old patch: two faces folded about the diagonal; the new fan face lies flat in
        // z = 0 over parts of both.
        let p = |x: f64, y: f64| DVec3::new(x, y, if x > y { 0.1 * (x - y) } else { 0.0 });
        let old = [[p(-1.0, -1.0), p(1.0, -1.0), p(1.0, 1.0)], [p(-1.0, -1.0), p(1.0, 1.0), p(-1.0, 1.0)]];
        let new = [[p(-1.0, -1.0), p(0.0, -1.0), p(-1.0, 1.0)]];
        let new = [new[0].map(|x| DVec3::new(x.x, x.y, 0.0))];
        let cones = old.map(|t| Cone::of_face(&t));
        let got = fan_cones(&old, &cones, &new, DVec3::Z, 1.0).unwrap();
        // The old faces: one flat (normal z), one tilted by atan(0.1 * sqrt 2) about the
        // diagonal; the new face's normal z. Its deviation: the whole tilt.
        let tilt = angle(DVec3::Z, (old[0][1] - old[0][0]).cross(old[0][2] - old[0][0]));
        assert!(tilt > 0.1);
        let deviation = got[0].deviation(DVec3::Z);
        assert!((deviation - tilt).abs() < 1e-9, "{deviation} {tilt}");
        assert!(fan_cones(&old, &cones, &new, DVec3::Z, tilt * 0.99).is_none());
        // A new face over the flat face alone keeps its cone: deviation 0.
        let corner = [[DVec3::new(-1.0, 0.5, 0.0), DVec3::new(-0.5, 0.5, 0.0), DVec3::new(-1.0, 1.0, 0.0)]];
        let got = fan_cones(&old, &cones, &corner, DVec3::Z, 1e-6).unwrap();
        assert!(got[0].deviation(DVec3::Z) < 1e-9);
    }
}
