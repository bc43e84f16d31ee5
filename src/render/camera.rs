//! Cameras: pinhole perspective and orthographic, look-at, auto-framing.

use glam::DVec3;

use crate::aabb::Aabb;

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
/// eye, for a z-up world: front-right and above.
pub const DEFAULT_VIEW: DVec3 = DVec3::new(1.0, -1.7, 1.1);

impl Camera {
    /// A perspective camera at `eye` looking at `target`.
    #[must_use]
    pub fn look_at(eye: DVec3, target: DVec3, up: DVec3, fov_y: f64) -> Self {
        Camera { eye, target, up, projection: Projection::Perspective { fov_y } }
    }

    /// A perspective camera (35 degrees) framing `bounds` from `view` (a direction from
    /// the target to the eye; use [`DEFAULT_VIEW`]) with `up`, for an image of `aspect`
    /// = width / height: the nearest distance at which all eight corners of the box
    /// project inside the image, plus a 6% margin.
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

    /// The image point `(x, y)` (in `[-1, 1]^2` when visible) of world point `p`;
    /// `None` when `p` is not in front of a perspective camera.
    #[must_use]
    pub fn project(&self, p: DVec3, aspect: f64) -> Option<(f64, f64)> {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        let v = p - self.eye;
        match self.projection {
            Projection::Perspective { fov_y } => {
                let z = v.dot(forward);
                if z <= 0.0 {
                    return None;
                }
                let h = (fov_y.to_radians() * 0.5).tan();
                Some((v.dot(right) / (z * h * aspect), v.dot(up) / (z * h)))
            }
            Projection::Orthographic { height } => {
                let h = height * 0.5;
                Some((v.dot(right) / (h * aspect), v.dot(up) / h))
            }
        }
    }

    /// The ray through the image point `(x, y)` in `[-1, 1]^2` (x right, y up) of an
    /// image with `aspect` = width / height: origin and unit direction.
    #[must_use]
    pub fn ray(&self, x: f64, y: f64, aspect: f64) -> (DVec3, DVec3) {
        let forward = (self.target - self.eye).normalize();
        let right = forward.cross(self.up).normalize();
        let up = right.cross(forward);
        match self.projection {
            Projection::Perspective { fov_y } => {
                let h = (fov_y.to_radians() * 0.5).tan();
                (self.eye, (forward + right * (x * h * aspect) + up * (y * h)).normalize())
            }
            Projection::Orthographic { height } => {
                let h = height * 0.5;
                (self.eye + right * (x * h * aspect) + up * (y * h), forward)
            }
        }
    }
}
