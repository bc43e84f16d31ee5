//! `octsolid render IN [-o OUT] [...]`: a scene file, a solid, or a mesh (voxelized
//! first, or drawn as polygons with `--shading`) rendered to a PNG (8-bit sRGB) or an
//! OpenEXR file (linear radiance), by `-o`'s extension.
//!
//! A solid file of several coloured solids (a `.vox` file's palette colours, a `.vdb`
//! grid) is rendered as a scene of those solids, each in its file's colour (sRGB
//! decoded to linear) with the default material otherwise; a solid without a colour
//! has the default material's.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use glam::DVec3;
use octsolid::import::{self, ImportOptions, Input};
use octsolid::io::{PictureFormat, save_picture};
use octsolid::mesh::{BoundaryOptions, try_boundary_mesh};
use octsolid::render::radiosity::{Radiosity, RadiosityOptions};
use octsolid::render::{
    self, AntiAliasing, Camera, DEFAULT_AA_DEPTH, DEFAULT_AA_THRESHOLD, Light, Material, RenderOptions, Scene,
    silhouette_points,
};
use octsolid::scene_file::{self, CachePolicy, LoadOptions};
use octsolid::shape::Axis;
use octsolid::{FileKind, MemoryBudget};

use super::{load_input, print_warnings, render_with_bar};
use crate::camera_flags::{self, CameraFlags, Framing};
use crate::output::check_extension;
use crate::progress_bar::Bar;
use crate::solid_input::{ReadFlags, read_for_display, read_solid_file};
use crate::values::{Up, parse_size};

/// Arguments of `octsolid render`.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct RenderArgs {
    /// Scene (.toml), solid (.oct, .vox, .binvox, .vdb) or mesh (.obj, .stl, .ply,
    /// .patches).
    pub input: PathBuf,
    /// Output picture: .png (8-bit sRGB, clamped) or .exr (linear radiance, 32-bit
    /// float, unclamped) (default: the input's name with .png, in the current folder).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Exposure in stops: every pixel's radiance is scaled by 2^STOPS before it is
    /// written (PNG and EXR alike; +1 doubles, -1 halves; default 0).
    #[arg(long, value_name = "STOPS", value_parser = crate::values::parse_finite)]
    pub exposure: Option<f64>,
    /// Image size WIDTHxHEIGHT (default: the scene's, or 960x720).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<[u32; 2]>,
    /// Samples a pixel side: N x N stratified samples (default: the scene's, or 2).
    #[arg(long)]
    pub spp: Option<u32>,
    /// How primary visibility is decided (every method finds the same hits; the
    /// front-to-back display finds a whole image's fastest).
    #[arg(long, default_value = "front-to-back")]
    pub method: Method,
    /// Depth to voxelize a mesh at (default 9; not for solid files or scenes).
    #[arg(long)]
    pub depth: Option<u8>,
    #[command(flatten)]
    pub camera: CameraFlags,
    /// Skip shadow rays.
    #[arg(long)]
    pub no_shadows: bool,
    /// Shading normals: axis (the voxel faces'), smooth (the source shape's where a
    /// solid has one, else estimated from the octree) or octree (always estimated)
    /// (default: the scene's, or smooth).
    #[arg(long)]
    pub normals: Option<Normals>,
    /// Longest chain of reflected and refracted rays (default: the scene's, or 6).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Share of a pixel below which a reflected or refracted ray is not traced
    /// (POV-Ray's adc_bailout; default: the scene's, or 0.001).
    #[arg(long)]
    pub cutoff: Option<f64>,
    /// Anti-aliasing: uniform (--spp N x N samples in every pixel), adaptive (one
    /// sample a pixel, N x N where a neighbour differs by --aa-threshold; POV-Ray's +A)
    /// or recursive (samples at the pixels' corners, a square split in four where its
    /// corners differ by --aa-threshold, up to --aa-depth times; POV-Ray's +AM2)
    /// (default: the scene's, or uniform).
    #[arg(long)]
    pub aa: Option<Aa>,
    /// Contrast that makes adaptive anti-aliasing supersample a pixel (recursive: split
    /// a square): the sum of the red, green and blue differences with a neighbour (a
    /// corner), 0 to 3 (default: the scene's, or 0.3; implies --aa adaptive unless
    /// --aa is given or the scene's is recursive).
    #[arg(long, value_parser = crate::values::parse_finite)]
    pub aa_threshold: Option<f64>,
    /// Recursive anti-aliasing: the most times a pixel's square is split, 1 to 6
    /// (POV-Ray's +R; default: the scene's, or 3; implies --aa recursive unless --aa is
    /// given).
    #[arg(long)]
    pub aa_depth: Option<u32>,
    /// Scenes: voxelize every solid, neither reading nor writing the scene's solid
    /// cache (.octsolid-cache beside the scene, which otherwise holds the solids of the
    /// last render so an unchanged scene is not voxelized again).
    #[arg(long)]
    pub no_cache: bool,
    /// Scenes: remove the scene's cached solids first (the render then stores fresh
    /// ones unless --no-cache is given).
    #[arg(long)]
    pub clear_cache: bool,
    /// A section view: cut every solid at AXIS,POS (e.g. x,0.25) and keep what lies at
    /// or below the plane (snapped to the voxel lattice); the cut shows as a filled cap.
    #[arg(long, value_parser = parse_section, allow_hyphen_values = true)]
    pub section: Option<Section>,
    /// Render a mesh (or Bezier patches, tessellated) as polygons with this
    /// interpolation shading instead of voxelizing it.
    #[arg(long)]
    pub shading: Option<Shading>,
    #[command(flatten)]
    pub read: ReadFlags,
    /// How surfaces are lit: direct (Phong with shadows, Whitted's mirrors and glass)
    /// or radiosity (diffuse interreflection solved first, mirrors and glass traced on
    /// top) (default: radiosity with --radiosity, else direct).
    #[arg(long)]
    pub illumination: Option<Illumination>,
    /// Show this saved radiosity solution of the scene (from `octsolid radiosity`).
    #[arg(long, value_name = "SOLUTION.rad", conflicts_with = "shading")]
    pub radiosity: Option<PathBuf>,
    /// With --illumination radiosity (solved here): adaptive subdivision, as
    /// `octsolid radiosity --subdivide THRESHOLD` (a saved solution has its elements).
    #[arg(long, value_name = "THRESHOLD", value_parser = crate::values::parse_finite, conflicts_with = "radiosity")]
    pub subdivide: Option<f64>,
    /// With radiosity: show each element flat with its borders drawn (patch borders
    /// darker) instead of interpolating, a picture of the patches and elements.
    #[arg(long)]
    pub show_elements: bool,
}

