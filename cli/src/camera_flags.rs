//! The camera `render`'s flags ask for: `--eye`, `--target`, `--up`, `--fov`,
//! `--view`, `--azimuth`/`--elevation`, `--zoom` and `--ortho`, over a scene's own
//! camera or the auto-framing of a solid or mesh (its silhouette fills the picture,
//! [`Camera::frame_points`]).
//!
//! A scene's camera is kept as its file says unless a flag changes it: `--up`, `--fov`,
//! `--eye` and `--target` replace its fields; a view or orbit flag re-frames the
//! scene's solids from that direction; `--ortho` shows what the perspective showed at
//! the target's distance; `--zoom` comes last.

use anyhow::{Result, bail};
use glam::DVec3;
use octsolid::render::{
    Camera, NamedView, Projection, Scene, default_orbit, orbit_direction, silhouette_points, up_for,
};

use crate::values::Up;
use octsolid::shape::Axis;

/// The flags that place the camera (`render`'s, flattened into its arguments).
#[derive(clap::Args, Debug, Clone, Default)]
pub struct CameraFlags {
    /// The world's up: an axis (x, y, z) or a vector X,Y,Z (default: the scene's
    /// camera's; an .oct file's recorded axis; by extension for meshes: y for .obj and
    /// .ply, y-up by convention; z otherwise, octsolid's own).
    #[arg(long, value_parser = crate::values::parse_up)]
    pub up: Option<Up>,
    /// Eye position X,Y,Z (looking at --target, default the object's centre).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_vec3, conflicts_with_all = ["view", "azimuth", "elevation"])]
    pub eye: Option<[f64; 3]>,
    /// Point looked at X,Y,Z (default: the middle of the object's silhouette).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_vec3)]
    pub target: Option<[f64; 3]>,
    /// Vertical field of view in degrees (default: the scene's, or 35).
    #[arg(long, value_parser = crate::values::parse_finite)]
    pub fov: Option<f64>,
    /// A named view in the up axis's frame (front looks from -y in a z-up world).
    #[arg(long, conflicts_with_all = ["azimuth", "elevation"])]
    pub view: Option<NamedView>,
    /// Orbit: degrees around the up axis from the front view, towards the right.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_finite)]
    pub azimuth: Option<f64>,
    /// Orbit: degrees above the horizon.
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_finite)]
    pub elevation: Option<f64>,
    /// Magnify by F (the eye moves F times closer; orthographic: F times less shown).
    #[arg(long, value_parser = crate::values::parse_finite)]
    pub zoom: Option<f64>,
    /// Orthographic projection instead of perspective.
    #[arg(long)]
    pub ortho: bool,
    /// The way the model's front faces, a signed axis across --up: the named views and
    /// orbits turn about the up axis to match (default: -y for z-up, +z for y-up,
    /// Blender's and glTF's front; Spot and assimp's Wuson face -z).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_facing)]
    pub front: Option<DVec3>,
}

/// What the camera frames: the object's silhouette points and up, and a scene's own
/// camera when there is one.
pub(crate) struct Framing {
    pub points: Vec<DVec3>,
    pub up: Up,
    pub scene_camera: Option<Camera>,
}

impl Framing {
    /// A scene's framing: its camera's up, and its solids' silhouettes when the
    /// flags re-frame it (only then are they computed).
    pub(crate) fn of_scene(scene: &Scene, camera: Camera, a: &CameraFlags) -> Framing {
        let points = if reframes(a) {
            scene.solids.iter().flat_map(|s| silhouette_points(&s.tree)).collect()
        } else {
            Vec::new()
        };
        Framing { points, up: Up::Vector(camera.up), scene_camera: Some(camera) }
    }
}

const DEFAULT_FOV: f64 = 35.0;

/// Whether the flags ask for a new viewing direction (a view or orbit angles).
fn reframes(a: &CameraFlags) -> bool {
    a.view.is_some() || a.azimuth.is_some() || a.elevation.is_some()
}

