//! Cameras: pinhole perspective and orthographic, look-at, auto-framing.

use glam::DVec3;

use crate::aabb::Aabb;
use crate::error::{Error, Number, Result, Vector};
use crate::ray::Ray;
use crate::shape::Axis;

/// How the camera projects.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Projection {
    /// Pinhole with a vertical field of view in degrees.
    Perspective {
        /// Vertical field of view, degrees.
        fov_y: f64,
    },
    /// Parallel projection of a view `height` world units tall.
    Orthographic {
        /// Height of the view in world units.
        height: f64,
    },
}

/// A camera looking from `eye` at `target`, `up` giving the vertical.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position.
    pub eye: DVec3,
    /// Point looked at (the image centre).
    pub target: DVec3,
    /// World up direction.
    pub up: DVec3,
    /// Projection.
    pub projection: Projection,
}

/// The default viewing direction of [`Camera::frame`], from the target towards the
/// eye, for a z-up world: front-right and above. [`Camera::default_view`] gives it for
/// any up axis.
pub const DEFAULT_VIEW: DVec3 = DVec3::new(1.0, -1.7, 1.1);

/// `v` given in a z-up world, turned with the world so that its z goes to `up`: for
/// y-up `(v.x, v.z, -v.y)`, for x-up `(v.z, v.x, -v.y)`.
pub(crate) fn turned_to_up(v: DVec3, up: Axis) -> DVec3 {
    match up {
        Axis::Z => v,
        Axis::Y => DVec3::new(v.x, v.z, -v.y),
        Axis::X => DVec3::new(v.z, v.x, -v.y),
    }
}

impl Camera {
    /// Fails unless the camera can make a picture: finite `eye`, `target` and `up`,
    /// `eye` away from `target`, `up` not along the line of sight, a perspective field
    /// of view strictly between 0 and 180 degrees, an orthographic height finite and
    /// positive.
    pub fn validate(&self) -> Result<()> {
        let bad = |reason: String| Err(Error::invalid("camera", reason));
        let (eye, target, up) = (self.eye, self.target, self.up);
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return bad(format!("eye {}, target {} and up {} must be finite", Vector(eye), Vector(target), Vector(up)));
        }
        let sight = target - eye;
        if sight.length() == 0.0 || !sight.normalize().is_finite() {
            return bad(format!("the eye {} is at the target", Vector(eye)));
        }
        let unit_up = up.normalize_or_zero();
        if unit_up == DVec3::ZERO || sight.normalize().cross(unit_up).length() < 1e-9 {
            return bad(format!("up {} gives no vertical: it is zero or along the line of sight", Vector(up)));
        }
        match self.projection {
            Projection::Perspective { fov_y } if !(fov_y > 0.0 && fov_y < 180.0) => {
                bad(format!("field of view {} must be between 0 and 180 degrees", Number(fov_y)))
            }
            Projection::Orthographic { height } if !(height.is_finite() && height > 0.0) => {
                bad(format!("orthographic height {} must be finite and positive", Number(height)))
            }
            _ => Ok(()),
        }
    }

    /// A perspective camera at `eye` looking at `target`.
    #[must_use]
    pub fn look_at(eye: DVec3, target: DVec3, up: DVec3, fov_y: f64) -> Self {
        Camera { eye, target, up, projection: Projection::Perspective { fov_y } }
    }

    /// The default viewing direction (from the target towards the eye) for a world
    /// whose up vector is `up.unit()`: [`DEFAULT_VIEW`] `v` for z-up; for y-up
    /// `(v.x, v.z, -v.y)`, the z-up view turned with the world so that its z goes to
    /// y; for x-up `(v.z, v.x, -v.y)`. The one place an up axis becomes a view.
    #[must_use]
    pub fn default_view(up: Axis) -> DVec3 {
        turned_to_up(DEFAULT_VIEW, up)
    }

    /// A perspective camera (35 degrees) framing `bounds` from `view` (a direction from
    /// the target to the eye; use [`Camera::default_view`]) with `up`, for an image of
    /// `aspect` = width / height: the nearest distance at which all eight corners of the
    /// box project inside the image, plus a 6% margin.
    #[must_use]
    pub fn frame(bounds: &Aabb, view: DVec3, up: DVec3, aspect: f64) -> Self {
        let fov_y: f64 = 35.0;
        let target = bounds.center();
        let w = view.normalize();
        let right = (-w).cross(up).normalize();
        let true_up = right.cross(-w);
        let ty = (fov_y.to_radians() * 0.5).tan();
        let tx = ty * aspect;
        // A corner p (from the target) at eye distance D has depth D - p.w, so it fits
        // when D >= p.w + |p.right| / tx and D >= p.w + |p.up| / ty.
        let distance = (0..8)
            .map(|i| {
                let p = bounds.corner(i) - target;
                p.dot(w) + (p.dot(right).abs() / tx).max(p.dot(true_up).abs() / ty)
            })
            .fold(f64::MIN_POSITIVE, f64::max)
            * 1.06;
        Camera { eye: target + w * distance, target, up, projection: Projection::Perspective { fov_y } }
    }

    /// An orthographic camera looking along `-view` at `bounds`, showing all of them.
    #[must_use]
    pub fn frame_orthographic(bounds: &Aabb, view: DVec3, up: DVec3) -> Self {
        let radius = (bounds.size().length() * 0.5).max(1e-12);
        let target = bounds.center();
        Camera {
            eye: target + view.normalize() * 4.0 * radius,
            target,
            up,
            projection: Projection::Orthographic { height: 2.0 * radius },
        }
    }

    /// The camera's frame for an image of `aspect` = width / height, computed once for
    /// many rays or projections ([`Camera::ray`] and [`Camera::project`] use it too, so
    /// the numbers are the same).
    #[must_use]
    pub fn view(&self, aspect: f64) -> View {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let half = match self.projection {
            Projection::Perspective { fov_y } => (fov_y.to_radians() * 0.5).tan(),
            Projection::Orthographic { height } => height * 0.5,
        };
        View { eye: self.eye, forward, right, up, projection: self.projection, aspect, half }
    }

    /// The image point `(x, y)` (in `[-1, 1]^2` when visible) of world point `p`;
    /// `None` when `p` is not in front of a perspective camera.
    #[must_use]
    pub fn project(&self, p: DVec3, aspect: f64) -> Option<(f64, f64)> {
        self.view(aspect).project(p)
    }

    /// The ray through the image point `(x, y)` in `[-1, 1]^2` (x right, y up) of an
    /// image with `aspect` = width / height, with a unit direction.
    #[must_use]
    pub fn ray(&self, x: f64, y: f64, aspect: f64) -> Ray {
        self.view(aspect).ray(x, y)
    }
}