/// How surfaces are lit.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Illumination {
    /// Phong with shadows, and Whitted's reflected and refracted rays.
    Direct,
    /// A radiosity solution (saved with --radiosity, else solved first).
    Radiosity,
}

/// Polygon interpolation shading.
#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum Shading {
    /// One colour a triangle.
    Flat,
    /// Vertex colours interpolated.
    Gouraud,
    /// Vertex normals interpolated, lit at every pixel.
    Phong,
}

impl From<Shading> for octsolid::render::polygon::Interpolation {
    fn from(s: Shading) -> Self {
        match s {
            Shading::Flat => Self::Flat,
            Shading::Gouraud => Self::Gouraud,
            Shading::Phong => Self::Phong,
        }
    }
}

/// Anti-aliasing.
#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aa {
    /// N x N samples in every pixel.
    Uniform,
    /// N x N samples where a pixel differs from a neighbour.
    Adaptive,
    /// Corner samples, squares split where their corners differ.
    Recursive,
}

/// The anti-aliasing `--aa`, `--aa-threshold` and `--aa-depth` ask for over the
/// scene's `scene`: without `--aa`, a depth asks for recursive sampling and a
/// threshold for adaptive (unless the scene's is recursive); what is not given is the
/// scene's, or the default.
fn anti_aliasing(a: &RenderArgs, scene: AntiAliasing) -> AntiAliasing {
    let (scene_threshold, scene_depth) = match scene {
        AntiAliasing::Uniform => (None, None),
        AntiAliasing::Adaptive { threshold } => (Some(threshold), None),
        AntiAliasing::Recursive { threshold, depth } => (Some(threshold), Some(depth)),
    };
    let threshold = a.aa_threshold.or(scene_threshold).unwrap_or(DEFAULT_AA_THRESHOLD);
    let depth = a.aa_depth.or(scene_depth).unwrap_or(DEFAULT_AA_DEPTH);
    let kind = match (a.aa, scene) {
        (Some(kind), _) => kind,
        (None, _) if a.aa_depth.is_some() => Aa::Recursive,
        (None, AntiAliasing::Recursive { .. }) => Aa::Recursive,
        (None, AntiAliasing::Adaptive { .. }) => Aa::Adaptive,
        (None, AntiAliasing::Uniform) if a.aa_threshold.is_some() => Aa::Adaptive,
        (None, AntiAliasing::Uniform) => Aa::Uniform,
    };
    match kind {
        Aa::Uniform => AntiAliasing::Uniform,
        Aa::Adaptive => AntiAliasing::Adaptive { threshold },
        Aa::Recursive => AntiAliasing::Recursive { threshold, depth },
    }
}

