//! Scene files (TOML): solids from shape CSG trees, mesh files and solid files (`.oct`,
//! `.octs`, `.vox`, `.binvox`, `.vdb` through [`crate::SolidFile::read`]), their
//! materials, lights, camera and image settings. The format is described in
//! `docs/SCENES.md`; bundled scenes are in `scenes/`.
//!
//! Loading is two steps. Reading deserializes the whole file into the private `*Spec`
//! types and checks every value where it is read: enum-like values are serde enums
//! (shape and texture kinds, light `type`, `normals`, `projection`, `inside`,
//! `mapping`, `axis`), shape nodes are built as they are read ([`ShapeSpec`]'s
//! deserializer), colours are checked in form and range ([`ColorSpec`]). So a
//! misspelt key or value, a negative radius or a colour out of range is refused by the
//! reader, an [`Error::Scene`] around [`Error::Toml`] with the place of the value (the
//! reader's span as line and column) and, when it lies in a `[[solid]]`, that solid's
//! name (found from the spans of the parsed document: the solid whose header, keys and
//! values hold the place). Building then voxelizes the solids and sets up lights,
//! image and camera; what fails there is an [`Error::Scene`] holding its cause as it
//! was (the I/O, format or over-budget error of a mesh or `.oct` file the scene names,
//! a mesh shape that is not closed, a refused material), with the place of the key it
//! concerns (`shape`, `mesh`, `oct`, `transform`, `material`, else the `[[solid]]`
//! header) and the solid's name.
//!
//! Solids, and where their octrees come from:
//! - `shape`: a CSG tree ([`ShapeSpec`]) whose leaves may also be `{ mesh = "..." }`
//!   (a closed mesh, as a [`MeshShape`]) and `{ oct = "..." }` (a stored octree, as an
//!   [`OctreeShape`]: nearest sampling through the tree's transforms; any solid file,
//!   see `oct` below). The whole tree,
//!   moved by the solid's `transform`, is one [`Shape`], voxelized once into the
//!   domain every `shape` solid shares. By the soundness contract of [`Shape`] this is
//!   exactly the octree CSG of the leaves voxelized into that domain, an `.oct` leaf
//!   being its octree resampled into it: exact when the domain's lattice is the `.oct`
//!   file's moved by whole voxels (the same `[domain]`, say), sampled otherwise. One
//!   tree of shapes is the simplest design that is correct for any nesting of the three
//!   kinds (no per-node domains, no conversions); the cost is that a mesh or `.oct`
//!   leaf is asked point by point (no state handed down the tree).
//! - `mesh`: the mesh file voxelized alone in its own bounding cube at its `depth`,
//!   with its `inside` rule (meshes need not be closed here); a `transform` moves the
//!   vertices (or patch control points) first, so it is exact.
//! - `oct`: the stored octree of a solid file, `.oct`, a sharded `.octs` (whole, within
//!   the budget), `.vox`, `.binvox` or `.vdb` by extension (a file of several solids, such as a `.vox` file's palette colours, is
//!   their union, in the solid's material; a `.vdb` fog volume is read at the default
//!   threshold, 0.5); a `transform` moves it by
//!   [`LinearOctree::transformed`]: exactly (the keys permuted and mirrored, the domain
//!   moved) for translations, uniform scales, quarter turns and mirrors, resampled at
//!   the same depth otherwise.
//!
//! Relative paths inside a scene are relative to the scene file's folder.
//!
//! Caching ([`load_scene_with`] and [`LoadOptions::cache`]): the octrees of `shape` and
//! `mesh` solids and of moved `oct` solids can be read from and stored in the scene's
//! solid cache ([`CACHE_DIR`] beside the scene; its layout and keys in `docs/FORMAT.md`), keyed
//! by everything that decides them, so loading an unchanged scene again voxelizes
//! nothing. [`load_scene`] leaves the cache alone. A mesh solid read from the cache
//! does not read its mesh, so the mesh's warnings come with the load that voxelized it.

use std::cell::RefCell;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DAffine3, DVec3};
use serde::Deserialize;
use toml::Spanned;

