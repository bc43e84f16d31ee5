//! Surface simplification (`surface::simplify`): the staircase of the classic CSG part
//! at depth 9 (one voxel face = two triangles) simplified within half a voxel and
//! within two voxels, with a stats line (triangles before and after, the distance
//! bound, collapses, rounds) for each.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::mesh::{BoundaryOptions, boundary_mesh};
use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
use octsolid::surface::{SimplifyOptions, simplify};

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("surface");
    group.sample_size(10);
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 9).unwrap();
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let tree = voxelize(&octsolid::samples::classic_csg(), domain, &options).unwrap();
    let staircase = boundary_mesh(&tree, &BoundaryOptions { unit_faces: true });
    let voxel = domain.voxel_size();
    for voxels in [0.5, 2.0] {
        let options = SimplifyOptions::new(voxels * voxel);
        let started = std::time::Instant::now();
        let (_, report) = simplify(&staircase, &options).unwrap();
        eprintln!(
            "stats: classic part depth 9 staircase, tolerance {voxels} voxel: {} -> {} triangles, bound {:.3} voxel, \
             rms quadric distance {:.4} voxel, {} collapses, {} rounds, {:.2} s",
            report.triangles_before,
            report.triangles_after,
            report.max_distance_bound / voxel,
            report.rms_quadric_distance / voxel,
            report.collapses,
            report.rounds,
            started.elapsed().as_secs_f64()
        );
        group.bench_function(BenchmarkId::new("classic_staircase", voxels), |b| {
            b.iter(|| simplify(&staircase, &options).unwrap())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
