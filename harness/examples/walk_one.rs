//! One kind of ray traced through the octree on one thread, for profiles of the walk
//! (docs/benchmark-log/2026-12.md, "Incoherent rays"): `walk_one MODEL DEPTH KIND N` with KIND one of
//! `primary` (512x512 camera rays at the framed model), `packet` (the same in 8x8
//! packets), `shadow` (N shadow rays from primary hits to a light), `lights` (the
//! shadow rays from every primary hit to two lights, in the order a renderer casts
//! them: both of a hit, hit after hit; `lights-batched` all of the
//! first light's, then the second's; `lights-shuffled` in random order; N unused),
//! `random` (N random rays, the harness's set), `display` (the primary rays answered
//! by the front-to-back display, a frustum walk for the rays of one eye, checked hit
//! for hit against the walk), and issue 41's sets leaving the primary hits
//! (`harness/src/secondary_rays.rs`, the report's `--issue-rays` section): `bounce`
//! (cosine-weighted about the normal) and `hit-shadow` (to a point light), the first N
//! of them (0: all; `SIZE=1024` for the issue's). `SIZE` (default 512) sets the primary
//! rays' image edge.
//! `TREE=tree64` traces the kinds of single rays through the 64-tree (`Tree64`, issue
//! 41) instead of the traversal octree, after checking every hit against the octree's;
//! either way the build time (best of 5) and bytes of both trees go to stderr.
//! Prints the hit count, and on stderr the best CPU time a ray over `REPEAT` runs
//! (default 1); for `display` also the best wall time a ray on 2 threads. Under
//! callgrind, collect only the tracing:
//! `valgrind --tool=callgrind --branch-sim=yes --toggle-collect='walk_one::trace*'`.
//!
//! `CONTENDER=NAME` (a `ContenderKind::slug`: `octree`, `obvhs-faces`, `bvh-faces`,
//! `embree-faces`, `embree-mesh`, ...; Embree's need `--features embree`) traces the
//! primary, bounce and hit-shadow rays through that structure instead, as the report
//! does (a 1-thread rayon pool, chunks of 256 rays). Under `perf stat --delay=-1
//! --control fifo:CTL,ACK` with `PERF_CTL_FIFO` and `PERF_ACK_FIFO` naming the fifos,
//! the counters run only while rays are traced (`benches/peers/branch_misses.sh`).
use glam::DVec3;
use octsolid::mesh::{BoundaryOptions, try_boundary_mesh};
use octsolid::render::{Camera, Method, PACKET, SampleGrid, Scene, TILE, Traversal, Tree64, visibility_into};
use octsolid::{MemoryBudget, NoProgress, Ray, RayCast};
use octsolid_harness::ContenderKind;
use octsolid_harness::any_contender::{Inputs, Traced, build_contender};
use octsolid_harness::perf_window::counted;
use octsolid_harness::rays::{RayKind, RaySet, random_rays};
use octsolid_harness::scenes::voxelized_model;
use octsolid_harness::secondary_rays::{SEED, secondary_rays, view_camera, view_rays};

/// CPU time of this thread, ns (schedstat), so a loaded machine does not count.
fn cpu_ns() -> u64 {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").unwrap();
    s.split_whitespace().next().unwrap().parse().unwrap()
}

#[inline(never)]
fn trace_packets(t: &Traversal, tiles: &[Ray]) -> usize {
    let mut hits = [None; PACKET];
    tiles
        .chunks(PACKET)
        .map(|tile| {
            t.hit_packet(tile, &mut hits);
            hits.iter().filter(|h| h.is_some()).count()
        })
        .sum()
}

