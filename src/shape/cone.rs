//! Capped cones along a coordinate axis.
//!
//! With `t` the height above the base along the axis and `(u, v)` the offset from the
//! axis: `0 <= t <= H` and `sqrt(u^2 + v^2) <= r(t) = R (1 - t/H)`. Over a box the
//! radius shrinks with `t`, so the box is surely inside when its farthest radial
//! point is within `r(t_max)` (the narrowest section it meets) and surely outside when
//! its nearest radial point is beyond `r(t_min)` (the widest).

use std::f64::consts::PI;

use glam::DVec3;

use super::axis::Axis;
use super::bounds::{both, classify_below, finite, positive, radial_range};
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::Result;

/// A solid capped cone.
#[derive(Clone, Debug, PartialEq)]
pub struct Cone {
    base: DVec3,
    axis: Axis,
    radius: f64,
    height: f64,
}

impl Cone {
    /// The cone with base disc of `radius` centred on `base`, apex at
    /// `base + height * axis`.
    pub fn new(base: DVec3, axis: Axis, radius: f64, height: f64) -> Result<Self> {
        Ok(Cone {
            base: finite("base", base)?,
            axis,
            radius: positive("radius", radius)?,
            height: positive("height", height)?,
        })
    }

    /// Volume `pi R^2 H / 3`.
    #[must_use]
    pub fn volume(&self) -> f64 {
        PI * self.radius * self.radius * self.height / 3.0
    }

    /// Radius of the section at height `t` (clamped to the cone's extent).
    fn radius_at(&self, t: f64) -> f64 {
        self.radius * (1.0 - t.clamp(0.0, self.height) / self.height)
    }
}

impl Shape for Cone {
    fn classify(&self, b: &Aabb) -> Class {
        let (t0, [u0, v0]) = self.axis.split(b.min - self.base);
        let (t1, [u1, v1]) = self.axis.split(b.max - self.base);
        let (rl, rh) = radial_range((u0, u1), (v0, v1));
        // Axial condition |t - H/2| <= H/2.
        let half = self.height * 0.5;
        let (al, ah) = super::bounds::square_range(t0 - half, t1 - half);
        let axial = classify_below(al, ah, half * half);
        let (narrow, wide) = (self.radius_at(t1), self.radius_at(t0));
        let radial = match classify_below(rl, rh, narrow * narrow) {
            Class::Inside => Class::Inside,
            _ => match classify_below(rl, rh, wide * wide) {
                Class::Outside => Class::Outside,
                _ => Class::Boundary,
            },
        };
        both(axial, radial)
    }

    fn contains(&self, p: DVec3) -> bool {
        let (t, [u, v]) = self.axis.split(p - self.base);
        let r = self.radius * (1.0 - t / self.height);
        (0.0..=self.height).contains(&t) && u * u + v * v <= r * r
    }

    /// The intersection of the lateral surface `f = rho + (R / H) t - R` (first order,
    /// `grad f = radial + (R / H) axis`) and the slab `0 <= t <= H`.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let (t, [u, v]) = self.axis.split(p - self.base);
        let rho = u.hypot(v);
        let slope = self.radius / self.height;
        let radial = if rho > 0.0 { [u / rho, v / rho] } else { [0.0, 0.0] };
        let side = Surface::from_field(rho + slope * t - self.radius, self.axis.join(slope, radial))?;
        let half = self.height * 0.5;
        let slab = Surface::from_field((t - half).abs() - half, self.axis.unit() * (t - half).signum())?;
        Some(side.intersection(slab))
    }

    /// The apex or the base's rim point towards `d`'s radial part, the farther.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        let (_, [u, v]) = self.axis.split(d);
        let across = u.hypot(v);
        let rim = if across > 0.0 { [u / across, v / across].map(|x| x * self.radius) } else { [0.0, 0.0] };
        let (apex, rim) = (self.base + self.axis.unit() * self.height, self.base + self.axis.join(0.0, rim));
        Some(if apex.dot(d) > rim.dot(d) { apex } else { rim })
    }

    fn bounds(&self) -> Option<Aabb> {
        let mut half = DVec3::splat(self.radius);
        half[self.axis.index()] = self.height * 0.5;
        Some(Aabb::from_center_half(self.base + self.axis.unit() * (self.height * 0.5), half))
    }
}
