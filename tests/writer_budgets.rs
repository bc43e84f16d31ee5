//! The writers' memory budgets, measured: a counting global allocator records the
//! most heap each writer holds, so a refusal can be seen to come before the writer
//! allocates, and an estimate can be seen to hold what the writer then allocates.
//! The tests take turns (one lock), as the allocator's counts are the process's.
//! They pin issue 36's writer budgets (a writer that allocated before asking).

mod common;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use common::{Rng, random_octree};
use glam::DVec3;
use octsolid::io::{ColouredSolid, Solids, WriteOptions, binvox, gltf, vdb, vox};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::shape::{Axis, Sphere};
use octsolid::{Error, MemoryBudget, NoProgress};

/// The system allocator, counting the bytes it holds and the most it held.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call goes to `System` unchanged; only counters are added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            PEAK.fetch_max(LIVE.fetch_add(layout.size(), Relaxed) + layout.size(), Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // A moving realloc holds the old block and the new one at once.
        PEAK.fetch_max(LIVE.load(Relaxed) + new_size, Relaxed);
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            LIVE.fetch_add(new_size, Relaxed);
            LIVE.fetch_sub(layout.size(), Relaxed);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

static TURN: Mutex<()> = Mutex::new(());

/// `f`'s result and the most heap it held beyond what was held before it.
fn peak<T>(f: impl FnOnce() -> T) -> (T, u64) {
    let base = LIVE.load(Relaxed);
    PEAK.store(base, Relaxed);
    let out = f();
    (out, (PEAK.load(Relaxed) - base) as u64)
}

fn scratch(test: &str) -> std::path::PathBuf {
    common::scratch_dir("writer_budgets", test)
}

fn one(tree: &LinearOctree) -> Solids {
    Solids { domain: *tree.domain(), solids: vec![ColouredSolid::new("s", None, tree.clone())] }
}

fn full(depth: u8) -> LinearOctree {
    LinearOctree::full(Domain::new(DVec3::ZERO, 1.0, depth).unwrap())
}

fn sphere(depth: u8) -> LinearOctree {
    let domain = Domain::new(DVec3::splat(-1.02), 2.04, depth).unwrap();
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress };
    voxelize(&Sphere::new(DVec3::ZERO, 1.0).unwrap(), domain, &options).unwrap()
}

/// The estimate of a refusal, or `None` when it is not one for memory.
fn estimate<T>(result: octsolid::Result<T>) -> Option<u64> {
    match result {
        Err(Error::OverBudget { estimate, .. }) => Some(estimate),
        _ => None,
    }
}

/// `.vdb` and `.binvox` used to write whatever they were given (a full domain of
/// depth 20 took 2.7 GiB as `.vdb`, of depth 14 34 GB as `.binvox`), and `.glb`
/// refused only after listing the boundary's squares: each is now refused, naming
/// the output, before it allocates a fraction of the budget, and writes nothing. The
/// mesh formats' refusal was once folded into "cannot write" (`Error::Unwritable`):
/// it is a refusal for memory like the others.
#[test]
fn writers_refuse_over_budget_before_allocating() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let dir = scratch("refuse");
    let budget = MemoryBudget(1 << 20);
    let options = WriteOptions { budget, ..WriteOptions::default() };
    // A full domain of depth 17 is 32,768 root tiles; of depth 9 134 million voxels
    // that a binvox reader holds at a bit and a node each; a sphere at depth 8 has
    // 330,000 exposed squares.
    let formats = [
        ("full.vdb", full(17)),
        ("full.binvox", full(9)),
        ("ball.glb", sphere(8)),
        ("ball.stl", sphere(8)),
        ("ball.obj", sphere(8)),
        ("ball.ply", sphere(8)),
        ("ball.3mf", sphere(8)),
    ];
    for (name, tree) in formats {
        let path = dir.join(name);
        let solids = one(&tree);
        let (result, held) = peak(|| octsolid::write_solid_file(&path, &solids.borrowed(), &options, &NoProgress));
        let e = result.expect_err(name);
        assert!(matches!(e, Error::OverBudget { .. }), "{name}: {e}");
        assert!(e.to_string().contains(name), "{name}: the output is named: {e}");
        assert!(held < budget.0 / 4, "{name}: {held} bytes held before the refusal");
        assert!(!path.exists(), "{name}: nothing is written");
    }
}

