//! Building a read scene: the [`Context`] every step shares (the file, its text for
//! places, its folder, the budget and the solid cache), each `[[solid]]` as a
//! [`SolidBuild`] (its one source: a `shape` tree voxelized in the shapes' shared
//! domain, its offset, shell and round nodes resolved there first, a `mesh` voxelized in its own cube, an `oct` solid file read and moved),
//! through the cache when the load uses one, then lights, image and camera. Every
//! failure is an [`Error::Scene`] at the place of the key it concerns.

use std::cell::RefCell;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{DAffine3, DVec3};
use toml::Spanned;

use super::SceneFile;
use super::cache::{SceneCache, SolidKey};
use super::place::{line_column, solid_at};
use super::spec::*;
use crate::aabb::Aabb;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result, printable, quoted};
use crate::import::{self, ImportOptions, Input};
use crate::io::ReadOptions;
use crate::mesh::{InsideRule, MeshShape, read_mesh};
use crate::octree::{Domain, LinearOctree, OctreeShape, VoxelizeOptions, voxelize};
use crate::progress::{CancelOnly, Progress};
use crate::render::{Light, Material, Scene};
use crate::shape::{Csg, FileLeaves, Shape, Transformed};
use crate::solid_file::SolidFile;
use crate::surface::resolve_offsets;
use crate::warning::Warning;

/// The solid [`build_solid`] makes from the parsed file.
pub(super) fn solid_octree(
    spec: &SceneSpec,
    cx: &Context,
    name: Option<&str>,
    options: &VoxelizeOptions,
) -> Result<LinearOctree> {
    let whole = |e| cx.error(None, None, e);
    let solids = solid_builds(spec, cx)?;
    let shapes: Vec<Option<Csg>> = solids.iter().map(|s| Ok(s.shape()?.0)).collect::<Result<_>>()?;
    let depth = spec.domain.as_ref().and_then(|d| d.get_ref().depth).unwrap_or(DEFAULT_DEPTH);
    let domain = shape_domain(spec.domain.as_ref(), depth, &solids, &shapes, cx)?;
    let Some(name) = name else {
        let union = shapes.iter().flatten().cloned().reduce(|a, b| a | b);
        let union =
            union.ok_or_else(|| whole(Error::invalid("scene", "it has no shape solid; name the solid to build")))?;
        let domain = domain.expect("shapes have a domain");
        let union = resolve_offsets(&union, domain, options).map_err(whole)?;
        return voxelize(&union, domain, options).map_err(whole);
    };
    let i = named(&solids, name, cx)?;
    Ok(solids[i].octree(shapes[i].as_ref(), domain, depth, options)?.0)
}

/// The position of the solid named `name`; fails listing the names there are.
pub(super) fn named(solids: &[SolidBuild], name: &str, cx: &Context) -> Result<usize> {
    solids.iter().position(|s| s.name == name).ok_or_else(|| {
        let names: Vec<String> = solids.iter().map(|s| printable(&s.name).into_owned()).collect();
        let reason = format!("no solid is named {} (its solids: {})", quoted(name.as_bytes()), names.join(", "));
        cx.error(None, None, Error::invalid("solid", reason))
    })
}

/// The scene's solids to build, named (`solid N` when the file gives no name); fails
/// when there is none, when a solid gives none or several of `shape`, `mesh` and `oct`
/// (whether or not it is the one built), and when two share a name.
pub(super) fn solid_builds<'a>(spec: &'a SceneSpec, cx: &'a Context) -> Result<Vec<SolidBuild<'a>>> {
    if spec.solids.is_empty() {
        return Err(cx.error(None, None, Error::invalid("scene", "it has no [[solid]]")));
    }
    let solids: Vec<SolidBuild> = spec
        .solids
        .iter()
        .enumerate()
        .map(|(i, s)| SolidBuild {
            spec: s.get_ref(),
            name: s.get_ref().name.clone().unwrap_or_else(|| format!("solid {}", i + 1)),
            header: s.span(),
            cx,
        })
        .collect();
    for (i, solid) in solids.iter().enumerate() {
        solid.check_one_source()?;
        if solids[..i].iter().any(|other| other.name == solid.name) {
            let reason = format!(
                "another solid is named {} too; names pick solids, so they differ",
                quoted(solid.name.as_bytes())
            );
            return Err(solid.at(None)(Error::invalid("solid", reason)));
        }
    }
    Ok(solids)
}

