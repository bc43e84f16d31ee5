//! The `.oct` format with its surface section (`io::oct`, `io/oct_surface.rs`): reading
//! (checks included) and writing the two solids of issues 38 and 39 as `build` makes
//! them, each with and without its section: OpenSCAD PR 6647's cube minus sphere
//! (`benches/peers/offset_openscad_6647.toml`, depth 9) and the classic CSG part
//! (`benches/peers/surface_classic.toml`, depth 9). `read` decodes the file's bytes,
//! `encode` makes them, `write` writes them to a file atomically (the temporary file,
//! its flush to disk, the rename); throughput in file bytes, with a stats line of the
//! counts and sizes.

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::io::oct::{self, Metadata};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::shape::{Csg, Cuboid, Sphere};
use octsolid::surface::HermiteData;
use octsolid::{MemoryBudget, NoProgress};

/// A solid of `shape` in `domain` with its exact surface data, as `build` writes it.
fn solid(shape: &Csg, domain: Domain) -> (LinearOctree, HermiteData) {
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let tree = voxelize(shape, domain, &options).unwrap();
    let surface = HermiteData::from_shape(shape, &tree);
    (tree, surface)
}

fn bench(c: &mut Criterion) {
    let cube = Cuboid::new(DVec3::ZERO, DVec3::splat(10.0)).unwrap();
    let ball = Sphere::new(DVec3::ZERO, 6.0).unwrap();
    let cases = [
        ("pr6647", solid(&(cube - ball), Domain::new(DVec3::splat(-7.0), 14.0, 9).unwrap())),
        ("classic", solid(&octsolid::samples::classic_csg(), Domain::new(DVec3::splat(-1.1), 2.2, 9).unwrap())),
    ];
    let dir = std::env::temp_dir().join(format!("octsolid-bench-oct-io-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let meta = Metadata::default();
    let mut group = c.benchmark_group("oct_io");
    group.sample_size(10);
    for (name, (tree, surface)) in &cases {
        for (kind, surface) in [("surface", Some(surface)), ("plain", None)] {
            let bytes = oct::encode_with_surface(tree, &meta, surface);
            eprintln!(
                "stats: {name} {kind}: {} nodes, {} faces, {} bytes",
                tree.node_count(),
                surface.map_or(0, HermiteData::len),
                bytes.len()
            );
            let path = dir.join(format!("{name}-{kind}.oct"));
            group.throughput(Throughput::Bytes(bytes.len() as u64));
            group.bench_function(BenchmarkId::new(format!("{name}_read"), kind), |b| {
                b.iter(|| oct::decode_and_surface(&bytes, &path, MemoryBudget::unlimited()).unwrap())
            });
            group.bench_function(BenchmarkId::new(format!("{name}_encode"), kind), |b| {
                b.iter(|| oct::encode_with_surface(tree, &meta, surface))
            });
            group.bench_function(BenchmarkId::new(format!("{name}_write"), kind), |b| {
                b.iter(|| oct::write_with_surface(tree, &meta, surface, &path).unwrap())
            });
        }
    }
    group.finish();
    let _ = std::fs::remove_dir_all(&dir);
}

criterion_group!(benches, bench);
criterion_main!(benches);