/// A `.glb` of several solids' surfaces keeps every mesh until the file is written:
/// the budget holds them together, refused before any is made when each fits alone
/// but not all, and the estimate holds what the writer then allocates.
#[test]
fn a_glb_of_several_surfaces_is_refused_when_their_meshes_together_pass_the_budget() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let dir = scratch("glb-together");
    let d = Domain::new(DVec3::splat(-1.02), 2.04, 7).unwrap();
    let (a, b) = (sphere(7), sphere(7).translate([20, 3, 0]));
    assert_eq!(*a.domain(), d);
    let two = Solids { domain: d, solids: vec![ColouredSolid::new("a", None, a), ColouredSolid::new("b", None, b)] };
    let path = dir.join("two.glb");
    let write = |solids: &Solids, budget: MemoryBudget| {
        let options = WriteOptions { budget, ..WriteOptions::default() };
        octsolid::write_solid_file(&path, &solids.borrowed(), &options, &NoProgress)
    };
    let alone: Vec<u64> = two
        .solids
        .iter()
        .map(|s| estimate(write(&one(&s.tree), MemoryBudget(0))).expect("refused with nothing"))
        .collect();
    let together = estimate(write(&two, MemoryBudget(0))).expect("refused with nothing");
    assert_eq!(together, alone[0] + alone[1]);
    let budget = MemoryBudget(alone[0].max(alone[1]));
    let (result, held) = peak(|| write(&two, budget));
    let e = result.expect_err("each fits alone, not both");
    assert!(matches!(e, Error::OverBudget { .. }) && e.to_string().contains("two.glb"), "{e}");
    assert!(held < budget.0 / 4, "{held} bytes held before the refusal");
    assert!(!path.exists());
    let (bytes, held) = peak(|| write(&two, MemoryBudget(together)).unwrap());
    assert!(held <= together, "held {held} bytes, estimated {together}");
    assert_eq!(std::fs::metadata(&path).unwrap().len(), bytes);
}

/// The surface's estimate holds what `extract` allocates, with the crossings of the
/// shape or estimated from the voxels, simplified or not, and is not ten times more.
#[test]
fn the_surface_estimate_holds_what_extraction_allocates() {
    use octsolid::surface::{ExtractOptions, HermiteData, extract};
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    for depth in [5, 6, 8] {
        let tree = sphere(depth);
        let exact = HermiteData::from_shape(&Sphere::new(DVec3::ZERO, 1.0).unwrap(), &tree);
        for (surface, hermite) in [("exact", &exact), ("estimated", &HermiteData::none())] {
            for tolerance in [0.0, 0.04] {
                let case = format!("sphere {depth}, {surface}, tolerance {tolerance}");
                let options = |budget| ExtractOptions { tolerance, budget, ..ExtractOptions::default() };
                let refused = extract(&tree, hermite, &options(MemoryBudget(0)), &NoProgress).map(|_| ());
                let Some(need) = estimate(refused) else { panic!("{case}: not refused") };
                let (_, held) = peak(|| extract(&tree, hermite, &options(MemoryBudget(need)), &NoProgress).unwrap());
                assert!(held <= need, "{case}: held {held} bytes, estimated {need}");
                assert!(need <= 10 * held, "{case}: estimated {need}, held {held}");
            }
        }
    }
}

/// A writer into memory under a budget.
type Encode<'a> = dyn Fn(MemoryBudget) -> octsolid::Result<Vec<u8>> + 'a;

