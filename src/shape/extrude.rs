//! Linear extrusions: a [`Profile`] swept along an axis, optionally twisted and scaled
//! as OpenSCAD's `linear_extrude`.
//!
//! In coordinates `(w; u, v)` (`w` along the axis, `(u, v)` the next two axes in
//! cyclic order: `(x, y)` for z, `(y, z)` for x, `(z, x)` for y), the layer at height
//! fraction `t = (w - w0) / H in [0, 1]` is the profile turned by `-twist t` (a
//! positive twist turns clockwise seen from `+axis`, OpenSCAD's left-hand rule), then
//! scaled by `s(t) = 1 + (scale - 1) t` per axis. So a point `x = (u, v)` at `t` is
//! inside when the profile contains its preimage `q(x, t) = R(twist t) (x / s(t))`,
//! and the volume is `A H (1 + (a + b) / 2 + a b / 3)` for `a, b = scale - 1` (twist
//! keeps each layer's area; a uniform scale `s` gives `A H (1 + s + s^2) / 3`).
//!
//! Classification: a box's `t` range `[t0, t1]` and its cross-section's disc (centre
//! `c`, radius `r`) map into the profile's plane within the disc around `q(c, tm)`
//! (`tm` the middle of the range) of radius `r / s_min + L (t1 - t0) / 2`, where
//! `s_min` is the least scale over the range and `L = |c| (|twist| / s_min +
//! max|scale - 1| / s_min^2)` bounds `|dq/dt|` at `c`; that disc is classified by
//! [`Profile::classify_disc`] and combined with the box's axial class. Without twist
//! or scale the disc is exactly the cross-section's.
//!
//! Surface: the side is the implicit `f(x, w) = D(q(x, t))` (`D` the profile's signed
//! distance), its gradient by the chain rule (`grad_x f = diag(1 / s) R(-twist t) n`,
//! `df/dw = n . dq/dt / H`, `n` the profile's normal), so the distance is exact for a
//! plain extrusion and first order otherwise; the caps are the slab `|w - w_mid| <= H /
//! 2`; the solid is their intersection (`max`).

use glam::{DMat2, DVec2, DVec3};

use super::axis::Axis;
use super::bounds::{EPS, both, classify_below, positive, square_range};
use super::profile::Profile;
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// A profile swept along an axis (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Extrude {
    profile: Profile,
    axis: Axis,
    /// `w` of the bottom.
    bottom: f64,
    height: f64,
    /// Radians over the height.
    twist: f64,
    /// The top layer's scale along `u` and `v`.
    scale: DVec2,
}

impl Extrude {
    /// `profile` swept along `axis` from `w = 0` (or centred on `w = 0` when `center`)
    /// by `height`, turned by `twist_degrees` and scaled to `scale` at the top.
    pub fn new(
        profile: Profile,
        axis: Axis,
        height: f64,
        center: bool,
        twist_degrees: f64,
        scale: DVec2,
    ) -> Result<Extrude> {
        let height = positive("height", height)?;
        if !twist_degrees.is_finite() {
            return Err(Error::invalid("twist", format!("{} must be finite", crate::error::Number(twist_degrees))));
        }
        if !(scale.is_finite() && scale.min_element() >= 0.0) {
            return Err(Error::invalid("scale", format!("{scale} must be finite and not negative")));
        }
        let bottom = if center { -0.5 * height } else { 0.0 };
        Ok(Extrude { profile, axis, bottom, height, twist: twist_degrees.to_radians(), scale })
    }

    /// The profile swept.
    #[must_use]
    pub fn profile(&self) -> &Profile {
        &self.profile
    }

    /// `A H (1 + (a + b) / 2 + a b / 3)`, `a, b` the top scale minus one (see the
    /// module doc); `A` is [`Profile::area`].
    #[must_use]
    pub fn volume(&self) -> f64 {
        let (a, b) = (self.scale.x - 1.0, self.scale.y - 1.0);
        self.profile.area() * self.height * (1.0 + 0.5 * (a + b) + a * b / 3.0)
    }

    fn scale_at(&self, t: f64) -> DVec2 {
        DVec2::ONE + (self.scale - DVec2::ONE) * t
    }

    /// The preimage `q(x, t)` in the profile's plane.
    fn preimage(&self, x: DVec2, t: f64) -> DVec2 {
        if self.twist == 0.0 {
            x / self.scale_at(t)
        } else {
            DMat2::from_angle(self.twist * t) * (x / self.scale_at(t))
        }
    }

    fn plain(&self) -> bool {
        self.twist == 0.0 && self.scale == DVec2::ONE
    }
}

