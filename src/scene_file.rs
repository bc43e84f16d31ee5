//! Scene files (TOML): solids from shape CSG trees, mesh files and `.oct` files, their
//! materials, lights, camera and image settings. The format is described in
//! `docs/SCENES.md`; bundled scenes are in `scenes/`.
//!
//! Loading is two steps. Parsing deserializes the whole file into the private `*Spec`
//! types; every enum-like value is a serde enum (shape and texture kinds
//! ([`ShapeSpec`]), light `type`, `normals`, `projection`, `inside`, `mapping`, `axis`),
//! so a misspelt value is reported like a misspelt key or a syntax error: an
//! [`Error::Parse`] with the file, the line and the column. Building then voxelizes the
//! solids and sets up lights, image and camera; what fails there is an
//! [`Error::Scene`] holding its cause as it was (the I/O, format or over-budget error of
//! a mesh or `.oct` file the scene names, a refused value), with the scene file and the
//! name of the solid it concerns.
//!
//! Relative paths inside a scene are relative to the scene file's folder.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;
use serde::Deserialize;

use crate::aabb::Aabb;
use crate::budget::MemoryBudget;
use crate::color::{Hsi, cmy_to_rgb, hsi_to_rgb};
use crate::error::{Error, Result};
use crate::import::{self, ImportOptions, Input};
use crate::io::oct;
use crate::mesh::InsideRule;
use crate::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use crate::progress::NoProgress;
use crate::render::{
    Bump, Camera, DEFAULT_VIEW, Light, Mapping, Material, Normals, Projection, RenderOptions, Scene, Texture,
};
use crate::shape::{Axis, Csg, Shape, ShapeSpec};
use crate::warning::Warning;

/// The whole file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SceneSpec {
    #[serde(default)]
    image: ImageSpec,
    #[serde(default)]
    camera: CameraSpec,
    domain: Option<DomainSpec>,
    #[serde(default, rename = "light")]
    lights: Vec<LightSpec>,
    #[serde(rename = "solid")]
    solids: Vec<SolidSpec>,
    ambient: Option<[f64; 3]>,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct ImageSpec {
    #[serde(default = "default_size")]
    size: [u32; 2],
    #[serde(default = "default_samples")]
    samples: u32,
    #[serde(default = "default_true")]
    shadows: bool,
    background: Option<[f64; 3]>,
    /// Axis (the default), smooth or octree.
    normals: Option<Normals>,
    /// Longest chain of reflected and refracted rays.
    max_depth: Option<u32>,
}

fn default_size() -> [u32; 2] {
    [960, 720]
}
fn default_samples() -> u32 {
    2
}
fn default_true() -> bool {
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
        }
    }
}

#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
struct CameraSpec {
    eye: Option<[f64; 3]>,
    target: Option<[f64; 3]>,
    /// Direction from the target to the eye when the eye is not given (auto-framing).
    view: Option<[f64; 3]>,
    up: Option<[f64; 3]>,
    fov: Option<f64>,
    /// Perspective (the default) or orthographic.
    projection: Option<ProjectionSpec>,
    /// View height of an orthographic camera.
    height: Option<f64>,
}

