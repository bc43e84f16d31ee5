//! Capped cylinders along a coordinate axis.
//!
//! `u^2 + v^2 <= R^2` and `|w| <= H/2` in coordinates `(w; u, v)` relative to the
//! centre, `w` along the axis. A box is classified by the range of `u^2 + v^2` over its
//! cross-section rectangle and by its axial interval.

use std::f64::consts::PI;

use glam::DVec3;

use super::axis::Axis;
use super::bounds::{both, classify_below, finite, positive, radial_range, square_range};
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::Result;

/// A solid capped cylinder.
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    center: DVec3,
    axis: Axis,
    radius: f64,
    height: f64,
}

impl Cylinder {
    /// The cylinder of `radius` and `height` along `axis`, centred on `center`
    /// (it reaches `height / 2` each way along the axis).
    pub fn new(center: DVec3, axis: Axis, radius: f64, height: f64) -> Result<Self> {
        Ok(Cylinder {
            center: finite("center", center)?,
            axis,
            radius: positive("radius", radius)?,
            height: positive("height", height)?,
        })
    }

    /// Volume `pi R^2 H`.
    #[must_use]
    pub fn volume(&self) -> f64 {
        PI * self.radius * self.radius * self.height
    }
}

impl Shape for Cylinder {
    fn classify(&self, b: &Aabb) -> Class {
        let (w0, [u0, v0]) = self.axis.split(b.min - self.center);
        let (w1, [u1, v1]) = self.axis.split(b.max - self.center);
        let (rl, rh) = radial_range((u0, u1), (v0, v1));
        let (wl, wh) = square_range(w0, w1);
        let half = self.height * 0.5;
        both(classify_below(rl, rh, self.radius * self.radius), classify_below(wl, wh, half * half))
    }

    fn contains(&self, p: DVec3) -> bool {
        let (w, [u, v]) = self.axis.split(p - self.center);
        u * u + v * v <= self.radius * self.radius && w.abs() <= self.height * 0.5
    }

    /// The intersection of the infinite cylinder (`d = sqrt(u^2 + v^2) - R`, radial
    /// normal) and the slab between the caps (`d = |w| - H / 2`, axial normal).
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let (w, [u, v]) = self.axis.split(p - self.center);
        if w.is_nan() {
            return None;
        }
        // The axial normal is a unit vector already (what normalizing it would give).
        let caps = Surface { distance: w.abs() - self.height * 0.5, normal: self.axis.unit() * w.signum() };
        // `sqrt(u^2 + v^2)`, not `hypot` (whose care for overflow no cylinder needs: it
        // was 2% of a Whitted render with three cylinders).
        match Surface::exact((u * u + v * v).sqrt() - self.radius, self.axis.join(0.0, [u, v])) {
            Some(side) => Some(side.intersection(caps)),
            // On the axis: no radial direction, and the caps are nearer anyway.
            None => Some(caps),
        }
    }

    /// The cap on `d`'s side, at its rim towards `d`'s radial part.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        let (w, [u, v]) = self.axis.split(d);
        let across = u.hypot(v);
        let rim = if across > 0.0 { [u / across, v / across].map(|x| x * self.radius) } else { [0.0, 0.0] };
        Some(self.center + self.axis.join((self.height * 0.5).copysign(w), rim))
    }

    fn bounds(&self) -> Option<Aabb> {
        let mut half = DVec3::splat(self.radius);
        half[self.axis.index()] = self.height * 0.5;
        Some(Aabb::from_center_half(self.center, half))
    }
}
