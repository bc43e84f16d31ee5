//! Revolutions: a [`Profile`] in the `(r, z)` half-plane turned about an axis through
//! the origin, by a full turn or by an angle, as OpenSCAD's `rotate_extrude`.
//!
//! In coordinates `(w; u, v)` (`w` along the axis, `(u, v)` the next two axes in
//! cyclic order, as [`super::Extrude`]'s), a point is inside when the profile contains
//! `(r, z) = (sqrt(u^2 + v^2), w)` and, for an angle `A < 360` degrees, its angle
//! `atan2(v, u)` is in `[0, A]` (from `+u` towards `+v`: from `+x` counter-clockwise
//! for the z axis). The wedge is the intersection of the half-planes `v >= 0` and
//! `cos A v - sin A u <= 0` for `A <= 180` degrees and their union above, so no angle
//! is ever computed. The profile must lie in `r >= 0` (refused otherwise).
//!
//! Classification: over a box, `r` ranges over `[sqrt(min u^2 + v^2), sqrt(max ...)]`
//! and `w` over the box's own range; that `(r, z)` rectangle is classified by
//! [`Profile::classify_box`], the wedge's half-planes by the box's corners, and the
//! classes combined. Surface: the profile's distance and normal in the meridian
//! half-plane through the point, which is the exact 3D distance to a full revolution
//! (the nearest point of a surface of revolution lies in the point's own meridian);
//! a partial one intersects it with the wedge's planes (distance bounds).
//!
//! Volume by Pappus's centroid theorem is `A theta r_c` (`r_c` the profile's centroid's
//! `r`); the tests hold the voxels to it.

use std::f64::consts::PI;

use glam::{DVec2, DVec3};

use super::axis::Axis;
use super::bounds::{EPS, both, radial_range};
use super::profile::Profile;
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// A profile turned about an axis (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Revolve {
    profile: Profile,
    axis: Axis,
    /// Radians, in `(0, 2 pi]`.
    angle: f64,
    /// `(cos A, sin A)`.
    end: DVec2,
    /// Whether the angle is a full turn (360 degrees as given, not as rounded).
    full: bool,
}

impl Revolve {
    /// `profile` (in `(r, z)`, `r >= 0`) turned about `axis` by `angle_degrees` (in
    /// `(0, 360]`).
    pub fn new(profile: Profile, axis: Axis, angle_degrees: f64) -> Result<Revolve> {
        if !(angle_degrees > 0.0 && angle_degrees <= 360.0) {
            return Err(Error::invalid(
                "angle",
                format!("{} must be in (0, 360] degrees", crate::error::Number(angle_degrees)),
            ));
        }
        let (lo, _) = profile.bounds();
        if lo.x < 0.0 {
            return Err(Error::invalid(
                "revolve",
                format!("the profile reaches r = {}: a profile to revolve lies in r >= 0", lo.x),
            ));
        }
        let angle = angle_degrees.to_radians();
        Ok(Revolve { profile, axis, angle, end: DVec2::new(angle.cos(), angle.sin()), full: angle_degrees == 360.0 })
    }

    /// The profile turned.
    #[must_use]
    pub fn profile(&self) -> &Profile {
        &self.profile
    }

    fn full(&self) -> bool {
        self.full
    }

    /// The two half-planes' functions at `(u, v)` (each `<= 0` on the wedge's side).
    fn planes(&self, u: f64, v: f64) -> [f64; 2] {
        [-v, self.end.x * v - self.end.y * u]
    }

    fn in_wedge(&self, u: f64, v: f64) -> bool {
        let [a, b] = self.planes(u, v);
        if self.angle <= PI { a <= 0.0 && b <= 0.0 } else { a <= 0.0 || b <= 0.0 }
    }
}

