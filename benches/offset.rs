//! Offsets: the band transform (`LinearOctree::offset`, exact Euclidean distance in the
//! bricks a ball can reach, `src/octree/offset/`) on the classic CSG part at depth 8 in
//! `[-1.1, 1.1]^3` (the domain of `benches/peers/surface_classic.toml`, voxel 2.2/256),
//! grown by 10 voxels and shrunk by 10, so regressions show. The peer comparison with the
//! dense transform of the `edt` package, at depth 9, is `benches/peers/offset.sh`.

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::octree::{Domain, OffsetOptions, VoxelizeOptions, voxelize};
use octsolid::samples::classic_csg;
use octsolid::{MemoryBudget, NoProgress};

fn bench(c: &mut Criterion) {
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 8).unwrap();
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let part = voxelize(&classic_csg(), domain, &options).unwrap();
    let offset = OffsetOptions { budget: MemoryBudget::unlimited(), ..OffsetOptions::default() };
    eprintln!("stats: depth 8: {} nodes, {} voxels", part.node_count(), part.voxel_count());
    let mut group = c.benchmark_group("offset");
    group.sample_size(10);
    group.bench_function("classic_grow_10/8", |bench| bench.iter(|| part.offset(10.0, &offset).unwrap()));
    group.bench_function("classic_shrink_10/8", |bench| bench.iter(|| part.offset(-10.0, &offset).unwrap()));
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
