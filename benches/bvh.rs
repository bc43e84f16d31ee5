//! Octree traversal against BVHs (obvhs CWBVH and the bvh crate) over the octree's
//! boundary faces and, for the bunny, over its original mesh: build, and primary, shadow
//! and random rays on 1 thread and all threads. The same scenes, rays and pools as
//! `octsolid bench --report` (`octsolid_harness`).
//!
//! Ids: `bvh/{scene}_d{depth}/{contender}/{build|primary|shadow|random}_{threads}t`.
//! The whole matrix takes long; pick a subset by filter, e.g.
//! `cargo bench --bench bvh -- 'bunny_d10/.*/primary'` (the setup still voxelizes every
//! scene and builds every structure once, about a minute). At depth 12 only the octree
//! runs: its boundary meshes exceed the matrix's 4 million triangle limit for BVHs.

#[path = "common/contender.rs"]
mod common_contender;

use common_contender::contender;
use criterion::{Criterion, criterion_group, criterion_main};
use octsolid::MemoryBudget;
use octsolid::mesh::{BoundaryOptions, TriangleMesh, boundary_mesh};
use octsolid::render::Traversal;
use octsolid_harness::rays::{light_position, primary_rays, random_rays, shadow_rays};
use octsolid_harness::{BvhCrateBvh, ObvhsBvh, SceneKind, build_scene};

const IMAGE: u32 = 256;
const RANDOM: usize = 1 << 16;

fn bench(c: &mut Criterion) {
    let all = std::thread::available_parallelism().map_or(1, usize::from);
    let pools: Vec<rayon::ThreadPool> =
        [1, all].iter().map(|&n| rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap()).collect();
    let models = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/models"));
    for kind in SceneKind::ALL {
        for depth in [8, 10, 12].into_iter().filter(|&d| d <= kind.max_depth()) {
            let scene = build_scene(kind, depth, models, MemoryBudget::unlimited()).unwrap();
            let octree = Traversal::new(&scene.tree);
            let bounds = scene.tree.bounds().unwrap();
            let primary = primary_rays(&bounds, kind.view(), kind.up(), IMAGE);
            let shadow = shadow_rays(&octree, &primary, light_position(&bounds));
            let rays = [primary, shadow, random_rays(&bounds, RANDOM, 0x5EED)];
            let faces: Option<TriangleMesh> =
                (depth <= 10).then(|| boundary_mesh(&scene.tree, &BoundaryOptions::default()));
            let case = format!("{}_d{depth}", kind.name());
            eprintln!(
                "stats: {case}: {} octree nodes, {} traversal bytes, {} boundary triangles",
                scene.tree.node_count(),
                octree.bytes(),
                faces.as_ref().map_or(0, |f| f.triangles.len())
            );
            contender::<Traversal>(c, &format!("{case}/octree"), &scene.tree, &rays, &pools);
            if let Some(faces) = &faces {
                contender::<ObvhsBvh>(c, &format!("{case}/obvhs_faces"), faces, &rays, &pools);
                contender::<BvhCrateBvh>(c, &format!("{case}/bvh_faces"), faces, &rays, &pools);
            }
            if let Some(mesh) = &scene.mesh {
                contender::<ObvhsBvh>(c, &format!("{case}/obvhs_mesh"), mesh, &rays, &pools);
                contender::<BvhCrateBvh>(c, &format!("{case}/bvh_mesh"), mesh, &rays, &pools);
            }
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