/// What building a scene needs besides its spec.
pub(super) struct Context<'a> {
    /// The scene file, for errors.
    pub(super) path: &'a Path,
    /// Its text, for the line and column of a span.
    pub(super) text: &'a str,
    /// The folder its relative paths start from.
    pub(super) folder: &'a Path,
    /// Every voxelization and load is checked against it.
    pub(super) budget: MemoryBudget,
    /// The solid cache, when the load uses one.
    pub(super) cache: RefCell<Option<SceneCache>>,
    /// Whether to stop (only asked: `SceneReadOptions::stop`).
    pub(super) stop: &'a dyn Progress,
}

impl Context<'_> {
    /// `source` as an error of this scene at the start of the byte range `span` when
    /// given, about the solid `solid` if it concerns one.
    pub(super) fn error(&self, solid: Option<&str>, span: Option<&Range<usize>>, source: Error) -> Error {
        source.wrapped(|source| Error::Scene {
            path: self.path.to_path_buf(),
            place: span.map(|s| line_column(self.text, s.start)),
            solid: solid.map(str::to_owned),
            source: Box::new(source),
        })
    }

    /// The reader's refusal `e`, at its place, naming the solid that place lies in.
    pub(super) fn refused(&self, e: &toml::de::Error) -> Error {
        let span = e.span();
        let solid = span.as_ref().and_then(|s| solid_at(self.text, s.start));
        self.error(solid.as_deref(), span.as_ref(), Error::Toml { reason: printable(e.message().trim()).into_owned() })
    }
}

/// The scene, its camera and image settings from the parsed file.
pub(super) fn build(spec: &SceneSpec, cx: &Context) -> Result<SceneFile> {
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
    let camera_spec = spec.camera.as_ref();
    let camera = match camera_spec {
        Some(c) => c.get_ref().camera(&bounds, aspect),
        None => CameraSpec::default().camera(&bounds, aspect),
    };
    camera.validate().map_err(|e| cx.error(None, camera_spec.map(Spanned::span).as_ref(), e))?;
    Ok(SceneFile { scene, camera, options, warnings, cache })
}

/// The domain every `shape` solid is voxelized in: the `[domain]`'s when it gives `min`
/// and `edge`; with `voxel_size`, the cube on that grid around all shapes
/// (`Domain::on_grid`); else the cube around all shapes with a 2% margin at `depth`;
/// `None` when no solid is a shape. An unbounded shape needs the first.
pub(super) fn shape_domain(
    spec: Option<&Spanned<DomainSpec>>,
    depth: u8,
    solids: &[SolidBuild],
    shapes: &[Option<Csg>],
    cx: &Context,
) -> Result<Option<Domain>> {
    let span = spec.map(Spanned::span);
    let at_domain = |e| cx.error(None, span.as_ref(), e);
    let given = spec.map(Spanned::get_ref);
    if let Some(DomainSpec { min, edge, .. }) = given
        && min.is_some() != edge.is_some()
    {
        let (has, lacks) = if min.is_some() { ("min", "edge") } else { ("edge", "min") };
        return Err(at_domain(Error::invalid("domain", format!("{has} without {lacks}: give both, or neither"))));
    }
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
pub(super) struct SceneFiles<'a> {
    pub(super) cx: &'a Context<'a>,
    pub(super) read: RefCell<Vec<PathBuf>>,
}

impl FileLeaves for SceneFiles<'_> {
    /// The mesh as a [`MeshShape`]; a refusal (not closed) names the file.
    fn mesh(&self, file: &Path) -> Result<Csg> {
        let path = self.cx.folder.join(file);
        self.read.borrow_mut().push(path.clone());
        let mesh = read_mesh(&path)?;
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
        let tree = read_solid(&path, self.cx.budget)?;
        Ok(Csg::leaf(OctreeShape::new(Arc::new(tree), DAffine3::IDENTITY)?))
    }
}

