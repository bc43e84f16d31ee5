//! The camera a user asks for ([`CameraRequest`]: eye, target, up, field of view, a
//! named view or orbit angles, zoom, orthographic, the model's front) over what frames
//! the picture ([`Framing`]: a scene's own camera, or the silhouette of a solid or
//! mesh, which then fills the picture, [`Camera::frame_points`]). The command line's
//! camera flags, a viewer's query and [`crate::quick`] all come here.
//!
//! Rules, in order:
//! - With an eye, the camera looks from it at the target (the request's, else the
//!   scene camera's, else the middle of the points' box) with the field of view (the
//!   request's, else the scene camera's, else [`DEFAULT_FOV`]).
//! - Else a scene's camera is kept as its file says unless the request re-frames it
//!   (a view or orbit angles): its up and target are the request's where given, and a
//!   perspective's field of view.
//! - Else the points are framed from the view direction: the named view, the orbit
//!   (missing angles [`default_orbit`](super::default_orbit)'s), or
//!   [`Camera::default_view`] of the up axis; turned about up to the model's `front`;
//!   a target moves the framed camera across without turning it.
//! - `ortho` then shows what the perspective showed at the target's distance, and
//!   `zoom` comes last (the eye F times closer; orthographic: F times less shown).

use glam::DVec3;

use super::camera::{Camera, Projection};
use super::framing::{NamedView, default_orbit, orbit_direction, silhouette_points, up_for};
use super::up::Up;
use crate::error::{Error, Result};
use crate::octree::LinearOctree;
use crate::shape::Axis;

/// The vertical field of view, in degrees, when neither the request nor a scene gives
/// one.
pub const DEFAULT_FOV: f64 = 35.0;

/// How a user places the camera; every field left `None` (or `false`) keeps what the
/// framing gives. [`CameraRequest::default`] asks for nothing: a solid framed from
/// [`Camera::default_view`], a scene's camera as it is.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CameraRequest {
    /// The world's up (default: the framing's).
    pub up: Option<Up>,
    /// Eye position (looking at `target`); not with `view` or orbit angles.
    pub eye: Option<DVec3>,
    /// Point looked at (default: the middle of the silhouette, or the scene camera's).
    pub target: Option<DVec3>,
    /// Vertical field of view in degrees, in `(0, 180)`.
    pub fov: Option<f64>,
    /// A named view in the up axis's frame; not with orbit angles.
    pub view: Option<NamedView>,
    /// Orbit: degrees around the up axis from the front view, towards the right.
    pub azimuth: Option<f64>,
    /// Orbit: degrees above the horizon.
    pub elevation: Option<f64>,
    /// Magnification, positive: the eye F times closer (orthographic: F times less
    /// shown).
    pub zoom: Option<f64>,
    /// Orthographic projection instead of perspective.
    pub ortho: bool,
    /// The way the model's front faces, a unit axis across the up axis: the named
    /// views and orbits turn about up to match (default: [`NamedView::Front`]'s side).
    pub front: Option<DVec3>,
}

impl CameraRequest {
    /// Checks the fields: a finite field of view in `(0, 180)`, a positive finite zoom,
    /// finite positions, finite angles, an eye not given with a view or orbit angles, a
    /// view not given with orbit angles, a `front` across the up axis of `up` (the
    /// request's, else this one). Errors name the field.
    pub fn validate(&self, up: Up) -> Result<()> {
        if let Some(fov) = self.fov.filter(|f| !(f.is_finite() && *f > 0.0 && *f < 180.0)) {
            return Err(Error::invalid(
                "fov",
                format!("{}: the field of view must be between 0 and 180 degrees", crate::error::Number(fov)),
            ));
        }
        if let Some(zoom) = self.zoom.filter(|z| !(z.is_finite() && *z > 0.0)) {
            return Err(Error::invalid(
                "zoom",
                format!("{}: the zoom must be a positive number", crate::error::Number(zoom)),
            ));
        }
        for (what, p) in [("eye", self.eye), ("target", self.target), ("front", self.front)] {
            if let Some(p) = p.filter(|p| !p.is_finite()) {
                return Err(Error::invalid(what, format!("{p} is not finite")));
            }
        }
        for (what, a) in [("azimuth", self.azimuth), ("elevation", self.elevation)] {
            if let Some(a) = a.filter(|a| !a.is_finite()) {
                return Err(Error::invalid(what, format!("{a} is not finite")));
            }
        }
        if self.eye.is_some() && self.reframes() {
            return Err(Error::invalid("eye", "an eye is not given with a view or orbit angles"));
        }
        if self.view.is_some() && (self.azimuth.is_some() || self.elevation.is_some()) {
            return Err(Error::invalid("view", "a named view is not given with orbit angles"));
        }
        let axis = self.up.unwrap_or(up).axis();
        if let Some(front) = self.front
            && front.dot(axis.unit()) != 0.0
        {
            return Err(Error::invalid(
                "front",
                format!("must lie across the up axis {axis:?}: a model's front is horizontal"),
            ));
        }
        Ok(())
    }

