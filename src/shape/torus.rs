//! Tori around a coordinate axis.
//!
//! `(sqrt(u^2 + v^2) - R)^2 + w^2 <= r^2`, `w` along the axis. Over a box, `rho =
//! sqrt(u^2 + v^2)` ranges over `[rho0, rho1]` (from the cross-section rectangle) and
//! `w` over `[w0, w1]`; the distance to the centre circle squared is bounded below by
//! clamping `R` into the `rho` range and `0` into the `w` range, and above by the
//! farther ends. This bounds the image of the box, so the classes are conservative.

use std::f64::consts::PI;

use glam::DVec3;

use super::axis::Axis;
use super::bounds::{classify_below, finite, positive, radial_range, square_range};
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// A solid ring torus.
#[derive(Clone, Debug, PartialEq)]
pub struct Torus {
    center: DVec3,
    axis: Axis,
    major: f64,
    minor: f64,
}

impl Torus {
    /// The torus around `axis` through `center`, with centre-line radius `major` and
    /// tube radius `minor < major`.
    pub fn new(center: DVec3, axis: Axis, major: f64, minor: f64) -> Result<Self> {
        let (major, minor) = (positive("radius", major)?, positive("tube radius", minor)?);
        if minor >= major {
            return Err(Error::invalid(
                "tube radius",
                format!("{} must be below the radius {}", crate::error::Number(minor), crate::error::Number(major)),
            ));
        }
        Ok(Torus { center: finite("center", center)?, axis, major, minor })
    }

    /// Volume `2 pi^2 R r^2`.
    #[must_use]
    pub fn volume(&self) -> f64 {
        2.0 * PI * PI * self.major * self.minor * self.minor
    }
}

impl Shape for Torus {
    fn classify(&self, b: &Aabb) -> Class {
        let (w0, [u0, v0]) = self.axis.split(b.min - self.center);
        let (w1, [u1, v1]) = self.axis.split(b.max - self.center);
        let (r2l, r2h) = radial_range((u0, u1), (v0, v1));
        let (rho0, rho1) = (r2l.sqrt(), r2h.sqrt());
        let (dl, dh) = square_range(rho0 - self.major, rho1 - self.major);
        let (wl, wh) = square_range(w0, w1);
        classify_below(dl + wl, dh + wh, self.minor * self.minor)
    }

    fn contains(&self, p: DVec3) -> bool {
        let (w, [u, v]) = self.axis.split(p - self.center);
        let d = (u * u + v * v).sqrt() - self.major;
        d * d + w * w <= self.minor * self.minor
    }

    /// Exact: `d = |(rho - R, w)| - r`, the normal along `(rho - R)` radially and `w`
    /// axially.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let (w, [u, v]) = self.axis.split(p - self.center);
        let rho = u.hypot(v);
        if rho == 0.0 {
            return None;
        }
        let across = rho - self.major;
        Surface::exact(across.hypot(w) - self.minor, self.axis.join(w, [across * u / rho, across * v / rho]))
    }

    /// The centre circle's support plus the tube's: `c + R e + r d / |d|`, `e` the
    /// unit radial part of `d`.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        let (_, [u, v]) = self.axis.split(d);
        let across = u.hypot(v);
        let e = if across > 0.0 { [u / across, v / across] } else { [1.0, 0.0] };
        Some(self.center + self.axis.join(0.0, e.map(|x| x * self.major)) + d.try_normalize()? * self.minor)
    }

    fn bounds(&self) -> Option<Aabb> {
        let mut half = DVec3::splat(self.major + self.minor);
        half[self.axis.index()] = self.minor;
        Some(Aabb::from_center_half(self.center, half))
    }
}
