//! The scene file as read: the private `*Spec` types serde fills from the TOML text,
//! each value checked where it is read (enum-like values as serde enums, shape nodes
//! through [`ShapeSpec`]'s deserializer, colours through [`ColorSpec`]), and each spec's
//! conversion to what the renderer takes (material, light, render options, camera).
//! Unknown keys are refused (`deny_unknown_fields`); `docs/SCENES.md` is the format.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;
use serde::Deserialize;
use serde::de::{self, Deserializer};
use toml::Spanned;

use crate::aabb::Aabb;
use crate::color::ColorSpec;
use crate::error::{Error, Result};
use crate::mesh::InsideRule;
use crate::render::{
    AntiAliasingKind, Bump, Camera, DEFAULT_VIEW, Light, MAX_AA_DEPTH, MAX_IMAGE_SIZE, MAX_RAY_DEPTH, Mapping,
    Material, Normals, Projection, RenderOptions, RenderOverrides, Texture,
};
use crate::shape::{Axis, ShapeSpec, TransformSpec};

/// The whole file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct SceneSpec {
    #[serde(default)]
    pub(super) image: ImageSpec,
    /// Spanned, so that a camera found wrong once the solids' bounds are known (the eye
    /// at the target, up along the line of sight) is blamed on its table.
    pub(super) camera: Option<Spanned<CameraSpec>>,
    pub(super) domain: Option<Spanned<DomainSpec>>,
    #[serde(default, rename = "light")]
    pub(super) lights: Vec<Spanned<LightSpec>>,
    #[serde(rename = "solid")]
    pub(super) solids: Vec<Spanned<SolidSpec>>,
    pub(super) ambient: Option<ColorSpec>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct ImageSpec {
    #[serde(default = "default_size", deserialize_with = "image_size")]
    pub(super) size: [u32; 2],
    #[serde(default = "default_samples", deserialize_with = "samples_a_side")]
    pub(super) samples: u32,
    #[serde(default = "default_true")]
    pub(super) shadows: bool,
    pub(super) background: Option<ColorSpec>,
    /// Smooth (the default), axis or octree.
    pub(super) normals: Option<Normals>,
    /// Longest chain of reflected and refracted rays.
    #[serde(default, deserialize_with = "ray_depth")]
    pub(super) max_depth: Option<u32>,
    /// Share of a pixel below which a secondary ray is not traced.
    #[serde(default, deserialize_with = "ray_cutoff")]
    pub(super) cutoff: Option<f64>,
    /// Uniform (the default), adaptive or recursive anti-aliasing.
    pub(super) aa: Option<AntiAliasingKind>,
    /// Contrast at which adaptive anti-aliasing supersamples, recursive splits
    /// (implies adaptive when `aa` is not given).
    #[serde(default, deserialize_with = "aa_threshold")]
    pub(super) aa_threshold: Option<f64>,
    /// Most splits of a pixel's square by recursive anti-aliasing (implies recursive
    /// when `aa` is not given).
    #[serde(default, deserialize_with = "aa_depth")]
    pub(super) aa_depth: Option<u32>,
}

/// `[image] max_depth`, checked where it is read (as [`RenderOptions::validate`] does,
/// here at the value's place): at most [`MAX_RAY_DEPTH`].
fn ray_depth<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<u32>, D::Error> {
    let depth = u32::deserialize(d)?;
    if depth > MAX_RAY_DEPTH {
        return Err(de::Error::custom(format!("max depth {depth} is above the limit of {MAX_RAY_DEPTH}")));
    }
    Ok(Some(depth))
}

/// `[image] cutoff`, checked where it is read: within 0..=1.
fn ray_cutoff<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<f64>, D::Error> {
    let cutoff = f64::deserialize(d)?;
    // (A value that is not finite is named by the file's check of every float.)
    if cutoff.is_finite() && !(0.0..=1.0).contains(&cutoff) {
        return Err(de::Error::custom(format!("ray cutoff {} is outside 0..=1", crate::error::Number(cutoff))));
    }
    Ok(Some(cutoff))
}

/// `[image] aa_threshold`, checked where it is read: 0 or more (a negative one was
/// refused by the render, without its place).
fn aa_threshold<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<f64>, D::Error> {
    let threshold = f64::deserialize(d)?;
    // (A value that is not finite is named by the file's check of every float.)
    if threshold < 0.0 {
        let t = crate::error::Number(threshold);
        return Err(de::Error::custom(format!("anti-aliasing threshold {t} must be at least 0")));
    }
    Ok(Some(threshold))
}

