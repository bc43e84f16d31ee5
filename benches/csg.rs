//! Octree CSG: one linear merge. Two offset spheres at depth 10, every operation,
//! against a dense-grid baseline at depth 7 (where a dense grid still fits easily).

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::octree::{Domain, LinearOctree, SetOp, VoxelizeOptions, voxelize};
use octsolid::shape::Sphere;

fn spheres(depth: u8) -> (LinearOctree, LinearOctree) {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap();
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let a = voxelize(&Sphere::new(DVec3::new(-0.2, 0.0, 0.0), 0.7).unwrap(), domain, &options).unwrap();
    let b = voxelize(&Sphere::new(DVec3::new(0.25, 0.1, 0.05), 0.6).unwrap(), domain, &options).unwrap();
    (a, b)
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("csg");
    for depth in [7, 10] {
        let (a, b) = spheres(depth);
        eprintln!("stats: depth {depth}: operands {} + {} nodes", a.node_count(), b.node_count());
        for op in [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference] {
            group.bench_function(BenchmarkId::new(format!("{op:?}"), depth), |bench| {
                bench.iter(|| a.combine(&b, op).unwrap())
            });
        }
        group.bench_function(BenchmarkId::new("Complement", depth), |bench| bench.iter(|| a.complement()));
    }
    // Dense baseline: the same union as a bit-per-voxel grid at depth 7.
    let (a, b) = spheres(7);
    let dense = |t: &LinearOctree| {
        let mut grid = vec![0u64; (t.domain().voxel_total() / 64) as usize];
        for k in t.keys() {
            for code in k.start()..k.end() {
                grid[(code / 64) as usize] |= 1 << (code % 64);
            }
        }
        grid
    };
    let (ga, gb) = (dense(&a), dense(&b));
    group.bench_function("dense_union/7", |bench| {
        bench.iter(|| ga.iter().zip(&gb).map(|(x, y)| x | y).collect::<Vec<u64>>())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
