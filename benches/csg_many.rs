//! CSG with many primitives (issue targets in BENCHMARKS.md): the perforated plate
//! (200 x 200 x 10 minus 400 holes, one CSG tree, pruned) at depths 9 to 11, the
//! classic CSG part at depth 9, the k-way merge of the plate's 401 octrees against
//! the pairwise fold, and the merge of two depth-12 solids on 1 and 2 threads.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::octree::{Domain, LinearOctree, SetOp, VoxelizeOptions, voxelize};
use octsolid::samples;
use octsolid::shape::{Axis, Csg, Cuboid, Cylinder, ShapeExt, Sphere, linear_array};
use octsolid::{MemoryBudget, NoProgress};

fn options() -> VoxelizeOptions<'static> {
    VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress }
}

fn plate_domain(depth: u8) -> Domain {
    Domain::new(DVec3::new(-2.4, -2.4, -97.2), 204.8, depth).unwrap()
}

fn slab() -> Cuboid {
    Cuboid::from_corners(DVec3::ZERO, DVec3::new(200.0, 200.0, 10.0)).unwrap()
}

fn hole() -> Cylinder {
    Cylinder::new(DVec3::new(5.0, 5.0, 5.0), Axis::Z, 3.0, 12.0).unwrap()
}

fn voxelizing(c: &mut Criterion) {
    let mut group = c.benchmark_group("csg_many");
    group.sample_size(10);
    let plate = slab() - linear_array(hole(), [20, 20, 1], DVec3::new(10.0, 10.0, 0.0)).unwrap();
    for depth in [9, 10, 11] {
        let domain = plate_domain(depth);
        let tree = voxelize(&plate, domain, &options()).unwrap();
        eprintln!("stats: plate depth {depth}: {} nodes, volume {}", tree.node_count(), tree.volume());
        group.bench_function(BenchmarkId::new("plate", depth), |b| b.iter(|| voxelize(&plate, domain, &options())));
    }
    let classic = samples::classic_csg();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 9).unwrap();
    group.bench_function(BenchmarkId::new("classic_csg", 9), |b| b.iter(|| voxelize(&classic, domain, &options())));
    group.finish();
}

fn merging(c: &mut Criterion) {
    let mut group = c.benchmark_group("merge");
    group.sample_size(10);
    // The plate's 401 shapes voxelized one by one, then combined.
    let domain = plate_domain(9);
    let mut operands = vec![voxelize(&slab(), domain, &options()).unwrap()];
    for j in 0..20 {
        for i in 0..20 {
            let offset = DVec3::new(10.0 * f64::from(i), 10.0 * f64::from(j), 0.0);
            let placed: Csg = hole().translate(offset).into();
            operands.push(voxelize(&placed, domain, &options()).unwrap());
        }
    }
    let refs: Vec<&LinearOctree> = operands.iter().collect();
    let inputs: usize = refs.iter().map(|t| t.node_count()).sum();
    eprintln!("stats: plate depth 9 as 401 octrees: {inputs} input nodes");
    group.bench_function("plate_401_k_way/9", |b| b.iter(|| LinearOctree::combine_all(&refs, SetOp::Difference)));
    group.bench_function("plate_401_pairwise/9", |b| {
        b.iter(|| refs[1..].iter().fold(refs[0].clone(), |acc, t| acc.difference(t).unwrap()))
    });
    // Two overlapping spheres at depth 12, on 1 and 2 threads.
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 12).unwrap();
    let a = voxelize(&Sphere::new(DVec3::new(-0.2, 0.0, 0.0), 0.7).unwrap(), domain, &options()).unwrap();
    let b = voxelize(&Sphere::new(DVec3::new(0.25, 0.1, 0.05), 0.6).unwrap(), domain, &options()).unwrap();
    eprintln!("stats: spheres depth 12: {} + {} input nodes", a.node_count(), b.node_count());
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        for op in [SetOp::Union, SetOp::Difference] {
            group.bench_function(BenchmarkId::new(format!("spheres_12_{op:?}"), threads), |bench| {
                bench.iter(|| pool.install(|| a.combine(&b, op).unwrap()))
            });
        }
    }
    group.finish();
}

criterion_group!(benches, voxelizing, merging);
criterion_main!(benches);
