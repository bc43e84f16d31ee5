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

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use octsolid::import::Input;
use octsolid::io::write_picture;
use octsolid::mesh::{BoundaryOptions, try_boundary_mesh};
use octsolid::render::polygon::{DepthSortCounts, Interpolation, MeshVisibility};
use octsolid::render::radiosity::{Radiosity, RadiosityOptions};
use octsolid::render::{
    self, AntiAliasingKind, Framing, Material, Method, Normals, RenderOverrides, Scene, Section, Up,
};
use octsolid::scene_file::{self, CachePolicy};
use octsolid::{FileKind, MemoryBudget};

use super::{read_input, render_with_bar};
use crate::camera_flags::{CameraFlags, in_flags_words};
use crate::drawn::{self, Source};
use crate::output::check_extension;
use crate::progress_bar::Bar;
use crate::solid_input::{ReadFlags, read_solid_file};
use crate::stages::Stages;
use crate::values::{names, parse_size};

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
    /// How primary visibility is decided: trace (rays through the octree),
    /// front-to-back (Meagher's display), painter, zbuffer or scanline (every method
    /// finds the same hits; the front-to-back display, the default, a whole image's
    /// fastest). With --shading (polygons): painter (the depth sort with its five
    /// overlap tests, swaps and splits), zbuffer or scanline (the default).
    #[arg(long, value_parser = names::<Method>(Method::ALL.map(Method::name)))]
    pub method: Option<Method>,
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
    #[arg(long, value_parser = names::<Normals>(Normals::ALL.map(Normals::name)))]
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
    #[arg(long, value_parser = names::<AntiAliasingKind>(AntiAliasingKind::ALL.map(AntiAliasingKind::name)))]
    pub aa: Option<AntiAliasingKind>,
    /// Contrast that makes adaptive anti-aliasing supersample a pixel (recursive: split
    /// a square): the sum of the red, green and blue differences with a neighbour (a
    /// corner), 0 to 3; above 3 nothing is supersampled (default: the scene's, or 0.3;
    /// implies --aa adaptive unless --aa is given or the scene's is recursive).
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
    #[arg(long, allow_hyphen_values = true)]
    pub section: Option<Section>,
    /// Render a mesh (or Bezier patches, tessellated) as polygons with this
    /// interpolation shading instead of voxelizing it: flat (one colour a triangle),
    /// gouraud (vertex colours interpolated) or phong (vertex normals interpolated).
    #[arg(long, value_parser = names::<Interpolation>(Interpolation::ALL.map(Interpolation::name)))]
    pub shading: Option<Interpolation>,
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

impl RenderArgs {
    /// The library's option overrides these flags make.
    pub(crate) fn overrides(&self) -> RenderOverrides {
        RenderOverrides {
            size: self.size,
            spp: self.spp,
            method: self.method,
            shadows: self.no_shadows.then_some(false),
            normals: self.normals,
            max_depth: self.max_depth,
            cutoff: self.cutoff,
            aa: self.aa,
            aa_threshold: self.aa_threshold,
            aa_depth: self.aa_depth,
            exposure: self.exposure,
        }
    }
}

/// `octsolid render IN [-o OUT] [--size WxH] [--spp N] [--method M] [--depth D] [camera flags] [--shading S]`
pub fn run(a: &RenderArgs, budget: MemoryBudget) -> Result<()> {
    let input = &a.input;
    let output = a
        .output
        .clone()
        .unwrap_or_else(|| Path::new(input.file_stem().unwrap_or_default()).with_extension(FileKind::Png.extension()));
    check_extension(&output, FileKind::PICTURES)?;
    let mut stages = Stages::new();
    let kind = FileKind::of(input, FileKind::DRAWN)?;
    if let Some(interpolation) = a.shading {
        // Meshes, patch sets (tessellated) and solids (their boundary); not scenes.
        if kind == FileKind::Scene {
            bail!("{}: --shading draws a mesh or a solid as polygons, not a scene", input.display());
        }
        return polygon_command(a, kind, &output, interpolation, budget);
    }
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
    let drawn = drawn::open(input, kind, &source, cache, budget, &mut stages)?;
    let (request, overrides) = (a.camera.request(), a.overrides());
    let camera = drawn.camera(&request, &overrides, a.section).map_err(in_flags_words)?;
    let options = drawn.options(&overrides, budget);
    let mut scene = drawn.into_scene(a.section);
    light_by_radiosity(a, &mut scene, budget, &mut stages)?;
    let picture =
        render_with_bar(&scene, &camera, &options).with_context(|| format!("{}: cannot render", input.display()))?;
    stages.done("rendering");
    write_out(&picture, &output, stages)
}

