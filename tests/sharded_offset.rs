//! Offsets, shells and rounds of sharded solids, cell by cell with a halo, against the
//! same operations on the merged solid in memory: equal node for node, and crossing
//! for crossing when the shards carry a surface; a window over the budget is computed
//! from smaller cells' windows to the same result, and a budget too small even for
//! the smallest is refused before anything is written.

mod common;

use std::path::{Path, PathBuf};

use common::Rng;
use glam::DVec3;
use octsolid::io::oct::Metadata;
use octsolid::octree::{Domain, LinearOctree, OffsetOptions, VoxelizeOptions, voxelize};
use octsolid::shape::{Csg, Cuboid, Sphere};
use octsolid::sharded::{self, Morph, ShardedSolid, StreamOptions};
use octsolid::surface::{Crossing, FaceKey, HermiteData, offset_with_surface, round_with_surface, shell_with_surface};
use octsolid::{Error, MemoryBudget};

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("sharded_offset", name)
}

/// A random union, difference and intersection of boxes and balls in the unit cube.
fn random_csg(rng: &mut Rng, levels: u32) -> Csg {
    if levels == 0 || rng.below(4) == 0 {
        let center = rng.vec(0.1, 0.9);
        return if rng.below(2) == 0 {
            Cuboid::new(center, rng.vec(0.1, 0.6)).unwrap().into()
        } else {
            Sphere::new(center, rng.range(0.08, 0.35)).unwrap().into()
        };
    }
    let (a, b) = (random_csg(rng, levels - 1), random_csg(rng, levels - 1));
    match rng.below(4) {
        0 | 1 => a | b,
        2 => a - b,
        _ => a & b,
    }
}

fn at_level(level: u8) -> StreamOptions<'static> {
    StreamOptions { level: Some(level), budget: MemoryBudget::unlimited(), ..StreamOptions::default() }
}

/// The operations tried, distances in voxels: grown, shrunk, both shells, a round.
fn operations(rng: &mut Rng) -> Vec<Morph> {
    let r = rng.range(1.2, 4.5);
    vec![
        Morph::Offset(r),
        Morph::Offset(-r),
        Morph::Shell { thickness: r, outward: false },
        Morph::Shell { thickness: r, outward: true },
        Morph::Round { radius: rng.range(1.2, 3.0), convex: true, concave: true },
    ]
}

/// The operation on a solid in memory, along `surface` when given.
fn in_memory(tree: &LinearOctree, surface: Option<&HermiteData>, op: Morph) -> (LinearOctree, Option<HermiteData>) {
    let o = OffsetOptions::default();
    match (op, surface) {
        (Morph::Offset(d), None) => (tree.offset(d, &o).unwrap(), None),
        (Morph::Shell { thickness, outward }, None) => (tree.shell(thickness, outward, &o).unwrap(), None),
        (Morph::Round { radius, convex, concave }, None) => (tree.round(radius, convex, concave, &o).unwrap(), None),
        (Morph::Offset(d), Some(s)) => {
            let (t, s) = offset_with_surface(tree, s, d, &o).unwrap();
            (t, Some(s))
        }
        (Morph::Shell { thickness, outward }, Some(s)) => {
            let (t, s) = shell_with_surface(tree, s, thickness, outward, &o).unwrap();
            (t, Some(s))
        }
        (Morph::Round { radius, convex, concave }, Some(s)) => {
            let (t, s) = round_with_surface(tree, s, radius, convex, concave, &o).unwrap();
            (t, Some(s))
        }
    }
}

/// Every shard's crossings together (full cells carry none), as the files store them.
fn shards_surface(dir: &Path) -> HermiteData {
    let solid = ShardedSolid::open(dir).unwrap();
    let mut faces = Vec::new();
    for i in 0..solid.index().shards.len() {
        let (_, surface) = solid.read_shard_and_surface(i, MemoryBudget::unlimited()).unwrap();
        faces.extend_from_slice(surface.expect("a shape's shards carry a surface").faces());
    }
    HermiteData::from_faces(faces)
}

/// The crossings of `data` on the voxels of the shards of `dir` (what a sharded solid
/// can carry: full cells have no file).
fn on_shards(data: &HermiteData, dir: &Path) -> Vec<(FaceKey, Crossing)> {
    let solid = ShardedSolid::open(dir).unwrap();
    let layout = solid.index().layout();
    let cells: Vec<u64> = solid.index().shards.iter().map(|s| s.cell).collect();
    data.faces().iter().filter(|(f, _)| cells.binary_search(&layout.cell_of(f.voxel)).is_ok()).copied().collect()
}

