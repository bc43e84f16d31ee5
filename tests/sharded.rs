//! Sharded solids against the single-file solid they store: voxelized cell by cell,
//! cut from memory, split among tasks, merged cell by cell, read back at a coarser
//! level, and refused when a shard or the index is corrupted.

mod common;

use std::path::{Path, PathBuf};

use common::{Rng, folder_files, random_octree};
use glam::DVec3;
use octsolid::io::oct::{self, Metadata};
use octsolid::mesh::{MeshVoxelizeOptions, load_mesh, voxelize_mesh};
use octsolid::octree::{CoarsenRule, Domain, LinearOctree, SetOp, VoxelizeOptions, voxelize};
use octsolid::samples::{classic_csg, showcase_domain};
use octsolid::sharded::{self, ShardIndex, ShardedSolid, StreamOptions};
use octsolid::{Error, MemoryBudget};

/// A fresh folder for one test's files.
fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("sharded", name)
}

fn at_level(level: u8) -> StreamOptions<'static> {
    StreamOptions { level: Some(level), budget: MemoryBudget::unlimited(), ..StreamOptions::default() }
}

/// The solid read back, as `.oct` bytes.
fn oct_bytes(dir: &Path) -> Vec<u8> {
    oct::encode(&ShardedSolid::open(dir).unwrap().load(MemoryBudget::unlimited()).unwrap())
}

