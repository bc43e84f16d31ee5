//! Primary visibility by every method on the bunny at depth 10, 1024x1024, one sample
//! a pixel (no shading), into one frame buffer kept between frames as a viewer keeps
//! it: the octree display's frames a second against the ray tracer.
//! Target: front-to-back display at 20 frames a second or more.
//!
//! `shading_normals`: a whole default render of the bunny at depth 9 (960x720, 2x2
//! samples, shadows, the CLI's y-up framing; `Scene::from_solid`) with axis normals
//! and with the octree's estimated normals, each iteration on a fresh scene (cold
//! normal caches, as one CLI run). Target: the estimate costs at most 1.5x the axis
//! render.
//!
//! `viewer_frame`: what `octsolid view` does for a moving frame, server side: the bunny
//! at depth 10 rendered at 1280x720 by the front-to-back display (1 sample a pixel,
//! axis normals, no shadows) and encoded as the PNG it sends. Target: 40 ms.
//!
//! `hard_views`: primary visibility (800x600, one sample a pixel) of views an
//! object-order display finds hard (`common/hard_views.rs`: the eye inside a large
//! floor's domain, a grazing floor, the eye inside a bore, a narrow close-up) by the
//! default front-to-back display and by the ray walk. Target: the default within 25%
//! of the faster of the two on every view.

use criterion::{BatchSize, BenchmarkId, Criterion, criterion_group, criterion_main};
use octsolid::io::png;
use octsolid::mesh::{MeshVoxelizeOptions, read_mesh, voxelize_mesh};
use octsolid::octree::{Domain, LinearOctree};
use octsolid::render::{
    Camera, Material, Method, Normals, RenderOptions, SampleGrid, Scene, ShadeOptions, render, visibility,
    visibility_into,
};
use octsolid::shape::Axis;
use octsolid::{MemoryBudget, NoProgress};

#[path = "common/hard_views.rs"]
mod hard_views;

/// The bunny voxelized at `depth` in its bounding cube (2% margin), as the CLI does.
fn bunny(depth: u8) -> LinearOctree {
    let mesh = read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/models/stanford-bunny.obj")).unwrap();
    let options = MeshVoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
    voxelize_mesh(&mesh, Domain::around(&mesh.bounds(), 0.02, depth).unwrap(), &options).unwrap().0
}

fn shading_normals(c: &mut Criterion) {
    let mut group = c.benchmark_group("shading_normals");
    group.sample_size(10);
    let tree = bunny(9);
    let bounds = tree.bounds().unwrap();
    let options = RenderOptions::default();
    let aspect = f64::from(options.width) / f64::from(options.height);
    let camera = Camera::frame(&bounds, Camera::default_view(Axis::Y), Axis::Y.unit(), aspect);
    for (name, normals) in [("axis", Normals::Axis), ("octree", Normals::Octree)] {
        let options = RenderOptions { shade: ShadeOptions { normals, ..options.shade }, ..options };
        group.bench_function(BenchmarkId::new("bunny_d9_960x720_4spp", name), |b| {
            b.iter_batched(
                || Scene::from_solid(tree.clone()),
                |scene| render(&scene, &camera, &options, &NoProgress).unwrap().1,
                BatchSize::PerIteration,
            )
        });
    }
    group.finish();
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("visibility");
    group.sample_size(10);
    let tree = bunny(10);
    let bounds = tree.bounds().unwrap();
    let mut scene = Scene::new();
    scene.add("bunny", tree, Material::default());
    let camera = Camera::frame(&bounds, Camera::default_view(Axis::Y), Axis::Y.unit(), 1.0);
    let samples = SampleGrid { width: 1024, height: 1024, spp: 1 };
    // Frames of a viewer: one frame buffer drawn into again and again.
    let mut frame = Vec::new();
    for method in [Method::Trace, Method::FrontToBack, Method::ZBuffer, Method::Painter, Method::ScanLine] {
        group.bench_function(BenchmarkId::new(format!("{method:?}"), "bunny_d10_1024"), |b| {
            b.iter(|| visibility_into(&scene, &camera, &samples, method, &mut frame))
        });
    }
    // A fresh frame buffer every frame: its first writes fault in 32 MiB of pages.
    group.bench_function(BenchmarkId::new("FrontToBackFreshBuffer", "bunny_d10_1024"), |b| {
        b.iter(|| visibility(&scene, &camera, &samples, Method::FrontToBack).0)
    });
    group.finish();
}

fn viewer_frame(c: &mut Criterion) {
    let mut group = c.benchmark_group("viewer_frame");
    group.sample_size(10);
    let tree = bunny(10);
    let bounds = tree.bounds().unwrap();
    let scene = Scene::from_solid(tree);
    let (width, height) = (1280, 720);
    let camera = Camera::frame(&bounds, Camera::default_view(Axis::Y), Axis::Y.unit(), 1280.0 / 720.0);
    let options = RenderOptions {
        width,
        height,
        spp: 1,
        shade: ShadeOptions { shadows: false, normals: Normals::Axis, ..ShadeOptions::default() },
        method: Method::FrontToBack,
        ..RenderOptions::default()
    };
    group.bench_function(BenchmarkId::new("moving", "bunny_d10_1280x720"), |b| {
        b.iter(|| png::render_png(&scene, &camera, &options, &NoProgress).unwrap().0)
    });
    let (img, _) = render(&scene, &camera, &options, &NoProgress).unwrap();
    group.bench_function(BenchmarkId::new("png_only", "bunny_d10_1280x720"), |b| b.iter(|| png::encode(&img).unwrap()));
    group.finish();
}

fn hard_views(c: &mut Criterion) {
    let mut group = c.benchmark_group("hard_views");
    group.sample_size(10);
    let samples = SampleGrid { width: 800, height: 600, spp: 1 };
    let mut frame = Vec::new();
    for view in hard_views::hard_views(10) {
        for method in [Method::FrontToBack, Method::Trace] {
            group.bench_function(BenchmarkId::new(format!("{method:?}"), view.name), |b| {
                b.iter(|| visibility_into(&view.scene, &view.camera, &samples, method, &mut frame))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, bench, shading_normals, viewer_frame, hard_views);
criterion_main!(benches);