#[inline(never)]
fn trace<T: RayCast>(t: &T, rays: &[Ray], any: bool) -> usize {
    rays.iter().filter(|r| if any { t.occluded(r) } else { t.hit(r).is_some() }).count()
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let depth: u8 = args[2].parse().unwrap();
    let kind = args[3].as_str();
    let n: usize = args[4].parse().unwrap();
    let (tree, mesh) = voxelized_model(args[1].as_ref(), depth, MemoryBudget::unlimited()).unwrap();
    let bounds = mesh.bounds();
    let t = Traversal::new(&tree);
    let tree64 = std::env::var("TREE").is_ok_and(|v| v == "tree64");
    let t64 = Tree64::new(&tree);
    let build = |f: &dyn Fn() -> usize| {
        (0..5)
            .map(|_| {
                let start = cpu_ns();
                std::hint::black_box(f());
                (cpu_ns() - start) as f64 * 1e-6
            })
            .fold(f64::INFINITY, f64::min)
    };
    eprintln!(
        "octree: {} bytes, built in {:.2} ms; 64-tree: {} bytes, built in {:.2} ms ({} voxels)",
        t.bytes(),
        build(&|| Traversal::new(&tree).node_count()),
        t64.bytes(),
        build(&|| Tree64::new(&tree).node_count()),
        tree.voxel_count()
    );
    let size: u32 = std::env::var("SIZE").map_or(512, |v| v.parse().unwrap());
    let camera = view_camera(&bounds);
    let primary = view_rays(&camera, size);
    let cap = |rays: Vec<Ray>| if n == 0 { rays } else { rays.into_iter().take(n).collect() };
    if let Ok(name) = std::env::var("CONTENDER") {
        let contender =
            ContenderKind::from_slug(&name).unwrap_or_else(|| panic!("CONTENDER={name}: no such contender"));
        let secondary = secondary_rays(&t, &bounds, size, SEED);
        let set = match kind {
            "primary" => RaySet { kind: RayKind::Primary, rays: cap(primary) },
            "bounce" => RaySet { kind: RayKind::Bounce, rays: cap(secondary.bounce.rays) },
            "hit-shadow" => RaySet { kind: RayKind::Shadow, rays: cap(secondary.shadow.rays) },
            other => panic!("CONTENDER={name}: KIND must be primary, bounce or hit-shadow, not {other}"),
        };
        let faces = if contender == ContenderKind::Octree {
            octsolid::mesh::TriangleMesh::default()
        } else {
            try_boundary_mesh(&tree, &BoundaryOptions::default(), MemoryBudget::unlimited(), &NoProgress).unwrap()
        };
        let c = build_contender(contender, Inputs { tree: &tree, faces: &faces, mesh: Some(&mesh) }).unwrap();
        trace_contender(&*c, &set, kind, repeat());
        return;
    }
    let diag = bounds.size().length();
    let light = bounds.center() + DVec3::new(2.0, 3.0, 4.0) * diag;
    let primary_all = primary.clone();
    let rays: Vec<Ray> = match kind {
        "primary" | "packet" => primary,
        "shadow" => primary
            .iter()
            .filter_map(|r| {
                let h = t.hit(r)?;
                let origin = r.origin + r.dir * (h.t - 1e-4 * diag);
                let to = light - origin;
                Some(Ray { origin, dir: to.normalize(), t_max: to.length() })
            })
            .take(n)
            .collect(),
        "bounce" => cap(secondary_rays(&t, &bounds, size, SEED).bounce.rays),
        "hit-shadow" => cap(secondary_rays(&t, &bounds, size, SEED).shadow.rays),
        "lights" | "lights-batched" | "lights-shuffled" => {
            let second = bounds.center() + DVec3::new(-3.0, 2.0, 1.0) * diag;
            two_lights(&t, &primary, [light, second], diag, kind)
        }
        _ => random_rays(&bounds, n, 1).rays,
    };
    if tree64 {
        for ray in &rays {
            assert_eq!(t64.hit(ray), t.hit(ray), "the 64-tree and the octree differ on {ray:?}");
        }
    }
    let repeat = repeat();
    if kind == "display" {
        display(tree, &t, &camera, &primary_all, size, repeat);
        return;
    }
    let mut best = f64::INFINITY;
    let mut hits = 0;
    for _ in 0..repeat {
        let start = cpu_ns();
        hits = if kind == "packet" {
            let s = size as usize;
            let mut tiles = Vec::new();
            for r0 in (0..s).step_by(TILE) {
                for c0 in (0..s).step_by(TILE) {
                    for r in r0..r0 + TILE {
                        tiles.extend_from_slice(&primary_all[r * s + c0..][..TILE]);
                    }
                }
            }
            trace_packets(&t, &tiles)
        } else if tree64 {
            trace(&t64, &rays, kind.ends_with("shadow") || kind.starts_with("lights"))
        } else {
            counted(|| trace(&t, &rays, kind.ends_with("shadow") || kind.starts_with("lights"))).0
        };
        best = best.min((cpu_ns() - start) as f64 * 1e-9);
    }
    let count = if kind == "packet" { primary_all.len() } else { rays.len() };
    let name = if tree64 { "64-tree" } else { "octree" };
    eprintln!("{kind} ({name}): {:.1} ns/ray (best of {repeat})", best * 1e9 / count as f64);
    println!("{kind}: {hits} of {}", rays.len());
}

/// Runs of the timing (`REPEAT`, default 1).
fn repeat() -> usize {
    std::env::var("REPEAT").map_or(1, |v| v.parse().unwrap())
}

