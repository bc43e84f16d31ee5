//! A section view as a user asks for it ([`Section`]: `AXIS,POS`): the scene cut by
//! the plane ([`Scene::sectioned`]) and the camera turned to see the cap. The cap
//! faces `+axis`, so an eye on the other side of the plane through the target is
//! mirrored across it, unless the request placed the eye itself (an eye, a view or
//! orbit angles): then the user sees what they asked for.

use super::Scene;
use crate::render::film::{Camera, CameraRequest};
use crate::shape::Axis;

/// A section plane: keep what lies at or below `at` along `axis`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    /// The plane's normal axis.
    pub axis: Axis,
    /// The plane's coordinate along `axis` (snapped to each solid's voxel lattice).
    pub at: f64,
}

impl Section {
    /// The scene cut by this plane.
    #[must_use]
    pub fn cut(self, scene: &Scene) -> Scene {
        scene.sectioned(self.axis, self.at)
    }

    /// `camera` turned to see the cap (see the module doc).
    #[must_use]
    pub fn facing_the_cap(self, camera: Camera, request: &CameraRequest) -> Camera {
        let a = self.axis.index();
        let mut camera = camera;
        if !request.places_eye() && camera.eye[a] < camera.target[a] {
            camera.eye[a] = 2.0 * camera.target[a] - camera.eye[a];
        }
        camera
    }
}

impl std::str::FromStr for Section {
    type Err = String;

    /// Parses `AXIS,POS`: x, y or z and a finite coordinate.
    fn from_str(s: &str) -> Result<Self, String> {
        let (axis, at) = s.split_once(',').ok_or_else(|| format!("'{s}' is not AXIS,POS like x,0.25"))?;
        let axis = axis.trim().parse::<Axis>().map_err(|e| format!("'{s}': {e}"))?;
        let at = at.trim().parse::<f64>().ok().filter(|v| v.is_finite());
        let at = at.ok_or_else(|| format!("'{s}': the position is not a finite number"))?;
        Ok(Section { axis, at })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn a_section_parses_and_turns_an_eye_below_the_plane_unless_placed() {
        assert_eq!("y, -0.5".parse::<Section>(), Ok(Section { axis: Axis::Y, at: -0.5 }));
        assert!("y".parse::<Section>().is_err() && "w,1".parse::<Section>().is_err());
        assert!("x,inf".parse::<Section>().is_err());
        let s = Section { axis: Axis::Z, at: 0.0 };
        let below = Camera::look_at(DVec3::new(0.0, -3.0, -2.0), DVec3::ZERO, DVec3::Z, 35.0);
        assert_eq!(s.facing_the_cap(below, &CameraRequest::default()).eye, DVec3::new(0.0, -3.0, 2.0));
        let placed = CameraRequest { eye: Some(below.eye), ..Default::default() };
        assert_eq!(s.facing_the_cap(below, &placed).eye, below.eye);
    }
}
