//! Scene files (TOML): solids from shape CSG trees, mesh files and solid files (`.oct`,
//! `.octs`, `.vox`, `.binvox`, `.vdb` through [`crate::SolidFile::read`]), their
//! materials, lights, camera and image settings. The format is described in
//! `docs/SCENES.md`; bundled scenes are in `scenes/`.
//!
//! Loading is two steps. Reading deserializes the whole file into the private `*Spec`
//! types and checks every value where it is read: enum-like values are serde enums
//! (shape and texture kinds, light `type`, `normals`, `projection`, `inside`,
//! `mapping`, `axis`), shape nodes are built as they are read ([`ShapeSpec`](crate::shape::ShapeSpec)'s
//! deserializer), colours are checked in form and range ([`ColorSpec`](crate::color::ColorSpec)). So a
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
//! - `shape`: a CSG tree ([`ShapeSpec`](crate::shape::ShapeSpec)) whose leaves may also be `{ mesh = "..." }`
//!   (a closed mesh, as a [`MeshShape`](crate::mesh::MeshShape)) and `{ oct = "..." }` (a stored octree, as an
//!   [`OctreeShape`](crate::octree::OctreeShape): nearest sampling through the tree's transforms; any solid file,
//!   see `oct` below). The whole tree,
//!   moved by the solid's `transform`, is one [`Shape`](crate::shape::Shape), voxelized once into the
//!   domain every `shape` solid shares. By the soundness contract of [`Shape`](crate::shape::Shape) this is
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
//!   [`LinearOctree::transformed`](crate::octree::LinearOctree::transformed): exactly (the keys permuted and mirrored, the domain
//!   moved) for translations, uniform scales, quarter turns and mirrors, resampled at
//!   the same depth otherwise.
//!
//! Relative paths inside a scene are relative to the scene file's folder.
//!
//! Caching ([`read_scene_with`] and [`SceneReadOptions::cache`]): the octrees of `shape` and
//! `mesh` solids and of moved `oct` solids can be read from and stored in the scene's
//! solid cache ([`CACHE_DIR`] beside the scene; its layout and keys in `docs/FORMAT.md`), keyed
//! by everything that decides them, so loading an unchanged scene again voxelizes
//! nothing. [`read_scene`] leaves the cache alone. A mesh solid read from the cache
//! does not read its mesh, so the mesh's warnings come with the load that voxelized it.

use std::cell::RefCell;
use std::path::Path;

use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::octree::{Domain, LinearOctree, VoxelizeOptions};
use crate::progress::{NoProgress, Progress};
use crate::render::{Camera, RenderOptions, Scene};
use crate::shape::Csg;
use crate::warning::Warning;

mod build;
mod cache;
mod place;
mod spec;

use build::{Context, build, named, shape_domain, solid_builds, solid_octree};
use cache::SceneCache;
pub use cache::{CACHE_DIR, CachePolicy, CacheReport, clear_cache};
use place::{first_non_finite, solid_at};
use spec::{DEFAULT_DEPTH, SceneSpec};

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

/// How [`read_scene_with`] loads a scene.
#[derive(Clone, Copy)]
pub struct SceneReadOptions<'a> {
    /// Every voxelization and load is checked against it.
    pub budget: MemoryBudget,
    /// Whether solids are read from and stored in the scene's solid cache.
    pub cache: CachePolicy,
    /// Asked between the solids' voxelizations' units whether to stop
    /// ([`Progress::cancelled`]; the load then returns [`Error::Cancelled`]); nothing
    /// is reported to it.
    pub stop: &'a dyn Progress,
}

impl Default for SceneReadOptions<'_> {
    fn default() -> Self {
        SceneReadOptions { budget: MemoryBudget::default(), cache: CachePolicy::default(), stop: &NoProgress }
    }
}

