//! Axis-aligned boxes (rotate one with [`super::ShapeExt::rotate`]).
//!
//! Classification is exact interval logic: Inside when the query box lies within the
//! cuboid, Outside when they are disjoint along some axis.

use glam::DVec3;

use super::bounds::{EPS, finite, positive};
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::Result;

/// A solid axis-aligned box.
#[derive(Clone, Debug, PartialEq)]
pub struct Cuboid {
    b: Aabb,
}

impl Cuboid {
    /// The box centred on `center` with edge lengths `size` (all positive).
    pub fn new(center: DVec3, size: DVec3) -> Result<Self> {
        for s in size.to_array() {
            positive("size", s)?;
        }
        Ok(Cuboid { b: Aabb::from_center_half(finite("center", center)?, size * 0.5) })
    }

    /// The box between two opposite corners.
    pub fn from_corners(a: DVec3, b: DVec3) -> Result<Self> {
        Cuboid::new((finite("corner", a)? + finite("corner", b)?) * 0.5, (b - a).abs())
    }

    /// Volume: the product of the edges.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.b.size().element_product()
    }
}

impl Shape for Cuboid {
    fn classify(&self, q: &Aabb) -> Class {
        let m = EPS * self.b.size().max_element();
        if q.min.cmpgt(self.b.min + m).all() && q.max.cmplt(self.b.max - m).all() {
            Class::Inside
        } else if q.max.cmplt(self.b.min - m).any() || q.min.cmpgt(self.b.max + m).any() {
            Class::Outside
        } else {
            Class::Boundary
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        self.b.contains(p)
    }

    /// The corner on `d`'s side.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        Some(DVec3::select(d.cmpge(DVec3::ZERO), self.b.max, self.b.min))
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(self.b)
    }

    /// Exact: with `e = |p - c| - h` (`h` the half size), outside
    /// `d = |max(e, 0)|`, `n` along `max(e, 0)` signed like `p - c`; inside
    /// `d = max_i e_i`, `n` the axis of that face.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let q = p - self.b.center();
        let e = q.abs() - self.b.size() * 0.5;
        let outside = e.max(DVec3::ZERO);
        if outside != DVec3::ZERO {
            return Surface::exact(outside.length(), outside * q.signum());
        }
        let a = e.max_position();
        let mut normal = DVec3::ZERO;
        normal[a] = q[a].signum();
        Some(Surface { distance: e[a], normal })
    }
}