use crate::aabb::Aabb;
use crate::budget::MemoryBudget;
use crate::color::ColorSpec;
use crate::error::{Error, Result, printable, quoted};
use crate::import::{self, ImportOptions, Input};
use crate::io::ReadOptions;
use crate::mesh::{InsideRule, MeshShape, load_mesh};
use crate::octree::{Domain, LinearOctree, OctreeShape, VoxelizeOptions, voxelize};
use crate::progress::NoProgress;
use crate::render::{
    AntiAliasingKind, Bump, Camera, DEFAULT_VIEW, Light, Mapping, Material, Normals, Projection, RenderOptions,
    RenderOverrides, Scene, Texture,
};
use crate::shape::{Axis, Csg, FileLeaves, Shape, ShapeSpec, TransformSpec, Transformed};
use crate::solid_file::SolidFile;
use crate::warning::Warning;

mod cache;

pub use cache::{CACHE_DIR, CachePolicy, CacheReport, clear_cache};
use cache::{SceneCache, SolidKey};

/// The whole file.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SceneSpec {
    #[serde(default)]
    image: ImageSpec,
    #[serde(default)]
    camera: CameraSpec,
    domain: Option<Spanned<DomainSpec>>,
    #[serde(default, rename = "light")]
    lights: Vec<Spanned<LightSpec>>,
    #[serde(rename = "solid")]
    solids: Vec<Spanned<SolidSpec>>,
    ambient: Option<ColorSpec>,
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
    background: Option<ColorSpec>,
    /// Axis (the default), smooth or octree.
    normals: Option<Normals>,
    /// Longest chain of reflected and refracted rays.
    max_depth: Option<u32>,
    /// Share of a pixel below which a secondary ray is not traced.
    cutoff: Option<f64>,
    /// Uniform (the default), adaptive or recursive anti-aliasing.
    aa: Option<AntiAliasingKind>,
    /// Contrast at which adaptive anti-aliasing supersamples, recursive splits
    /// (implies adaptive when `aa` is not given).
    aa_threshold: Option<f64>,
    /// Most splits of a pixel's square by recursive anti-aliasing (implies recursive
    /// when `aa` is not given).
    aa_depth: Option<u32>,
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
            cutoff: None,
            aa: None,
            aa_threshold: None,
            aa_depth: None,
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
    /// Default 9; with `voxel_size`, the least that holds the shapes.
    depth: Option<u8>,
    /// A voxel's edge instead of `min` and `edge` (`Domain::on_grid`).
    voxel_size: Option<f64>,
}

/// The depth of a scene without `[domain] depth`.
const DEFAULT_DEPTH: u8 = 9;

/// A light: a struct with its `type` rather than an internally tagged enum, which
/// serde reads from a buffered copy without the reader's spans; whether `position` or
/// `direction` is given is checked when it is built, at the light's header.
#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct LightSpec {
    #[serde(rename = "type")]
    kind: LightKind,
    position: Option<[f64; 3]>,
    direction: Option<[f64; 3]>,
    color: Option<ColorSpec>,
}

