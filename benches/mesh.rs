//! Mesh and patch voxelization: the Stanford bunny (69,451 triangles, open, so the
//! winding rule) solid at depths 8, 9, 10, and the Utah teapot at depth 9.
//! Targets: bunny depth 10 under 1 s, depth 8 under 60 ms, about 4x a level.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::import::{self, ImportOptions, Input};
use octsolid::mesh::{InsideRule, MeshVoxelizeOptions, read_mesh, voxelize_mesh};
use octsolid::octree::{Domain, VoxelizeOptions};
use octsolid::patch::voxelize_patch_surface;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("mesh");
    group.sample_size(10);
    let bunny = read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/models/stanford-bunny.obj")).unwrap();
    let options =
        MeshVoxelizeOptions { inside: InsideRule::Auto, budget: MemoryBudget::unlimited(), progress: &NoProgress };
    for depth in [8, 9, 10] {
        let domain = Domain::around(&bunny.bounds(), 0.02, depth).unwrap();
        let (tree, stats) = voxelize_mesh(&bunny, domain, &options).unwrap();
        eprintln!(
            "stats: bunny depth {depth}: {:?} rule, {} nodes, {} nodes visited, {:.2} triangle-box tests a visited node, {} point queries",
            stats.rule.unwrap(),
            tree.node_count(),
            stats.nodes_visited,
            stats.triangle_box_tests as f64 / stats.nodes_visited as f64,
            stats.point_queries
        );
        group.bench_function(BenchmarkId::new("bunny_solid", depth), |b| {
            b.iter(|| voxelize_mesh(&bunny, domain, &options).unwrap())
        });
    }
    let teapot = Input::read(concat!(env!("CARGO_MANIFEST_DIR"), "/models/teapot.patches")).unwrap();
    let domain = import::default_domain(&teapot, 9).unwrap();
    let Input::Patches(patches) = &teapot else { unreachable!() };
    let surface_options = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let shell = voxelize_patch_surface(patches, domain, &surface_options).unwrap();
    eprintln!("stats: teapot depth 9 surface: {} nodes", shell.node_count());
    group.bench_function(BenchmarkId::new("teapot_surface", 9), |b| {
        b.iter(|| voxelize_patch_surface(patches, domain, &surface_options).unwrap())
    });
    group.bench_function(BenchmarkId::new("teapot_solid", 9), |b| {
        b.iter(|| {
            let options = ImportOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
            import::voxelize_input(&teapot, domain, &options).unwrap()
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
