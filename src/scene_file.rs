//! Scene files (TOML): solids from shape CSG trees, mesh files and `.oct` files, their
//! materials, lights, camera and image settings. The format is described in
//! `docs/SCENES.md`; bundled scenes are in `scenes/`.
//!
//! Errors name the file with the line and column (TOML syntax and field errors) or the
//! solid and what is wrong with it. Relative paths inside a scene are relative to the
//! scene file's folder.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;
use serde::Deserialize;

use crate::budget::MemoryBudget;
use crate::color::{Hsi, cmy_to_rgb, hsi_to_rgb};
use crate::error::{Error, Result};
use crate::import::{self, Fill, Input};
use crate::io::oct;
use crate::mesh::InsideRule;
use crate::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use crate::progress::NoProgress;
use crate::render::scene::{Bump, Mapping, Texture};
use crate::render::{Camera, DEFAULT_VIEW, Light, Material, Projection, RenderOptions, Scene};
use crate::shape::{Axis, Csg, Shape, ShapeSpec};

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
    /// "axis" (default), "smooth" or "octree".
    normals: Option<String>,
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
    /// "perspective" (default) or "orthographic".
    projection: Option<String>,
    /// View height of an orthographic camera.
    height: Option<f64>,
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
    inside: Option<String>,
    #[serde(default)]
    material: MaterialSpec,
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
    Wood { axis: String, center: Option<[f64; 3]>, size: f64, a: ColorSpec, b: ColorSpec },
    Marble { size: f64, a: ColorSpec, b: ColorSpec },
    Image { file: PathBuf, mapping: String, axis: Option<String>, center: Option<[f64; 3]>, scale: Option<f64> },
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
            TextureSpec::Wood { axis: ax, center, size, a, b } => Texture::Wood {
                axis: axis(ax)?,
                center: center.map_or(DVec3::ZERO, DVec3::from_array),
                size: positive("size", *size)?,
                a: a.rgb(),
                b: b.rgb(),
            },
            TextureSpec::Marble { size, a, b } => {
                Texture::Marble { size: positive("size", *size)?, a: a.rgb(), b: b.rgb() }
            }
            TextureSpec::Image { file, mapping, axis: ax, center, scale } => {
                let path = folder.join(file);
                let texels = image::open(&path)
                    .map_err(|e| Error::invalid("texture", format!("{}: {e}", path.display())))?
                    .to_rgb8();
                let axis = axis(ax.as_deref().unwrap_or("z"))?;
                let center = center.map_or(DVec3::ZERO, DVec3::from_array);
                let scale = positive("scale", scale.unwrap_or(1.0))?;
                let mapping = match mapping.as_str() {
                    "planar" => Mapping::Planar { axis, origin: center, scale },
                    "cylindrical" => Mapping::Cylindrical { axis, center, scale },
                    "spherical" => Mapping::Spherical { axis, center },
                    other => {
                        return Err(Error::invalid(
                            "mapping",
                            format!("{other:?} is not planar, cylindrical or spherical"),
                        ));
                    }
                };
                Texture::Image { texels: std::sync::Arc::new(texels), mapping }
            }
        })
    }
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct BumpSpec {
    amplitude: f64,
    scale: f64,
}

fn axis(s: &str) -> Result<Axis> {
    s.parse().map_err(|e: String| Error::invalid("axis", e))
}

/// A scene file, loaded: the scene, its camera and its image settings.
pub struct SceneFile {
    /// The solids, lights and background.
    pub scene: Scene,
    /// The camera (auto-framed when the file gives no eye).
    pub camera: Camera,
    /// Image size and samples.
    pub options: RenderOptions,
}

/// Reads, checks and builds the scene at `path` (voxelizing its shapes and meshes).
pub fn load_scene(path: &Path, budget: MemoryBudget) -> Result<SceneFile> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    let spec: SceneSpec = toml::from_str(&text).map_err(|e| {
        let (line, column) = e.span().map_or((1, 1), |s| line_column(&text, s.start));
        Error::Parse { path: path.to_path_buf(), line, reason: format!("column {column}: {}", e.message().trim()) }
    })?;
    let folder = path.parent().unwrap_or(Path::new("."));
    let at = |what: String| move |e: Error| Error::invalid("scene", format!("{}: {what}: {e}", path.display()));
    build(&spec, folder, budget).map_err(at("cannot build the scene".into()))
}

/// One-based line and column of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rfind('\n').map_or(before.len(), |i| before.len() - i - 1) + 1;
    (line, column)
}