/// What each estimate is for: every writer allocates at most its estimate (measured),
/// and not ten times less (the budget refuses no job it could do twice over).
#[test]
fn estimates_hold_what_the_writers_allocate() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let mut rng = Rng(0x5eed_b0d6);
    let mut cases: Vec<(&str, Solids)> = vec![
        ("sphere 7", one(&sphere(7))),
        ("sphere 8", one(&sphere(8))),
        ("full 15", one(&full(15))),
        ("random 9", one(&random_octree(&mut rng, Domain::new(DVec3::ZERO, 1.0, 9).unwrap()))),
    ];
    let d = Domain::new(DVec3::splat(-1.02), 2.04, 8).unwrap();
    let moved = sphere(8).translate([37, 5, 0]);
    cases.push((
        "two spheres",
        Solids {
            domain: d,
            solids: vec![ColouredSolid::new("a", None, sphere(8)), ColouredSolid::new("b", None, moved)],
        },
    ));
    let nothing = MemoryBudget(0);
    for (name, solids) in &cases {
        let checks: [(&str, &Encode); 4] = [
            ("vdb zip", &|b| vdb::encode(solids, vdb::Compression::Zip, b)),
            ("vdb raw", &|b| vdb::encode(solids, vdb::Compression::None, b)),
            ("glb", &|b| gltf::encode(solids, Axis::Z, b)),
            ("vox", &|b| vox::encode(solids, b)),
        ];
        // .vox stores every voxel: not the full domain's 2^45.
        let voxels: u64 = solids.solids.iter().map(|s| s.tree.voxel_count()).sum();
        for (format, encode) in checks.into_iter().filter(|(f, _)| *f != "vox" || voxels < 1 << 24) {
            let Some(estimate) = estimate(encode(nothing)) else { panic!("{name} {format}: not refused") };
            let (bytes, held) = peak(|| encode(MemoryBudget::unlimited()).unwrap());
            assert!(held <= estimate, "{name} {format}: held {held} bytes, estimated {estimate}");
            assert!(estimate <= 10 * held.max(1 << 20), "{name} {format}: estimated {estimate}, held {held}");
            assert!(estimate >= bytes.len() as u64);
        }
    }
}

/// A `.binvox` file is written exactly when our reader reads it back under the same
/// budget: the writer refuses at the reader's estimate, not a byte before or after.
#[test]
fn binvox_is_written_exactly_when_it_can_be_read_back() {
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let mut rng = Rng(0xb1_7b0c);
    let trees = [sphere(6), full(7), random_octree(&mut rng, Domain::new(DVec3::ZERO, 1.0, 8).unwrap())];
    for tree in &trees {
        let need = estimate(binvox::encode(tree, MemoryBudget(0))).expect("refused with nothing");
        let bytes = binvox::encode(tree, MemoryBudget(need)).unwrap();
        let path = std::path::Path::new("t.binvox");
        assert_eq!(binvox::decode(&bytes, path, MemoryBudget(need)).unwrap(), *tree);
        assert!(estimate(binvox::decode(&bytes, path, MemoryBudget(need - 1))).is_some());
        assert!(estimate(binvox::encode(tree, MemoryBudget(need - 1))).is_some());
    }
}

/// Radiosity's tiles of the solids' true surfaces, cut side by side, are counted
/// together against the budget: each solid's count alone let every solid on the cores
/// take a whole budget before the total was checked (1.37 GB under 1 GiB at
/// `--patch-size 3e-3` on the Cornell box).
#[test]
fn radiosity_tiles_of_several_solids_are_refused_when_together_they_pass_the_budget() {
    use common::radiosity_room::{cuboid, diffuse, tree};
    use octsolid::render::Scene;
    use octsolid::render::radiosity::{Radiosity, RadiosityOptions};
    let _turn = TURN.lock().unwrap_or_else(|e| e.into_inner());
    let scene_of = |count: usize| {
        let mut scene = Scene::new();
        for (k, [x, y]) in [[-0.5, -0.5], [0.5, -0.5], [-0.5, 0.5], [0.5, 0.5]].into_iter().take(count).enumerate() {
            let block = cuboid([x - 0.4, y - 0.4, -0.4], [x + 0.4, y + 0.4, 0.4]);
            scene.add_shaped(format!("block {k}"), tree(&block), diffuse(0.5, 0.5), std::sync::Arc::new(block));
        }
        scene
    };
    let budget = MemoryBudget(24 << 20);
    let options = RadiosityOptions {
        patch_size: Some(0.01),
        elements: 1,
        max_shots: Some(1),
        budget,
        ..RadiosityOptions::default()
    };
    // One block's tiles fit (whatever the solve does after them).
    let alone = Radiosity::solve(&scene_of(1), &options, &NoProgress).err().map(|e| e.to_string());
    assert!(!alone.as_deref().is_some_and(|e| e.contains("patches of side")), "{alone:?}");
    // Four do not, and are refused before they are all made.
    let (result, held) = peak(|| Radiosity::solve(&scene_of(4), &options, &NoProgress));
    let e = result.expect_err("four blocks' tiles pass the budget").to_string();
    assert!(e.contains("patches of side 0.01"), "{e}");
    assert!(held < budget.0 + budget.0 / 4, "{held} bytes held before the refusal, budget {}", budget.0);
}