/// Shading normals.
#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum Normals {
    /// The entered voxel face's axis normal.
    Axis,
    /// The source shape's normal where the solid has one, else the octree's estimate.
    Smooth,
    /// Estimated from the octree's occupancy around the hit, always.
    Octree,
}

impl From<Normals> for octsolid::render::Normals {
    fn from(n: Normals) -> Self {
        match n {
            Normals::Axis => octsolid::render::Normals::Axis,
            Normals::Smooth => octsolid::render::Normals::Smooth,
            Normals::Octree => octsolid::render::Normals::Octree,
        }
    }
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum Method {
    /// Ray tracing through the octree.
    Trace,
    /// Meagher's front-to-back octree display.
    FrontToBack,
    /// Painter's algorithm (far to near, overwrite).
    Painter,
    /// Z-buffer.
    Zbuffer,
    /// Scan-line Z-buffer (polygon, edge, active polygon and active edge tables).
    Scanline,
}

impl From<Method> for octsolid::render::Method {
    fn from(m: Method) -> Self {
        match m {
            Method::Trace => octsolid::render::Method::Trace,
            Method::FrontToBack => octsolid::render::Method::FrontToBack,
            Method::Painter => octsolid::render::Method::Painter,
            Method::Zbuffer => octsolid::render::Method::ZBuffer,
            Method::Scanline => octsolid::render::Method::ScanLine,
        }
    }
}

/// `octsolid render IN [-o OUT] [--size WxH] [--spp N] [--method M] [--depth D] [camera flags] [--shading S]`
pub fn run(a: &RenderArgs, budget: MemoryBudget) -> Result<()> {
    let input = &a.input;
    let output =
        a.output.clone().unwrap_or_else(|| Path::new(input.file_stem().unwrap_or_default()).with_extension("png"));
    check_extension(&output, PictureFormat::EXTENSIONS)?;
    let mut stages = Stages::new();
    if let Some(interpolation) = a.shading {
        // Meshes, patch sets (tessellated) and solids (their boundary); not scenes.
        let kind = FileKind::of(input, FileKind::ALL)?;
        if kind == FileKind::Scene {
            bail!("{}: --shading draws a mesh or a solid as polygons, not a scene", input.display());
        }
        return polygon_command(a, kind, &output, interpolation.into(), budget);
    }
    let kind = FileKind::of(input, FileKind::ALL)?;
    if a.depth.is_some() && (kind == FileKind::Scene || FileKind::SOLIDS.contains(&kind)) {
        warn!("--depth is ignored for {}: its solids already have their depths", input.display());
    }
    if (a.no_cache || a.clear_cache) && kind != FileKind::Scene {
        warn!("--no-cache and --clear-cache are for scenes: {} is not one", input.display());
    }
    if a.clear_cache && kind == FileKind::Scene {
        let removed = scene_file::clear_cache(input)?;
        out!("cleared    {removed} cached solid{} of {}", if removed == 1 { "" } else { "s" }, input.display());
    }
    let cache = if a.no_cache { CachePolicy::Off } else { CachePolicy::ReadWrite };
    let source = Source { depth: a.depth, up: a.camera.up, read: a.read.clone() };
    let drawn = Drawn::load(input, kind, &source, LoadOptions { budget, cache }, &mut stages)?;
    let camera = drawn.camera(a)?;
    let options = drawn.options(a, budget);
    let mut scene = drawn.into_scene(a.section);
    light_by_radiosity(a, &mut scene, budget, &mut stages)?;
    let picture =
        render_with_bar(&scene, &camera, &options).with_context(|| format!("{}: cannot render", input.display()))?;
    stages.done("rendering");
    save_picture(&picture, &output)?;
    stages.done("writing");
    out!("wrote {} ({}x{})", output.display(), picture.width(), picture.height());
    stages.report();
    Ok(())
}

/// What `render` draws (and `view` shows): a scene, or one solid file with the default
/// lights, with what frames it and the options its file gives.
pub(crate) struct Drawn {
    pub scene: Scene,
    framed: Framed,
    /// The scene file's options, or the defaults for a solid.
    options: RenderOptions,
}

impl Drawn {
    /// Loads a scene file (through its solid cache as `load` says), an `.oct` file or
    /// a mesh (voxelized at `depth`, default 9) as `render` does; `up` is `--up` (it
    /// turns a solid's default light).
    pub(crate) fn load(
        input: &Path,
        kind: FileKind,
        source: &Source,
        load: LoadOptions,
        stages: &mut Stages,
    ) -> Result<Drawn> {
        if kind == FileKind::Scene {
            let file = scene_file::load_scene_with(input, &load)?;
            print_warnings(&file.warnings);
            let solids = |n: usize| if n == 1 { "1 solid".to_owned() } else { format!("{n} solids") };
            stages.done(match (file.cache.hits, file.cache.misses) {
                (0, _) => "loading and voxelizing the scene".to_owned(),
                (hits, 0) => format!("loading the scene ({} from its cache)", solids(hits)),
                (hits, misses) => format!("loading the scene ({} from its cache, {misses} voxelized)", solids(hits)),
            });
            return Ok(Drawn { scene: file.scene, framed: Framed::Scene(file.camera), options: file.options });
        }
        solid_scene(input, kind, source, load.budget, stages)
    }

