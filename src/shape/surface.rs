//! The nearest surface of a shape seen from a point: what smooth shading needs from
//! the shape a solid was voxelized from.
//!
//! A [`Surface`] is a signed distance `d` (negative inside; exact for spheres, boxes,
//! planes and tori, first order `f / |grad f|` for other implicit surfaces `f = 0`) and
//! the outward unit normal `grad f / |grad f|`. CSG combines them as distance bounds
//! do: union the nearer (`min`), intersection the farther (`max`), difference
//! `max(a, -b)`, complement `-a`; the normal comes with the chosen distance.

use glam::DVec3;

/// A signed distance to a shape's surface and the outward unit normal there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// Signed distance (negative inside), exact or first order near the surface.
    pub distance: f64,
    /// Outward unit normal of the nearest surface.
    pub normal: DVec3,
}

impl Surface {
    /// From an implicit function's value `f` and gradient `grad` at a point:
    /// `d = f / |grad|`, `n = grad / |grad|`; `None` where the gradient vanishes.
    #[must_use]
    pub fn from_field(f: f64, grad: DVec3) -> Option<Surface> {
        let length = grad.length();
        (length > 0.0 && length.is_finite() && f.is_finite())
            .then(|| Surface { distance: f / length, normal: grad / length })
    }

    /// An exact distance `distance` with the normal along `direction` (any length);
    /// `None` where the direction vanishes.
    #[must_use]
    pub fn exact(distance: f64, direction: DVec3) -> Option<Surface> {
        Some(Surface { distance, normal: direction.try_normalize()? })
    }

    /// The complement's surface: the same surface, seen from the other side.
    #[must_use]
    pub fn flipped(self) -> Surface {
        Surface { distance: -self.distance, normal: -self.normal }
    }

    /// The union's surface: the nearer one (`min`).
    #[must_use]
    pub fn union(self, other: Surface) -> Surface {
        if other.distance < self.distance { other } else { self }
    }

    /// The intersection's surface: the farther one (`max`).
    #[must_use]
    pub fn intersection(self, other: Surface) -> Surface {
        if other.distance > self.distance { other } else { self }
    }
}
