//! Ray traversal: primary rays (coherent, one per pixel of a 1024x1024 view, walked as
//! packets of 8x8 tiles as the renderer does; `primary_single` walks them one by one) and
//! shadow rays (from the visible points to a light) on the bunny at depth 10 and a
//! sphere at depth 12, all cores; traversal-structure build time and bytes a node, of
//! the traversal octree (`build`) and of the 64-tree (`build_tree64`, issue 41: built at
//! least as fast, in no more memory).
//! Target: 20 million primary rays a second at depth 10 on two cores.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::mesh::{MeshVoxelizeOptions, read_mesh, voxelize_mesh};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::{Camera, PACKET, TILE, Traversal, Tree64};
use octsolid::shape::{Axis, Sphere};
use octsolid::{Ray, RayCast};
use rayon::prelude::*;

const SIZE: u32 = 1024;

fn solids() -> Vec<(&'static str, LinearOctree, Axis)> {
    let bunny = read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/models/stanford-bunny.obj")).unwrap();
    let options = MeshVoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
    let (bunny, _) = voxelize_mesh(&bunny, Domain::around(&bunny.bounds(), 0.02, 10).unwrap(), &options).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 12).unwrap();
    let opts = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let sphere = voxelize(&Sphere::new(DVec3::ZERO, 0.8).unwrap(), domain, &opts).unwrap();
    vec![("bunny_d10", bunny, Axis::Y), ("sphere_d12", sphere, Axis::Z)]
}

/// Primary rays of a framed 1024x1024 view, row-major.
fn primary_rays(tree: &LinearOctree, up: Axis) -> Vec<Ray> {
    let b = tree.bounds().unwrap();
    let camera = Camera::frame(&b, Camera::default_view(up), up.unit(), 1.0);
    (0..SIZE * SIZE)
        .map(|i| {
            let (x, y) = (f64::from(i % SIZE) + 0.5, f64::from(i / SIZE) + 0.5);
            camera.ray(2.0 * x / f64::from(SIZE) - 1.0, 1.0 - 2.0 * y / f64::from(SIZE), 1.0)
        })
        .collect()
}

/// The rays of `primary_rays` in tile order: the TILE x TILE tiles row by row, each
/// tile's rays row-major (one packet a tile).
fn tiles(rays: &[Ray]) -> Vec<Ray> {
    let size = SIZE as usize;
    let mut out = Vec::with_capacity(rays.len());
    for r0 in (0..size).step_by(TILE) {
        for c0 in (0..size).step_by(TILE) {
            for r in r0..r0 + TILE {
                out.extend_from_slice(&rays[r * size + c0..][..TILE]);
            }
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("traverse");
    group.sample_size(10);
    for (name, tree, up) in solids() {
        let t = Traversal::new(&tree);
        eprintln!(
            "stats: {name}: {} octree nodes ({} bytes), traversal {} inner nodes, {} bytes ({:.2}x the linear octree, {:.2} bytes a leaf node)",
            tree.node_count(),
            tree.bytes(),
            t.node_count(),
            t.bytes(),
            t.bytes() as f64 / tree.bytes() as f64,
            t.bytes() as f64 / tree.node_count() as f64
        );
        let t64 = Tree64::new(&tree);
        eprintln!(
            "stats: {name}: 64-tree {} nodes of 4x4x4, {} bytes ({:.2}x the traversal octree's)",
            t64.node_count(),
            t64.bytes(),
            t64.bytes() as f64 / t.bytes() as f64
        );
        drop(t64);
        group.throughput(Throughput::Elements(tree.node_count() as u64));
        group.bench_function(BenchmarkId::new("build", name), |b| b.iter(|| Traversal::new(&tree)));
        group.bench_function(BenchmarkId::new("build_tree64", name), |b| b.iter(|| Tree64::new(&tree)));

        let rays = primary_rays(&tree, up);
        let tiles = tiles(&rays);
        let hits: Vec<(DVec3, DVec3)> =
            rays.par_iter().filter_map(|r| t.hit(r).map(|h| (r.at(h.t) - r.dir * 1e-6, r.dir))).collect();
        eprintln!("stats: {name}: {} of {} primary rays hit", hits.len(), rays.len());
        group.throughput(Throughput::Elements(rays.len() as u64));
        group.bench_function(BenchmarkId::new("primary", name), |b| {
            b.iter(|| {
                tiles
                    .par_chunks(TILE * SIZE as usize)
                    .map(|band| {
                        let mut hits = [None; PACKET];
                        band.chunks(PACKET)
                            .map(|tile| {
                                t.hit_packet(tile, &mut hits);
                                hits.iter().filter(|h| h.is_some()).count()
                            })
                            .sum::<usize>()
                    })
                    .sum::<usize>()
            })
        });
        group.bench_function(BenchmarkId::new("primary_single", name), |b| {
            b.iter(|| {
                rays.par_chunks(SIZE as usize)
                    .map(|row| row.iter().filter(|r| t.hit(r).is_some()).count())
                    .sum::<usize>()
            })
        });
        let light = tree.bounds().unwrap().center() + DVec3::new(2.0, 3.0, 4.0) * tree.domain().edge();
        group.throughput(Throughput::Elements(hits.len() as u64));
        group.bench_function(BenchmarkId::new("shadow", name), |b| {
            b.iter(|| {
                hits.par_chunks(4096)
                    .map(|chunk| {
                        chunk
                            .iter()
                            .filter(|(p, d)| {
                                let lift = *p - *d * (1e-3 * tree.domain().voxel_size());
                                let to = light - lift;
                                t.occluded(&Ray::segment(lift, to.normalize(), to.length()))
                            })
                            .count()
                    })
                    .sum::<usize>()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