/// The camera for an image of `aspect` = width / height.
pub(crate) fn camera(a: &CameraFlags, framing: &Framing, aspect: f64) -> Result<Camera> {
    if let Some(fov) = a.fov.filter(|f| !(f.is_finite() && *f > 0.0 && *f < 180.0)) {
        bail!("--fov {fov}: the field of view must be between 0 and 180 degrees");
    }
    if let Some(zoom) = a.zoom.filter(|z| !(z.is_finite() && *z > 0.0)) {
        bail!("--zoom {zoom}: the zoom must be a positive number");
    }
    let up = a.up.unwrap_or(framing.up);
    let (axis, up_vec) = (up.axis(), up.vector());
    let oriented = reframes(a);
    let view = if let Some(v) = a.view {
        v.direction(axis)
    } else if oriented {
        let (azimuth, elevation) = default_orbit();
        orbit_direction(a.azimuth.unwrap_or(azimuth), a.elevation.unwrap_or(elevation), axis)
    } else {
        Camera::default_view(axis)
    };
    let view = match a.front {
        Some(front) => turned_to_front(view, front, axis)?,
        None => view,
    };
    let mut camera = match (framing.scene_camera, a.eye) {
        (_, Some(eye)) => {
            let eye = DVec3::from(eye);
            let scene_target = framing.scene_camera.map(|c| c.target);
            let target = a.target.map(DVec3::from).or(scene_target).unwrap_or_else(|| centre(&framing.points));
            let fov = a.fov.or(framing.scene_camera.and_then(fov_of)).unwrap_or(DEFAULT_FOV);
            Camera::look_at(eye, target, up_for(eye - target, up_vec, axis), fov)
        }
        (Some(scene), None) if !oriented => {
            let mut c = scene;
            c.up = up_vec;
            if let Some(t) = a.target {
                c.target = DVec3::from(t);
            }
            if let (Some(fov), Projection::Perspective { .. }) = (a.fov, c.projection) {
                c.projection = Projection::Perspective { fov_y: fov };
            }
            c
        }
        (scene, None) => {
            let fov = a.fov.or(scene.and_then(fov_of)).unwrap_or(DEFAULT_FOV);
            let fov = (!a.ortho).then_some(fov);
            let Some(mut c) = Camera::frame_points(&framing.points, view, up_for(view, up_vec, axis), aspect, fov)
            else {
                bail!("there is nothing to frame: the solids are empty");
            };
            if let Some(t) = a.target {
                let t = DVec3::from(t);
                c.eye += t - c.target;
                c.target = t;
            }
            c
        }
    };
    if let (true, Projection::Perspective { fov_y }) = (a.ortho, camera.projection) {
        let height = 2.0 * (camera.eye - camera.target).length() * (fov_y.to_radians() * 0.5).tan();
        camera.projection = Projection::Orthographic { height };
    }
    if let Some(zoom) = a.zoom {
        match &mut camera.projection {
            Projection::Perspective { .. } => camera.eye = camera.target + (camera.eye - camera.target) / zoom,
            Projection::Orthographic { height } => *height /= zoom,
        }
    }
    Ok(camera)
}

/// `view` turned about the up axis `up` by the quarter turns that take the default
/// front (where [`NamedView::Front`] looks from) to `front`.
fn turned_to_front(view: DVec3, front: DVec3, up: Axis) -> Result<DVec3> {
    let up_vec = up.unit();
    if front.dot(up_vec) != 0.0 {
        bail!("--front must lie across the up axis {up:?}: a model's front is horizontal");
    }
    let from = NamedView::Front.direction(up);
    let angle = from.cross(front).dot(up_vec).atan2(from.dot(front));
    Ok(glam::DQuat::from_axis_angle(up_vec, angle) * view)
}

fn fov_of(c: Camera) -> Option<f64> {
    match c.projection {
        Projection::Perspective { fov_y } => Some(fov_y),
        Projection::Orthographic { .. } => None,
    }
}

/// The middle of the points' box.
fn centre(points: &[DVec3]) -> DVec3 {
    let lo = points.iter().fold(DVec3::splat(f64::MAX), |a, p| a.min(*p));
    let hi = points.iter().fold(DVec3::splat(f64::MIN), |a, p| a.max(*p));
    if points.is_empty() { DVec3::ZERO } else { (lo + hi) * 0.5 }
}
