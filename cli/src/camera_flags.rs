//! The flags that place the camera (`render`'s, flattened into its arguments):
//! `--eye`, `--target`, `--up`, `--fov`, `--view`, `--azimuth`/`--elevation`,
//! `--zoom`, `--ortho` and `--front`, each one field of the library's
//! [`CameraRequest`], whose module doc holds the rules; its refusals are told in the
//! flags' words ([`in_flags_words`]).

use glam::DVec3;
use octsolid::render::{CameraRequest, NamedView, Up};

/// The flags that place the camera.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct CameraFlags {
    /// The world's up: an axis (x, y, z) or a vector X,Y,Z (default: the scene's
    /// camera's; an .oct file's recorded axis; by extension for meshes: y for .obj and
    /// .ply, y-up by convention; z otherwise, octsolid's own).
    #[arg(long)]
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
    /// A named view in the up axis's frame: front, back, left, right, top, bottom or
    /// iso (front looks from -y in a z-up world).
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

/// A camera request's refusal in the flags' words: a field the flags set is named as
/// its flag (`--fov 180: the field of view must be ...`); anything else as it is.
pub(crate) fn in_flags_words(e: octsolid::Error) -> anyhow::Error {
    const FLAGS: [&str; 8] = ["up", "eye", "target", "fov", "view", "azimuth", "elevation", "zoom"];
    match e {
        octsolid::Error::InvalidArgument { what, reason } if what == "front" || FLAGS.contains(&what) => {
            anyhow::anyhow!("--{what} {reason}")
        }
        e => e.into(),
    }
}

impl CameraFlags {
    /// The library's camera request these flags make.
    pub(crate) fn request(&self) -> CameraRequest {
        CameraRequest {
            up: self.up,
            eye: self.eye.map(DVec3::from),
            target: self.target.map(DVec3::from),
            fov: self.fov,
            view: self.view,
            azimuth: self.azimuth,
            elevation: self.elevation,
            zoom: self.zoom,
            ortho: self.ortho,
            front: self.front,
        }
    }
}