    /// The camera the flags ask for, at the flags' (or the options') aspect; for a
    /// section view, turned to see the cap ([`Section::facing_the_cap`]).
    pub(crate) fn camera(&self, a: &RenderArgs) -> Result<Camera> {
        let aspect = size_aspect(a.size, &self.options);
        let camera = match &self.framed {
            Framed::Solid(framing) => camera_flags::camera(&a.camera, framing, aspect),
            Framed::Scene(camera) => {
                camera_flags::camera(&a.camera, &Framing::of_scene(&self.scene, *camera, &a.camera), aspect)
            }
        }?;
        Ok(a.section.map_or(camera, |s| s.facing_the_cap(camera, &a.camera)))
    }

    /// The scene to draw, cut by `--section` when it is given.
    pub(crate) fn into_scene(self, section: Option<Section>) -> Scene {
        match section {
            Some(section) => section.cut(&self.scene),
            None => self.scene,
        }
    }

    /// The render options: the file's, with the flags' changes.
    pub(crate) fn options(&self, a: &RenderArgs, budget: MemoryBudget) -> RenderOptions {
        let mut options = self.options;
        if let Some([w, h]) = a.size {
            options.width = w;
            options.height = h;
        }
        if let Some(n) = a.spp {
            options.spp = n;
        }
        options.shade.shadows &= !a.no_shadows;
        options.shade.normals = a.normals.map_or(options.shade.normals, Into::into);
        options.shade.max_depth = a.max_depth.unwrap_or(options.shade.max_depth);
        options.shade.cutoff = a.cutoff.unwrap_or(options.shade.cutoff);
        options.aa = anti_aliasing(a, options.aa);
        options.method = a.method.into();
        options.budget = budget;
        options.exposure = a.exposure.unwrap_or(options.exposure);
        options
    }
}

/// A section plane: `--section AXIS,POS`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Section {
    pub axis: Axis,
    pub at: f64,
}

impl Section {
    /// The scene cut by this plane.
    pub(crate) fn cut(self, scene: &Scene) -> Scene {
        scene.sectioned(self.axis, self.at)
    }

    /// `camera` turned to see the cap (it faces `+axis`): an eye on the other side of
    /// the plane through the target is mirrored across it, unless the flags placed it
    /// (`--eye`, `--view`, `--azimuth`, `--elevation`).
    pub(crate) fn facing_the_cap(self, camera: Camera, flags: &CameraFlags) -> Camera {
        let placed =
            flags.eye.is_some() || flags.view.is_some() || flags.azimuth.is_some() || flags.elevation.is_some();
        let a = self.axis.index();
        let mut camera = camera;
        if !placed && camera.eye[a] < camera.target[a] {
            camera.eye[a] = 2.0 * camera.target[a] - camera.eye[a];
        }
        camera
    }
}