/// How the camera projects; the field of view and the view height are keys of their own.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
enum ProjectionSpec {
    Perspective,
    Orthographic,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct DomainSpec {
    min: Option<[f64; 3]>,
    edge: Option<f64>,
    depth: u8,
}

#[derive(Deserialize, Debug)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
enum LightSpec {
    Point { position: [f64; 3], color: Option<[f64; 3]> },
    Directional { direction: [f64; 3], color: Option<[f64; 3]> },
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SolidSpec {
    name: Option<String>,
    shape: Option<ShapeSpec>,
    mesh: Option<PathBuf>,
    oct: Option<PathBuf>,
    /// Depth for a mesh (default: the scene domain's).
    depth: Option<u8>,
    /// How a mesh decides its inside (default auto).
    inside: Option<InsideSpec>,
    #[serde(default)]
    material: MaterialSpec,
}

/// [`InsideRule`] as a scene writes it.
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum InsideSpec {
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
struct MaterialSpec {
    color: Option<ColorSpec>,
    ka: Option<f64>,
    kd: Option<f64>,
    ks: Option<f64>,
    shininess: Option<f64>,
    reflectance: Option<f64>,
    transmittance: Option<f64>,
    ior: Option<f64>,
    texture: Option<TextureSpec>,
    bump: Option<BumpSpec>,
}

/// A colour: `[r, g, b]`, or one of `{ rgb = [..] }`, `{ cmy = [..] }`, `{ hsi = [h, s, i] }`.
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(untagged)]
enum ColorSpec {
    Rgb([f64; 3]),
    Model(ColorModelSpec),
}

#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum ColorModelSpec {
    Rgb([f64; 3]),
    Cmy([f64; 3]),
    Hsi([f64; 3]),
}

impl ColorSpec {
    /// Linear RGB.
    fn rgb(self) -> DVec3 {
        match self {
            ColorSpec::Rgb(c) | ColorSpec::Model(ColorModelSpec::Rgb(c)) => DVec3::from_array(c),
            ColorSpec::Model(ColorModelSpec::Cmy(c)) => cmy_to_rgb(DVec3::from_array(c)),
            ColorSpec::Model(ColorModelSpec::Hsi([h, s, i])) => hsi_to_rgb(Hsi { h, s, i }),
        }
    }
}

#[derive(Deserialize, Debug)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
enum TextureSpec {
    Checker { size: f64, a: ColorSpec, b: ColorSpec },
    Wood { axis: Axis, center: Option<[f64; 3]>, size: f64, a: ColorSpec, b: ColorSpec },
    Marble { size: f64, a: ColorSpec, b: ColorSpec },
    Image { file: PathBuf, mapping: MappingSpec, axis: Option<Axis>, center: Option<[f64; 3]>, scale: Option<f64> },
}

/// The projection of an image texture ([`Mapping`] without its parameters).
#[derive(Deserialize, Debug, Clone, Copy)]
#[serde(rename_all = "snake_case")]
enum MappingSpec {
    Planar,
    Cylindrical,
    Spherical,
}

impl TextureSpec {
    fn build(&self, folder: &Path) -> Result<Texture> {
        let positive = |what: &'static str, v: f64| {
            if v.is_finite() && v > 0.0 { Ok(v) } else { Err(Error::invalid(what, format!("{v} must be positive"))) }
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
                let texels = load_texels(&path)?;
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
fn load_texels(path: &Path) -> Result<image::RgbImage> {
    match image::open(path) {
        Ok(img) => Ok(img.to_rgb8()),
        Err(image::ImageError::IoError(source)) => Err(Error::Io { path: path.to_path_buf(), source }),
        Err(e) => Err(Error::invalid("texture", format!("{}: {e}", path.display()))),
    }
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct BumpSpec {
    amplitude: f64,
    scale: f64,
}

/// A scene file, loaded: the scene, its camera and its image settings.
pub struct SceneFile {
    /// The solids, lights and background.
    pub scene: Scene,
    /// The camera (auto-framed when the file gives no eye).
    pub camera: Camera,
    /// Image size and samples.
    pub options: RenderOptions,
    /// What the loaders of its mesh files read past, file by file.
    pub warnings: Vec<Warning>,
}

/// Reads, checks and builds the scene at `path` (voxelizing its shapes and meshes).
/// Errors: [`Error::Io`] when the file cannot be read, [`Error::Parse`] (with the line
/// and column) when it is not a scene, [`Error::Scene`] when the scene cannot be built.
pub fn load_scene(path: impl AsRef<Path>, budget: MemoryBudget) -> Result<SceneFile> {
    let path = path.as_ref();
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    let spec: SceneSpec = toml::from_str(&text).map_err(|e| {
        let (line, column) = e.span().map_or((1, 1), |s| line_column(&text, s.start));
        Error::Parse { path: path.to_path_buf(), line, reason: format!("column {column}: {}", e.message().trim()) }
    })?;
    let folder = path.parent().unwrap_or(Path::new("."));
    build(&spec, &Context { path, folder, budget })
}

/// One-based line and column of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rfind('\n').map_or(before.len(), |i| before.len() - i - 1) + 1;
    (line, column)
}

/// What building a scene needs besides its spec.
struct Context<'a> {
    /// The scene file, for errors.
    path: &'a Path,
    /// The folder its relative paths start from.
    folder: &'a Path,
    /// Every voxelization and load is checked against it.
    budget: MemoryBudget,
}

impl Context<'_> {
    /// `source` as an error of this scene, about the solid `solid` if it concerns one.
    fn error(&self, solid: Option<&str>, source: Error) -> Error {
        Error::Scene { path: self.path.to_path_buf(), solid: solid.map(str::to_owned), source: Box::new(source) }
    }
}

/// The scene, its camera and image settings from the parsed file.
fn build(spec: &SceneSpec, cx: &Context) -> Result<SceneFile> {
    let whole = |e| cx.error(None, e);
    if spec.solids.is_empty() {
        return Err(whole(Error::invalid("scene", "it has no [[solid]]")));
    }
    let names: Vec<String> = spec
        .solids
        .iter()
        .enumerate()
        .map(|(i, s)| s.name.clone().unwrap_or_else(|| format!("solid {}", i + 1)))
        .collect();
    // Step 1: every solid's shape tree, and the shape solids' shared domain.
    let shapes: Vec<Option<Csg>> = spec
        .solids
        .iter()
        .zip(&names)
        .map(|(s, name)| s.shape.as_ref().map(ShapeSpec::build).transpose().map_err(|e| cx.error(Some(name), e)))
        .collect::<Result<_>>()?;
    let depth = spec.domain.as_ref().map_or(9, |d| d.depth);
    let domain = shape_domain(spec.domain.as_ref(), depth, &names, &shapes, cx)?;
    // Step 2: every solid to an octree, with its material.
    let mut scene = Scene::new();
    let mut warnings = Vec::new();
    for ((solid, shape), name) in spec.solids.iter().zip(&shapes).zip(&names) {
        let source = SolidSource { shape: shape.as_ref(), shape_domain: domain, depth };
        warnings.extend(add_solid(&mut scene, solid, name, &source, cx).map_err(|e| cx.error(Some(name), e))?);
    }
    // Step 3: lights, image and camera, from the solids' bounds.
    let bounds = scene.bounds().ok_or_else(|| whole(Error::invalid("scene", "every solid is empty")))?;
    scene.lights = spec.lights.iter().map(LightSpec::light).collect();
    if scene.lights.is_empty() {
        scene.lights = Scene::default_lights(&bounds);
    }
    if let Some(a) = spec.ambient {
        scene.ambient = DVec3::from_array(a);
    }
    if let Some(b) = spec.image.background {
        scene.background = DVec3::from_array(b);
    }
    let options = spec.image.options();
    let aspect = f64::from(options.width.max(1)) / f64::from(options.height.max(1));
    Ok(SceneFile { scene, camera: spec.camera.camera(&bounds, aspect), options, warnings })
}

/// The domain every `shape` solid is voxelized in: the `[domain]`'s when it gives `min`
/// and `edge`, else the cube around all shapes with a 2% margin at `depth`; `None`
/// when no solid is a shape. An unbounded shape needs the former.
fn shape_domain(
    spec: Option<&DomainSpec>,
    depth: u8,
    names: &[String],
    shapes: &[Option<Csg>],
    cx: &Context,
) -> Result<Option<Domain>> {
    if let Some(DomainSpec { min: Some(min), edge: Some(edge), depth }) = spec {
        return Domain::new(DVec3::from_array(*min), *edge, *depth).map(Some).map_err(|e| cx.error(None, e));
    }
    let mut bounds: Option<Aabb> = None;
    for (shape, name) in shapes.iter().zip(names) {
        let Some(shape) = shape else { continue };
        let b = shape.bounds().ok_or_else(|| {
            cx.error(Some(name), Error::invalid("shape", "an unbounded shape needs a [domain] with min and edge"))
        })?;
        bounds = Some(bounds.map_or(b, |a| a.union(&b)));
    }
    bounds.map(|b| Domain::around(&b, 0.02, depth)).transpose().map_err(|e| cx.error(None, e))
}

/// Where a solid's octree comes from, besides its own keys.
struct SolidSource<'a> {
    /// Its shape's tree, for a `shape` solid.
    shape: Option<&'a Csg>,
    /// The domain shape solids share (`Some` when any solid is a shape).
    shape_domain: Option<Domain>,
    /// The depth a mesh is voxelized at without a `depth` of its own.
    depth: u8,
}