/// The kinds of light.
#[derive(Deserialize, Debug, Clone, Copy, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
enum LightKind {
    Point,
    Directional,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct SolidSpec {
    name: Option<String>,
    shape: Option<Spanned<ShapeSpec>>,
    mesh: Option<Spanned<PathBuf>>,
    oct: Option<Spanned<PathBuf>>,
    /// Moves the solid: scale, rotate, translate (as a shape's `transform`).
    transform: Option<Spanned<TransformSpec>>,
    /// Depth for a mesh (default: the scene domain's).
    depth: Option<u8>,
    /// How a mesh decides its inside (default auto).
    inside: Option<InsideSpec>,
    material: Option<Spanned<MaterialSpec>>,
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
    emission: Option<[f64; 3]>,
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
    /// What loading its meshes read past without refusing them, and cache entries
    /// that could not be used or written.
    pub warnings: Vec<Warning>,
    /// What the solid cache did (all zero under [`CachePolicy::Off`]).
    pub cache: CacheReport,
}

/// How [`load_scene_with`] loads a scene.
#[derive(Clone, Copy, Debug, Default)]
pub struct LoadOptions {
    /// Every voxelization and load is checked against it.
    pub budget: MemoryBudget,
    /// Whether solids are read from and stored in the scene's solid cache.
    pub cache: CachePolicy,
}

/// Reads, checks and builds the scene at `path` (voxelizing its shapes and meshes).
/// Errors: [`Error::Io`] when the file cannot be read; else an [`Error::Scene`] with
/// the place (see the module doc): around [`Error::Toml`] when the reader refuses the
/// text (syntax, an unknown key or value, a value out of range), around the cause when
/// the scene cannot be built.
pub fn load_scene(path: impl AsRef<Path>, budget: MemoryBudget) -> Result<SceneFile> {
    load_scene_with(path, &LoadOptions { budget, cache: CachePolicy::Off })
}

/// [`load_scene`] with the solid cache of `options` (see the module doc): under
/// [`CachePolicy::ReadWrite`] a solid whose inputs are unchanged since it was stored
/// is read, not built, and the others are built and stored. The cache never turns a
/// load into an error: an entry that cannot be used or written is a warning and the
/// solid is built.
pub fn load_scene_with(path: impl AsRef<Path>, options: &LoadOptions) -> Result<SceneFile> {
    read_scene(path.as_ref(), options.budget, options.cache, build)
}

/// Reads and checks the scene at `path` (its errors as [`load_scene`]'s) and voxelizes
/// one solid without rendering: the `[[solid]]` named `solid`, else the union of the
/// scene's `shape` solids (one CSG tree, voxelized in one pass into the shapes' shared
/// domain, exactly the union of their octrees there). A named `mesh` or `oct` solid
/// comes in its own domain, as [`load_scene`] makes it. Progress goes to
/// `options.progress` and every voxelization is checked against `options.budget`.
pub fn build_solid(path: impl AsRef<Path>, solid: Option<&str>, options: &VoxelizeOptions) -> Result<LinearOctree> {
    read_scene(path.as_ref(), options.budget, CachePolicy::Off, |spec, cx| solid_octree(spec, cx, solid, options))
}

/// The shape and domain [`build_solid`] would voxelize, without voxelizing: for
/// streaming the solid out cell by cell (`crate::sharded`). Refuses a named solid
/// that is a `mesh` or an `oct` (those are voxelized or read whole).
pub fn build_shape(path: impl AsRef<Path>, solid: Option<&str>, budget: MemoryBudget) -> Result<(Csg, Domain)> {
    read_scene(path.as_ref(), budget, CachePolicy::Off, |spec, cx| {
        let whole = |e| cx.error(None, None, e);
        let solids = solid_builds(spec, cx)?;
        let shapes: Vec<Option<Csg>> = solids.iter().map(|s| Ok(s.shape()?.0)).collect::<Result<_>>()?;
        let depth = spec.domain.as_ref().and_then(|d| d.get_ref().depth).unwrap_or(DEFAULT_DEPTH);
        let domain = shape_domain(spec.domain.as_ref(), depth, &solids, &shapes, cx)?;
        let shape = match solid {
            None => shapes.iter().flatten().cloned().reduce(|a, b| a | b),
            Some(name) => shapes[named(&solids, name, cx)?].clone(),
        };
        let shape = shape.ok_or_else(|| {
            whole(Error::invalid("solid", "it is no shape solid (only shape solids stream cell by cell)"))
        })?;
        Ok((shape, domain.expect("shapes have a domain")))
    })
}

/// Reads the scene at `path` with the solid cache `cache`, checks its text, and hands
/// the spec to `then`.
fn read_scene<T>(
    path: &Path,
    budget: MemoryBudget,
    cache: CachePolicy,
    then: impl FnOnce(&SceneSpec, &Context) -> Result<T>,
) -> Result<T> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    let folder = path.parent().unwrap_or(Path::new("."));
    let cache = RefCell::new(SceneCache::new(path, cache));
    let cx = Context { path, text: &text, folder, budget, cache };
    let spec: SceneSpec = toml::from_str(&text).map_err(|e| cx.refused(&e))?;
    if let Some((span, key, literal)) = first_non_finite(&text) {
        let solid = solid_at(&text, span.start);
        let reason = format!("{key} = {literal} is not a finite number");
        return Err(cx.error(solid.as_deref(), Some(&span), Error::Toml { reason }));
    }
    then(&spec, &cx)
}

