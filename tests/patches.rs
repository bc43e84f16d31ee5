//! Bezier patch voxelization of the Utah teapot against dense samples of its surface.

mod common;

use std::collections::HashMap;
use std::path::Path;

use common::Recorder;
use glam::DVec3;
use octsolid::Error;
use octsolid::MemoryBudget;
use octsolid::import::{self, Fill, ImportOptions, Input};
use octsolid::mesh::{InsideRule, PolygonTables};
use octsolid::octree::{Domain, VoxelizeOptions};
use octsolid::patch::{BezierPatch, read_patches, tessellate, voxelize_patch_surface};

#[test]
fn teapot_surface_voxels_hug_the_surface() {
    let patches = read_patches(Path::new("models/teapot.patches")).unwrap();
    let input = Input::Patches(patches.clone());
    let domain = Domain::around(&input.bounds(), 0.02, 7).unwrap();
    let h = domain.voxel_size();
    let shell = voxelize_patch_surface(&patches, domain, &VoxelizeOptions::default()).unwrap();
    shell.validate().unwrap();

    // Dense samples of every patch, bucketed by voxel; `spacing` bounds how far a
    // surface point can be from the nearest sample.
    const N: u32 = 300;
    let mut buckets: HashMap<[u32; 3], Vec<DVec3>> = HashMap::new();
    let mut spacing: f64 = 0.0;
    for patch in &patches {
        for i in 0..=N {
            for j in 0..=N {
                let (u, v) = (f64::from(i) / f64::from(N), f64::from(j) / f64::from(N));
                let p = patch.eval(u, v);
                if i > 0 {
                    spacing = spacing.max(p.distance(patch.eval(f64::from(i - 1) / f64::from(N), v)));
                }
                if j > 0 {
                    spacing = spacing.max(p.distance(patch.eval(u, f64::from(j - 1) / f64::from(N))));
                }
                let voxel = domain.voxel_of(p).expect("inside the domain");
                // Every sampled surface point lies in a surface voxel.
                assert!(shell.contains_voxel(voxel), "{p} is in no shell voxel");
                buckets.entry(voxel).or_default().push(p);
            }
        }
    }
    assert!(spacing < 0.5 * h, "samples too sparse: {spacing} vs voxel {h}");
    // Every shell voxel lies within half a voxel of the surface (plus the sampling gap).
    let voxels = shell.keys().iter().flat_map(|k| k.start()..k.end()).map(octsolid::morton::decode);
    for min in voxels {
        let b = domain.cube_box(min, 1);
        let mut nearest = f64::INFINITY;
        for dx in -1i64..=1 {
            for dy in -1i64..=1 {
                for dz in -1i64..=1 {
                    let c = [min[0] as i64 + dx, min[1] as i64 + dy, min[2] as i64 + dz];
                    if let Some(points) = c.iter().all(|&x| x >= 0).then(|| buckets.get(&c.map(|x| x as u32))).flatten()
                    {
                        for p in points {
                            nearest = nearest.min((b.min - *p).max(*p - b.max).max(DVec3::ZERO).length());
                        }
                    }
                }
            }
        }
        assert!(nearest <= 0.5 * h + spacing, "shell voxel {min:?} is {nearest} from the surface (h = {h})");
    }
}

#[test]
fn teapot_solid_matches_its_tessellation() {
    let input = Input::read(Path::new("models/teapot.patches")).unwrap();
    let domain = import::default_domain(&input, 8).unwrap();
    let (tree, summary) = import::voxelize_input(&input, domain, &ImportOptions::default()).unwrap();
    tree.validate().unwrap();
    assert_eq!(summary.rule, Some(InsideRule::Winding), "the teapot is not watertight");
    let Input::Patches(patches) = &input else { unreachable!() };
    let fine = PolygonTables::new(&tessellate(patches, 64)).report().volume;
    assert!((tree.volume() / fine - 1.0).abs() < 0.01, "{} vs {fine}", tree.volume());
}

/// The surface voxelizers once had no memory estimate: one patch across the domain at
/// depth 14 (about 2.7e8 voxel faces) must be refused before any work under a small
/// budget, through the library call and the import path the CLI takes.
#[test]
fn one_patch_surface_at_depth_14_is_refused_under_a_small_budget() {
    // A unit square tilted across all three axes, its odd control rows lifted a little.
    let p = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let (u, v) = (i as f64 / 3.0, j as f64 / 3.0);
            DVec3::new(u, v, 0.5 * (u + v) + 0.1 * (i % 2) as f64)
        })
    });
    let patches = vec![BezierPatch { p }];
    let input = Input::Patches(patches.clone());
    let domain = Domain::around(&input.bounds(), 0.02, 14).unwrap();
    let budget = MemoryBudget(256 << 20);
    let progress = Recorder::default();
    let err = voxelize_patch_surface(&patches, domain, &VoxelizeOptions { budget, progress: &progress }).unwrap_err();
    assert!(matches!(err, Error::OverBudget { estimate, .. } if estimate > 2 << 30), "{err}");
    assert_eq!(progress.read().0, 0, "work started before the budget check");
    let result =
        import::voxelize_input(&input, domain, &ImportOptions { fill: Fill::Surface, budget, ..Default::default() });
    assert!(matches!(result, Err(Error::OverBudget { .. })), "the import path passed");
}

#[test]
fn teapot_surface_is_the_same_on_any_thread_count_with_progress_adding_up() {
    let patches = read_patches(Path::new("models/teapot.patches")).unwrap();
    let domain = Domain::around(&Input::Patches(patches.clone()).bounds(), 0.02, 7).unwrap();
    let run = |threads| {
        let progress = Recorder::default();
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        let options = VoxelizeOptions { budget: MemoryBudget::default(), progress: &progress };
        let tree = pool.install(|| voxelize_patch_surface(&patches, domain, &options).unwrap());
        assert_eq!(progress.read(), (1, 512, 512, 1), "{threads} threads");
        tree
    };
    let one = run(1);
    assert!(one.voxel_count() > 10_000, "{} voxels", one.voxel_count());
    assert_eq!(one, run(2), "1 vs 2 threads");
    assert_eq!(one, run(3), "1 vs 3 threads");
}