/// Voxelizes or loads `solid` and adds it to `scene` under `name` with its material;
/// returns the warnings of loading its mesh.
fn add_solid(
    scene: &mut Scene,
    solid: &SolidSpec,
    name: &str,
    source: &SolidSource,
    cx: &Context,
) -> Result<Vec<Warning>> {
    let mut warnings = Vec::new();
    let sources =
        usize::from(solid.shape.is_some()) + usize::from(solid.mesh.is_some()) + usize::from(solid.oct.is_some());
    if sources != 1 {
        return Err(Error::invalid("solid", "give exactly one of shape, mesh or oct"));
    }
    let tree: LinearOctree = if let Some(shape) = source.shape {
        let options = VoxelizeOptions { budget: cx.budget, progress: &NoProgress };
        voxelize(shape, source.shape_domain.expect("shapes have a domain"), &options)?
    } else if let Some(mesh) = &solid.mesh {
        let input;
        (input, warnings) = Input::load_with_warnings(cx.folder.join(mesh))?;
        let domain = import::default_domain(&input, solid.depth.unwrap_or(source.depth))?;
        let inside = solid.inside.map_or(InsideRule::Auto, InsideRule::from);
        import::voxelize_input(&input, domain, &ImportOptions { inside, budget: cx.budget, ..Default::default() })?.0
    } else {
        oct::load(cx.folder.join(solid.oct.as_ref().expect("one source")), cx.budget)?
    };
    let material = solid.material.material(cx.folder)?;
    material.check()?;
    match source.shape {
        Some(shape) => scene.add_shaped(name, tree, material, Arc::new(shape.clone())),
        None => scene.add(name, tree, material),
    }
    Ok(warnings)
}