/// The solid [`build_solid`] makes from the parsed file.
fn solid_octree(spec: &SceneSpec, cx: &Context, name: Option<&str>, options: &VoxelizeOptions) -> Result<LinearOctree> {
    let whole = |e| cx.error(None, None, e);
    let solids = solid_builds(spec, cx)?;
    let shapes: Vec<Option<Csg>> = solids.iter().map(|s| Ok(s.shape()?.0)).collect::<Result<_>>()?;
    let depth = spec.domain.as_ref().and_then(|d| d.get_ref().depth).unwrap_or(DEFAULT_DEPTH);
    let domain = shape_domain(spec.domain.as_ref(), depth, &solids, &shapes, cx)?;
    let Some(name) = name else {
        let union = shapes.iter().flatten().cloned().reduce(|a, b| a | b);
        let union =
            union.ok_or_else(|| whole(Error::invalid("scene", "it has no shape solid; name the solid to build")))?;
        return voxelize(&union, domain.expect("shapes have a domain"), options).map_err(whole);
    };
    let i = named(&solids, name, cx)?;
    Ok(solids[i].octree(shapes[i].as_ref(), domain, depth, options)?.0)
}

/// The position of the solid named `name`; fails listing the names there are.
fn named(solids: &[SolidBuild], name: &str, cx: &Context) -> Result<usize> {
    solids.iter().position(|s| s.name == name).ok_or_else(|| {
        let names: Vec<String> = solids.iter().map(|s| printable(&s.name).into_owned()).collect();
        let reason = format!("no solid is named {} (its solids: {})", quoted(name.as_bytes()), names.join(", "));
        cx.error(None, None, Error::invalid("solid", reason))
    })
}

/// The scene's solids to build, named (`solid N` when the file gives no name); fails
/// when there is none.
fn solid_builds<'a>(spec: &'a SceneSpec, cx: &'a Context) -> Result<Vec<SolidBuild<'a>>> {
    if spec.solids.is_empty() {
        return Err(cx.error(None, None, Error::invalid("scene", "it has no [[solid]]")));
    }
    Ok(spec
        .solids
        .iter()
        .enumerate()
        .map(|(i, s)| SolidBuild {
            spec: s.get_ref(),
            name: s.get_ref().name.clone().unwrap_or_else(|| format!("solid {}", i + 1)),
            header: s.span(),
            cx,
        })
        .collect())
}

/// The first float of the TOML `text` that is not finite (`nan`, `inf`, or a literal
/// past `f64`'s range such as `1e400`): its span, dotted key and literal. Every float
/// of a scene is a coordinate, size, angle or coefficient, none of which may be
/// infinite, so the whole document is checked once here rather than field by field.
fn first_non_finite(text: &str) -> Option<(Range<usize>, String, String)> {
    use toml::de::{DeTable, DeValue};
    fn walk(value: &toml::Spanned<DeValue>, key: &str) -> Option<(Range<usize>, String, String)> {
        match value.get_ref() {
            DeValue::Float(f) => {
                let literal = f.as_str();
                let finite = literal.replace('_', "").parse::<f64>().is_ok_and(f64::is_finite);
                (!finite).then(|| (value.span(), key.to_owned(), literal.to_owned()))
            }
            DeValue::Array(items) => items.iter().enumerate().find_map(|(i, item)| walk(item, &format!("{key}[{i}]"))),
            DeValue::Table(table) => table.iter().find_map(|(k, v)| {
                let name = if key.is_empty() { k.get_ref().to_string() } else { format!("{key}.{}", k.get_ref()) };
                walk(v, &name)
            }),
            _ => None,
        }
    }
    let doc = DeTable::parse(text).ok()?;
    doc.get_ref().iter().find_map(|(k, v)| walk(v, k.get_ref()))
}

/// One-based line and column (in bytes) of byte `offset` in `text`.
fn line_column(text: &str, offset: usize) -> (usize, usize) {
    let before = &text.as_bytes()[..offset.min(text.len())];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = before.iter().rposition(|&b| b == b'\n').map_or(before.len(), |i| before.len() - i - 1) + 1;
    (line, column)
}

/// The name of the `[[solid]]` whose header, keys or values hold byte `offset` of
/// `text` (its `name`, else `solid N`); `None` when the place lies in no solid or
/// `text` is not TOML.
fn solid_at(text: &str, offset: usize) -> Option<String> {
    use toml::de::{DeTable, DeValue};
    let doc = DeTable::parse(text).ok()?;
    let DeValue::Array(solids) = doc.get_ref().get("solid")?.get_ref() else { return None };
    solids.iter().enumerate().find_map(|(i, solid)| {
        let mut region = solid.span();
        let mut name = None;
        if let DeValue::Table(table) = solid.get_ref() {
            for (key, value) in table.iter() {
                region = region.start.min(key.span().start)..region.end.max(value.span().end);
            }
            name = table.get("name").and_then(|v| v.get_ref().as_str()).map(str::to_owned);
        }
        region.contains(&offset).then(|| name.unwrap_or_else(|| format!("solid {}", i + 1)))
    })
}