/// A camera's orthonormal frame (`forward`, `right`, `up`) for one image aspect.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct View {
    /// Eye position.
    pub eye: DVec3,
    /// Unit vector from the eye to the target.
    pub forward: DVec3,
    /// Unit vector to the image's right: `forward x up`, normalized.
    pub right: DVec3,
    /// Unit vector to the image's top: `right x forward`.
    pub up: DVec3,
    /// Projection.
    pub projection: Projection,
    /// Image aspect, width / height.
    pub aspect: f64,
    /// Half the image height: `tan(fov_y / 2)` at unit distance (perspective), or
    /// `height / 2` in world units (orthographic).
    pub half: f64,
}

impl View {
    /// The image point `(x, y)` of world point `p`: perspective `x = v.right / (z tan(fov/2)
    /// aspect)`, `y = v.up / (z tan(fov/2))` with `v = p - eye`, `z = v.forward`;
    /// `None` when `z <= 0`. Orthographic: `x = v.right / (height/2 aspect)`, `y = v.up / (height/2)`.
    #[must_use]
    pub fn project(&self, p: DVec3) -> Option<(f64, f64)> {
        let v = p - self.eye;
        match self.projection {
            Projection::Perspective { .. } => {
                let z = v.dot(self.forward);
                if z <= 0.0 {
                    return None;
                }
                let h = self.half;
                Some((v.dot(self.right) / (z * h * self.aspect), v.dot(self.up) / (z * h)))
            }
            Projection::Orthographic { .. } => {
                let h = self.half;
                Some((v.dot(self.right) / (h * self.aspect), v.dot(self.up) / h))
            }
        }
    }

    /// The ray through image point `(x, y)`, with a unit direction.
    #[must_use]
    pub fn ray(&self, x: f64, y: f64) -> Ray {
        match self.projection {
            Projection::Perspective { .. } => {
                let h = self.half;
                Ray::new(self.eye, (self.forward + self.right * (x * h * self.aspect) + self.up * (y * h)).normalize())
            }
            Projection::Orthographic { .. } => {
                let h = self.half;
                Ray::new(self.eye + self.right * (x * h * self.aspect) + self.up * (y * h), self.forward)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_view_looks_down_from_the_same_height_for_every_up_axis() {
        assert_eq!(Camera::default_view(Axis::Z), DEFAULT_VIEW);
        for up in [Axis::X, Axis::Y, Axis::Z] {
            let v = Camera::default_view(up);
            // The same direction in the up axis's frame: as far above the target, as
            // long, and never along the up vector (which would leave no image right).
            assert_eq!(v.dot(up.unit()), DEFAULT_VIEW.z, "{up:?}");
            assert_eq!(v.length_squared(), DEFAULT_VIEW.length_squared(), "{up:?}");
            assert!(v.cross(up.unit()).length() > 1.0, "{up:?}");
        }
        assert_eq!(Camera::default_view(Axis::Y), DVec3::new(1.0, 1.1, 1.7));
    }
}
