//! Embree 3 (the harness's `embree` feature, the system library `libembree3`) on the
//! work of `benches/bvh.rs`: the same scenes, depths, rays and pools, over the octree's
//! boundary faces and, for the bunny, over its original mesh; build, and primary, shadow
//! and random rays on 1 thread and all threads, one ray a call (`embree`) and 8 rays a
//! call (`embree_packets`).
//!
//! Ids: `bvh/{scene}_d{depth}/{embree|embree_packets}_{faces|mesh}/{build|primary|shadow|random}_{threads}t`,
//! the group and naming of `benches/bvh.rs`, so criterion's reports put them beside the
//! octree's and the other BVHs'. Run with
//! `cargo bench --features embree --bench embree`, e.g.
//! `... -- 'bunny_d10/.*/primary'`. Depth 12 is left out, as in `benches/bvh.rs` for
//! every BVH (its boundary meshes exceed the matrix's 4 million triangle limit).

#[path = "common/contender.rs"]
mod common_contender;

use common_contender::contender;
use criterion::{Criterion, criterion_group, criterion_main};
use octsolid::MemoryBudget;
use octsolid::mesh::{BoundaryOptions, TriangleMesh, boundary_mesh};
use octsolid::render::Traversal;
use octsolid_harness::rays::{light_position, primary_rays, random_rays, shadow_rays};
use octsolid_harness::{Contender, EmbreeBvh, EmbreePackets, RaySet, SceneKind, build_scene};

const IMAGE: u32 = 256;
const RANDOM: usize = 1 << 16;

/// Both of Embree's contenders over `mesh`.
fn embree(
    c: &mut Criterion,
    case: &str,
    over: &str,
    mesh: &TriangleMesh,
    rays: &[RaySet],
    pools: &[rayon::ThreadPool],
) {
    contender::<EmbreeBvh>(c, &format!("{case}/embree_{over}"), mesh, rays, pools);
    contender::<EmbreePackets>(c, &format!("{case}/embree_packets_{over}"), mesh, rays, pools);
}

fn bench(c: &mut Criterion) {
    let version = octsolid_harness::embree_contender::available().clone().expect("an Embree device");
    let all = std::thread::available_parallelism().map_or(1, usize::from);
    let pools: Vec<rayon::ThreadPool> =
        [1, all].iter().map(|&n| rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap()).collect();
    let models = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../models"));
    for kind in SceneKind::ALL {
        for depth in [8, 10].into_iter().filter(|&d| d <= kind.max_depth()) {
            let scene = build_scene(kind, depth, models, MemoryBudget::unlimited()).unwrap();
            let octree = Traversal::new(&scene.tree);
            let bounds = scene.tree.bounds().unwrap();
            let primary = primary_rays(&bounds, kind.view(), kind.up(), IMAGE);
            let shadow = shadow_rays(&octree, &primary, light_position(&bounds));
            let rays = [primary, shadow, random_rays(&bounds, RANDOM, 0x5EED)];
            let faces = boundary_mesh(&scene.tree, &BoundaryOptions::default());
            let case = format!("{}_d{depth}", kind.name());
            let embree_bytes = EmbreeBvh::build(&faces).bytes();
            eprintln!(
                "stats: {case}: Embree {version}, {} boundary triangles, {embree_bytes} bytes",
                faces.triangles.len()
            );
            embree(c, &case, "faces", &faces, &rays, &pools);
            if let Some(mesh) = &scene.mesh {
                embree(c, &case, "mesh", mesh, &rays, &pools);
            }
        }
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