#[test]
fn shapes_voxelized_cell_by_cell_are_the_single_file_solid_bit_for_bit_at_every_level() {
    let dir = scratch("shapes");
    for depth in [1u8, 4, 7] {
        let domain = showcase_domain(depth).unwrap();
        let whole = voxelize(&classic_csg(), domain, &VoxelizeOptions::default()).unwrap();
        for level in 0..=depth.min(4) {
            let out = dir.join(format!("part-{depth}-{level}.octs"));
            let index = sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &out, &at_level(level))
                .unwrap()
                .expect("every cell: an index");
            assert_eq!((index.nodes, index.voxels), (whole.node_count() as u64, whole.voxel_count()));
            assert_eq!(oct_bytes(&out), oct::encode(&whole), "depth {depth}, level {level}");
            // The index alone gives the counts and the bounds.
            let opened = ShardedSolid::open(&out).unwrap();
            assert_eq!(opened.index().voxel_bounds(), whole.voxel_bounds());
            // Cutting the solid from memory gives the same folder, file for file.
            let cut = dir.join(format!("cut-{depth}-{level}.octs"));
            sharded::save(&whole, Metadata::default(), &cut, &at_level(level)).unwrap();
            assert_eq!(folder_files(&cut), folder_files(&out), "depth {depth}, level {level}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_mesh_voxelized_cell_by_cell_is_the_single_file_solid() {
    let dir = scratch("mesh");
    let mesh = load_mesh(Path::new(env!("CARGO_MANIFEST_DIR")).join("models/bunny-watertight.obj")).unwrap();
    let domain = Domain::around(&mesh.bounds(), 0.02, 7).unwrap();
    let options = MeshVoxelizeOptions::default();
    let (whole, _) = voxelize_mesh(&mesh, domain, &options).unwrap();
    let out = dir.join("bunny.octs");
    let meta = Metadata { up: Some(octsolid::shape::Axis::Y), units: None };
    sharded::voxelize_mesh(&mesh, domain, meta, &options, &out, &at_level(2)).unwrap();
    let solid = ShardedSolid::open(&out).unwrap();
    assert_eq!(solid.index().meta, meta);
    assert_eq!(solid.load(MemoryBudget::unlimited()).unwrap(), whole);
    assert!(solid.index().shards.len() > 8, "the surface crosses many cells");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn tasks_over_any_split_of_the_cells_joined_give_the_same_bytes_as_one_job() {
    let dir = scratch("tasks");
    let domain = showcase_domain(7).unwrap();
    let one = dir.join("one.octs");
    sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &one, &at_level(3)).unwrap();
    let split = dir.join("split.octs");
    // Uneven ranges, written out of order (as workers finish).
    for range in [300..512u64, 0..1, 1..299, 299..300] {
        let options = StreamOptions { cells: Some(&range), ..at_level(3) };
        let written = sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &split, &options).unwrap();
        assert!(written.is_none(), "a task writes a part, not the index");
    }
    assert!(!split.exists(), "the solid appears only at the join");
    sharded::join(&split).unwrap();
    assert_eq!(folder_files(&split), folder_files(&one));
    assert!(!sharded::staging_dir(&split).exists());
    // One task over every cell is still a task: it leaves its part for the join.
    let single = dir.join("single.octs");
    let every = 0..512u64;
    let options = StreamOptions { cells: Some(&every), ..at_level(3) };
    let written = sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &single, &options).unwrap();
    assert!(written.is_none() && !single.exists(), "a task over every cell writes a part, not the index");
    sharded::join(&single).unwrap();
    assert_eq!(folder_files(&single), folder_files(&one));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_join_with_a_missing_or_overlapping_part_is_refused() {
    let dir = scratch("join");
    let domain = showcase_domain(6).unwrap();
    let out = dir.join("gap.octs");
    for range in [0..100u64, 200..512] {
        let options = StreamOptions { cells: Some(&range), ..at_level(3) };
        sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &out, &options).unwrap();
    }
    let err = sharded::join(&out).unwrap_err().to_string();
    assert!(err.contains("no part covers cells 100..200"), "{err}");
    let range = 50..200u64;
    let options = StreamOptions { cells: Some(&range), ..at_level(3) };
    sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &out, &options).unwrap();
    let err = sharded::join(&out).unwrap_err().to_string();
    assert!(err.contains("two parts cover cells 50..100"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn set_operations_merged_cell_by_cell_equal_the_in_memory_merge() {
    let dir = scratch("csg");
    let mut rng = Rng(21);
    let domain = Domain::new(DVec3::ZERO, 1.0, 6).unwrap();
    for round in 0..3 {
        let trees: Vec<LinearOctree> = (0..3).map(|_| random_octree(&mut rng, domain)).collect();
        // Operands cut at different levels: the output's cells meet several of an
        // operand's shards, or a part of one.
        let dirs: Vec<PathBuf> = trees
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let d = dir.join(format!("in-{round}-{i}.octs"));
                sharded::save(t, Metadata::default(), &d, &at_level(i as u8 + 1)).unwrap();
                d
            })
            .collect();
        let solids: Vec<ShardedSolid> = dirs.iter().map(|d| ShardedSolid::open(d).unwrap()).collect();
        for op in [SetOp::Union, SetOp::Intersection, SetOp::Difference, SetOp::SymmetricDifference] {
            let want = LinearOctree::combine_all(&trees.iter().collect::<Vec<_>>(), op).unwrap();
            for level in [None, Some(1), Some(3)] {
                let out = dir.join(format!("out-{round}.octs"));
                let options = StreamOptions { level, ..at_level(0) };
                sharded::combine(&solids, op, &out, &options).unwrap();
                assert_eq!(oct_bytes(&out), oct::encode(&want), "round {round}, {op:?}, level {level:?}");
            }
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_budget_smaller_than_the_solid_still_combines_and_refuses_a_whole_load() {
    let dir = scratch("budget");
    let domain = showcase_domain(9).unwrap();
    let part = voxelize(&classic_csg(), domain, &VoxelizeOptions::default()).unwrap();
    let ring = voxelize(&octsolid::samples::showcase(), domain, &VoxelizeOptions::default()).unwrap();
    let (a, b) = (dir.join("a.octs"), dir.join("b.octs"));
    sharded::save(&part, Metadata::default(), &a, &at_level(4)).unwrap();
    sharded::save(&ring, Metadata::default(), &b, &at_level(4)).unwrap();
    let solids = [ShardedSolid::open(&a).unwrap(), ShardedSolid::open(&b).unwrap()];
    // A tenth of either solid's nodes.
    let budget = MemoryBudget(part.node_count() as u64 * 8 / 10);
    let out = dir.join("ring.octs");
    let options = StreamOptions { budget, ..at_level(4) };
    sharded::combine(&solids[..], SetOp::SymmetricDifference, &out, &options).unwrap();
    let result = ShardedSolid::open(&out).unwrap();
    match result.load(budget) {
        Err(Error::OverBudget { .. }) => {}
        other => panic!("a whole load over the budget was not refused: {other:?}"),
    }
    let want = LinearOctree::combine_all(&[&part, &ring], SetOp::SymmetricDifference).unwrap();
    assert_eq!(result.load(MemoryBudget::unlimited()).unwrap(), want);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_level_of_detail_within_a_budget_is_the_coarsened_solid() {
    let dir = scratch("lod");
    let domain = showcase_domain(8).unwrap();
    let whole = voxelize(&classic_csg(), domain, &VoxelizeOptions::default()).unwrap();
    let out = dir.join("part.octs");
    sharded::save(&whole, Metadata::default(), &out, &at_level(2)).unwrap();
    let solid = ShardedSolid::open(&out).unwrap();
    assert_eq!(solid.load_within(MemoryBudget::unlimited()).unwrap(), whole);
    let budget = MemoryBudget(whole.node_count() as u64 * 8 / 10);
    let coarse = solid.load_within(budget).unwrap();
    assert!(coarse.depth() < 8 && coarse.depth() >= 2, "depth {}", coarse.depth());
    assert_eq!(coarse, whole.coarsen(coarse.depth(), CoarsenRule::Any).unwrap());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sharded solid of the classic part at depth 6, level 2, and its index.
fn small_solid(dir: &Path, name: &str) -> (PathBuf, ShardIndex) {
    let out = dir.join(name);
    let domain = showcase_domain(6).unwrap();
    let index =
        sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &out, &at_level(2)).unwrap().unwrap();
    (out, index)
}

/// Loading refuses with a message naming `name` and holding `words`.
fn assert_refused(dir: &Path, name: &str, words: &str) {
    let err = ShardedSolid::open(dir).and_then(|s| s.load(MemoryBudget::unlimited())).unwrap_err().to_string();
    assert!(err.contains(name) && err.contains(words), "{err}");
}

#[test]
fn corrupted_shards_and_indexes_are_refused_by_name() {
    let dir = scratch("corrupt");
    // A flipped byte in a shard: the index's checksum of the file catches it.
    let (out, index) = small_solid(&dir, "flip.octs");
    let shard = index.layout().shard_file(index.shards[3].cell);
    let path = out.join(&shard);
    let mut bytes = std::fs::read(&path).unwrap();
    let last = bytes.len() - 1;
    bytes[last] ^= 0x40;
    std::fs::write(&path, &bytes).unwrap();
    assert_refused(&out, &shard, "checksum mismatch");
    // A truncated shard.
    let (out, index) = small_solid(&dir, "short.octs");
    let shard = index.layout().shard_file(index.shards[0].cell);
    let bytes = std::fs::read(out.join(&shard)).unwrap();
    std::fs::write(out.join(&shard), &bytes[..bytes.len() - 3]).unwrap();
    assert_refused(&out, &shard, "the index says");
    // A missing shard.
    let (out, index) = small_solid(&dir, "missing.octs");
    let shard = index.layout().shard_file(index.shards[1].cell);
    std::fs::remove_file(out.join(&shard)).unwrap();
    assert_refused(&out, &shard, "");
    // Two shards swapped (each file intact, each under the other's name).
    let (out, index) = small_solid(&dir, "swap.octs");
    let (s0, s1) = (index.layout().shard_file(index.shards[0].cell), index.layout().shard_file(index.shards[1].cell));
    std::fs::rename(out.join(&s0), out.join("tmp")).unwrap();
    std::fs::rename(out.join(&s1), out.join(&s0)).unwrap();
    std::fs::rename(out.join("tmp"), out.join(&s1)).unwrap();
    assert_refused(&out, &s0, "");
    // The index: a flipped byte, a truncation, counts that do not fit the file.
    for (name, damage) in [("index-flip.octs", 0usize), ("index-short.octs", 1), ("index-count.octs", 2)] {
        let (out, _) = small_solid(&dir, name);
        let path = out.join(sharded::INDEX_FILE);
        let mut bytes = std::fs::read(&path).unwrap();
        match damage {
            0 => bytes[100] ^= 1,
            1 => bytes.truncate(bytes.len() - 10),
            _ => bytes[72..80].copy_from_slice(&u64::MAX.to_le_bytes()),
        }
        std::fs::write(&path, &bytes).unwrap();
        let err = ShardedSolid::open(&out).unwrap_err().to_string();
        assert!(err.contains("index"), "{err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_shard_with_a_node_reaching_out_of_its_cell_is_refused() {
    let dir = scratch("span");
    let (out, mut index) = small_solid(&dir, "span.octs");
    let layout = index.layout();
    // Rewrite shard 0 with a node spanning its cell's end (the first node of the next
    // cell's parent-sized block), with the index updated to match the file, so only
    // the cell check can refuse it.
    let entry = index.shards[0].clone();
    let cell = layout.cell_key(entry.cell);
    let shard = layout.shard_file(entry.cell);
    let mut keys: Vec<_> = ShardedSolid::open(&out).unwrap().load_shard(0, MemoryBudget::unlimited()).unwrap();
    let spanning = octsolid::octree::NodeKey::new(cell.end() - 8, 1); // inside: a 2-voxel node at the end
    keys.retain(|k| k.end() <= spanning.start());
    let beyond = octsolid::octree::NodeKey::new(cell.end(), 0); // the next cell's first voxel
    keys.push(beyond);
    let tree = LinearOctree::from_keys(index.domain, keys).unwrap();
    let bytes = oct::encode(&tree);
    std::fs::write(out.join(&shard), &bytes).unwrap();
    let e = &mut index.shards[0];
    (e.nodes, e.voxels, e.bytes, e.crc32) =
        (tree.node_count() as u64, tree.voxel_count(), bytes.len() as u64, crc32fast::hash(&bytes));
    index.nodes = index.full.len() as u64 + index.shards.iter().map(|s| s.nodes).sum::<u64>();
    index.voxels = index.full.iter().map(|k| k.len()).sum::<u64>() + index.shards.iter().map(|s| s.voxels).sum::<u64>();
    std::fs::write(out.join(sharded::INDEX_FILE), index.encode()).unwrap();
    assert_refused(&out, &shard, "reaches beyond its cell");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_scene_names_a_sharded_solid_like_any_solid_file() {
    let dir = scratch("scene");
    let domain = showcase_domain(6).unwrap();
    let whole = voxelize(&classic_csg(), domain, &VoxelizeOptions::default()).unwrap();
    sharded::save(&whole, Metadata::default(), &dir.join("part.octs"), &at_level(2)).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "[[solid]]\nname = \"part\"\noct = \"part.octs\"\n").unwrap();
    let loaded = octsolid::scene_file::load_scene(&scene, MemoryBudget::unlimited()).unwrap();
    assert_eq!(loaded.scene.solids[0].tree, whole);
    std::fs::remove_dir_all(&dir).unwrap();
}