/// The union of the solids of a solid file (one octree for `.oct`, `.octs` and
/// `.binvox`), read through the door for solid files.
pub(super) fn read_solid(path: &Path, budget: MemoryBudget) -> Result<LinearOctree> {
    Ok(read_solid_file(path, budget)?.into_union())
}

/// The solid file at `path`, read within `budget`.
fn read_solid_file(path: &Path, budget: MemoryBudget) -> Result<SolidFile> {
    SolidFile::read(path, &ReadOptions { budget, ..ReadOptions::default() })
}

/// One solid being built: its spec, its name, the span of its `[[solid]]` header, and
/// the scene's context; its errors carry the place of the key they concern.
pub(super) struct SolidBuild<'a> {
    pub(super) spec: &'a SolidSpec,
    pub(super) name: String,
    pub(super) header: Range<usize>,
    pub(super) cx: &'a Context<'a>,
}

impl SolidBuild<'_> {
    /// What turns a cause into this solid's error at the value `span` of one of its
    /// keys (its header when `None`).
    pub(super) fn at(&self, span: Option<Range<usize>>) -> impl Fn(Error) -> Error + '_ {
        move |e| self.cx.error(Some(&self.name), Some(span.as_ref().unwrap_or(&self.header)), e)
    }

    /// The span of the solid's `transform`, if it has one.
    pub(super) fn transform_span(&self) -> Option<Range<usize>> {
        self.spec.transform.as_ref().map(Spanned::span)
    }

    /// The map of the solid's `transform`, `None` without one.
    pub(super) fn transform(&self) -> Result<Option<DAffine3>> {
        let map = self.spec.transform.as_ref().map(|t| t.get_ref().map());
        map.transpose().map_err(self.at(self.transform_span()))
    }

    /// The solid's shape tree moved by its transform, `None` unless it is a `shape`
    /// solid; and the files its leaves read.
    pub(super) fn shape(&self) -> Result<(Option<Csg>, Vec<PathBuf>)> {
        let Some(shape) = &self.spec.shape else { return Ok((None, Vec::new())) };
        let files = SceneFiles { cx: self.cx, read: RefCell::new(Vec::new()) };
        let tree = shape.get_ref().build_with(&files).map_err(self.at(Some(shape.span())))?;
        let tree = match self.transform()? {
            Some(map) => Transformed::new(tree, map).map_err(self.at(self.transform_span()))?.into(),
            None => tree,
        };
        Ok((Some(tree), files.read.into_inner()))
    }

    /// Refuses a solid that gives none or several of `shape`, `mesh` and `oct`, and a
    /// mesh's keys (`depth`, `inside`) on a solid that is not a mesh, at the key.
    pub(super) fn check_one_source(&self) -> Result<()> {
        let s = self.spec;
        let sources = usize::from(s.shape.is_some()) + usize::from(s.mesh.is_some()) + usize::from(s.oct.is_some());
        if sources != 1 {
            return Err(self.at(None)(Error::invalid("solid", "give exactly one of shape, mesh or oct")));
        }
        if s.mesh.is_none() {
            let kind =
                if s.shape.is_some() { "a shape takes the [domain]'s depth" } else { "an .oct file keeps its own" };
            if let Some(depth) = &s.depth {
                return Err(self.at(Some(depth.span()))(Error::invalid(
                    "depth",
                    format!("only a mesh solid takes one ({kind})"),
                )));
            }
            if let Some(inside) = &s.inside {
                let e = Error::invalid(
                    "inside",
                    "only a mesh solid takes an inside rule (a shape or an .oct file has its inside)",
                );
                return Err(self.at(Some(inside.span()))(e));
            }
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
    pub(super) fn cache_key(
        &self,
        leaf_files: &[PathBuf],
        domain: Option<&Domain>,
        depth: u8,
    ) -> Result<Option<SolidKey>> {
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
                key.line("depth", &s.depth.as_ref().map_or(depth, |d| *d.get_ref()).to_string());
                key.line("inside", &format!("{:?}", s.inside.as_ref().map_or(InsideSpec::Auto, |i| *i.get_ref())));
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
    pub(super) fn add_to(
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
        let stop = CancelOnly(self.cx.stop);
        let options = VoxelizeOptions { budget: self.cx.budget, progress: &stop };
        let build = |warnings: &mut Vec<Warning>| {
            let (tree, read) = self.octree(shape, shape_domain, depth, &options)?;
            warnings.extend(read);
            Ok(tree)
        };
        // An `.oct` (or level set `.vdb`) solid not moved: its file's surface data gives
        // its smooth normals, as when the file is drawn alone. (A moved one is cached,
        // and its cache keeps its voxels only: its normals are the octree's estimate.)
        if let (None, Some(file), None) = (shape, &self.spec.oct, &self.spec.transform) {
            let (tree, surface) = self.oct_file(file)?;
            scene.add(&self.name, tree, self.material()?);
            if let Some(surface) = surface {
                scene.solids.last_mut().expect("just added").set_surface(surface);
            }
            return Ok(warnings);
        }
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
    pub(super) fn octree(
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
                let at_shape = self.at(s.shape.as_ref().map(Spanned::span));
                let shape = resolve_offsets(shape, domain, options).map_err(&at_shape)?;
                let tree = voxelize(&shape, domain, options).map_err(at_shape)?;
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
    pub(super) fn mesh_tree(
        &self,
        file: &Spanned<PathBuf>,
        depth: u8,
        voxelize: &VoxelizeOptions,
    ) -> Result<(LinearOctree, Vec<Warning>)> {
        let at_file = self.at(Some(file.span()));
        let (mut input, warnings) = Input::read_and_warnings(self.cx.folder.join(file.get_ref())).map_err(&at_file)?;
        if let Some(map) = self.transform()? {
            input.transform(map);
        }
        let domain = import::default_domain(&input, self.spec.depth.as_ref().map_or(depth, |d| *d.get_ref()))
            .map_err(&at_file)?;
        let inside = self.spec.inside.as_ref().map_or(InsideRule::Auto, |i| InsideRule::from(*i.get_ref()));
        let options =
            ImportOptions { inside, budget: voxelize.budget, progress: voxelize.progress, ..Default::default() };
        Ok((import::voxelize_input(&input, domain, &options).map_err(at_file)?.0, warnings))
    }

    /// The solid file's octree and its surface data, when it carries any.
    fn oct_file(&self, file: &Spanned<PathBuf>) -> Result<(LinearOctree, Option<crate::surface::HermiteData>)> {
        let path = self.cx.folder.join(file.get_ref());
        let mut read = read_solid_file(&path, self.cx.budget).map_err(self.at(Some(file.span())))?;
        // (Data of one solid only: a union of several has other boundary faces.)
        let surface = read.surface.take().filter(|_| read.solids.solids.len() == 1);
        Ok((read.into_union(), surface))
    }

    /// The `.oct` file's octree moved by the solid's transform.
    pub(super) fn oct_tree(&self, file: &Spanned<PathBuf>) -> Result<LinearOctree> {
        let tree =
            read_solid(&self.cx.folder.join(file.get_ref()), self.cx.budget).map_err(self.at(Some(file.span())))?;
        match self.transform()? {
            Some(map) => {
                let stop = CancelOnly(self.cx.stop);
                let options = VoxelizeOptions { budget: self.cx.budget, progress: &stop };
                tree.transformed(map, Ok, &options).map(|(tree, _)| tree).map_err(self.at(self.transform_span()))
            }
            None => Ok(tree),
        }
    }

    /// The solid's material, checked; the default without one.
    pub(super) fn material(&self) -> Result<Material> {
        let default = MaterialSpec::default();
        let (spec, span) = match &self.spec.material {
            Some(m) => (m.get_ref(), Some(m.span())),
            None => (&default, None),
        };
        let material = spec.material(self.cx.folder).map_err(self.at(span.clone()))?;
        material.validate().map_err(self.at(span))?;
        Ok(material)
    }
}