/// `[image] aa_depth`, checked where it is read: within 1..=[`MAX_AA_DEPTH`].
fn aa_depth<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<u32>, D::Error> {
    let depth = u32::deserialize(d)?;
    if !(1..=MAX_AA_DEPTH).contains(&depth) {
        return Err(de::Error::custom(format!("anti-aliasing depth {depth} is outside 1..={MAX_AA_DEPTH}")));
    }
    Ok(Some(depth))
}

pub(super) fn default_size() -> [u32; 2] {
    [960, 720]
}
pub(super) fn default_samples() -> u32 {
    2
}
pub(super) fn default_true() -> bool {
    true
}

impl Default for ImageSpec {
    fn default() -> Self {
        ImageSpec {
            size: default_size(),
            samples: default_samples(),
            shadows: true,
            background: None,
            normals: None,
            max_depth: None,
            cutoff: None,
            aa: None,
            aa_threshold: None,
            aa_depth: None,
        }
    }
}

#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct CameraSpec {
    pub(super) eye: Option<[f64; 3]>,
    pub(super) target: Option<[f64; 3]>,
    /// Direction from the target to the eye when the eye is not given (auto-framing).
    #[serde(default, deserialize_with = "direction")]
    pub(super) view: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "direction")]
    pub(super) up: Option<[f64; 3]>,
    #[serde(default, deserialize_with = "field_of_view")]
    pub(super) fov: Option<f64>,
    /// Perspective (the default) or orthographic.
    pub(super) projection: Option<ProjectionSpec>,
    /// View height of an orthographic camera.
    #[serde(default, deserialize_with = "view_height")]
    pub(super) height: Option<f64>,
}

/// `[image] size`, checked where it is read: 1 to [`MAX_IMAGE_SIZE`] a side (as
/// [`RenderOptions::validate`] asks, refused here at the value's place).
fn image_size<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<[u32; 2], D::Error> {
    let [width, height] = <[u32; 2]>::deserialize(d)?;
    if !(1..=MAX_IMAGE_SIZE).contains(&width) || !(1..=MAX_IMAGE_SIZE).contains(&height) {
        return Err(de::Error::custom(format!("image size {width}x{height} is outside 1..={MAX_IMAGE_SIZE} a side")));
    }
    Ok([width, height])
}

/// `[image] samples`, checked where it is read: 1 to 16 a side.
fn samples_a_side<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<u32, D::Error> {
    let samples = u32::deserialize(d)?;
    if !(1..=16).contains(&samples) {
        return Err(de::Error::custom(format!("samples {samples} a side is outside 1..=16")));
    }
    Ok(samples)
}

/// `[camera] fov`, checked where it is read: strictly between 0 and 180 degrees.
fn field_of_view<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<f64>, D::Error> {
    let fov = f64::deserialize(d)?;
    // (A value that is not finite is named by the file's check of every float.)
    if fov.is_finite() && !(fov > 0.0 && fov < 180.0) {
        return Err(de::Error::custom(format!(
            "field of view {} must be between 0 and 180 degrees",
            crate::error::Number(fov)
        )));
    }
    Ok(Some(fov))
}

/// `[camera] view` and `up`, checked where they are read: not zero (a zero view or up
/// left the eye at the target, and the camera's error blamed the eye).
fn direction<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<[f64; 3]>, D::Error> {
    let v = <[f64; 3]>::deserialize(d)?;
    if v == [0.0; 3] {
        return Err(de::Error::custom("the direction [0, 0, 0] points nowhere"));
    }
    Ok(Some(v))
}

/// `[camera] height`, checked where it is read: positive.
fn view_height<'de, D: Deserializer<'de>>(d: D) -> std::result::Result<Option<f64>, D::Error> {
    let height = f64::deserialize(d)?;
    if height.is_finite() && height <= 0.0 {
        return Err(de::Error::custom(format!(
            "orthographic height {} must be positive",
            crate::error::Number(height)
        )));
    }
    Ok(Some(height))
}

/// How the camera projects; the field of view and the view height are keys of their own.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum ProjectionSpec {
    Perspective,
    Orthographic,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct DomainSpec {
    pub(super) min: Option<[f64; 3]>,
    pub(super) edge: Option<f64>,
    /// Default 9; with `voxel_size`, the least that holds the shapes.
    pub(super) depth: Option<u8>,
    /// A voxel's edge instead of `min` and `edge` (`Domain::on_grid`).
    pub(super) voxel_size: Option<f64>,
}

/// The depth of a scene without `[domain] depth`.
pub(super) const DEFAULT_DEPTH: u8 = 9;

