//! `octsolid render IN [-o OUT] [...]`: a scene file, a solid, or a mesh (voxelized
//! first, or drawn as polygons with `--shading`) rendered to a PNG.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::ValueEnum;
use glam::DVec3;
use octsolid::import::{self, ImportOptions, Input};
use octsolid::io::{oct, png};
use octsolid::mesh::{BoundaryOptions, try_boundary_mesh};
use octsolid::render::{self, Camera, Light, Material, RenderOptions, Scene};
use octsolid::scene_file;
use octsolid::shape::Axis;
use octsolid::{FileKind, MemoryBudget};

use super::render_with_bar;
use crate::args::parse_size;
use crate::progress_bar::Bar;

/// Arguments of `octsolid render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene (.toml), solid (.oct) or mesh (.obj, .stl, .ply, .patches).
    pub input: PathBuf,
    /// Output PNG (default: the input's name with .png, in the current folder).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Image size WIDTHxHEIGHT (default: the scene's, or 960x720).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<[u32; 2]>,
    /// Samples a pixel side: N x N stratified samples (default: the scene's, or 2).
    #[arg(long)]
    pub spp: Option<u32>,
    /// How primary visibility is decided.
    #[arg(long, default_value = "trace")]
    pub method: Method,
    /// Depth to voxelize a mesh at.
    #[arg(long, default_value_t = 9)]
    pub depth: u8,
    /// The world's up axis for solids and meshes without a scene (default by the
    /// file's extension: y for .obj and .ply, y-up by convention, as the bunny and
    /// Spot are; z otherwise, as octsolid's shapes are: pass --up z to view a shape
    /// exported to .obj or .ply as it was built).
    #[arg(long)]
    pub up: Option<octsolid::shape::Axis>,
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
    /// Render a mesh (or Bezier patches, tessellated) as polygons with this
    /// interpolation shading instead of voxelizing it.
    #[arg(long)]
    pub shading: Option<Shading>,
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

/// What `render --shading` draws as polygons: meshes, patch sets (tessellated) and
/// solids (their boundary); not scenes.
const POLYGON_INPUTS: &[FileKind] = &[FileKind::Oct, FileKind::Obj, FileKind::Stl, FileKind::Ply, FileKind::Patches];

/// `octsolid render IN [-o OUT] [--size WxH] [--spp N] [--method M] [--depth D] [--up A] [--shading S]`
pub fn run(a: &RenderArgs, budget: MemoryBudget) -> Result<()> {
    let input = &a.input;
    let output =
        a.output.clone().unwrap_or_else(|| Path::new(input.file_stem().unwrap_or_default()).with_extension("png"));
    if let Some(interpolation) = a.shading {
        let kind = FileKind::of(input, POLYGON_INPUTS)?;
        return polygon_command(a, kind, &output, interpolation.into(), budget);
    }
    let (scene, camera, mut options) = match FileKind::of(input, FileKind::ALL)? {
        FileKind::Scene => {
            let file = scene_file::load_scene(input, budget)?;
            (file.scene, file.camera, file.options)
        }
        kind => solid_scene(a, kind, budget)?,
    };
    if let Some([w, h]) = a.size {
        options.width = w;
        options.height = h;
    }
    if let Some(n) = a.spp {
        options.spp = n;
    }
    options.shadows &= !a.no_shadows;
    options.normals = a.normals.map_or(options.normals, Into::into);
    options.max_depth = a.max_depth.unwrap_or(options.max_depth);
    options.method = a.method.into();
    let img =
        render_with_bar(&scene, &camera, &options).with_context(|| format!("{}: cannot render", input.display()))?;
    png::save(&img, &output)?;
    out!("wrote {} ({}x{})", output.display(), img.width(), img.height());
    Ok(())
}

/// The scene of one solid file (`.oct`, or a mesh or patches voxelized at `--depth`)
/// with the default lights and camera for its up axis (`--up`, else its kind's).
fn solid_scene(a: &RenderArgs, kind: FileKind, budget: MemoryBudget) -> Result<(Scene, Camera, RenderOptions)> {
    let input = &a.input;
    let tree = if kind == FileKind::Oct {
        oct::load(input, budget)?
    } else {
        let loaded = Input::load(input)?;
        let domain = import::default_domain(&loaded, a.depth)?;
        let bar = Bar::new("voxelizing");
        import::voxelize_input(&loaded, domain, &ImportOptions { budget, progress: &bar, ..Default::default() })
            .with_context(|| format!("{}: cannot voxelize", input.display()))?
            .0
    };
    let bounds = tree.bounds().with_context(|| format!("{}: the solid is empty", input.display()))?;
    let mut scene = Scene::from_solid(tree);
    scene.solids[0].name = input.display().to_string();
    let options = RenderOptions::default();
    let up = a.up.unwrap_or(kind.default_up());
    let (up_vec, view) = (up.unit(), Camera::default_view(up));
    if up != Axis::Z {
        let c = bounds.center();
        let r = bounds.size().length();
        scene.lights[0] = Light::Point { position: c + (view + up_vec * 1.5) * r, color: DVec3::splat(0.85) };
    }
    let aspect = f64::from(options.width) / f64::from(options.height);
    Ok((scene, Camera::frame(&bounds, view, up_vec, aspect), options))
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
    let mesh = if kind == FileKind::Oct {
        // The solid's boundary, in unit faces so that vertex normals average locally.
        let tree = oct::load(input, budget)?;
        try_boundary_mesh(&tree, &BoundaryOptions { unit_faces: true }, budget, &Bar::new("meshing"))?
    } else {
        match Input::load(input)? {
            Input::Mesh(mesh) => mesh,
            Input::Patches(patches) => octsolid::patch::tessellate(&patches, 16),
        }
    };
    if mesh.triangles.is_empty() {
        bail!("{}: nothing to draw", input.display());
    }
    let bounds = mesh.bounds();
    let [width, height] = a.size.unwrap_or([960, 720]);
    let up = a.up.unwrap_or(kind.default_up());
    let camera =
        Camera::frame(&bounds, Camera::default_view(up), up.unit(), f64::from(width) / f64::from(height.max(1)));
    let scene = render::polygon::MeshScene {
        mesh: &mesh,
        material: Material::default(),
        lights: Scene::default_lights(&bounds),
        ambient: DVec3::ONE,
        background: Scene::new().background,
    };
    let started = Instant::now();
    let img = render::polygon::render_mesh(&scene, &camera, width, height, a.spp.unwrap_or(2), interpolation)
        .with_context(|| format!("{}: cannot render", input.display()))?;
    out!(
        "drew {} triangles with {interpolation:?} shading in {:.2} s",
        mesh.triangles.len(),
        started.elapsed().as_secs_f64()
    );
    png::save(&img, output)?;
    out!("wrote {} ({}x{})", output.display(), img.width(), img.height());
    Ok(())
}