/// The two lists of crossings are equal; else the first difference and the counts.
fn assert_same_faces(got: &[(FaceKey, Crossing)], want: &[(FaceKey, Crossing)], what: &str) {
    if got == want {
        return;
    }
    let at = got.iter().zip(want).position(|(a, b)| a != b).unwrap_or(got.len().min(want.len()));
    panic!(
        "{what}: crossings differ at {at} of {} (want {}): got {:?}, want {:?}",
        got.len(),
        want.len(),
        got.get(at),
        want.get(at)
    );
}

#[test]
fn offsets_shells_and_rounds_of_sharded_random_solids_are_the_merged_solids_node_for_node() {
    let dir = scratch("random");
    let mut rng = Rng(0x0c75_0039);
    let domain = Domain::new(DVec3::ZERO, 1.0, 6).unwrap();
    for case in 0..2 {
        let shape = random_csg(&mut rng, 3);
        let whole = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
        let ops = operations(&mut rng);
        let wants: Vec<LinearOctree> = ops.iter().map(|&op| in_memory(&whole, None, op).0).collect();
        for level in [1u8, 2] {
            // Cut from memory (no surface) and voxelized cell by cell (with one).
            let cut = dir.join(format!("cut-{case}-{level}.octs"));
            sharded::write(&whole, Metadata::default(), &cut, &at_level(level)).unwrap();
            let made = dir.join(format!("made-{case}-{level}.octs"));
            sharded::voxelize_shape(&shape, domain, Metadata::default(), &made, &at_level(level)).unwrap();
            let surface = shards_surface(&made);
            for (n, &op) in ops.iter().enumerate() {
                let what = format!("case {case}, level {level}, {op:?}");
                let want = &wants[n];
                let out = dir.join(format!("out-{case}-{level}-{n}.octs"));
                sharded::morph(&ShardedSolid::open(&cut).unwrap(), op, &out, &at_level(level)).unwrap();
                let got = ShardedSolid::open(&out).unwrap().read(MemoryBudget::unlimited()).unwrap();
                assert_eq!(got.keys(), want.keys(), "{what}, no surface");

                // Along the surface every operation at level 1, the two offsets at level 2
                // (the test's time).
                if level == 2 && n >= 2 {
                    continue;
                }
                let (want, want_surface) = in_memory(&whole, Some(&surface), op);
                let out = dir.join(format!("surf-{case}-{level}-{n}.octs"));
                sharded::morph(&ShardedSolid::open(&made).unwrap(), op, &out, &at_level(level)).unwrap();
                let got = ShardedSolid::open(&out).unwrap().read(MemoryBudget::unlimited()).unwrap();
                assert_eq!(got.keys(), want.keys(), "{what}, along the surface");
                let got_faces = if got.is_empty() { Vec::new() } else { shards_surface(&out).faces().to_vec() };
                assert_same_faces(&got_faces, &on_shards(&want_surface.unwrap().as_stored(), &out), &what);
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn output_cells_of_another_level_give_the_same_solid() {
    let dir = scratch("levels");
    let domain = Domain::new(DVec3::ZERO, 1.0, 6).unwrap();
    let shape = random_csg(&mut Rng(0x1e7e_1539), 3);
    let whole = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
    let input = dir.join("in.octs");
    sharded::write(&whole, Metadata::default(), &input, &at_level(1)).unwrap();
    let want = whole.offset(3.0, &OffsetOptions::default()).unwrap();
    for level in [0u8, 2, 3] {
        let out = dir.join(format!("out-{level}.octs"));
        sharded::morph(&ShardedSolid::open(&input).unwrap(), Morph::Offset(3.0), &out, &at_level(level)).unwrap();
        let solid = ShardedSolid::open(&out).unwrap();
        assert_eq!(solid.index().level, level);
        assert_eq!(solid.read(MemoryBudget::unlimited()).unwrap(), want, "output level {level}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_budget_too_small_for_a_window_is_refused_before_anything_is_written() {
    let dir = scratch("budget");
    let domain = Domain::new(DVec3::ZERO, 1.0, 7).unwrap();
    let whole = voxelize(&Sphere::new(DVec3::splat(0.5), 0.4).unwrap(), domain, &VoxelizeOptions::default()).unwrap();
    let input = dir.join("ball.octs");
    sharded::write(&whole, Metadata::default(), &input, &at_level(2)).unwrap();
    let solid = ShardedSolid::open(&input).unwrap();
    // Enough to read any shard, not enough for a window's band.
    let largest = (0..solid.index().shards.len()).map(|i| solid.shard_bytes(i)).max().unwrap();
    let budget = MemoryBudget(4 * largest);
    let out = dir.join("grown.octs");
    for op in [Morph::Offset(6.0), Morph::Round { radius: 3.0, convex: true, concave: false }] {
        match sharded::morph(&solid, op, &out, &StreamOptions { budget, ..at_level(2) }) {
            Err(e @ Error::OverBudget { .. }) => assert!(e.to_string().contains("window of cell"), "{e}"),
            other => panic!("{op:?} over the budget was not refused: {other:?}"),
        }
        assert!(!out.exists(), "nothing is written");
        let mut staging = out.file_name().unwrap().to_os_string();
        staging.push(".partial");
        assert!(!out.with_file_name(staging).exists(), "no staging folder is made");
    }
    // Bad distances are refused too, naming the distance.
    let e = sharded::morph(&solid, Morph::Offset(f64::NAN), &out, &at_level(2)).unwrap_err();
    assert!(e.to_string().contains("offset distance"), "{e}");
    let e = sharded::morph(&solid, Morph::Shell { thickness: -1.0, outward: false }, &out, &at_level(2)).unwrap_err();
    assert!(e.to_string().contains("shell thickness"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The solid `whole` in the voxel box `lo..hi` (what a window holds).
fn in_box(whole: &LinearOctree, lo: [u32; 3], hi: [u32; 3]) -> LinearOctree {
    let voxels = (lo[2]..hi[2]).flat_map(|z| (lo[1]..hi[1]).flat_map(move |y| (lo[0]..hi[0]).map(move |x| [x, y, z])));
    whole.intersection(&LinearOctree::from_voxels(*whole.domain(), voxels).unwrap()).unwrap()
}

#[test]
fn a_window_over_the_budget_is_split_into_smaller_cells_with_the_same_result() {
    let dir = scratch("split");
    let domain = Domain::new(DVec3::ZERO, 1.0, 7).unwrap();
    let shape = random_csg(&mut Rng(0x5e1f_0039), 3) | Sphere::new(DVec3::splat(0.5), 0.3).unwrap();
    let whole = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
    let op = Morph::Offset(3.0);
    // The largest window of the cells of 64 voxels, built here from the whole solid:
    // each cell and the halo around it, clipped to the domain.
    let (size, halo, n) = (64u32, op.halo(), domain.resolution());
    // Over the cubes and along the surface (whose crossings the step needs besides).
    let (mut largest, mut largest_along) = (0, 0);
    for c in 0..8u32 {
        let min = [c & 1, (c >> 1) & 1, c >> 2].map(|b| b * size);
        let window = in_box(&whole, min.map(|m| m.saturating_sub(halo)), min.map(|m| (m + size + halo).min(n)));
        largest = largest.max(window.offset_estimate(3.0, false));
        largest_along = largest_along.max(window.offset_estimate(3.0, true));
    }
    assert!(largest > 0 && largest_along > 0);
    let cut = dir.join("cut.octs");
    sharded::write(&whole, Metadata::default(), &cut, &at_level(1)).unwrap();
    let made = dir.join("made.octs");
    sharded::voxelize_shape(&shape, domain, Metadata::default(), &made, &at_level(1)).unwrap();
    let options = StreamOptions { budget: MemoryBudget(largest - 1), ..at_level(1) };

    // Over the cubes: the same nodes as the merged solid's offset.
    let out = dir.join("grown.octs");
    sharded::morph(&ShardedSolid::open(&cut).unwrap(), op, &out, &options).unwrap();
    let got = ShardedSolid::open(&out).unwrap();
    assert_eq!(got.index().level, 1, "the output keeps its cells");
    let want = whole.offset(3.0, &OffsetOptions::default()).unwrap();
    assert_eq!(got.read(MemoryBudget::unlimited()).unwrap().keys(), want.keys(), "over the cubes");

    // Along the surface (its estimate larger still): the same nodes and crossings.
    let surface = shards_surface(&made);
    let (want, want_surface) = in_memory(&whole, Some(&surface), op);
    let out = dir.join("grown-along.octs");
    let options = StreamOptions { budget: MemoryBudget(largest_along - 1), ..at_level(1) };
    sharded::morph(&ShardedSolid::open(&made).unwrap(), op, &out, &options).unwrap();
    let got = ShardedSolid::open(&out).unwrap().read(MemoryBudget::unlimited()).unwrap();
    assert_eq!(got.keys(), want.keys(), "along the surface");
    assert_same_faces(
        shards_surface(&out).faces(),
        &on_shards(&want_surface.unwrap().as_stored(), &out),
        "along the surface",
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