impl Shape for Revolve {
    fn classify(&self, b: &Aabb) -> Class {
        let (w0, [u0, v0]) = self.axis.split(b.min);
        let (w1, [u1, v1]) = self.axis.split(b.max);
        let (rl, rh) = radial_range((u0, u1), (v0, v1));
        let meridian = self.profile.classify_box(DVec2::new(rl.sqrt(), w0), DVec2::new(rh.sqrt(), w1));
        if self.full() || meridian == Class::Outside {
            return meridian;
        }
        let margin = EPS * (u0.abs().max(u1.abs()).max(v0.abs()).max(v1.abs())) + f64::MIN_POSITIVE;
        let corners = [(u0, v0), (u1, v0), (u0, v1), (u1, v1)].map(|(u, v)| self.planes(u, v));
        let class = |i: usize| {
            let (lo, hi) =
                corners.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), c| (l.min(c[i]), h.max(c[i])));
            if hi < -margin {
                Class::Inside
            } else if lo > margin {
                Class::Outside
            } else {
                Class::Boundary
            }
        };
        let wedge = if self.angle <= PI {
            both(class(0), class(1))
        } else {
            both(class(0).complement(), class(1).complement()).complement()
        };
        both(meridian, wedge)
    }

    fn contains(&self, p: DVec3) -> bool {
        let (w, [u, v]) = self.axis.split(p);
        (self.full() || self.in_wedge(u, v)) && self.profile.contains(DVec2::new((u * u + v * v).sqrt(), w))
    }

    /// The meridian's distance and normal, cut by the wedge's planes (module doc).
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let (w, [u, v]) = self.axis.split(p);
        let r = (u * u + v * v).sqrt();
        let s = self.profile.surface(DVec2::new(r, w))?;
        let radial = if r > 0.0 { [u / r, v / r] } else { [0.0, 0.0] };
        let meridian = Surface::exact(s.distance, self.axis.join(s.normal.y, radial.map(|x| x * s.normal.x)))?;
        if self.full() {
            return Some(meridian);
        }
        let [a, b] = self.planes(u, v);
        let first = Surface { distance: a, normal: self.axis.join(0.0, [0.0, -1.0]) };
        let second = Surface { distance: b, normal: self.axis.join(0.0, [-self.end.y, self.end.x]) };
        let wedge = if self.angle <= PI { first.intersection(second) } else { first.union(second) };
        Some(meridian.intersection(wedge))
    }

    fn bounds(&self) -> Option<Aabb> {
        let (lo, hi) = self.profile.bounds();
        Some(Aabb::new(self.axis.join(lo.y, [-hi.x, -hi.x]), self.axis.join(hi.y, [hi.x, hi.x])))
    }

    /// A full turn: the profile's support in the meridian of `d`'s radial part,
    /// towards `(|d_radial|, d_w)`; a partial one: none.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        if !self.full() {
            return None;
        }
        let (dw, [du, dv]) = self.axis.split(d);
        let across = du.hypot(dv);
        let q = self.profile.support(DVec2::new(across, dw))?;
        let e = if across > 0.0 { [du / across, dv / across] } else { [1.0, 0.0] };
        Some(self.axis.join(q.y, e.map(|x| x * q.x)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn partial_turns_classify_soundly_and_refuse_negative_radii() {
        let ring = Profile::circle(DVec2::new(1.0, 0.0), 0.4).unwrap();
        assert!(Revolve::new(Profile::circle(DVec2::new(0.2, 0.0), 0.4).unwrap(), Axis::Z, 360.0).is_err());
        for degrees in [90.0, 200.0, 360.0] {
            let shape = Revolve::new(ring.clone(), Axis::X, degrees).unwrap();
            for i in 0..10 {
                for j in 0..10 {
                    for k in 0..10 {
                        let lo = DVec3::new(f64::from(i), f64::from(j), f64::from(k)) * 0.3 - 1.5;
                        let class = shape.classify(&Aabb::new(lo, lo + 0.3));
                        for n in 0..27 {
                            let f = DVec3::new(f64::from(n % 3), f64::from(n / 3 % 3), f64::from(n / 9)) * 0.5;
                            let p = lo + f * 0.3;
                            match class {
                                Class::Inside => assert!(shape.contains(p), "{degrees} {p}"),
                                Class::Outside => assert!(!shape.contains(p), "{degrees} {p}"),
                                Class::Boundary => {}
                            }
                        }
                    }
                }
            }
        }
    }
}