    /// Whether the request asks for a new viewing direction (a view or orbit angles).
    #[must_use]
    pub fn reframes(&self) -> bool {
        self.view.is_some() || self.azimuth.is_some() || self.elevation.is_some()
    }

    /// Whether the request places the eye itself (an eye, a view or orbit angles).
    #[must_use]
    pub fn places_eye(&self) -> bool {
        self.eye.is_some() || self.reframes()
    }

    /// The camera for a picture of `aspect` = width / height (see the module doc).
    ///
    /// # Errors
    /// What [`CameraRequest::validate`] refuses; [`Error::InvalidArgument`] when there
    /// is nothing to frame (no points where they are needed).
    pub fn camera(&self, framing: &Framing, aspect: f64) -> Result<Camera> {
        self.validate(framing.up)?;
        let up = self.up.unwrap_or(framing.up);
        let (axis, up_vec) = (up.axis(), up.vector());
        let oriented = self.reframes();
        let view = if let Some(v) = self.view {
            v.direction(axis)
        } else if oriented {
            let (azimuth, elevation) = default_orbit();
            orbit_direction(self.azimuth.unwrap_or(azimuth), self.elevation.unwrap_or(elevation), axis)
        } else {
            Camera::default_view(axis)
        };
        let view = match self.front {
            Some(front) => turned_to_front(view, front, axis),
            None => view,
        };
        let mut camera = match (framing.scene_camera, self.eye) {
            (_, Some(eye)) => {
                let scene_target = framing.scene_camera.map(|c| c.target);
                let target = self.target.or(scene_target).unwrap_or_else(|| centre(&framing.points));
                let fov = self.fov.or(framing.scene_camera.and_then(fov_of)).unwrap_or(DEFAULT_FOV);
                Camera::look_at(eye, target, up_for(eye - target, up_vec, axis), fov)
            }
            (Some(scene), None) if !oriented => {
                let mut c = scene;
                c.up = up_vec;
                if let Some(t) = self.target {
                    c.target = t;
                }
                if let (Some(fov), Projection::Perspective { .. }) = (self.fov, c.projection) {
                    c.projection = Projection::Perspective { fov_y: fov };
                }
                c
            }
            (scene, None) => {
                let fov = self.fov.or(scene.and_then(fov_of)).unwrap_or(DEFAULT_FOV);
                let fov = (!self.ortho).then_some(fov);
                let Some(mut c) = Camera::frame_points(&framing.points, view, up_for(view, up_vec, axis), aspect, fov)
                else {
                    return Err(Error::invalid("camera", "there is nothing to frame: the solids are empty"));
                };
                if let Some(t) = self.target {
                    c.eye += t - c.target;
                    c.target = t;
                }
                c
            }
        };
        if let (true, Projection::Perspective { fov_y }) = (self.ortho, camera.projection) {
            let height = 2.0 * (camera.eye - camera.target).length() * (fov_y.to_radians() * 0.5).tan();
            camera.projection = Projection::Orthographic { height };
        }
        if let Some(zoom) = self.zoom {
            match &mut camera.projection {
                Projection::Perspective { .. } => camera.eye = camera.target + (camera.eye - camera.target) / zoom,
                Projection::Orthographic { height } => *height /= zoom,
            }
        }
        Ok(camera)
    }
}