/// Parses `AXIS,POS` (x, y or z and a finite coordinate).
fn parse_section(s: &str) -> Result<Section, String> {
    let (axis, at) = s.split_once(',').ok_or_else(|| format!("'{s}' is not AXIS,POS like x,0.25"))?;
    let axis = axis.trim().parse::<Axis>().map_err(|e| format!("'{s}': {e}"))?;
    let at = crate::values::parse_finite(at.trim())?;
    Ok(Section { axis, at })
}

/// How a solid file or mesh is read for drawing: `--depth` (meshes), `--up` (it turns
/// a solid's default light) and the formats' read flags.
#[derive(Clone, Debug)]
pub(crate) struct Source {
    pub depth: Option<u8>,
    pub up: Option<Up>,
    pub read: ReadFlags,
}

/// How the camera frames what is drawn (see [`camera_flags::camera`]).
enum Framed {
    /// A scene file's camera (its framing is worked out for the flags: the solids'
    /// silhouettes only when they re-frame it).
    Scene(Camera),
    /// A solid's silhouette and up.
    Solid(Framing),
}

/// Attaches the radiosity solution `--radiosity` and `--illumination` ask for, if any:
/// loaded (and checked against the scene) or solved now.
fn light_by_radiosity(a: &RenderArgs, scene: &mut Scene, budget: MemoryBudget, stages: &mut Stages) -> Result<()> {
    let solution = match (a.illumination, &a.radiosity) {
        (Some(Illumination::Direct), Some(_)) => {
            bail!("--radiosity needs --illumination radiosity (or no --illumination)")
        }
        (Some(Illumination::Direct), None) | (None, None) if a.show_elements => {
            bail!("--show-elements needs radiosity: --radiosity SOLUTION.rad or --illumination radiosity")
        }
        (Some(Illumination::Direct), None) | (None, None) if a.subdivide.is_some() => {
            bail!("--subdivide needs a radiosity solution solved here: --illumination radiosity")
        }
        (Some(Illumination::Direct), None) | (None, None) => return Ok(()),
        (_, Some(path)) => {
            let solution = Radiosity::load(path, scene, budget)
                .with_context(|| format!("{}: cannot use the solution for {}", path.display(), a.input.display()))?;
            stages.done("loading the radiosity solution");
            solution
        }
        (Some(Illumination::Radiosity), None) => {
            let options = RadiosityOptions { subdivide: a.subdivide, budget, ..Default::default() };
            let solution = super::radiosity::solve(scene, &options, &a.input)?;
            let s = solution.stats();
            out!(
                "radiosity: {} patches, {} elements, {} shots, unshot {:.4}",
                s.patches,
                s.elements,
                s.shots,
                s.unshot_fraction
            );
            stages.done("solving radiosity");
            solution
        }
    };
    scene.illumination = Some(Arc::new(solution.showing_elements(a.show_elements)));
    Ok(())
}

/// Image width / height: `--size`, else the options'.
fn size_aspect(size: Option<[u32; 2]>, options: &RenderOptions) -> f64 {
    let [w, h] = size.unwrap_or([options.width, options.height]);
    f64::from(w) / f64::from(h.max(1))
}

/// The scene of one solid file (`.oct`, `.vox`, `.binvox`, `.vdb`, or a mesh or patches
/// voxelized at `depth`) with the default lights.
fn solid_scene(
    input: &Path,
    kind: FileKind,
    source: &Source,
    budget: MemoryBudget,
    stages: &mut Stages,
) -> Result<Drawn> {
    let Source { depth, up, read } = source;
    let (tree, recorded_up, coloured) = if FileKind::SOLIDS.contains(&kind) {
        // A sharded solid gets a quarter of the budget: the picture needs the rest.
        let file = read_for_display(input, read, MemoryBudget(budget.0 / 4))?;
        stages.done("loading");
        let up = file.meta.up;
        // One solid without a colour is drawn as it always was; else each in its colour.
        if matches!(file.solids.solids.as_slice(), [one] if one.color.is_none()) {
            (file.into_union(), up, None)
        } else {
            (file.union(), up, Some(file.solids))
        }
    } else {
        let loaded = load_input(input)?;
        stages.done("loading");
        let domain = import::default_domain(&loaded, depth.unwrap_or(9))
            .with_context(|| format!("{}: cannot voxelize", input.display()))?;
        let bar = Bar::new("voxelizing");
        let tree =
            import::voxelize_input(&loaded, domain, &ImportOptions { budget, progress: &bar, ..Default::default() })
                .with_context(|| format!("{}: cannot voxelize", input.display()))?
                .0;
        stages.done("voxelizing");
        (tree, None, None)
    };
    let bounds = tree.bounds().with_context(|| format!("{}: the solid is empty", input.display()))?;
    let up = up.unwrap_or(Up::Axis(recorded_up.unwrap_or(kind.default_up())));
    let framing = Framing { points: silhouette_points(&tree), up, scene_camera: None };
    let mut scene = match coloured {
        None => {
            let mut scene = Scene::from_solid(tree);
            scene.solids[0].name = input.display().to_string();
            scene
        }
        Some(solids) => solids.scene(&input.display().to_string(), &bounds),
    };
    stages.done("building the traversal");
    if up.axis() != Axis::Z {
        let c = bounds.center();
        let r = bounds.size().length();
        let view = Camera::default_view(up.axis());
        scene.lights[0] = Light::Point { position: c + (view + up.vector() * 1.5) * r, color: DVec3::splat(0.85) };
    }
    Ok(Drawn { scene, framed: Framed::Solid(framing), options: RenderOptions::default() })
}

