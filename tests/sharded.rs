//! Sharded solids against the single-file solid they store: voxelized cell by cell,
//! cut from memory, split among tasks, merged cell by cell, read back at a coarser
//! level, and refused when a shard or the index is corrupted.

mod common;

use std::path::{Path, PathBuf};

use common::{Rng, folder_files, random_octree};
use glam::DVec3;
use octsolid::io::oct::{self, Metadata};
use octsolid::mesh::{MeshVoxelizeOptions, read_mesh, voxelize_mesh};
use octsolid::octree::{CoarsenRule, Domain, LinearOctree, SetOp, VoxelizeOptions, voxelize};
use octsolid::samples::{classic_csg, showcase_domain};
use octsolid::sharded::{self, ShardIndex, ShardedSolid, StreamOptions};
use octsolid::surface::HermiteData;
use octsolid::{Error, MemoryBudget};

/// The staging folder of output `out`, as docs/FORMAT.md names it: `OUT.partial`
/// beside the output.
fn staging_dir(out: &Path) -> PathBuf {
    let mut name = out.file_name().expect("an output file name").to_os_string();
    name.push(".partial");
    out.with_file_name(name)
}

/// A fresh folder for one test's files.
fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("sharded", name)
}

fn at_level(level: u8) -> StreamOptions<'static> {
    StreamOptions { level: Some(level), budget: MemoryBudget::unlimited(), ..StreamOptions::default() }
}

