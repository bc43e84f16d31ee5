//! Primary visibility by every method on the bunny at depth 10, 1024x1024, one sample
//! a pixel (no shading), into one frame buffer kept between frames as a viewer keeps
//! it: the octree display's frames a second against the ray tracer.
//! Target: front-to-back display at 20 frames a second or more.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use octsolid::MemoryBudget;
use octsolid::mesh::{MeshVoxelizeOptions, load_mesh, voxelize_mesh};
use octsolid::octree::Domain;
use octsolid::render::{Camera, Material, Method, SampleGrid, Scene, visibility, visibility_into};
use octsolid::shape::Axis;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("visibility");
    group.sample_size(10);
    let mesh = load_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/models/stanford-bunny.obj")).unwrap();
    let options = MeshVoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
    let (tree, _) = voxelize_mesh(&mesh, Domain::around(&mesh.bounds(), 0.02, 10).unwrap(), &options).unwrap();
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

criterion_group!(benches, bench);
criterion_main!(benches);
