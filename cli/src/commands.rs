//! One function a subcommand: validate, call the library, print a summary.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use glam::DVec3;
use octsolid::FileKind;
use octsolid::MemoryBudget;
use octsolid::human_bytes;
use octsolid::import::{self, Fill, ImportOptions, Input};
use octsolid::io::{oct, png};
use octsolid::mesh::{BoundaryOptions, InsideRule, MeshFormat, save_mesh, try_boundary_mesh};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::{self, Camera, DEFAULT_VIEW, Light, Material, RenderOptions, Scene};
use octsolid::samples;
use octsolid::scene_file;
use octsolid::shape::{Axis, Shape};
use octsolid_harness::markdown::render_section;
use octsolid_harness::report::IMAGES;
use octsolid_harness::{MatrixOptions, run_matrix, write_report};
use serde::Serialize;

use super::args::{Args, Command, CsgOp, RenderArgs, ShapeArgs};
use super::progress_bar::Bar;

/// Runs the parsed command line.
pub fn run(args: Args) -> Result<()> {
    let budget = args.memory_budget.map_or_else(MemoryBudget::default, MemoryBudget);
    match args.command {
        Command::Shape(shape) => shape_command(&shape, budget),
        Command::Csg { op, inputs, output } => csg_command(op, &inputs, &output, budget),
        Command::Info { file, json } => info_command(&file, json, budget),
        Command::Slice { file, axis, at, size, output } => slice_command(&file, axis, at, size, &output, budget),
        Command::Voxelize { input, depth, fill, inside, domain, output } => {
            voxelize_command(&input, depth, fill, inside, domain, &output, budget)
        }
        Command::MeshInfo { input, json } => mesh_info_command(&input, json),
        Command::Export { file, output, unit_faces } => export_command(&file, &output, unit_faces, budget),
        Command::Render(render) => render_command(&render, budget),
        Command::Demo { output, depth } => demo_command(&output, depth, budget),
        Command::Bench { report, quick, out, threads, models } => {
            bench_command(report, quick, &out, threads, models, budget)
        }
    }
}

/// `octsolid shape KIND ...`
fn shape_command(a: &ShapeArgs, budget: MemoryBudget) -> Result<()> {
    let spec = a.spec();
    let shape = spec.build()?;
    let domain = match a.domain {
        Some([x, y, z, edge]) => Domain::new(DVec3::new(x, y, z), edge, a.depth)?,
        None => Domain::around(&shape.bounds().context("the shape is unbounded; give --domain")?, 0.02, a.depth)?,
    };
    let tree = voxelize_with_bar(&shape, domain, budget)?;
    let bytes = oct::save(&tree, &a.output)?;
    out!("wrote {} ({})", a.output.display(), human_bytes(bytes));
    print_summary(&tree, spec.volume());
    Ok(())
}

/// `octsolid voxelize IN --depth D [--fill F] [--inside R] [--domain ...] -o OUT`
fn voxelize_command(
    input: &Path,
    depth: u8,
    fill: Fill,
    inside: InsideRule,
    domain: Option<[f64; 4]>,
    output: &Path,
    budget: MemoryBudget,
) -> Result<()> {
    let started = Instant::now();
    let loaded = Input::load(input)?;
    let domain = match domain {
        Some([x, y, z, edge]) => Domain::new(DVec3::new(x, y, z), edge, depth)?,
        None => import::default_domain(&loaded, depth)?,
    };
    let bar = Bar::new("voxelizing");
    let (tree, summary) =
        import::voxelize_input(&loaded, domain, &ImportOptions { fill, inside, budget, progress: &bar })
            .with_context(|| format!("{}: cannot voxelize", input.display()))?;
    let elapsed = started.elapsed().as_secs_f64();
    let bytes = oct::save(&tree, output)?;
    out!("read       {} ({} triangles)", input.display(), summary.triangles);
    if let Some(rule) = summary.rule {
        out!("inside     {rule:?} rule{}", if inside == InsideRule::Auto { " (auto)" } else { "" });
    }
    print_summary(&tree, None);
    match summary.mesh_volume {
        Some(v) if v.abs() > 0.0 => {
            out!("mesh vol.  {v:.6} ({:+.3}% voxelized vs mesh)", 100.0 * (tree.volume() / v - 1.0))
        }
        Some(_) => out!("mesh vol.  0 (the mesh encloses no volume)"),
        None => {}
    }
    out!("time       {:.1} ms (load and voxelize)", elapsed * 1e3);
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    Ok(())
}

