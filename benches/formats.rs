//! Voxel interchange formats: read and write of `.vox`, `.binvox`, `.vdb` (zip and
//! uncompressed) and `.glb` (write only) for the Stanford bunny voxelized at depth 10
//! (the mesh bench's solid), and `.oct` for reference; `.vox` of two voxels in opposite
//! corners of a depth-12 domain (`vox_write_far_corners`: the writer's time follows the
//! voxels, not their bounding box); throughput in file bytes, with a
//! stats line of file sizes against `.oct` and the voxel count (voxels a second = the
//! voxel count over a median time; BENCHMARKS.md).

use std::path::Path;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::io::{ColouredSolid, ReadOptions, Solids, binvox, gltf, oct, vdb, vox};
use octsolid::mesh::{InsideRule, MeshVoxelizeOptions, read_mesh, voxelize_mesh};
use octsolid::octree::{Domain, LinearOctree, Node};
use octsolid::shape::Axis;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("formats");
    group.sample_size(10);
    let bunny = read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/models/stanford-bunny.obj")).unwrap();
    let options =
        MeshVoxelizeOptions { inside: InsideRule::Auto, budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let domain = Domain::around(&bunny.bounds(), 0.02, 10).unwrap();
    let (tree, _) = voxelize_mesh(&bunny, domain, &options).unwrap();
    let solids = Solids { domain, solids: vec![ColouredSolid::new("bunny", None, tree.clone())] };
    let read = ReadOptions { budget: MemoryBudget::unlimited(), ..ReadOptions::default() };
    let path = Path::new("bunny");

    let oct_bytes = oct::encode(&tree);
    let vox_bytes = vox::encode(&solids, MemoryBudget::unlimited()).unwrap();
    let binvox_bytes = binvox::encode(&tree, MemoryBudget::unlimited()).unwrap();
    let vdb_zip = vdb::encode(&solids, vdb::Compression::Zip, MemoryBudget::unlimited()).unwrap();
    let vdb_raw = vdb::encode(&solids, vdb::Compression::None, MemoryBudget::unlimited()).unwrap();
    let glb = gltf::encode(&solids, Axis::Z, MemoryBudget::unlimited()).unwrap();
    eprintln!(
        "stats: bunny depth 10: {} nodes, {} voxels; .oct {} B, .vox {} B, .binvox {} B, .vdb zip {} B ({:.2}x .oct), \
         .vdb raw {} B ({:.2}x .oct), .glb {} B",
        tree.node_count(),
        tree.voxel_count(),
        oct_bytes.len(),
        vox_bytes.len(),
        binvox_bytes.len(),
        vdb_zip.len(),
        vdb_zip.len() as f64 / oct_bytes.len() as f64,
        vdb_raw.len(),
        vdb_raw.len() as f64 / oct_bytes.len() as f64,
        glb.len()
    );

    // Two voxels in opposite corners of a depth-12 domain: a box of 4,096 models' room
    // holding two (the writer's time follows the voxels, not the box).
    let far = Domain::new(DVec3::ZERO, 1.0, 12).unwrap();
    let corner = |min: [u32; 3]| Node { level: 12, min, size: 1 };
    let corners = LinearOctree::from_nodes(far, [corner([0; 3]), corner([4095; 3])]).unwrap();
    let corners = Solids { domain: far, solids: vec![ColouredSolid::new("corners", None, corners)] };
    let corners_vox = vox::encode(&corners, MemoryBudget::unlimited()).unwrap();

    // Each job with the file size its throughput counts.
    type Job<'a> = (String, usize, Box<dyn Fn() + 'a>);
    let mut jobs: Vec<Job> = vec![
        // octsolid's own format, for reference.
        ("oct_write".into(), oct_bytes.len(), Box::new(|| drop(oct::encode(&tree)))),
        (
            "oct_read".into(),
            oct_bytes.len(),
            Box::new(|| drop(oct::decode(&oct_bytes, path, MemoryBudget::unlimited()).unwrap())),
        ),
        (
            "vox_write".into(),
            vox_bytes.len(),
            Box::new(|| drop(vox::encode(&solids, MemoryBudget::unlimited()).unwrap())),
        ),
        ("vox_read".into(), vox_bytes.len(), Box::new(|| drop(vox::decode(&vox_bytes, path, &read).unwrap()))),
        (
            "vox_write_far_corners".into(),
            corners_vox.len(),
            Box::new(|| drop(vox::encode(&corners, MemoryBudget::unlimited()).unwrap())),
        ),
        (
            "binvox_write".into(),
            binvox_bytes.len(),
            Box::new(|| drop(binvox::encode(&tree, MemoryBudget::unlimited()).unwrap())),
        ),
        (
            "binvox_read".into(),
            binvox_bytes.len(),
            Box::new(|| drop(binvox::decode(&binvox_bytes, path, MemoryBudget::unlimited()).unwrap())),
        ),
        (
            "glb_write".into(),
            glb.len(),
            Box::new(|| drop(gltf::encode(&solids, Axis::Z, MemoryBudget::unlimited()).unwrap())),
        ),
    ];
    for (name, compression, bytes) in
        [("vdb_zip", vdb::Compression::Zip, &vdb_zip), ("vdb_raw", vdb::Compression::None, &vdb_raw)]
    {
        let (solids, read) = (&solids, &read);
        jobs.push((
            format!("{name}_write"),
            bytes.len(),
            Box::new(move || drop(vdb::encode(solids, compression, MemoryBudget::unlimited()).unwrap())),
        ));
        jobs.push((
            format!("{name}_read"),
            bytes.len(),
            Box::new(move || drop(vdb::decode(bytes, path, read).unwrap())),
        ));
    }
    for (name, bytes, job) in &jobs {
        group.throughput(Throughput::Bytes(*bytes as u64));
        group.bench_function(BenchmarkId::new(name.clone(), 10), |b| b.iter(job));
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