/// What the camera frames: the object's silhouette points and up, and a scene's own
/// camera when there is one.
#[derive(Clone, Debug, PartialEq)]
pub struct Framing {
    /// Points whose hull holds what is drawn (a solid's [`silhouette_points`], a
    /// mesh's vertices); empty for a scene the request does not re-frame.
    pub points: Vec<DVec3>,
    /// The up of the object (a scene camera's, a file's recorded axis).
    pub up: Up,
    /// A scene file's camera, kept unless the request re-frames it.
    pub scene_camera: Option<Camera>,
}

impl Framing {
    /// A solid's framing: its [`silhouette_points`] with `up` (a scene's:
    /// [`Scene::framing`](crate::render::Scene::framing)).
    #[must_use]
    pub fn of_solid(tree: &LinearOctree, up: Up) -> Framing {
        Framing { points: silhouette_points(tree), up, scene_camera: None }
    }
}

/// `view` turned about the up axis `up` by the quarter turns that take the default
/// front (where [`NamedView::Front`] looks from) to `front` (across `up`: checked by
/// [`CameraRequest::validate`]).
fn turned_to_front(view: DVec3, front: DVec3, up: Axis) -> DVec3 {
    let up_vec = up.unit();
    let from = NamedView::Front.direction(up);
    let angle = from.cross(front).dot(up_vec).atan2(from.dot(front));
    glam::DQuat::from_axis_angle(up_vec, angle) * view
}

fn fov_of(c: Camera) -> Option<f64> {
    match c.projection {
        Projection::Perspective { fov_y } => Some(fov_y),
        Projection::Orthographic { .. } => None,
    }
}

/// The middle of the points' box (the origin for none).
fn centre(points: &[DVec3]) -> DVec3 {
    let lo = points.iter().fold(DVec3::splat(f64::MAX), |a, p| a.min(*p));
    let hi = points.iter().fold(DVec3::splat(f64::MIN), |a, p| a.max(*p));
    if points.is_empty() { DVec3::ZERO } else { (lo + hi) * 0.5 }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cube_points() -> Vec<DVec3> {
        (0..8).map(|i| DVec3::new(f64::from(i & 1), f64::from(i >> 1 & 1), f64::from(i >> 2 & 1))).collect()
    }

    #[test]
    fn a_refused_request_names_its_field() {
        let what = |r: CameraRequest| match r.validate(Up::default()) {
            Err(Error::InvalidArgument { what, .. }) => what,
            other => panic!("{other:?}"),
        };
        assert_eq!(what(CameraRequest { fov: Some(180.0), ..Default::default() }), "fov");
        assert_eq!(what(CameraRequest { zoom: Some(0.0), ..Default::default() }), "zoom");
        assert_eq!(what(CameraRequest { eye: Some(DVec3::NAN), ..Default::default() }), "eye");
        let eye_and_view = CameraRequest { eye: Some(DVec3::ONE), view: Some(NamedView::Top), ..Default::default() };
        assert_eq!(what(eye_and_view), "eye");
        assert_eq!(what(CameraRequest { front: Some(DVec3::Z), ..Default::default() }), "front");
        assert!(
            CameraRequest { front: Some(-DVec3::Z), up: Some(Up::Axis(Axis::Y)), ..Default::default() }
                .validate(Up::default())
                .is_ok()
        );
    }

    #[test]
    fn zoom_and_ortho_change_a_framed_camera_as_the_module_doc_says() {
        let framing = Framing { points: cube_points(), up: Up::default(), scene_camera: None };
        let plain = CameraRequest::default().camera(&framing, 1.0).unwrap();
        let zoomed = CameraRequest { zoom: Some(2.0), ..Default::default() }.camera(&framing, 1.0).unwrap();
        assert_eq!(zoomed.target, plain.target);
        assert!(((zoomed.eye - zoomed.target).length() * 2.0 - (plain.eye - plain.target).length()).abs() < 1e-12);
        let ortho = CameraRequest { ortho: true, ..Default::default() }.camera(&framing, 1.0).unwrap();
        assert!(matches!(ortho.projection, Projection::Orthographic { .. }));
        let nothing = Framing { points: Vec::new(), ..framing };
        assert!(CameraRequest::default().camera(&nothing, 1.0).is_err());
    }
}