/// `octsolid export FILE.oct -o OUT.(obj|stl|ply) [--unit-faces]`
fn export_command(file: &Path, output: &Path, unit_faces: bool, budget: MemoryBudget) -> Result<()> {
    MeshFormat::of(output)?;
    let tree = oct::load(file, budget)?;
    if tree.is_empty() {
        bail!("{}: the solid is empty; there is no boundary to export", file.display());
    }
    let started = Instant::now();
    let bar = Bar::new("meshing");
    let mesh = try_boundary_mesh(&tree, &BoundaryOptions { unit_faces }, budget, &bar)
        .with_context(|| format!("{}: cannot export", file.display()))?;
    let elapsed = started.elapsed().as_secs_f64();
    let bytes = save_mesh(&mesh, output)?;
    let faces = if unit_faces { "unit faces" } else { "merged faces" };
    out!("read       {} ({} nodes, depth {})", file.display(), tree.node_count(), tree.depth());
    out!("mesh       {} triangles, {} vertices ({faces})", mesh.triangles.len(), mesh.vertices.len());
    let (enclosed, volume) = (mesh.volume(), tree.volume());
    out!("volume     {enclosed:.6} enclosed, {volume:.6} octree ({:+.1e} relative)", enclosed / volume - 1.0);
    out!("time       {:.1} ms (boundary mesh)", elapsed * 1e3);
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    Ok(())
}

