//! Any drawable file opened the way `octsolid render FILE` opens it: [`Drawing`].
//!
//! A drawing is a scene with what frames it and the options its file gives:
//! - a scene file (`.toml`): [`scene_file::read_scene_with`] (through its solid cache
//!   as [`DrawingOptions::cache`] says), framed by the file's camera, with its options;
//! - a solid file (`.oct`, `.octs`, `.vox`, `.binvox`, `.vdb`): read by
//!   [`SolidFile::read_to_draw`] within a quarter of the budget (the picture needs the
//!   rest; a sharded solid too large comes coarser), drawn in the library's default
//!   scene ([`Scene::of_solid`]) when it is one solid without a colour, else as the
//!   scene of its coloured solids ([`SolidSet::scene`](crate::io::SolidSet::scene))
//!   with the key light turned to up; framed by the union's silhouette;
//! - a mesh or patch file: voxelized at [`DrawingOptions::depth`] (9 by default) in
//!   the default domain around it ([`import::default_domain`]), then as one solid.
//!
//! Up is [`DrawingOptions::up`], else the one a solid file records, else the format's
//! ([`FileKind::default_up`]). The camera is a [`CameraRequest`] over the framing at
//! the aspect of the options [`RenderOverrides`] make over the file's
//! ([`Drawing::camera`], [`Drawing::options`]), so a request and overrides draw the
//! same picture whoever makes them (the CLI's flags, a viewer's query, a library user).
//!
//! The library never prints: what loading read past comes back as [`Warning`]s, and
//! each stage of opening is told to an observer as a [`DrawingStage`] as it ends, so a
//! caller can time the stages or show them ([`Drawing::open_with`]).

use std::path::Path;

use crate::MemoryBudget;
use crate::error::{Error, Result};
use crate::file_kind::FileKind;
use crate::import::{self, ImportOptions, Input};
use crate::io::ReadOptions;
use crate::octree::LinearOctree;
use crate::progress::{NoProgress, Progress};
use crate::render::{Camera, CameraRequest, Framing, RenderOptions, RenderOverrides, Scene, Section, Up};
use crate::scene_file::{self, CachePolicy, SceneReadOptions};
use crate::solid_file::SolidFile;
use crate::surface::HermiteData;
use crate::warning::Warning;

/// How [`Drawing::open`] reads a file.
#[derive(Clone)]
pub struct DrawingOptions<'a> {
    /// Meshes and patches: the depth they are voxelized at (default 9).
    pub depth: Option<u8>,
    /// Up for a solid file or mesh (default: the file's recorded up, else its
    /// format's); it turns the default key light and frames the camera.
    pub up: Option<Up>,
    /// Solid files: the formats' read options. Their budget is not used: a solid file
    /// is read within a quarter of [`DrawingOptions::budget`].
    pub read: ReadOptions,
    /// Scene files: whether solids come from and go to the scene's solid cache.
    pub cache: CachePolicy,
    /// Every load and voxelization is checked against it.
    pub budget: MemoryBudget,
    /// Receives a mesh's voxelization progress.
    pub progress: &'a dyn Progress,
}

impl Default for DrawingOptions<'_> {
    /// The formats' default read options, up from the file, meshes at depth 9, no
    /// cache, the default budget, no progress.
    fn default() -> Self {
        DrawingOptions {
            depth: None,
            up: None,
            read: ReadOptions::default(),
            cache: CachePolicy::Off,
            budget: MemoryBudget::default(),
            progress: &NoProgress,
        }
    }
}

/// A stage of [`Drawing::open_with`], told as it ends.
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub enum DrawingStage<'a> {
    /// A solid file, mesh or patch file was read, with what reading it read past.
    Read {
        /// What the mesh loader read past (none for solid files).
        warnings: &'a [Warning],
        /// A sharded solid too large for the budget, read coarser: its own depth and
        /// the depth it is drawn at (see [`Drawing::coarsened_from`]).
        coarsened: Option<(u8, u8)>,
    },
    /// A mesh or patch file was voxelized.
    Voxelized,
    /// The solid's scene was built.
    SceneBuilt,
    /// A scene file was loaded: its solids taken from its cache and voxelized.
    SceneLoaded {
        /// What loading it read past (see [`scene_file::SceneFile::warnings`]).
        warnings: &'a [Warning],
        /// Solids read from the scene's solid cache.
        hits: usize,
        /// Solids built because the cache had no usable entry (or was off).
        misses: usize,
    },
}