/// Reads, checks and builds the scene at `path` (voxelizing its shapes and meshes).
/// Errors: [`Error::Io`] when the file cannot be read; else an [`Error::Scene`] with
/// the place (see the module doc): around [`Error::Toml`] when the reader refuses the
/// text (syntax, an unknown key or value, a value out of range), around the cause when
/// the scene cannot be built.
pub fn read_scene(path: impl AsRef<Path>, budget: MemoryBudget) -> Result<SceneFile> {
    read_scene_with(path, &SceneReadOptions { budget, cache: CachePolicy::Off, stop: &NoProgress })
}

/// [`read_scene`] with the solid cache of `options` (see the module doc): under
/// [`CachePolicy::ReadWrite`] a solid whose inputs are unchanged since it was stored
/// is read, not built, and the others are built and stored. The cache never turns a
/// load into an error: an entry that cannot be used or written is a warning and the
/// solid is built.
pub fn read_scene_with(path: impl AsRef<Path>, options: &SceneReadOptions) -> Result<SceneFile> {
    parse_scene(path.as_ref(), options.budget, options.cache, options.stop, build)
}

/// Reads and checks the scene at `path` (its errors as [`read_scene`]'s) and voxelizes
/// one solid without rendering: the `[[solid]]` named `solid`, else the union of the
/// scene's `shape` solids (one CSG tree, voxelized in one pass into the shapes' shared
/// domain, exactly the union of their octrees there). A named `mesh` or `oct` solid
/// comes in its own domain, as [`read_scene`] makes it. Progress goes to
/// `options.progress` and every voxelization is checked against `options.budget`.
pub fn build_solid(path: impl AsRef<Path>, solid: Option<&str>, options: &VoxelizeOptions) -> Result<LinearOctree> {
    parse_scene(path.as_ref(), options.budget, CachePolicy::Off, options.progress, |spec, cx| {
        solid_octree(spec, cx, solid, options)
    })
}

/// The shape and domain [`build_solid`] would voxelize, without voxelizing: for
/// streaming the solid out cell by cell (`crate::sharded`). Its offset, shell and
/// round nodes are left to resolve on the lattice it is voxelized into
/// ([`crate::surface::resolve_offsets`]). Refuses a named solid
/// that is a `mesh` or an `oct` (those are voxelized or read whole).
pub fn build_shape(path: impl AsRef<Path>, solid: Option<&str>, budget: MemoryBudget) -> Result<(Csg, Domain)> {
    parse_scene(path.as_ref(), budget, CachePolicy::Off, &NoProgress, |spec, cx| {
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
fn parse_scene<T>(
    path: &Path,
    budget: MemoryBudget,
    cache: CachePolicy,
    stop: &dyn Progress,
    then: impl FnOnce(&SceneSpec, &Context) -> Result<T>,
) -> Result<T> {
    let text =
        String::from_utf8(crate::input_file::read(path)?).map_err(|e| not_utf8(path, e.as_bytes(), e.utf8_error()))?;
    let folder = path.parent().unwrap_or(Path::new("."));
    let cache = RefCell::new(SceneCache::new(path, cache));
    let cx = Context { path, text: &text, folder, budget, cache, stop };
    let spec: SceneSpec = toml::from_str(&text).map_err(|e| cx.refused(&e))?;
    if let Some((span, key, literal)) = first_non_finite(&text) {
        let solid = solid_at(&text, span.start);
        let reason = format!("{key} = {literal} is not a finite number");
        return Err(cx.error(solid.as_deref(), Some(&span), Error::Toml { reason }));
    }
    then(&spec, &cx)
}

/// A scene that is not UTF-8 text, refused at the first byte that is not, by its line
/// and column (in bytes, as a TOML error's place).
fn not_utf8(path: &Path, bytes: &[u8], e: std::str::Utf8Error) -> Error {
    let at = e.valid_up_to();
    let line_start = bytes[..at].iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1);
    let line = 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
    Error::Scene {
        path: path.to_path_buf(),
        place: Some((line, at - line_start + 1)),
        solid: None,
        source: Box::new(Error::Toml { reason: format!("byte 0x{:02x} is not UTF-8 text", bytes[at]) }),
    }
}