/// What building a scene needs besides its spec.
struct Context<'a> {
    /// The scene file, for errors.
    path: &'a Path,
    /// Its text, for the line and column of a span.
    text: &'a str,
    /// The folder its relative paths start from.
    folder: &'a Path,
    /// Every voxelization and load is checked against it.
    budget: MemoryBudget,
    /// The solid cache, when the load uses one.
    cache: RefCell<Option<SceneCache>>,
}

impl Context<'_> {
    /// `source` as an error of this scene at the start of the byte range `span` when
    /// given, about the solid `solid` if it concerns one.
    fn error(&self, solid: Option<&str>, span: Option<&Range<usize>>, source: Error) -> Error {
        Error::Scene {
            path: self.path.to_path_buf(),
            place: span.map(|s| line_column(self.text, s.start)),
            solid: solid.map(str::to_owned),
            source: Box::new(source),
        }
    }

    /// The reader's refusal `e`, at its place, naming the solid that place lies in.
    fn refused(&self, e: &toml::de::Error) -> Error {
        let span = e.span();
        let solid = span.as_ref().and_then(|s| solid_at(self.text, s.start));
        self.error(solid.as_deref(), span.as_ref(), Error::Toml { reason: printable(e.message().trim()).into_owned() })
    }
}

/// The scene, its camera and image settings from the parsed file.
fn build(spec: &SceneSpec, cx: &Context) -> Result<SceneFile> {
    let whole = |e| cx.error(None, None, e);
    let solids = solid_builds(spec, cx)?;
    // Step 1: the lights (checked before any work), every shape solid's tree (moved by
    // its transform), and the shape solids' shared domain.
    let lights: Vec<Light> = spec
        .lights
        .iter()
        .map(|l| l.get_ref().light().map_err(|e| cx.error(None, Some(&l.span()), e)))
        .collect::<Result<_>>()?;
    let (shapes, leaf_files): (Vec<Option<Csg>>, Vec<Vec<PathBuf>>) =
        solids.iter().map(SolidBuild::shape).collect::<Result<Vec<_>>>()?.into_iter().unzip();
    let depth = spec.domain.as_ref().and_then(|d| d.get_ref().depth).unwrap_or(DEFAULT_DEPTH);
    let domain = shape_domain(spec.domain.as_ref(), depth, &solids, &shapes, cx)?;
    // Step 2: every solid to an octree (from the cache when it holds it), with its
    // material.
    let mut scene = Scene::new();
    let mut warnings = Vec::new();
    for ((solid, shape), files) in solids.iter().zip(&shapes).zip(&leaf_files) {
        warnings.extend(solid.add_to(&mut scene, shape.as_ref().map(|s| (s, &files[..])), domain, depth)?);
    }
    let cache = cx.cache.take().map(SceneCache::finish).unwrap_or_default();
    // Step 3: lights, image and camera, from the solids' bounds.
    let bounds = scene.bounds().ok_or_else(|| whole(Error::invalid("scene", "every solid is empty")))?;
    scene.lights = lights;
    // A scene without lights gets the default ones, unless a solid emits: then it has
    // its light (an area light for radiosity), and extra point lights would shoot too.
    let emits = scene.solids.iter().any(|s| s.material.emission != DVec3::ZERO);
    if scene.lights.is_empty() && !emits {
        scene.lights = Scene::default_lights(&bounds);
    }
    if let Some(a) = spec.ambient {
        scene.ambient = a.rgb();
    }
    if let Some(b) = spec.image.background {
        scene.background = b.rgb();
    }
    let options = spec.image.options();
    let aspect = f64::from(options.width.max(1)) / f64::from(options.height.max(1));
    let camera = spec.camera.camera(&bounds, aspect);
    camera.check().map_err(|e| cx.error(None, None, e))?;
    Ok(SceneFile { scene, camera, options, warnings, cache })
}