/// The solid read back, as `.oct` bytes.
fn oct_bytes(dir: &Path) -> Vec<u8> {
    oct::encode(&ShardedSolid::open(dir).unwrap().read(MemoryBudget::unlimited()).unwrap())
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
            // Cutting the solid from memory gives the same shards' nodes (a cut has no
            // shape, so its shards carry no surface section).
            let cut = dir.join(format!("cut-{depth}-{level}.octs"));
            sharded::write(&whole, Metadata::default(), &cut, &at_level(level)).unwrap();
            let cut = ShardedSolid::open(&cut).unwrap();
            assert_eq!(cut.index().shards.len(), opened.index().shards.len());
            assert_eq!(cut.index().full, opened.index().full);
            for i in 0..cut.index().shards.len() {
                let budget = MemoryBudget::unlimited();
                assert_eq!(
                    cut.read_shard_and_surface(i, budget).unwrap(),
                    (opened.read_shard(i, budget).unwrap(), None)
                );
            }
            // The shape's shards carry the whole solid's crossings between them: the
            // single file's surface section, face for face, but for the faces of full
            // cells (kept in the index as nodes, with no file to carry their faces).
            let single = oct::encode_with_surface(
                &whole,
                &Metadata::default(),
                Some(&HermiteData::from_shape(&classic_csg(), &whole)),
            );
            let (_, _, single) =
                oct::decode_and_surface(&single, Path::new("whole.oct"), MemoryBudget::unlimited()).unwrap();
            let mut faces = Vec::new();
            for i in 0..opened.index().shards.len() {
                let (_, surface) = opened.read_shard_and_surface(i, MemoryBudget::unlimited()).unwrap();
                faces.extend_from_slice(surface.expect("a shape's shard carries its surface").faces());
            }
            let layout = opened.index().layout();
            let has_shard =
                |voxel: u64| opened.index().shards.binary_search_by_key(&layout.cell_of(voxel), |s| s.cell).is_ok();
            let single: Vec<_> = single.unwrap().faces().iter().filter(|(f, _)| has_shard(f.voxel)).copied().collect();
            assert_eq!(HermiteData::from_faces(faces).faces(), single.as_slice(), "depth {depth}, level {level}");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_mesh_voxelized_cell_by_cell_is_the_single_file_solid() {
    let dir = scratch("mesh");
    let mesh = read_mesh(Path::new(env!("CARGO_MANIFEST_DIR")).join("models/bunny-watertight.obj")).unwrap();
    let domain = Domain::around(&mesh.bounds(), 0.02, 7).unwrap();
    let options = MeshVoxelizeOptions::default();
    let (whole, _) = voxelize_mesh(&mesh, domain, &options).unwrap();
    let out = dir.join("bunny.octs");
    let meta = Metadata { up: Some(octsolid::shape::Axis::Y), units: None };
    sharded::voxelize_mesh(&mesh, domain, meta, &options, &out, &at_level(2)).unwrap();
    let solid = ShardedSolid::open(&out).unwrap();
    assert_eq!(solid.index().meta, meta);
    assert_eq!(solid.read(MemoryBudget::unlimited()).unwrap(), whole);
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
    assert!(!staging_dir(&split).exists());
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
                sharded::write(t, Metadata::default(), &d, &at_level(i as u8 + 1)).unwrap();
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
    sharded::write(&part, Metadata::default(), &a, &at_level(4)).unwrap();
    sharded::write(&ring, Metadata::default(), &b, &at_level(4)).unwrap();
    let solids = [ShardedSolid::open(&a).unwrap(), ShardedSolid::open(&b).unwrap()];
    // A tenth of either solid's nodes.
    let budget = MemoryBudget(part.node_count() as u64 * 8 / 10);
    let out = dir.join("ring.octs");
    let options = StreamOptions { budget, ..at_level(4) };
    sharded::combine(&solids[..], SetOp::SymmetricDifference, &out, &options).unwrap();
    let result = ShardedSolid::open(&out).unwrap();
    match result.read(budget) {
        Err(Error::OverBudget { .. }) => {}
        other => panic!("a whole load over the budget was not refused: {other:?}"),
    }
    let want = LinearOctree::combine_all(&[&part, &ring], SetOp::SymmetricDifference).unwrap();
    assert_eq!(result.read(MemoryBudget::unlimited()).unwrap(), want);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_level_of_detail_within_a_budget_is_the_coarsened_solid() {
    let dir = scratch("lod");
    let domain = showcase_domain(8).unwrap();
    let whole = voxelize(&classic_csg(), domain, &VoxelizeOptions::default()).unwrap();
    let out = dir.join("part.octs");
    sharded::write(&whole, Metadata::default(), &out, &at_level(2)).unwrap();
    let solid = ShardedSolid::open(&out).unwrap();
    assert_eq!(solid.read_within(MemoryBudget::unlimited()).unwrap(), whole);
    let budget = MemoryBudget(whole.node_count() as u64 * 8 / 10);
    let coarse = solid.read_within(budget).unwrap();
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
    let err = ShardedSolid::open(dir).and_then(|s| s.read(MemoryBudget::unlimited())).unwrap_err().to_string();
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
    let mut keys: Vec<_> = ShardedSolid::open(&out).unwrap().read_shard(0, MemoryBudget::unlimited()).unwrap();
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
    sharded::write(&whole, Metadata::default(), &dir.join("part.octs"), &at_level(2)).unwrap();
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, "[[solid]]\nname = \"part\"\noct = \"part.octs\"\n").unwrap();
    let loaded = octsolid::scene_file::read_scene(&scene, MemoryBudget::unlimited()).unwrap();
    assert_eq!(loaded.scene.solids[0].tree, whole);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The staging folder of the one job folder in `out`'s staging folder.
fn job_folder(out: &Path) -> PathBuf {
    let jobs: Vec<PathBuf> = std::fs::read_dir(staging_dir(out))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with("job-"))
        .collect();
    assert_eq!(jobs.len(), 1, "{jobs:?}");
    jobs[0].clone()
}

/// Runs the tasks `ranges` of the job voxelizing `shape` (told apart by `source`) at
/// depth 6, level 2 (64 cells), into `out`.
fn tasks(shape: &dyn octsolid::shape::Shape, source: &[u8], out: &Path, ranges: &[[u64; 2]]) {
    let domain = showcase_domain(6).unwrap();
    for &[first, end] in ranges {
        let range = first..end;
        let options = StreamOptions { cells: Some(&range), source, ..at_level(2) };
        assert!(sharded::voxelize_shape(shape, domain, Metadata::default(), out, &options).unwrap().is_none());
    }
}

/// The classic part at depth 6, in memory.
fn classic_whole() -> LinearOctree {
    voxelize(&classic_csg(), showcase_domain(6).unwrap(), &VoxelizeOptions::default()).unwrap()
}

fn loaded(out: &Path) -> LinearOctree {
    ShardedSolid::open(out).unwrap().read(MemoryBudget::unlimited()).unwrap()
}

#[test]
fn the_halves_of_two_jobs_over_one_domain_are_never_joined_into_one_solid() {
    let dir = scratch("two-jobs");
    let out = dir.join("mixed.octs");
    tasks(&classic_csg(), b"classic", &out, &[[0, 32]]);
    tasks(&octsolid::samples::showcase(), b"showcase", &out, &[[32, 64]]);
    let err = sharded::join(&out).unwrap_err().to_string();
    assert!(err.contains("none covers every cell") && err.contains("job-"), "{err}");
    assert!(!out.exists());
    // The first job's other half: that job alone is joined, the other one's parts kept.
    tasks(&classic_csg(), b"classic", &out, &[[32, 64]]);
    let index = sharded::join(&out).unwrap();
    assert_eq!(loaded(&out), classic_whole());
    assert_ne!(index.job, sharded::JobId::NONE);
    let parts = |folder: &Path| {
        std::fs::read_dir(folder)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with("part-"))
            .count()
    };
    assert_eq!(parts(&job_folder(&out)), 1, "the other job's part is left alone");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The part files and shards of a job's folder, by name, with their bytes.
fn staged(out: &Path) -> Vec<(String, Vec<u8>)> {
    folder_files(&job_folder(out))
}

#[test]
fn a_join_checks_every_shard_and_publishes_or_deletes_nothing_until_all_are_right() {
    let dir = scratch("join-checks");
    let out = dir.join("part.octs");
    tasks(&classic_csg(), b"classic", &out, &[[0, 20], [20, 64]]);
    let before = staged(&out);
    let job = job_folder(&out);
    let shard = before.iter().find(|(n, _)| n.ends_with(".oct")).unwrap().0.clone();
    let bytes = std::fs::read(job.join(&shard)).unwrap();
    // Missing, damaged, a FIFO: each refused by name; nothing published or removed.
    std::fs::remove_file(job.join(&shard)).unwrap();
    let mut damaged = bytes.clone();
    *damaged.last_mut().unwrap() ^= 1;
    let fifo = |path: &Path| assert!(std::process::Command::new("mkfifo").arg(path).status().unwrap().success());
    for (case, words) in [(0, "No such file"), (1, "checksum mismatch"), (2, "not a regular file")] {
        let _ = std::fs::remove_file(job.join(&shard));
        match case {
            0 => {}
            1 => std::fs::write(job.join(&shard), &damaged).unwrap(),
            _ => fifo(&job.join(&shard)),
        }
        let err = sharded::join(&out).unwrap_err().to_string();
        assert!(err.contains(&shard) && err.contains(words), "{err}");
        assert!(!out.exists(), "nothing published");
        let parts = std::fs::read_dir(&job)
            .unwrap()
            .filter(|e| e.as_ref().unwrap().file_name().to_string_lossy().starts_with("part-"));
        assert_eq!(parts.count(), 2, "the parts are kept");
    }
    std::fs::remove_file(job.join(&shard)).unwrap();
    std::fs::write(job.join(&shard), &bytes).unwrap();
    // The output is a file, not a sharded solid: publishing fails, the parts stay.
    std::fs::write(&out, b"not a solid").unwrap();
    let err = sharded::join(&out).unwrap_err().to_string();
    assert!(err.contains("not a sharded solid"), "{err}");
    assert_eq!(staged(&out), before, "the job's files are all there after a failed join");
    assert_eq!(std::fs::read(&out).unwrap(), b"not a solid");
    std::fs::remove_file(&out).unwrap();
    sharded::join(&out).unwrap();
    assert_eq!(loaded(&out), classic_whole());
    assert!(!staging_dir(&out).exists(), "the job's folder is removed once the solid is in place");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn staging_folders_that_are_links_to_other_folders_are_refused_and_left_untouched() {
    let dir = scratch("symlinked-staging");
    let victim = dir.join("victim");
    std::fs::create_dir(&victim).unwrap();
    std::fs::write(victim.join("precious.txt"), b"keep me").unwrap();
    let out = dir.join("solid.octs");
    std::os::unix::fs::symlink(&victim, staging_dir(&out)).unwrap();
    // A task, then the join (which once removed every file no shard entry names),
    // then a whole job: each refused, nothing written into the victim or removed.
    let domain = showcase_domain(6).unwrap();
    for range in [0..32u64, 32..64] {
        let task = StreamOptions { cells: Some(&range), ..at_level(2) };
        let err =
            sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &out, &task).unwrap_err().to_string();
        assert!(err.contains("symbolic link"), "{err}");
    }
    let err = sharded::join(&out).unwrap_err().to_string();
    assert!(err.contains("symbolic link"), "{err}");
    let err = sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &out, &at_level(2))
        .unwrap_err()
        .to_string();
    assert!(err.contains("symbolic link"), "{err}");
    let kept = folder_files(&victim);
    assert_eq!(kept, vec![("precious.txt".into(), b"keep me".to_vec())]);
    assert!(!out.exists());
    // A job's folder that is a link, in a plain staging folder.
    std::fs::remove_file(staging_dir(&out)).unwrap();
    std::fs::create_dir(staging_dir(&out)).unwrap();
    let job = staging_dir(&out).join(format!("job-{}", "ab".repeat(16)));
    std::os::unix::fs::symlink(&victim, &job).unwrap();
    let err = sharded::join(&out).unwrap_err().to_string();
    assert!(err.contains("symbolic link"), "{err}");
    assert_eq!(folder_files(&victim), kept);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Runs `f` on another thread and waits for it, so that a read that blocks forever
/// (a FIFO) fails the test instead of hanging it.
fn without_hanging<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    let (send, receive) = std::sync::mpsc::channel();
    std::thread::spawn(move || send.send(f()).unwrap());
    receive.recv_timeout(std::time::Duration::from_secs(120)).expect("the read blocked")
}