/// A file to draw: its scene, what frames it and the options its file gives (module
/// doc).
pub struct Drawing {
    scene: Scene,
    framed: Framed,
    options: RenderOptions,
    warnings: Vec<Warning>,
    coarsened_from: Option<u8>,
}

/// How the camera frames what is drawn: a scene file's camera (its framing is worked
/// out for the request: the solids' silhouettes only when it re-frames), or a solid's
/// silhouette and up.
enum Framed {
    Scene(Camera),
    Solid(Framing),
}

impl Drawing {
    /// Opens the scene file, solid file, mesh or patch file at `path` (module doc).
    ///
    /// # Errors
    /// What the file's reader refuses ([`FileKind::of`] for a kind that is not drawn,
    /// I/O, format and scene errors naming the file, over budget); an
    /// [`Error::Undrawable`] naming the file when a mesh cannot be voxelized or a
    /// solid is empty.
    pub fn open(path: impl AsRef<Path>, options: &DrawingOptions) -> Result<Drawing> {
        Drawing::open_with(path, options, &mut |_| {})
    }

    /// [`Drawing::open`], telling `stage` each stage as it ends.
    ///
    /// # Errors
    /// As [`Drawing::open`].
    pub fn open_with(
        path: impl AsRef<Path>,
        options: &DrawingOptions,
        stage: &mut dyn FnMut(DrawingStage<'_>),
    ) -> Result<Drawing> {
        let path = path.as_ref();
        let kind = FileKind::of(path, FileKind::DRAWN)?;
        if kind == FileKind::Scene {
            Drawing::open_scene(path, options, stage)
        } else if FileKind::SOLIDS.contains(&kind) {
            Drawing::open_solid_file(path, kind, options, stage)
        } else {
            Drawing::open_mesh(path, kind, options, stage)
        }
    }

    /// A scene file: its scene, camera and options.
    fn open_scene(path: &Path, options: &DrawingOptions, stage: &mut dyn FnMut(DrawingStage<'_>)) -> Result<Drawing> {
        let load = SceneReadOptions { budget: options.budget, cache: options.cache, stop: options.progress };
        let file = scene_file::read_scene_with(path, &load)?;
        stage(DrawingStage::SceneLoaded { warnings: &file.warnings, hits: file.cache.hits, misses: file.cache.misses });
        Ok(Drawing {
            scene: file.scene,
            framed: Framed::Scene(file.camera),
            options: file.options,
            warnings: file.warnings,
            coarsened_from: None,
        })
    }

    /// A solid file: one solid without a colour in the default scene, else its
    /// coloured solids' scene, the key light turned to up either way.
    fn open_solid_file(
        path: &Path,
        kind: FileKind,
        options: &DrawingOptions,
        stage: &mut dyn FnMut(DrawingStage<'_>),
    ) -> Result<Drawing> {
        let read = ReadOptions { budget: MemoryBudget(options.budget.0 / 4), ..options.read.clone() };
        let mut file = SolidFile::read_to_draw(path, &read)?;
        let coarsened_from = file.coarsened_from;
        let coarsened = coarsened_from.map(|from| (from, file.solids.domain.depth()));
        stage(DrawingStage::Read { warnings: &[], coarsened });
        let up = options.up.unwrap_or(Up::Axis(file.meta.up.unwrap_or(kind.default_up())));
        let name = path.display().to_string();
        // One solid without a colour is drawn as it always was; else each in its colour.
        let mut drawing = if matches!(file.solids.solids.as_slice(), [one] if one.color.is_none()) {
            let surface = file.surface.take();
            let drawing = Drawing::of_solid(file.into_union(), &name, up).map_err(|_| empty(path))?;
            match surface {
                Some(surface) => drawing.with_surface(surface),
                None => drawing,
            }
        } else {
            let tree = file.union();
            let bounds = tree.bounds().ok_or_else(|| empty(path))?;
            let mut scene = file.solids.scene(&name, &bounds);
            scene.turn_light_to_up(&bounds, up);
            Drawing::framing(scene, Framing::of_solid(&tree, up))
        };
        drawing.coarsened_from = coarsened_from;
        stage(DrawingStage::SceneBuilt);
        Ok(drawing)
    }

    /// A mesh or patch file, voxelized at the options' depth in the default domain
    /// around it, as one solid.
    fn open_mesh(
        path: &Path,
        kind: FileKind,
        options: &DrawingOptions,
        stage: &mut dyn FnMut(DrawingStage<'_>),
    ) -> Result<Drawing> {
        let (input, warnings) = Input::read_and_warnings(path)?;
        stage(DrawingStage::Read { warnings: &warnings, coarsened: None });
        let cannot = |e: Error| {
            e.wrapped(|e| Error::Undrawable {
                path: path.to_path_buf(),
                reason: "cannot voxelize".into(),
                cause: Some(Box::new(e)),
            })
        };
        let domain = import::default_domain(&input, options.depth.unwrap_or(9)).map_err(cannot)?;
        let import = ImportOptions { budget: options.budget, progress: options.progress, ..Default::default() };
        let tree = import::voxelize_input(&input, domain, &import).map_err(cannot)?.0;
        stage(DrawingStage::Voxelized);
        let up = options.up.unwrap_or(Up::Axis(kind.default_up()));
        let mut drawing = Drawing::of_solid(tree, &path.display().to_string(), up).map_err(|_| empty(path))?;
        drawing.warnings = warnings;
        stage(DrawingStage::SceneBuilt);
        Ok(drawing)
    }

    /// The drawing of one solid in memory, named `name`: the library's default scene
    /// ([`Scene::of_solid`], the key light turned to `up`) framed by its silhouette,
    /// the default options; what [`Drawing::open`] makes of a solid file of one solid
    /// without a colour.
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] for an empty solid (nothing to frame).
    pub fn of_solid(tree: LinearOctree, name: &str, up: Up) -> Result<Drawing> {
        if tree.is_empty() {
            return Err(Error::invalid("solid", "it is empty: there is nothing to frame"));
        }
        let framing = Framing::of_solid(&tree, up);
        Ok(Drawing::framing(Scene::of_solid(tree, name, up), framing))
    }

    /// The drawing of one solid ([`Drawing::of_solid`]) with its surface data, its
    /// shading normals then the smooth surface's: what [`Drawing::open`] makes of a
    /// `.oct` file with a surface section.
    #[must_use]
    pub fn with_surface(mut self, surface: HermiteData) -> Drawing {
        if let [solid] = self.scene.solids.as_mut_slice() {
            solid.set_surface(surface);
        }
        self
    }

    /// `scene` framed by `framing` with the default options.
    fn framing(scene: Scene, framing: Framing) -> Drawing {
        Drawing {
            scene,
            framed: Framed::Solid(framing),
            options: RenderOptions::default(),
            warnings: Vec::new(),
            coarsened_from: None,
        }
    }

    /// The camera `request` asks for at the overridden options' aspect; for a section
    /// view, turned to see the cap ([`Section::facing_the_cap`]).
    ///
    /// # Errors
    /// [`Error::InvalidArgument`] naming the request's field it refuses
    /// ([`CameraRequest::camera`]).
    pub fn camera(
        &self,
        request: &CameraRequest,
        overrides: &RenderOverrides,
        section: Option<Section>,
    ) -> Result<Camera> {
        let aspect = overrides.aspect(&self.options);
        let camera = match &self.framed {
            Framed::Solid(framing) => request.camera(framing, aspect),
            Framed::Scene(camera) => request.camera(&self.scene.framing(*camera, request), aspect),
        }?;
        Ok(section.map_or(camera, |s| s.facing_the_cap(camera, request)))
    }

    /// The render options: the file's, with the overrides, within `budget`.
    #[must_use]
    pub fn options(&self, overrides: &RenderOverrides, budget: MemoryBudget) -> RenderOptions {
        RenderOptions { budget, ..overrides.apply(self.options) }
    }

    /// The scene, uncut.
    #[must_use]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene to draw, cut by `section` when there is one.
    #[must_use]
    pub fn into_scene(self, section: Option<Section>) -> Scene {
        match section {
            Some(section) => section.cut(&self.scene),
            None => self.scene,
        }
    }

    /// What loading the file read past without refusing it (a scene file's, a mesh's).
    #[must_use]
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// A sharded solid too large for the budget: its own depth (it is drawn at its
    /// scene's solids' depth).
    #[must_use]
    pub fn coarsened_from(&self) -> Option<u8> {
        self.coarsened_from
    }
}

/// The error of a file whose solid is empty.
fn empty(path: &Path) -> Error {
    Error::Undrawable { path: path.to_path_buf(), reason: "the solid is empty".into(), cause: None }
}
