//! Spheres and axis-aligned ellipsoids.
//!
//! Ellipsoid: `sum ((p_i - c_i) / r_i)^2 <= 1`. Scaling by `1 / r` maps any
//! axis-aligned box to an axis-aligned box, so a box is classified by the range of
//! the squared distance to the origin over the scaled box (nearest and farthest
//! points, per axis) against 1. A sphere is the ellipsoid with equal radii.

use std::f64::consts::PI;

use glam::DVec3;

use super::bounds::{classify_below, finite, positive, square_range};
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::Result;

/// An ellipsoid with axis-aligned semi-axes.
#[derive(Clone, Debug, PartialEq)]
pub struct Ellipsoid {
    center: DVec3,
    radii: DVec3,
}

impl Ellipsoid {
    /// The ellipsoid with centre `center` and semi-axes `radii` (all positive).
    pub fn new(center: DVec3, radii: DVec3) -> Result<Self> {
        for r in radii.to_array() {
            positive("radius", r)?;
        }
        Ok(Ellipsoid { center: finite("center", center)?, radii })
    }

    /// Volume `4/3 pi a b c`.
    #[must_use]
    pub fn volume(&self) -> f64 {
        4.0 / 3.0 * PI * self.radii.x * self.radii.y * self.radii.z
    }
}

impl Shape for Ellipsoid {
    fn classify(&self, b: &Aabb) -> Class {
        let lo = (b.min - self.center) / self.radii;
        let hi = (b.max - self.center) / self.radii;
        let (mut near, mut far) = (0.0, 0.0);
        for i in 0..3 {
            let (l, h) = square_range(lo[i], hi[i]);
            near += l;
            far += h;
        }
        classify_below(near, far, 1.0)
    }

    fn contains(&self, p: DVec3) -> bool {
        ((p - self.center) / self.radii).length_squared() <= 1.0
    }

    /// `c + R^2 d / |R d|` (`R` the radii): the image of the unit sphere's support.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        let scaled = self.radii * d;
        let length = scaled.length();
        (length > 0.0 && length.is_finite()).then(|| self.center + self.radii * scaled / length)
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(Aabb::from_center_half(self.center, self.radii))
    }

    /// `f = |(p - c) / r|^2 - 1`, `grad f = 2 (p - c) / r^2` (first order).
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let q = (p - self.center) / self.radii;
        Surface::from_field(q.length_squared() - 1.0, 2.0 * q / self.radii)
    }
}

/// A ball `|p - c| <= r`.
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere(Ellipsoid);

impl Sphere {
    /// The ball of radius `radius` around `center`.
    pub fn new(center: DVec3, radius: f64) -> Result<Self> {
        Ok(Sphere(Ellipsoid::new(center, DVec3::splat(positive("radius", radius)?))?))
    }

    /// Volume `4/3 pi r^3`.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.0.volume()
    }
}

impl Shape for Sphere {
    fn classify(&self, b: &Aabb) -> Class {
        self.0.classify(b)
    }
    fn contains(&self, p: DVec3) -> bool {
        self.0.contains(p)
    }
    fn support(&self, d: DVec3) -> Option<DVec3> {
        self.0.support(d)
    }
    fn bounds(&self) -> Option<Aabb> {
        self.0.bounds()
    }
    /// Exact: `d = |p - c| - r`, `n = (p - c) / |p - c|`.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let q = p - self.0.center;
        Surface::exact(q.length() - self.0.radii.x, q)
    }
}
