//! Whitted's classic scene (scenes/whitted.toml: a glass and a mirror sphere over a
//! checkered floor, depth 10) at 1024x768, 2x2 samples a pixel: the whole render,
//! visibility and shading with reflection, refraction and shadow rays, each iteration
//! on a freshly loaded scene (cold normal and interior caches, as in one CLI run).
//! Throughput is all rays cast (primary, secondary and shadow). Target: under 10 s.
//! `smooth` shades with the spheres' own normals, `octree` with normals estimated
//! from the octree.

use criterion::{BatchSize, BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::render::{Normals, render};
use octsolid::scene_file::{SceneFile, read_scene};

fn scene(normals: Normals) -> SceneFile {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/whitted.toml");
    let mut file = read_scene(path, MemoryBudget::unlimited()).unwrap();
    file.options.shade.normals = normals;
    file
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("whitted");
    group.sample_size(10);
    for (name, normals) in [("smooth", Normals::Smooth), ("octree", Normals::Octree)] {
        let probe = scene(normals);
        let (_, stats) = render(&probe.scene, &probe.camera, &probe.options, &NoProgress).unwrap();
        group.throughput(Throughput::Elements(stats.samples + stats.secondary_rays));
        group.bench_function(BenchmarkId::new("classic_1024x768_4spp", name), |b| {
            b.iter_batched(
                || scene(normals),
                |s| render(&s.scene, &s.camera, &s.options, &NoProgress).unwrap().1,
                BatchSize::PerIteration,
            )
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