/// The domain every `shape` solid is voxelized in: the `[domain]`'s when it gives `min`
/// and `edge`; with `voxel_size`, the cube on that grid around all shapes
/// (`Domain::on_grid`); else the cube around all shapes with a 2% margin at `depth`;
/// `None` when no solid is a shape. An unbounded shape needs the first.
fn shape_domain(
    spec: Option<&Spanned<DomainSpec>>,
    depth: u8,
    solids: &[SolidBuild],
    shapes: &[Option<Csg>],
    cx: &Context,
) -> Result<Option<Domain>> {
    let span = spec.map(Spanned::span);
    let at_domain = |e| cx.error(None, span.as_ref(), e);
    let given = spec.map(Spanned::get_ref);
    if let Some(DomainSpec { min: Some(min), edge: Some(edge), voxel_size, .. }) = given {
        if voxel_size.is_some() {
            return Err(at_domain(Error::invalid("domain", "give either min and edge or voxel_size, not both")));
        }
        return Domain::new(DVec3::from_array(*min), *edge, depth).map(Some).map_err(at_domain);
    }
    let mut bounds: Option<Aabb> = None;
    for (shape, solid) in shapes.iter().zip(solids) {
        let Some(shape) = shape else { continue };
        let b = shape.bounds().ok_or_else(|| {
            let e = Error::invalid("shape", "an unbounded shape needs a [domain] with min and edge");
            solid.at(solid.spec.shape.as_ref().map(Spanned::span))(e)
        })?;
        bounds = Some(bounds.map_or(b, |a| a.union(&b)));
    }
    let voxel_size = given.and_then(|d| d.voxel_size);
    let explicit_depth = given.and_then(|d| d.depth);
    bounds
        .map(|b| match voxel_size {
            Some(voxel) => Domain::on_grid(&b, voxel, explicit_depth),
            None => Domain::around(&b, 0.02, depth),
        })
        .transpose()
        .map_err(at_domain)
}

/// The leaves of a scene's shape trees that name files, read relative to its folder;
/// remembers the files it read (they are part of the solid's cache key).
struct SceneFiles<'a> {
    cx: &'a Context<'a>,
    read: RefCell<Vec<PathBuf>>,
}

impl FileLeaves for SceneFiles<'_> {
    /// The mesh as a [`MeshShape`]; a refusal (not closed) names the file.
    fn mesh(&self, file: &Path) -> Result<Csg> {
        let path = self.cx.folder.join(file);
        self.read.borrow_mut().push(path.clone());
        let mesh = load_mesh(&path)?;
        match MeshShape::new(&mesh) {
            Ok(shape) => Ok(shape.into()),
            Err(Error::InvalidArgument { what, reason }) => {
                Err(Error::invalid(what, format!("{}: {reason}", path.display())))
            }
            Err(e) => Err(e),
        }
    }

    /// The octree as an [`OctreeShape`] where it lies.
    fn oct(&self, file: &Path) -> Result<Csg> {
        let path = self.cx.folder.join(file);
        self.read.borrow_mut().push(path.clone());
        let tree = load_solid(&path, self.cx.budget)?;
        Ok(Csg::leaf(OctreeShape::new(Arc::new(tree), DAffine3::IDENTITY)?))
    }
}

/// The union of the solids of a solid file (one octree for `.oct`, `.octs` and
/// `.binvox`), read through the door for solid files.
fn load_solid(path: &Path, budget: MemoryBudget) -> Result<LinearOctree> {
    Ok(SolidFile::read(path, &ReadOptions { budget, ..ReadOptions::default() })?.into_union())
}

/// One solid being built: its spec, its name, the span of its `[[solid]]` header, and
/// the scene's context; its errors carry the place of the key they concern.
struct SolidBuild<'a> {
    spec: &'a SolidSpec,
    name: String,
    header: Range<usize>,
    cx: &'a Context<'a>,
}

