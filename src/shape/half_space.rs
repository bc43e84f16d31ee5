//! Half-spaces `n . p <= d`.
//!
//! Over a box, `n . p` ranges between the corners picked by the signs of `n`.

use glam::DVec3;

use super::bounds::{EPS, finite};
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// The points `p` with `normal . p <= offset` (the normal points out of the solid).
#[derive(Clone, Debug, PartialEq)]
pub struct HalfSpace {
    normal: DVec3,
    offset: f64,
}

impl HalfSpace {
    /// The half-space below the plane `normal . p = offset`.
    pub fn new(normal: DVec3, offset: f64) -> Result<Self> {
        let normal = finite("normal", normal)?;
        if normal.length_squared() == 0.0 || !offset.is_finite() {
            return Err(Error::invalid(
                "half-space",
                format!(
                    "normal {} must be non-zero, offset {} finite",
                    crate::error::Vector(normal),
                    crate::error::Number(offset)
                ),
            ));
        }
        Ok(HalfSpace { normal, offset })
    }
}

impl Shape for HalfSpace {
    fn classify(&self, b: &Aabb) -> Class {
        let c = b.center();
        let r = (b.size() * 0.5).dot(self.normal.abs());
        let mid = self.normal.dot(c);
        // Absolute margin scaled by every magnitude in the sum (the offset may be 0).
        let m = EPS * (self.normal.abs().dot(c.abs()) + r + self.offset.abs()) + f64::MIN_POSITIVE;
        if mid + r + m < self.offset {
            Class::Inside
        } else if mid - r - m > self.offset {
            Class::Outside
        } else {
            Class::Boundary
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        self.normal.dot(p) <= self.offset
    }

    fn bounds(&self) -> Option<Aabb> {
        None
    }

    /// Exact: `d = (n . p - offset) / |n|`.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        Surface::from_field(self.normal.dot(p) - self.offset, self.normal)
    }
}