/// A light: a struct with its `type` rather than an internally tagged enum, which
/// serde reads from a buffered copy without the reader's spans; whether `position` or
/// `direction` is given is checked when it is built, at the light's header.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct LightSpec {
    #[serde(rename = "type")]
    pub(super) kind: LightKind,
    pub(super) position: Option<[f64; 3]>,
    pub(super) direction: Option<[f64; 3]>,
    pub(super) color: Option<ColorSpec>,
}

/// The kinds of light.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub(super) enum LightKind {
    Point,
    Directional,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct SolidSpec {
    pub(super) name: Option<String>,
    pub(super) shape: Option<Spanned<ShapeSpec>>,
    pub(super) mesh: Option<Spanned<PathBuf>>,
    pub(super) oct: Option<Spanned<PathBuf>>,
    /// Moves the solid: scale, rotate, translate (as a shape's `transform`).
    pub(super) transform: Option<Spanned<TransformSpec>>,
    /// Depth for a mesh (default: the scene domain's).
    pub(super) depth: Option<Spanned<u8>>,
    /// How a mesh decides its inside (default auto).
    pub(super) inside: Option<Spanned<InsideSpec>>,
    pub(super) material: Option<Spanned<MaterialSpec>>,
}

/// [`InsideRule`] as a scene writes it.
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum InsideSpec {
    Auto,
    Parity,
    Winding,
}

impl From<InsideSpec> for InsideRule {
    fn from(rule: InsideSpec) -> Self {
        match rule {
            InsideSpec::Auto => InsideRule::Auto,
            InsideSpec::Parity => InsideRule::Parity,
            InsideSpec::Winding => InsideRule::Winding,
        }
    }
}

#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct MaterialSpec {
    pub(super) color: Option<ColorSpec>,
    pub(super) ka: Option<f64>,
    pub(super) kd: Option<f64>,
    pub(super) ks: Option<f64>,
    pub(super) shininess: Option<f64>,
    pub(super) reflectance: Option<f64>,
    pub(super) transmittance: Option<f64>,
    pub(super) ior: Option<f64>,
    pub(super) texture: Option<TextureSpec>,
    pub(super) bump: Option<BumpSpec>,
    pub(super) emission: Option<[f64; 3]>,
}

#[derive(Deserialize, Debug)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub(super) enum TextureSpec {
    Checker { size: f64, a: ColorSpec, b: ColorSpec },
    Wood { axis: Axis, center: Option<[f64; 3]>, size: f64, a: ColorSpec, b: ColorSpec },
    Marble { size: f64, a: ColorSpec, b: ColorSpec },
    Image { file: PathBuf, mapping: MappingSpec, axis: Option<Axis>, center: Option<[f64; 3]>, scale: Option<f64> },
}

/// The projection of an image texture ([`Mapping`] without its parameters).
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(rename_all = "snake_case")]
pub(super) enum MappingSpec {
    Planar,
    Cylindrical,
    Spherical,
}

impl TextureSpec {
    pub(super) fn build(&self, folder: &Path) -> Result<Texture> {
        let positive = |what: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(Error::invalid(what, format!("{} must be positive", crate::error::Number(v))))
            }
        };
        Ok(match self {
            TextureSpec::Checker { size, a, b } => {
                Texture::Checker { size: positive("size", *size)?, a: a.rgb(), b: b.rgb() }
            }
            TextureSpec::Wood { axis, center, size, a, b } => Texture::Wood {
                axis: *axis,
                center: center.map_or(DVec3::ZERO, DVec3::from_array),
                size: positive("size", *size)?,
                a: a.rgb(),
                b: b.rgb(),
            },
            TextureSpec::Marble { size, a, b } => {
                Texture::Marble { size: positive("size", *size)?, a: a.rgb(), b: b.rgb() }
            }
            TextureSpec::Image { file, mapping, axis, center, scale } => {
                let path = folder.join(file);
                let texels = read_texels(&path)?;
                let axis = axis.unwrap_or(Axis::Z);
                let center = center.map_or(DVec3::ZERO, DVec3::from_array);
                let scale = positive("scale", scale.unwrap_or(1.0))?;
                let mapping = match mapping {
                    MappingSpec::Planar => Mapping::Planar { axis, origin: center, scale },
                    MappingSpec::Cylindrical => Mapping::Cylindrical { axis, center, scale },
                    MappingSpec::Spherical => Mapping::Spherical { axis, center },
                };
                Texture::Image { texels: Arc::new(texels), mapping }
            }
        })
    }
}

