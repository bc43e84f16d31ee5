//! Radiosity on the bundled Cornell box (scenes/cornell.toml, depth 8): the solve by
//! progressive refinement to 1% unshot energy (patches, elements and shots printed as
//! `stats:`), and a 512x512 render from a camera the scene does not have, with the
//! solved light (2x2 samples a pixel); and the solve with adaptive subdivision at
//! threshold 0.5 (`--subdivide 0.5`); and the Cornell box with its blocks turned 17
//! and -17 degrees (scenes/cornell-turned.toml: patches from the true surface's planar
//! regions, their extraction included). Targets: the solve in at most 20 s with at
//! least 5,000 elements, the re-render in at most 1 s, the turned box's solve in at
//! most 5 s.

use std::sync::Arc;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::render::radiosity::{Radiosity, RadiosityOptions};
use octsolid::render::{Camera, render};
use octsolid::scene_file::{SceneFile, read_scene};
use octsolid::{MemoryBudget, NoProgress};

fn cornell() -> SceneFile {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell.toml");
    read_scene(path, MemoryBudget::unlimited()).unwrap()
}

fn cornell_turned() -> SceneFile {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell-turned.toml");
    read_scene(path, MemoryBudget::unlimited()).unwrap()
}

fn bench(c: &mut Criterion) {
    let mut file = cornell();
    // 1% unshot, as the figures in BENCHMARKS.md (the default is 0.1% now).
    let options = RadiosityOptions { until: 0.01, ..RadiosityOptions::default() };
    let solution = Radiosity::solve(&file.scene, &options, &NoProgress).unwrap();
    let s = solution.stats();
    println!(
        "stats: {} patches, {} elements, {} shots, unshot {:.4}",
        s.patches, s.elements, s.shots, s.unshot_fraction
    );
    let subdivided = RadiosityOptions { subdivide: Some(0.5), ..options };
    let s = Radiosity::solve(&file.scene, &subdivided, &NoProgress).unwrap().stats().clone();
    println!(
        "stats: subdivided at 0.5: {} patches, {} elements ({} split), {} shots, unshot {:.4}",
        s.patches, s.elements, s.splits, s.shots, s.unshot_fraction
    );
    let mut group = c.benchmark_group("radiosity");
    group.sample_size(10);
    group.bench_function("cornell_solve_to_1_percent", |b| {
        b.iter(|| Radiosity::solve(&file.scene, &options, &NoProgress).unwrap().stats().shots)
    });
    group.bench_function("cornell_solve_to_1_percent_subdivided_0_5", |b| {
        b.iter(|| Radiosity::solve(&file.scene, &subdivided, &NoProgress).unwrap().stats().shots)
    });
    let turned = cornell_turned();
    let s = Radiosity::solve(&turned.scene, &options, &NoProgress).unwrap().stats().clone();
    println!(
        "stats: turned: {} patches, {} elements, {} shots, unshot {:.4}",
        s.patches, s.elements, s.shots, s.unshot_fraction
    );
    group.bench_function("cornell_turned_solve_to_1_percent", |b| {
        b.iter(|| Radiosity::solve(&turned.scene, &options, &NoProgress).unwrap().stats().shots)
    });
    file.scene.illumination = Some(Arc::new(solution));
    let camera = Camera::look_at(DVec3::new(0.8, -2.5, 1.7), DVec3::new(-0.2, 0.4, 0.6), DVec3::Z, 50.0);
    group.bench_function("cornell_render_512_new_camera", |b| {
        b.iter(|| render(&file.scene, &camera, &file.options, &NoProgress).unwrap().1.samples)
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