fn build(spec: &SceneSpec, folder: &Path, budget: MemoryBudget) -> Result<SceneFile> {
    if spec.solids.is_empty() {
        return Err(Error::invalid("scene", "it has no [[solid]]"));
    }
    let options = VoxelizeOptions { budget, progress: &NoProgress };
    // Step 1: the shape solids' shared domain: given, or around all shapes.
    let shapes: Vec<Option<Csg>> =
        spec.solids.iter().map(|s| s.shape.as_ref().map(ShapeSpec::build).transpose()).collect::<Result<_>>()?;
    let depth = spec.domain.as_ref().map_or(9, |d| d.depth);
    let shape_domain = match &spec.domain {
        Some(DomainSpec { min: Some(min), edge: Some(edge), depth }) => {
            Some(Domain::new(DVec3::from_array(*min), *edge, *depth)?)
        }
        _ => {
            let bounds =
                shapes.iter().flatten().map(|s| s.bounds()).try_fold(None, |acc: Option<crate::aabb::Aabb>, b| {
                    let b = b.ok_or_else(|| {
                        Error::invalid("shape", "an unbounded shape needs a [domain] with min and edge")
                    })?;
                    Ok::<_, Error>(Some(acc.map_or(b, |a| a.union(&b))))
                })?;
            bounds.map(|b| Domain::around(&b, 0.02, depth)).transpose()?
        }
    };
    // Step 2: every solid to an octree.
    let mut scene = Scene::new();
    for (i, (solid, shape)) in spec.solids.iter().zip(&shapes).enumerate() {
        let name = solid.name.clone().unwrap_or_else(|| format!("solid {}", i + 1));
        let sources =
            usize::from(solid.shape.is_some()) + usize::from(solid.mesh.is_some()) + usize::from(solid.oct.is_some());
        if sources != 1 {
            return Err(Error::invalid("solid", format!("{name}: give exactly one of shape, mesh or oct")));
        }
        let tree: LinearOctree = if let Some(shape) = shape {
            voxelize(shape, shape_domain.expect("shapes have a domain"), &options)?
        } else if let Some(mesh) = &solid.mesh {
            let input = Input::load(&folder.join(mesh))?;
            let depth = solid.depth.unwrap_or(depth);
            let domain = import::default_domain(&input, depth)?;
            let inside: InsideRule =
                solid.inside.as_deref().unwrap_or("auto").parse().map_err(|e: String| Error::invalid("inside", e))?;
            import::voxelize_input(&input, domain, Fill::Solid, inside, budget, &NoProgress)?.0
        } else {
            let file = folder.join(solid.oct.as_ref().expect("one source"));
            oct::load(&file, budget)?
        };
        let d = Material::default();
        let m = &solid.material;
        let material = Material {
            color: m.color.map_or(d.color, ColorSpec::rgb),
            texture: m.texture.as_ref().map(|t| t.build(folder)).transpose()?,
            bump: m.bump.as_ref().map(|b| Bump { amplitude: b.amplitude, scale: b.scale }),
            ka: m.ka.unwrap_or(d.ka),
            kd: m.kd.unwrap_or(d.kd),
            ks: m.ks.unwrap_or(d.ks),
            shininess: m.shininess.unwrap_or(d.shininess),
            reflectance: m.reflectance.unwrap_or(d.reflectance),
            transmittance: m.transmittance.unwrap_or(d.transmittance),
            ior: m.ior.unwrap_or(d.ior),
        };
        material.check().map_err(|e| Error::invalid("material", format!("{name}: {e}")))?;
        match shape {
            Some(shape) => scene.add_shaped(name, tree, material, Arc::new(shape.clone())),
            None => scene.add(name, tree, material),
        }
    }
    // Step 3: lights, camera, image.
    let bounds = scene.bounds().ok_or_else(|| Error::invalid("scene", "every solid is empty"))?;
    scene.lights = spec
        .lights
        .iter()
        .map(|l| match *l {
            LightSpec::Point { position, color } => Light::Point {
                position: DVec3::from_array(position),
                color: color.map_or(DVec3::ONE, DVec3::from_array),
            },
            LightSpec::Directional { direction, color } => Light::Directional {
                direction: DVec3::from_array(direction),
                color: color.map_or(DVec3::ONE, DVec3::from_array),
            },
        })
        .collect();
    if scene.lights.is_empty() {
        scene.lights = Scene::default_lights(&bounds);
    }
    if let Some(a) = spec.ambient {
        scene.ambient = DVec3::from_array(a);
    }
    if let Some(b) = spec.image.background {
        scene.background = DVec3::from_array(b);
    }
    let [width, height] = spec.image.size;
    let d = RenderOptions::default();
    let render = RenderOptions {
        width,
        height,
        spp: spec.image.samples,
        shadows: spec.image.shadows,
        normals: spec
            .image
            .normals
            .as_deref()
            .map_or(Ok(d.normals), str::parse)
            .map_err(|e| Error::invalid("normals", e))?,
        max_depth: spec.image.max_depth.unwrap_or(d.max_depth),
        ..d
    };
    let aspect = f64::from(width.max(1)) / f64::from(height.max(1));
    let c = &spec.camera;
    let up = c.up.map_or(DVec3::Z, DVec3::from_array);
    let view = c.view.map_or(DEFAULT_VIEW, DVec3::from_array);
    let mut camera = match c.eye {
        Some(eye) => {
            Camera::look_at(DVec3::from_array(eye), c.target.map_or(bounds.center(), DVec3::from_array), up, 35.0)
        }
        None => Camera::frame(&bounds, view, up, aspect),
    };
    match c.projection.as_deref() {
        None | Some("perspective") => {
            if let Some(fov) = c.fov {
                camera.projection = Projection::Perspective { fov_y: fov };
            }
        }
        Some("orthographic") => {
            let framed = Camera::frame_orthographic(&bounds, view, up);
            let height = c.height.unwrap_or(match framed.projection {
                Projection::Orthographic { height } => height,
                Projection::Perspective { .. } => 1.0,
            });
            if c.eye.is_none() {
                camera = framed;
            }
            camera.projection = Projection::Orthographic { height };
        }
        Some(other) => {
            return Err(Error::invalid("projection", format!("'{other}' (use perspective or orthographic)")));
        }
    }
    Ok(SceneFile { scene, camera, options: render })
}