impl SolidBuild<'_> {
    /// What turns a cause into this solid's error at the value `span` of one of its
    /// keys (its header when `None`).
    fn at(&self, span: Option<Range<usize>>) -> impl Fn(Error) -> Error + '_ {
        move |e| self.cx.error(Some(&self.name), Some(span.as_ref().unwrap_or(&self.header)), e)
    }

    /// The span of the solid's `transform`, if it has one.
    fn transform_span(&self) -> Option<Range<usize>> {
        self.spec.transform.as_ref().map(Spanned::span)
    }

    /// The map of the solid's `transform`, `None` without one.
    fn transform(&self) -> Result<Option<DAffine3>> {
        let map = self.spec.transform.as_ref().map(|t| t.get_ref().map());
        map.transpose().map_err(self.at(self.transform_span()))
    }

    /// The solid's shape tree moved by its transform, `None` unless it is a `shape`
    /// solid; and the files its leaves read.
    fn shape(&self) -> Result<(Option<Csg>, Vec<PathBuf>)> {
        let Some(shape) = &self.spec.shape else { return Ok((None, Vec::new())) };
        let files = SceneFiles { cx: self.cx, read: RefCell::new(Vec::new()) };
        let tree = shape.get_ref().build_with(&files).map_err(self.at(Some(shape.span())))?;
        let tree = match self.transform()? {
            Some(map) => Transformed::new(tree, map).map_err(self.at(self.transform_span()))?.into(),
            None => tree,
        };
        Ok((Some(tree), files.read.into_inner()))
    }

    /// Refuses a solid that gives none or several of `shape`, `mesh` and `oct`.
    fn check_one_source(&self) -> Result<()> {
        let s = self.spec;
        let sources = usize::from(s.shape.is_some()) + usize::from(s.mesh.is_some()) + usize::from(s.oct.is_some());
        if sources != 1 {
            return Err(self.at(None)(Error::invalid("solid", "give exactly one of shape, mesh or oct")));
        }
        Ok(())
    }

    /// The cache key of the solid (see the `cache` module): a shape solid's tree (its
    /// spec as read, in `Debug` form: every kind, field and float to the bit, however
    /// the scene writes it: inline or as sub-tables, whose spans would not cover
    /// their values), the files its leaves read (`leaf_files`) and the domain; a mesh solid's
    /// file, depth and inside rule; a moved `.oct` solid's file. Every kind adds its
    /// `transform`, in the same form. `None` for an `.oct` solid that is not moved (loading it is
    /// as fast as loading an entry).
    fn cache_key(&self, leaf_files: &[PathBuf], domain: Option<&Domain>, depth: u8) -> Result<Option<SolidKey>> {
        let s = self.spec;
        let mut key = match (&s.shape, &s.mesh, &s.oct) {
            (Some(shape), _, _) => {
                let mut key = SolidKey::new("shape");
                key.line("shape", &format!("{:?}", shape.get_ref()));
                for file in leaf_files {
                    key.file(file).map_err(self.at(Some(shape.span())))?;
                }
                key.domain(domain.expect("shapes have a domain"));
                key
            }
            (None, Some(mesh), _) => {
                let mut key = SolidKey::new("mesh");
                key.file(&self.cx.folder.join(mesh.get_ref())).map_err(self.at(Some(mesh.span())))?;
                key.line("depth", &s.depth.unwrap_or(depth).to_string());
                key.line("inside", &format!("{:?}", s.inside.unwrap_or(InsideSpec::Auto)));
                key
            }
            (None, None, Some(file)) if s.transform.is_some() => {
                let mut key = SolidKey::new("oct");
                key.file(&self.cx.folder.join(file.get_ref())).map_err(self.at(Some(file.span())))?;
                key
            }
            _ => return Ok(None),
        };
        key.line("transform", &format!("{:?}", s.transform.as_ref().map(Spanned::get_ref)));
        Ok(Some(key))
    }

    /// Voxelizes or loads the solid (from the cache when the load uses one and it
    /// holds the solid) and adds it to `scene` with its material: a shape (its tree and
    /// the files its leaves read, `shape`) into `shape_domain`, a mesh at its depth or
    /// `depth`. Returns the warnings of loading its mesh and of the cache.
    fn add_to(
        &self,
        scene: &mut Scene,
        shape: Option<(&Csg, &[PathBuf])>,
        shape_domain: Option<Domain>,
        depth: u8,
    ) -> Result<Vec<Warning>> {
        self.check_one_source()?;
        let mut warnings = Vec::new();
        let leaf_files = shape.map_or(&[][..], |(_, files)| files);
        let shape = shape.map(|(shape, _)| shape);
        let options = VoxelizeOptions { budget: self.cx.budget, progress: &NoProgress };
        let build = |warnings: &mut Vec<Warning>| {
            let (tree, read) = self.octree(shape, shape_domain, depth, &options)?;
            warnings.extend(read);
            Ok(tree)
        };
        let mut cache = self.cx.cache.borrow_mut();
        let tree = match (cache.as_mut(), self.cache_key(leaf_files, shape_domain.as_ref(), depth)?) {
            (Some(cache), Some(key)) => {
                let mut built = Vec::new();
                let domain = shape.and(shape_domain.as_ref());
                let tree = cache.solid(&key, domain, self.cx.budget, &mut warnings, || build(&mut built))?;
                warnings.extend(built);
                tree
            }
            _ => build(&mut warnings)?,
        };
        drop(cache);
        let material = self.material()?;
        match shape {
            Some(shape) => scene.add_shaped(&self.name, tree, material, Arc::new(shape.clone())),
            None => scene.add(&self.name, tree, material),
        }
        Ok(warnings)
    }

    /// Voxelizes or loads the solid: a shape (its tree `shape`) into `shape_domain`, a
    /// mesh at its depth or `depth`; with the warnings of loading its mesh.
    fn octree(
        &self,
        shape: Option<&Csg>,
        shape_domain: Option<Domain>,
        depth: u8,
        options: &VoxelizeOptions,
    ) -> Result<(LinearOctree, Vec<Warning>)> {
        self.check_one_source()?;
        let s = self.spec;
        Ok(match (shape, &s.mesh, &s.oct) {
            (Some(shape), _, _) => {
                let domain = shape_domain.expect("shapes have a domain");
                let tree = voxelize(shape, domain, options).map_err(self.at(s.shape.as_ref().map(Spanned::span)))?;
                (tree, Vec::new())
            }
            (None, Some(mesh), _) => self.mesh_tree(mesh, depth, options)?,
            (None, None, Some(file)) => (self.oct_tree(file)?, Vec::new()),
            (None, None, None) => unreachable!("one source"),
        })
    }

    /// The mesh (or patch) file moved by the solid's transform, voxelized in its own
    /// bounding cube at the solid's depth (else `depth`) by its inside rule; with the
    /// warnings of loading it.
    fn mesh_tree(
        &self,
        file: &Spanned<PathBuf>,
        depth: u8,
        voxelize: &VoxelizeOptions,
    ) -> Result<(LinearOctree, Vec<Warning>)> {
        let at_file = self.at(Some(file.span()));
        let (mut input, warnings) = Input::load_with_warnings(self.cx.folder.join(file.get_ref())).map_err(&at_file)?;
        if let Some(map) = self.transform()? {
            input.transform(map);
        }
        let domain = import::default_domain(&input, self.spec.depth.unwrap_or(depth)).map_err(&at_file)?;
        let inside = self.spec.inside.map_or(InsideRule::Auto, InsideRule::from);
        let options =
            ImportOptions { inside, budget: voxelize.budget, progress: voxelize.progress, ..Default::default() };
        Ok((import::voxelize_input(&input, domain, &options).map_err(at_file)?.0, warnings))
    }

    /// The `.oct` file's octree moved by the solid's transform.
    fn oct_tree(&self, file: &Spanned<PathBuf>) -> Result<LinearOctree> {
        let tree =
            load_solid(&self.cx.folder.join(file.get_ref()), self.cx.budget).map_err(self.at(Some(file.span())))?;
        match self.transform()? {
            Some(map) => {
                let options = VoxelizeOptions { budget: self.cx.budget, progress: &NoProgress };
                tree.transformed(map, Ok, &options).map(|(tree, _)| tree).map_err(self.at(self.transform_span()))
            }
            None => Ok(tree),
        }
    }

    /// The solid's material, checked; the default without one.
    fn material(&self) -> Result<Material> {
        let default = MaterialSpec::default();
        let (spec, span) = match &self.spec.material {
            Some(m) => (m.get_ref(), Some(m.span())),
            None => (&default, None),
        };
        let material = spec.material(self.cx.folder).map_err(self.at(span.clone()))?;
        material.check().map_err(self.at(span))?;
        Ok(material)
    }
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
            emission: self.emission.map_or(d.emission, DVec3::from_array),
        })
    }
}

impl LightSpec {
    /// The light, white without a colour; a point light takes a `position` and no
    /// `direction`, a directional light the other way round.
    fn light(&self) -> Result<Light> {
        let color = self.color.map_or(DVec3::ONE, ColorSpec::rgb);
        match (self.kind, self.position, self.direction) {
            (LightKind::Point, Some(p), None) => Ok(Light::Point { position: DVec3::from_array(p), color }),
            (LightKind::Directional, None, Some(d)) => {
                Ok(Light::Directional { direction: DVec3::from_array(d), color })
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
    fn options(&self) -> RenderOptions {
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