/// `octsolid render IN --shading flat|gouraud|phong`: a mesh drawn as polygons
/// (patches tessellated, a solid's boundary in unit faces).
fn polygon_command(
    a: &RenderArgs,
    kind: FileKind,
    output: &Path,
    interpolation: render::polygon::Interpolation,
    budget: MemoryBudget,
) -> Result<()> {
    let input = &a.input;
    let mut stages = Stages::new();
    let (mesh, recorded_up) = if FileKind::SOLIDS.contains(&kind) {
        // The solid's boundary (several solids': their union's), in unit faces so that
        // vertex normals average locally.
        let file = read_solid_file(input, &a.read, budget)?;
        let up = file.meta.up;
        let tree = file.into_union();
        (try_boundary_mesh(&tree, &BoundaryOptions { unit_faces: true }, budget, &Bar::new("meshing"))?, up)
    } else {
        let mesh = match load_input(input)? {
            Input::Mesh(mesh) => mesh,
            Input::Patches(patches) => octsolid::patch::tessellate_within(&patches, 16, budget)?,
        };
        (mesh, None)
    };
    stages.done("loading");
    if mesh.triangles.is_empty() {
        bail!("{}: nothing to draw", input.display());
    }
    let bounds = mesh.bounds();
    let [width, height] = a.size.unwrap_or([960, 720]);
    let up = a.camera.up.unwrap_or(Up::Axis(recorded_up.unwrap_or(kind.default_up())));
    let framing = Framing { points: mesh.vertices.clone(), up, scene_camera: None };
    let camera = camera_flags::camera(&a.camera, &framing, f64::from(width) / f64::from(height.max(1)))?;
    let scene = render::polygon::MeshScene {
        mesh: &mesh,
        material: Material::default(),
        lights: Scene::default_lights(&bounds),
        ambient: DVec3::ONE,
        background: Scene::new().background,
    };
    let spp = a.spp.unwrap_or(2);
    let exposure = a.exposure.unwrap_or(0.0);
    let options = render::polygon::MeshRenderOptions { width, height, spp, interpolation, budget, exposure };
    let picture = render::polygon::render_mesh(&scene, &camera, &options)
        .with_context(|| format!("{}: cannot render", input.display()))?;
    stages.done("drawing");
    let shading = format!("{interpolation:?}").to_lowercase();
    out!("drew {} triangles with {shading} shading", mesh.triangles.len());
    save_picture(&picture, output)?;
    stages.done("writing");
    out!("wrote {} ({}x{})", output.display(), picture.width(), picture.height());
    stages.report();
    Ok(())
}

/// Wall-clock time of each stage of a command, printed at the end with the total.
pub(crate) struct Stages {
    started: Instant,
    last: Instant,
    done: Vec<(String, f64)>,
}

impl Stages {
    pub(crate) fn new() -> Self {
        let now = Instant::now();
        Stages { started: now, last: now, done: Vec::new() }
    }

    pub(crate) fn done(&mut self, stage: impl Into<String>) {
        let now = Instant::now();
        self.done.push((stage.into(), (now - self.last).as_secs_f64()));
        self.last = now;
    }

    fn report(&self) {
        let parts: Vec<String> = self.done.iter().map(|(stage, s)| format!("{stage} {s:.2} s")).collect();
        out!("time       {:.2} s: {}", self.started.elapsed().as_secs_f64(), parts.join(", "));
    }
}