impl MaterialSpec {
    /// The material, every coefficient not given the default's.
    fn material(&self, folder: &Path) -> Result<Material> {
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
        })
    }
}

impl LightSpec {
    /// The light; white without a colour.
    fn light(&self) -> Light {
        match *self {
            LightSpec::Point { position, color } => Light::Point {
                position: DVec3::from_array(position),
                color: color.map_or(DVec3::ONE, DVec3::from_array),
            },
            LightSpec::Directional { direction, color } => Light::Directional {
                direction: DVec3::from_array(direction),
                color: color.map_or(DVec3::ONE, DVec3::from_array),
            },
        }
    }
}

impl ImageSpec {
    /// The render options, every one not given the default's.
    fn options(&self) -> RenderOptions {
        let [width, height] = self.size;
        let d = RenderOptions::default();
        RenderOptions {
            width,
            height,
            spp: self.samples,
            shadows: self.shadows,
            normals: self.normals.unwrap_or(d.normals),
            max_depth: self.max_depth.unwrap_or(d.max_depth),
            ..d
        }
    }
}

impl CameraSpec {
    /// The camera: at `eye` when given (35 degrees, looking at `target`, default the
    /// solids' centre), else framing `bounds` from `view` for an image of `aspect`; an
    /// orthographic one shows `height`, by default all of `bounds`.
    fn camera(&self, bounds: &Aabb, aspect: f64) -> Camera {
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