impl Shape for Extrude {
    fn classify(&self, b: &Aabb) -> Class {
        let (w0, [u0, v0]) = self.axis.split(b.min);
        let (w1, [u1, v1]) = self.axis.split(b.max);
        let half = 0.5 * self.height;
        let mid = self.bottom + half;
        let (al, ah) = square_range(w0 - mid, w1 - mid);
        let axial = classify_below(al, ah, half * half);
        if axial == Class::Outside {
            return Class::Outside;
        }
        let (lo, hi) = (DVec2::new(u0, v0), DVec2::new(u1, v1));
        if self.plain() {
            return both(axial, self.profile.classify_box(lo, hi));
        }
        let t0 = ((w0 - self.bottom) / self.height).clamp(0.0, 1.0);
        let t1 = ((w1 - self.bottom) / self.height).clamp(0.0, 1.0);
        let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
        let s_min = self.scale_at(t0).min(self.scale_at(t1)).min_element();
        if s_min <= 0.0 {
            return both(axial, Class::Boundary);
        }
        let slope = (self.scale - DVec2::ONE).abs().max_element();
        let lipschitz = c.length() * (self.twist.abs() / s_min + slope / (s_min * s_min));
        let tm = 0.5 * (t0 + t1);
        let radius = (r / s_min + lipschitz * (t1 - t0) * 0.5) * (1.0 + EPS);
        both(axial, self.profile.classify_disc(self.preimage(c, tm), radius))
    }

    fn contains(&self, p: DVec3) -> bool {
        let (w, [u, v]) = self.axis.split(p);
        let t = (w - self.bottom) / self.height;
        (0.0..=1.0).contains(&t) && self.profile.contains(self.preimage(DVec2::new(u, v), t))
    }

    /// The side's implicit distance and the caps' slab, intersected (module doc).
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let (w, [u, v]) = self.axis.split(p);
        if w.is_nan() {
            return None;
        }
        let half = 0.5 * self.height;
        let mid = self.bottom + half;
        let caps = Surface { distance: (w - mid).abs() - half, normal: self.axis.unit() * (w - mid).signum() };
        let x = DVec2::new(u, v);
        let t = ((w - self.bottom) / self.height).clamp(0.0, 1.0);
        let s = self.scale_at(t);
        let turn = DMat2::from_angle(self.twist * t);
        let q = turn * (x / s);
        let side = self.profile.surface(q)?;
        let n = side.normal;
        let across = (turn.transpose() * n) / s;
        let dq_dt = turn * (DVec2::new(-x.y / s.y, x.x / s.x) * self.twist - x * (self.scale - DVec2::ONE) / (s * s));
        let along = n.dot(dq_dt) / self.height;
        match Surface::from_field(side.distance, self.axis.join(along, [across.x, across.y])) {
            Some(side) => Some(side.intersection(caps)),
            None => Some(caps),
        }
    }

    fn bounds(&self) -> Option<Aabb> {
        let (lo, hi) = self.profile.bounds();
        let grow = DVec2::ONE.max(self.scale);
        let (lo, hi) = if self.twist == 0.0 {
            (lo.min(lo * self.scale), hi.max(hi * self.scale))
        } else {
            let reach = lo.abs().max(hi.abs()).length() * grow.max_element();
            (DVec2::splat(-reach), DVec2::splat(reach))
        };
        let a = self.axis.join(self.bottom, [lo.x, lo.y]);
        let b = self.axis.join(self.bottom + self.height, [hi.x, hi.y]);
        Some(Aabb::new(a, b))
    }

    /// Untwisted: the farther of the bottom's and the top's supports (a point's
    /// height and place are linear in `t`, so a linear function is largest at an
    /// end); twisted: none.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        if self.twist != 0.0 {
            return None;
        }
        let (_, [du, dv]) = self.axis.split(d);
        let ends = [(0.0, DVec2::ONE), (1.0, self.scale)].map(|(t, s)| {
            let q = self.profile.support(DVec2::new(du, dv) * s)?;
            let x = q * s;
            Some(self.axis.join(self.bottom + t * self.height, [x.x, x.y]))
        });
        let (a, b) = (ends[0]?, ends[1]?);
        Some(if b.dot(d) > a.dot(d) { b } else { a })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn twisted_and_scaled_boxes_never_contradict_their_points() {
        let square = Profile::rectangle(DVec2::new(0.3, 0.0), DVec2::new(1.0, 0.6)).unwrap();
        let shape = Extrude::new(square, Axis::Y, 2.0, true, 120.0, DVec2::new(0.4, 1.5)).unwrap();
        let mut decided = 0;
        for i in 0..12 {
            for j in 0..12 {
                for k in 0..12 {
                    let lo = DVec3::new(f64::from(i), f64::from(j), f64::from(k)) * 0.2 - 1.2;
                    let b = Aabb::new(lo, lo + 0.2);
                    let class = shape.classify(&b);
                    decided += usize::from(class != Class::Boundary);
                    for n in 0..27 {
                        let f = DVec3::new(f64::from(n % 3), f64::from(n / 3 % 3), f64::from(n / 9)) * 0.5;
                        let p = lo + f * 0.2;
                        match class {
                            Class::Inside => assert!(shape.contains(p), "{p}"),
                            Class::Outside => assert!(!shape.contains(p), "{p}"),
                            Class::Boundary => {}
                        }
                    }
                }
            }
        }
        assert!(decided > 1000, "{decided}");
    }
}