/// The image at `path` as 8-bit RGB; a file that cannot be read is [`Error::Io`].
pub(super) fn read_texels(path: &Path) -> Result<image::RgbImage> {
    match image::open(path) {
        Ok(img) => Ok(img.to_rgb8()),
        Err(image::ImageError::IoError(source)) => Err(Error::Io { path: path.to_path_buf(), source }),
        Err(e) => Err(Error::invalid("texture", format!("{}: {e}", path.display()))),
    }
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub(super) struct BumpSpec {
    pub(super) amplitude: f64,
    pub(super) scale: f64,
}

impl MaterialSpec {
    /// The material, every coefficient not given the default's.
    pub(super) fn material(&self, folder: &Path) -> Result<Material> {
        let d = Material::default();
        Ok(Material {
            color: self.color.map_or(d.color, ColorSpec::rgb),
            texture: self.texture.as_ref().map(|t| t.build(folder)).transpose()?,
            bump: self.bump.as_ref().map(|b| Bump { amplitude: b.amplitude, scale: b.scale }),
            ka: self.ka.unwrap_or(d.ka),
            kd: self.kd.unwrap_or(d.kd),
            ks: self.ks.unwrap_or(d.ks),
            shininess: self.shininess.unwrap_or(d.shininess),
            reflectance: self.reflectance.unwrap_or(d.reflectance),
            transmittance: self.transmittance.unwrap_or(d.transmittance),
            ior: self.ior.unwrap_or(d.ior),
            emission: self.emission.map_or(d.emission, DVec3::from_array),
        })
    }
}

impl LightSpec {
    /// The light, white without a colour; a point light takes a `position` and no
    /// `direction`, a directional light the other way round.
    pub(super) fn light(&self) -> Result<Light> {
        let color = self.color.map_or(DVec3::ONE, ColorSpec::rgb);
        match (self.kind, self.position, self.direction) {
            (LightKind::Point, Some(p), None) => Ok(Light::Point { position: DVec3::from_array(p), color }),
            (LightKind::Directional, None, Some(d)) => {
                let direction = DVec3::from_array(d);
                if direction.length_squared() == 0.0 {
                    return Err(Error::invalid("light", "a directional light's direction [0, 0, 0] points nowhere"));
                }
                Ok(Light::Directional { direction, color })
            }
            (LightKind::Point, ..) => Err(Error::invalid("light", "a point light takes a position and no direction")),
            (LightKind::Directional, ..) => {
                Err(Error::invalid("light", "a directional light takes a direction and no position"))
            }
        }
    }
}

impl ImageSpec {
    /// The render options, every one not given the default's (merged as the command
    /// line's flags are, by [`RenderOverrides`]).
    pub(super) fn options(&self) -> RenderOptions {
        let overrides = RenderOverrides {
            size: Some(self.size),
            spp: Some(self.samples),
            shadows: Some(self.shadows),
            normals: self.normals,
            max_depth: self.max_depth,
            cutoff: self.cutoff,
            aa: self.aa,
            aa_threshold: self.aa_threshold,
            aa_depth: self.aa_depth,
            ..RenderOverrides::default()
        };
        overrides.apply(RenderOptions::default())
    }
}

impl CameraSpec {
    /// The camera: at `eye` when given (35 degrees, looking at `target`, default the
    /// solids' centre), else framing `bounds` from `view` for an image of `aspect`; an
    /// orthographic one shows `height`, by default all of `bounds`.
    pub(super) fn camera(&self, bounds: &Aabb, aspect: f64) -> Camera {
        let up = self.up.map_or(DVec3::Z, DVec3::from_array);
        let view = self.view.map_or(DEFAULT_VIEW, DVec3::from_array);
        let mut camera = match self.eye {
            Some(eye) => Camera::look_at(
                DVec3::from_array(eye),
                self.target.map_or(bounds.center(), DVec3::from_array),
                up,
                35.0,
            ),
            None => Camera::frame(bounds, view, up, aspect),
        };
        match self.projection.unwrap_or(ProjectionSpec::Perspective) {
            ProjectionSpec::Perspective => {
                if let Some(fov) = self.fov {
                    camera.projection = Projection::Perspective { fov_y: fov };
                }
            }
            ProjectionSpec::Orthographic => {
                let framed = Camera::frame_orthographic(bounds, view, up);
                let height = self.height.unwrap_or(match framed.projection {
                    Projection::Orthographic { height } => height,
                    Projection::Perspective { .. } => 1.0,
                });
                if self.eye.is_none() {
                    camera = framed;
                }
                camera.projection = Projection::Orthographic { height };
            }
        }
        camera
    }
}
