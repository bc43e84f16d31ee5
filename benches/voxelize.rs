//! Adaptive voxelization: a sphere at depths 8, 10, 12 and the classic CSG part at 10.
//! Work should grow about 4x a level (surface), not 8x (volume).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
use octsolid::samples;
use octsolid::shape::{Shape, Sphere};

fn options() -> VoxelizeOptions<'static> {
    VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress }
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("voxelize");
    group.sample_size(10);
    let sphere = Sphere::new(DVec3::ZERO, 0.9).unwrap();
    let classic = samples::classic_csg();
    let cases: [(&str, &dyn Shape, u8); 4] =
        [("sphere", &sphere, 8), ("sphere", &sphere, 10), ("sphere", &sphere, 12), ("classic_csg", &classic, 10)];
    for (name, shape, depth) in cases {
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap();
        let tree = voxelize(shape, domain, &options()).unwrap();
        eprintln!(
            "stats: {name} depth {depth}: {} nodes, {:.2} bytes a node",
            tree.node_count(),
            tree.bytes() as f64 / tree.node_count() as f64
        );
        group
            .bench_function(BenchmarkId::new(name, depth), |b| b.iter(|| voxelize(shape, domain, &options()).unwrap()));
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