/// CPU time of the calling thread around `work`, seconds, and its result.
fn cpu_timed<T>(work: impl FnOnce() -> T) -> (f64, T) {
    let start = cpu_ns();
    let out = work();
    ((cpu_ns() - start) as f64 * 1e-9, out)
}

#[inline(never)]
fn trace_any(c: &dyn Traced, set: &RaySet) -> u64 {
    c.trace_set(set)
}

/// `set` through contender `c` in a 1-thread rayon pool (the report's way), timed by the
/// pool thread's CPU time, best of `repeat`; the counters of `perf stat` on (see the
/// module doc) during every run.
fn trace_contender(c: &dyn Traced, set: &RaySet, kind: &str, repeat: usize) {
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let mut best = f64::INFINITY;
    let mut hits = 0;
    for _ in 0..repeat {
        let (seconds, (h, perf)) = one.install(|| cpu_timed(|| counted(|| trace_any(c, set))));
        perf.expect("perf's control fifos");
        best = best.min(seconds);
        hits = h;
    }
    let count = set.rays.len();
    eprintln!("{kind}: {:.1} ns/ray (best of {repeat})", best * 1e9 / count as f64);
    println!("{kind}: {hits} of {count}");
}

/// The primary rays of `camera` (`primary`, row by row) answered by the front-to-back
/// display: every hit checked against the walk's, then the best thread CPU time a ray
/// on a pool of 1 thread and the best wall time a ray on 2 threads over `repeat` frames.
fn display(
    tree: octsolid::octree::LinearOctree,
    t: &Traversal,
    camera: &Camera,
    primary: &[Ray],
    size: u32,
    repeat: usize,
) {
    let scene = Scene::from_solid(tree);
    let samples = SampleGrid { width: size, height: size, spp: 1 };
    let mut seen = Vec::new();
    visibility_into(&scene, camera, &samples, Method::FrontToBack, &mut seen);
    for (i, (ray, sample)) in primary.iter().zip(&seen).enumerate() {
        assert_eq!(sample.map(|s| s.hit), t.hit(ray), "ray {i}: the display and the walk differ");
    }
    let hits = seen.iter().filter(|s| s.is_some()).count();
    let pool = |n| rayon::ThreadPoolBuilder::new().num_threads(n).build().unwrap();
    let (one, two) = (pool(1), pool(2));
    let mut cpu = f64::INFINITY;
    let mut wall = f64::INFINITY;
    for _ in 0..repeat {
        cpu = cpu.min(one.install(|| {
            let start = cpu_ns();
            visibility_into(&scene, camera, &samples, Method::FrontToBack, &mut seen);
            (cpu_ns() - start) as f64 * 1e-9
        }));
        wall = wall.min(two.install(|| {
            let start = std::time::Instant::now();
            visibility_into(&scene, camera, &samples, Method::FrontToBack, &mut seen);
            start.elapsed().as_secs_f64()
        }));
    }
    let n = primary.len() as f64;
    eprintln!(
        "display: {:.1} ns/ray on 1 thread (CPU), {:.1} ns/ray on 2 threads (wall), best of {repeat}",
        cpu * 1e9 / n,
        wall * 1e9 / n
    );
    println!("display: {hits} of {} (every hit the walk's)", primary.len());
}

/// The shadow rays from every primary hit (a ten-thousandth of the model's diagonal in
/// front of it) to each of `lights`, in the order `kind` names (see the module doc).
fn two_lights(t: &Traversal, primary: &[Ray], lights: [DVec3; 2], diag: f64, kind: &str) -> Vec<Ray> {
    let mut rays: Vec<Ray> = primary
        .iter()
        .filter_map(|r| {
            let h = t.hit(r)?;
            Some(r.origin + r.dir * (h.t - 1e-4 * diag))
        })
        .flat_map(|origin| {
            lights.map(|light| {
                let to = light - origin;
                Ray { origin, dir: to.normalize(), t_max: to.length() }
            })
        })
        .collect();
    match kind {
        "lights-batched" => {
            let (first, second): (Vec<_>, Vec<_>) = rays.chunks(2).map(|pair| (pair[0], pair[1])).unzip();
            rays = first.into_iter().chain(second).collect();
        }
        "lights-shuffled" => {
            // Fisher-Yates with a fixed xorshift, so every run has the same order.
            let mut x = 0x9e37_79b9_7f4a_7c15u64;
            for i in (1..rays.len()).rev() {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                rays.swap(i, (x % (i as u64 + 1)) as usize);
            }
        }
        _ => {}
    }
    rays
}