#[test]
fn indexes_and_shards_that_are_fifos_or_devices_are_refused_without_reading_them() {
    let dir = scratch("special-files");
    let fifo = |path: &Path| assert!(std::process::Command::new("mkfifo").arg(path).status().unwrap().success());
    for (what, case) in [("index", 0), ("index", 1), ("shard", 0), ("shard", 1)] {
        let (out, index) = small_solid(&dir, &format!("{what}-{case}.octs"));
        let target = if what == "index" {
            out.join(sharded::INDEX_FILE)
        } else {
            out.join(index.layout().shard_file(index.shards[0].cell))
        };
        std::fs::remove_file(&target).unwrap();
        if case == 0 {
            fifo(&target);
        } else {
            std::os::unix::fs::symlink("/dev/zero", &target).unwrap();
        }
        let err = without_hanging(move || {
            ShardedSolid::open(&out).and_then(|s| s.read(MemoryBudget::unlimited())).unwrap_err().to_string()
        });
        assert!(
            err.contains("not a regular file") && err.contains(target.file_name().unwrap().to_str().unwrap()),
            "{err}"
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn shard_bounds_in_the_index_are_checked_against_the_shards() {
    let dir = scratch("bounds");
    let (out, mut index) = small_solid(&dir, "bounds.octs");
    let whole = classic_whole();
    // The first shard's recorded bounds shrunk to its lowest voxel: still inside its
    // cell, so the index alone is consistent, but not what the shard holds.
    let i = index.shards.iter().position(|s| s.min != s.max).unwrap();
    index.shards[i].max = index.shards[i].min;
    std::fs::write(out.join(sharded::INDEX_FILE), index.encode()).unwrap();
    let solid = ShardedSolid::open(&out).unwrap();
    let shard = index.layout().shard_file(index.shards[i].cell);
    let err = solid.verify(MemoryBudget::unlimited()).unwrap_err().to_string();
    assert!(err.contains(&shard) && err.contains("the index says"), "{err}");
    assert_refused(&out, &shard, "the index says");
    // Untouched, the index's bounds are the solid's and every shard passes.
    let (out, _) = small_solid(&dir, "good.octs");
    let solid = ShardedSolid::open(&out).unwrap();
    solid.verify(MemoryBudget::unlimited()).unwrap();
    assert_eq!(solid.index().voxel_bounds(), whole.voxel_bounds());
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_version_1_index_is_still_read() {
    let dir = scratch("v1");
    let (out, index) = small_solid(&dir, "old.octs");
    let v2 = index.encode();
    // Version 1: the same fields without the job, an 80-byte header.
    let mut v1 = v2[..80].to_vec();
    v1[8..10].copy_from_slice(&1u16.to_le_bytes());
    v1.extend_from_slice(&v2[96..v2.len() - 4]);
    v1.extend_from_slice(&crc32fast::hash(&v1).to_le_bytes());
    std::fs::write(out.join(sharded::INDEX_FILE), &v1).unwrap();
    let solid = ShardedSolid::open(&out).unwrap();
    assert_eq!(solid.index().job, sharded::JobId::NONE);
    assert_eq!(solid.read(MemoryBudget::unlimited()).unwrap(), classic_whole());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// This host's name as the kernel gives it.
fn host() -> String {
    std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap().trim().to_owned()
}

/// The PID of a process that has ended.
fn dead_pid() -> u32 {
    let mut child = std::process::Command::new("true").spawn().unwrap();
    child.wait().unwrap();
    child.id()
}

#[test]
fn folders_of_writers_killed_on_this_host_are_removed_by_the_next_and_others_kept() {
    let dir = scratch("stale");
    let out = dir.join("solid.octs");
    let staging = staging_dir(&out);
    let (host, dead, me) = (host(), dead_pid(), std::process::id());
    let name = |kind: &str, host: &str, pid: u32| format!("{kind}-{host}-{pid}-0123456789abcdef");
    let stale = [name("run", &host, dead), name("old", &host, dead)];
    let kept = [name("run", &host, me), name("run", "another-host", dead), "notes".to_owned()];
    for folder in stale.iter().chain(&kept) {
        std::fs::create_dir_all(staging.join(folder)).unwrap();
        std::fs::write(staging.join(folder).join("c0.oct"), b"shard").unwrap();
    }
    let domain = showcase_domain(6).unwrap();
    sharded::voxelize_shape(&classic_csg(), domain, Metadata::default(), &out, &at_level(2)).unwrap();
    assert_eq!(loaded(&out), classic_whole());
    let mut left: Vec<String> =
        std::fs::read_dir(&staging).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    left.sort();
    let mut want = kept.to_vec();
    want.sort();
    assert_eq!(left, want, "the dead writers' folders of this host are gone, the rest kept");
    // A join lock of a join killed here is taken over; one of a live join refuses.
    tasks(&classic_csg(), b"classic", &out, &[[0, 64]]);
    let lock = job_folder(&out).join("join.lock");
    std::fs::write(
        &lock,
        format!(
            "{host}-{me}-0123456789abcdef
"
        ),
    )
    .unwrap();
    let err = sharded::join(&out).unwrap_err().to_string();
    assert!(err.contains("another join of this job is running"), "{err}");
    std::fs::write(
        &lock,
        format!(
            "{host}-{dead}-0123456789abcdef
"
        ),
    )
    .unwrap();
    sharded::join(&out).unwrap();
    assert_eq!(loaded(&out), classic_whole());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A sharded solid too large for a quarter of the budget is drawn coarser, and says so:
/// the ball at depth 10 within 16 MiB comes at a depth below 10, and its volume is still
/// the analytic ball's within a shell one coarse voxel thick.
#[test]
fn a_sharded_solid_too_large_to_draw_is_drawn_coarser_and_says_from_which_depth() {
    use octsolid::shape::Sphere;
    use octsolid::{Drawing, DrawingOptions};
    let dir = scratch("drawn-coarser");
    let out = dir.join("ball.octs");
    let domain = Domain::new(DVec3::splat(-1.04), 2.08, 10).unwrap();
    let ball = Sphere::new(DVec3::ZERO, 1.0).unwrap();
    sharded::voxelize_shape(&ball, domain, Metadata::default(), &out, &at_level(3)).unwrap();

    let whole = Drawing::open(&out, &DrawingOptions::default()).unwrap();
    assert_eq!(whole.coarsened_from(), None);
    let drawing =
        Drawing::open(&out, &DrawingOptions { budget: MemoryBudget(16 << 20), ..Default::default() }).unwrap();
    assert_eq!(drawing.coarsened_from(), Some(10));
    let tree = &drawing.scene().solids[0].tree;
    let depth = tree.domain().depth();
    assert!(depth < 10, "drawn at depth {depth}");
    let voxel = 2.08 / f64::from(1u32 << depth);
    let exact = 4.0 / 3.0 * std::f64::consts::PI;
    let shell = 4.0 * std::f64::consts::PI * voxel * 1.5;
    assert!((tree.volume() - exact).abs() < shell, "volume {} at depth {depth}, exact {exact}", tree.volume());
}
