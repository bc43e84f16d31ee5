//! Boundary mesh export: the Stanford bunny voxelized at depth 10 (the mesh bench's
//! solid), merged node faces against one voxel face = two triangles, with a stats line
//! (nodes, triangles, vertices) for each.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::mesh::{BoundaryOptions, InsideRule, MeshVoxelizeOptions, boundary_mesh, read_mesh, voxelize_mesh};
use octsolid::octree::Domain;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("export");
    group.sample_size(10);
    let bunny = read_mesh(concat!(env!("CARGO_MANIFEST_DIR"), "/models/stanford-bunny.obj")).unwrap();
    let options =
        MeshVoxelizeOptions { inside: InsideRule::Auto, budget: MemoryBudget::unlimited(), progress: &NoProgress };
    let domain = Domain::around(&bunny.bounds(), 0.02, 10).unwrap();
    let (tree, _) = voxelize_mesh(&bunny, domain, &options).unwrap();
    for (name, unit_faces) in [("bunny_merged", false), ("bunny_unit_faces", true)] {
        let options = BoundaryOptions { unit_faces };
        let mesh = boundary_mesh(&tree, &options);
        eprintln!(
            "stats: {name} depth 10: {} nodes, {} triangles, {} vertices",
            tree.node_count(),
            mesh.triangles.len(),
            mesh.vertices.len()
        );
        group.bench_function(BenchmarkId::new(name, 10), |b| b.iter(|| boundary_mesh(&tree, &options)));
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