/// `octsolid mesh-info IN [--json]`
fn mesh_info_command(input: &Path, json: bool) -> Result<()> {
    let report = Input::load(input)?.report();
    if json {
        out!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    out!("file               {}", input.display());
    out!("vertices           {}", report.vertices);
    out!("triangles          {}", report.triangles);
    out!("edges              {}", report.edges);
    out!("degenerate faces   {}", report.degenerate_faces);
    out!("boundary edges     {}", report.boundary_edges);
    out!("non-manifold edges {}", report.non_manifold_edges);
    out!("misoriented edges  {}", report.misoriented_edges);
    out!("watertight         {}", if report.watertight { "yes" } else { "no" });
    out!(
        "volume             {:.6} (signed tetrahedra{})",
        report.volume,
        if report.watertight { "" } else { "; not closed" }
    );
    out!("area               {:.6}", report.area);
    out!("bounds             {:?} .. {:?}", report.bounds_min, report.bounds_max);
    for (name, count) in &report.groups {
        out!("group              {name:?}: {count} triangles");
    }
    Ok(())
}

/// Voxelizes with a progress bar and prints the time taken.
fn voxelize_with_bar(shape: &dyn Shape, domain: Domain, budget: MemoryBudget) -> Result<LinearOctree> {
    let bar = Bar::new("voxelizing");
    let started = Instant::now();
    let tree = voxelize(shape, domain, &VoxelizeOptions { budget, progress: &bar })?;
    out!("voxelized at depth {} in {:.1} ms", domain.depth(), started.elapsed().as_secs_f64() * 1e3);
    Ok(tree)
}

/// `octsolid csg OP A B [MORE...] -o OUT`
fn csg_command(op: CsgOp, inputs: &[std::path::PathBuf], output: &Path, budget: MemoryBudget) -> Result<()> {
    let mut trees = Vec::with_capacity(inputs.len());
    for path in inputs {
        trees.push(oct::load(path, budget)?);
    }
    let started = Instant::now();
    let mut result = trees[0].clone();
    for (tree, path) in trees.iter().zip(inputs).skip(1) {
        result = match op {
            CsgOp::Union => result.union(tree),
            CsgOp::Intersect => result.intersection(tree),
            CsgOp::Difference => result.difference(tree),
            CsgOp::Xor => result.symmetric_difference(tree),
        }
        .with_context(|| format!("{}: cannot combine with {}", path.display(), inputs[0].display()))?;
    }
    out!("{op:?} of {} solids in {:.2} ms", trees.len(), started.elapsed().as_secs_f64() * 1e3);
    let bytes = oct::save(&result, output)?;
    out!("wrote {} ({})", output.display(), human_bytes(bytes));
    print_summary(&result, None);
    Ok(())
}

/// What `octsolid info --json` prints; the key names are a contract.
#[derive(Serialize)]
struct Info {
    depth: u8,
    domain: DomainInfo,
    nodes: usize,
    voxels: u64,
    volume: f64,
    bounds: Option<BoundsInfo>,
    bytes_memory: usize,
    bytes_file: u64,
}

#[derive(Serialize)]
struct DomainInfo {
    min: [f64; 3],
    edge: f64,
}

#[derive(Serialize)]
struct BoundsInfo {
    min: [f64; 3],
    max: [f64; 3],
}

/// `octsolid info FILE [--json]`
fn info_command(file: &Path, json: bool, budget: MemoryBudget) -> Result<()> {
    let tree = oct::load(file, budget)?;
    let bytes_file = std::fs::metadata(file).with_context(|| format!("{}", file.display()))?.len();
    let d = tree.domain();
    let info = Info {
        depth: d.depth(),
        domain: DomainInfo { min: d.min().to_array(), edge: d.edge() },
        nodes: tree.node_count(),
        voxels: tree.voxel_count(),
        volume: tree.volume(),
        bounds: tree.bounds().map(|b| BoundsInfo { min: b.min.to_array(), max: b.max.to_array() }),
        bytes_memory: tree.bytes(),
        bytes_file,
    };
    if json {
        out!("{}", serde_json::to_string(&info)?);
        return Ok(());
    }
    out!("file       {}", file.display());
    out!("depth      {} ({} voxels a side, voxel edge {})", info.depth, d.resolution(), d.voxel_size());
    out!("domain     min {:?} edge {}", info.domain.min, info.domain.edge);
    print_summary(&tree, None);
    let per_node = |b: f64| if info.nodes == 0 { 0.0 } else { b / info.nodes as f64 };
    out!("on disk    {} ({:.2} bytes a node)", human_bytes(bytes_file), per_node(bytes_file as f64));
    Ok(())
}

/// Prints nodes, voxels, volume (with the exact one when known), bounds and memory.
fn print_summary(tree: &LinearOctree, exact_volume: Option<f64>) {
    out!("nodes      {}", tree.node_count());
    out!("voxels     {}", tree.voxel_count());
    match exact_volume {
        Some(v) => {
            out!("volume     {:.6} (analytic {:.6}, {:+.3}%)", tree.volume(), v, 100.0 * (tree.volume() - v) / v)
        }
        None => out!("volume     {:.6}", tree.volume()),
    }
    match tree.bounds() {
        Some(b) => out!("bounds     {:?} .. {:?}", b.min.to_array(), b.max.to_array()),
        None => out!("bounds     (empty)"),
    }
    let per_node = if tree.node_count() == 0 { 0.0 } else { tree.bytes() as f64 / tree.node_count() as f64 };
    out!("in memory  {} ({per_node:.2} bytes a node)", human_bytes(tree.bytes() as u64));
}

/// `octsolid slice FILE --axis A --at V [--size N] -o OUT.png`
fn slice_command(
    file: &Path,
    axis: Axis,
    at: Option<f64>,
    size: u32,
    output: &Path,
    budget: MemoryBudget,
) -> Result<()> {
    let tree = oct::load(file, budget)?;
    let d = tree.domain();
    let at = at.unwrap_or(d.min()[axis.index()] + 0.5 * d.edge());
    let img = octsolid::slice::slice_image(&tree, axis.index(), at, size)
        .with_context(|| format!("{}: cannot slice", file.display()))?;
    png::save(&img, output)?;
    out!("wrote {} ({size}x{size}, {axis:?} = {at})", output.display());
    Ok(())
}

/// `octsolid demo`: the showcase scene, voxelized and ray-traced.
fn demo_command(output: &Path, depth: u8, budget: MemoryBudget) -> Result<()> {
    if output.extension().is_none_or(|e| !e.eq_ignore_ascii_case("png")) {
        bail!("{}: the demo writes a PNG image; give a .png path", output.display());
    }
    out!("showcase: {}", samples::SCENE_DESCRIPTION);
    let started = Instant::now();
    let bar = Bar::new("voxelizing");
    let scene = samples::showcase_scene(depth, &VoxelizeOptions { budget, progress: &bar })?;
    let nodes: usize = scene.solids.iter().map(|s| s.tree.node_count()).sum();
    out!(
        "voxelized {} solids at depth {depth}: {nodes} nodes in {:.0} ms",
        scene.solids.len(),
        started.elapsed().as_secs_f64() * 1e3
    );
    let bounds = scene.bounds().context("the showcase is empty")?;
    let options = RenderOptions { width: 1200, height: 720, spp: 3, ..Default::default() };
    let camera = Camera::frame(&bounds, DEFAULT_VIEW, DVec3::Z, f64::from(options.width) / f64::from(options.height));
    let img = render_with_bar(&scene, &camera, &options)?;
    png::save(&img, output)?;
    out!("wrote {} ({}x{})", output.display(), img.width(), img.height());
    Ok(())
}

/// What `render --shading` draws as polygons: meshes, patch sets (tessellated) and
/// solids (their boundary); not scenes.
const POLYGON_INPUTS: &[FileKind] = &[FileKind::Oct, FileKind::Obj, FileKind::Stl, FileKind::Ply, FileKind::Patches];

/// `octsolid render IN [-o OUT] [--size WxH] [--spp N] [--method M] [--depth D] [--up A] [--shading S]`
fn render_command(a: &RenderArgs, budget: MemoryBudget) -> Result<()> {
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
    let mut scene = Scene::new();
    scene.add(input.display().to_string(), tree, Material::default());
    scene.lights = Scene::default_lights(&bounds);
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

/// Renders with a progress bar and prints samples and rays a second (and faces drawn by
/// a raster method).
fn render_with_bar(scene: &Scene, camera: &Camera, options: &RenderOptions) -> Result<image::RgbImage> {
    let bar = Bar::new("rendering");
    let started = Instant::now();
    let (img, stats) = render::render(scene, camera, options, &bar)?;
    let seconds = started.elapsed().as_secs_f64();
    let secondary = stats.secondary_rays;
    let visibility = match options.method {
        // Every sample is a primary ray.
        render::Method::Trace => {
            let rays = stats.samples + secondary;
            let rate = rays as f64 / seconds / 1e6;
            format!("{rays} rays: {} primary, {secondary} secondary and shadow; {rate:.2} M rays/s", stats.samples)
        }
        _ => format!("{} faces drawn, {secondary} secondary and shadow rays", stats.faces_drawn),
    };
    out!(
        "rendered {}x{} at {}x{} samples a pixel by {:?} in {:.2} s ({:.2} M samples/s; {visibility})",
        options.width,
        options.height,
        options.spp,
        options.spp,
        options.method,
        seconds,
        stats.samples as f64 / seconds / 1e6,
    );
    Ok(img)
}

/// `octsolid bench [--report] [--quick] [--out FILE] [--threads N] [--models DIR]`
fn bench_command(
    report: bool,
    quick: bool,
    out: &Path,
    threads: Option<usize>,
    models: std::path::PathBuf,
    budget: MemoryBudget,
) -> Result<()> {
    let mut options = if quick { MatrixOptions::quick() } else { MatrixOptions::full() };
    if let Some(n) = threads {
        if n == 0 {
            bail!("--threads must be at least 1");
        }
        options.threads = n;
    }
    options.models = models;
    options.budget = budget;
    let started = Instant::now();
    let bar = Bar::new("benchmarking");
    let results = run_matrix(&options, &bar)?;
    out!("ran the matrix in {:.0} s", started.elapsed().as_secs_f64());
    if report {
        for path in write_report(&results, out)? {
            out!("wrote {}", path.display());
        }
    } else {
        out!("{}", render_section(&results, IMAGES, &[]));
    }
    Ok(())
}