/// Attaches the radiosity solution `--radiosity` and `--illumination` ask for, if any:
/// loaded (and checked against the scene) or solved now.
fn light_by_radiosity(a: &RenderArgs, scene: &mut Scene, budget: MemoryBudget, stages: &mut Stages) -> Result<()> {
    let direct = matches!(a.illumination, Some(Illumination::Direct) | None) && a.radiosity.is_none();
    if a.illumination == Some(Illumination::Direct) && a.radiosity.is_some() {
        bail!("--radiosity needs --illumination radiosity (or no --illumination)");
    } else if direct && a.show_elements {
        bail!("--show-elements needs radiosity: --radiosity SOLUTION.rad or --illumination radiosity");
    } else if direct && a.subdivide.is_some() {
        bail!("--subdivide needs a radiosity solution solved here: --illumination radiosity");
    } else if direct {
        return Ok(());
    }
    let solution = if let Some(path) = &a.radiosity {
        let solution = Radiosity::read(path, scene, budget)
            .with_context(|| format!("{}: cannot use the solution for {}", path.display(), a.input.display()))?;
        stages.done("loading the radiosity solution");
        solution
    } else {
        let options = RadiosityOptions { subdivide: a.subdivide, budget, ..Default::default() };
        let solution = super::radiosity::solve(scene, &options, &a.input)?;
        let s = solution.stats();
        let (patches, elements, shots, unshot) = (s.patches, s.elements, s.shots, s.unshot_fraction);
        out!("radiosity: {patches} patches, {elements} elements, {shots} shots, unshot {unshot:.4}");
        stages.done("solving radiosity");
        solution
    };
    scene.illumination = Some(Arc::new(solution.showing_elements(a.show_elements)));
    Ok(())
}

/// `octsolid render IN --shading flat|gouraud|phong`: a mesh drawn as polygons
/// (patches tessellated, a solid's boundary in unit faces).
fn polygon_command(
    a: &RenderArgs,
    kind: FileKind,
    output: &Path,
    interpolation: Interpolation,
    budget: MemoryBudget,
) -> Result<()> {
    let input = &a.input;
    let method = a.method.unwrap_or(Method::ScanLine);
    let Some(visibility) = MeshVisibility::of(method) else {
        bail!("--method {method} walks octrees: polygons are drawn by painter, zbuffer or scanline");
    };
    let mut stages = Stages::new();
    let (mesh, recorded_up) = if FileKind::SOLIDS.contains(&kind) {
        // The solid's boundary (several solids': their union's), in unit faces so that
        // vertex normals average locally.
        let file = read_solid_file(input, &a.read, budget)?;
        let up = file.meta.up;
        let tree = file.into_union();
        (try_boundary_mesh(&tree, &BoundaryOptions { unit_faces: true }, budget, &Bar::new("meshing"))?, up)
    } else {
        let mesh = match read_input(input)? {
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
    let aspect = f64::from(width) / f64::from(height.max(1));
    let camera = a.camera.request().camera(&framing, aspect).map_err(crate::camera_flags::in_flags_words)?;
    let scene = render::polygon::MeshScene {
        mesh: &mesh,
        material: Material::default(),
        lights: Scene::default_lights(&bounds),
        ambient: glam::DVec3::ONE,
        background: Scene::new().background,
    };
    let (spp, exposure) = (a.spp.unwrap_or(2), a.exposure.unwrap_or(0.0));
    let options = render::polygon::MeshRenderOptions { width, height, spp, interpolation, budget, exposure };
    let (picture, counts) = render::polygon::render_mesh_by(&scene, &camera, &options, visibility)
        .with_context(|| format!("{}: cannot render", input.display()))?;
    stages.done("drawing");
    out!("drew {} triangles with {interpolation} shading by {method}", mesh.triangles.len());
    if visibility == MeshVisibility::Painter {
        report_depth_sort(&counts);
    }
    write_out(&picture, output, stages)
}

/// The depth sort's summary: the pairs each of the five tests settled, swaps, splits.
fn report_depth_sort(c: &DepthSortCounts) {
    out!(
        "depth sort: pairs settled by x extents {}, y extents {}, behind plane {}, in front of plane {}, \
         disjoint projections {}; {} swaps, {} splits, {} polygons drawn",
        c.x_extents,
        c.y_extents,
        c.behind_plane,
        c.in_front_of_plane,
        c.projections_disjoint,
        c.swaps,
        c.splits,
        c.drawn
    );
    if c.unresolved > 0 {
        warn!("depth sort: {} polygons drawn with their order undecided", c.unresolved);
    }
}

/// Writes the picture, then the stages' report.
fn write_out(picture: &render::Picture, output: &Path, mut stages: Stages) -> Result<()> {
    write_picture(picture, output)?;
    stages.done("writing");
    out!("wrote {} ({}x{})", output.display(), picture.width(), picture.height());
    stages.report();
    Ok(())
}
