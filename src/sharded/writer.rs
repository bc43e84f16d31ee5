//! Writing a sharded solid: cells stream in ([`ShardWriter`] is a [`CellSink`]), each
//! partly full cell is written at once as its shard file, and the full cells are
//! only counted. A job is one or more tasks, each over a range of cells; a task ends
//! by writing a part file (its range, its full cells, its shards' entries) and
//! [`join`] turns the parts into the index once every cell is covered.
//!
//! Everything is written into a staging folder beside the output (`OUT.partial`),
//! each file atomically, and the staging folder becomes the output by a rename at
//! the end of the join, so a reader never sees a solid half written, an interrupted
//! job leaves the old solid in place, and a task run twice (a retry) writes the same
//! bytes again. The join is where the cells meet: the full cells are cut into the
//! largest aligned nodes ([`Cells::join_full`]), the only place eight cells can merge.

use std::path::{Path, PathBuf};

use super::INDEX_FILE;
use super::index::{Part, ShardEntry, ShardIndex};
use super::layout::Layout;
use crate::error::{Error, Result};
use crate::io::oct::{self, Metadata};
use crate::io::write_atomic;
use crate::morton;
use crate::octree::{CellNodes, CellSink, Cells, Domain, LinearOctree, NodeKey, check_level};

/// The prefix of part files in the staging folder.
const PART_PREFIX: &str = "part-";

/// The staging folder of output `out`: `OUT.partial` beside it.
#[must_use]
pub fn staging_dir(out: &Path) -> PathBuf {
    let mut name = out.file_name().map(std::ffi::OsStr::to_os_string).unwrap_or_default();
    name.push(".partial");
    out.with_file_name(name)
}

/// Writes the cells of one task of a sharded solid (see the module doc).
pub struct ShardWriter {
    out: PathBuf,
    staging: PathBuf,
    domain: Domain,
    meta: Metadata,
    cells: Cells,
    full: Vec<u64>,
    shards: Vec<ShardEntry>,
}

impl ShardWriter {
    /// A writer of the cells `cells` of the solid going to folder `out`. A writer of
    /// every cell starts from an empty staging folder; a task's writer adds to it.
    pub fn create(out: &Path, domain: Domain, meta: Metadata, cells: Cells) -> Result<ShardWriter> {
        check_level(&cells, &domain)?;
        let staging = staging_dir(out);
        let io = |path: &Path| {
            let path = path.to_path_buf();
            move |source| Error::Io { path, source }
        };
        if cells == Cells::all(cells.level) && staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(io(&staging))?;
        }
        std::fs::create_dir_all(&staging).map_err(io(&staging))?;
        Ok(ShardWriter { out: out.to_path_buf(), staging, domain, meta, cells, full: Vec::new(), shards: Vec::new() })
    }

    fn layout(&self) -> Layout {
        Layout { depth: self.domain.depth(), level: self.cells.level }
    }

    /// Ends this task: writes its part file. The solid is complete once [`join`] has
    /// run over the parts of every task.
    pub fn finish_part(self) -> Result<()> {
        let range = &self.cells.range;
        let name = format!("{PART_PREFIX}{:016x}-{:016x}", range.start, range.end);
        let part =
            Part { domain: self.domain, meta: self.meta, cells: self.cells, full: self.full, shards: self.shards };
        let bytes = part.encode();
        write_atomic(self.staging.join(name), |w| w.write_all(&bytes))?;
        Ok(())
    }

    /// Ends a job of one task over every cell: its part, then the join.
    pub fn finish(self) -> Result<ShardIndex> {
        let out = self.out.clone();
        self.finish_part()?;
        join(&out)
    }
}

impl CellSink for ShardWriter {
    fn cell(&mut self, index: u64, nodes: CellNodes) -> Result<()> {
        let keys = match nodes {
            CellNodes::Full => {
                self.full.push(index);
                return Ok(());
            }
            CellNodes::Nodes(keys) => keys,
        };
        let (nodes, depth) = (keys.len() as u64, self.domain.depth());
        let (mut min, mut max) = ([u32::MAX; 3], [0u32; 3]);
        for key in &keys {
            let lo = morton::decode(key.start());
            let size = 1u32 << key.k();
            for a in 0..3 {
                min[a] = min[a].min(lo[a]);
                max[a] = max[a].max(lo[a] + size - 1);
            }
        }
        debug_assert!(keys.iter().all(|k| k.level(depth) > self.cells.level));
        let tree = LinearOctree::from_canonical(self.domain, keys);
        let bytes = oct::encode_with(&tree, &self.meta);
        let path = self.staging.join(self.layout().shard_file(index));
        write_atomic(&path, |w| w.write_all(&bytes))?;
        let entry = ShardEntry {
            cell: index,
            nodes,
            voxels: tree.voxel_count(),
            bytes: bytes.len() as u64,
            crc32: crc32fast::hash(&bytes),
            min,
            max,
        };
        self.shards.push(entry);
        Ok(())
    }
}

/// Joins the parts in `out`'s staging folder into the sharded solid `out`: checks
/// that they are of one solid and cover every cell exactly once, writes the index
/// (full cells cut into the largest aligned nodes), removes the parts and any file
/// no entry names, and puts the folder in place of `out` (replacing an earlier
/// sharded solid there).
pub fn join(out: &Path) -> Result<ShardIndex> {
    let staging = staging_dir(out);
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    let mut parts = Vec::new();
    let mut others = Vec::new();
    for entry in std::fs::read_dir(&staging).map_err(io(&staging))? {
        let entry = entry.map_err(io(&staging))?;
        let (path, name) = (entry.path(), entry.file_name().to_string_lossy().into_owned());
        if name.starts_with(PART_PREFIX) {
            let bytes = std::fs::read(&path).map_err(io(&path))?;
            parts.push((Part::decode(&bytes, &path)?, path));
        } else {
            others.push((path, name));
        }
    }
    parts.sort_by_key(|(p, _)| (p.cells.range.start, p.cells.range.end));
    let Some((first, first_path)) = parts.first() else {
        return Err(Error::invalid(
            "sharded job",
            format!("{}: no part to join (did any task finish?)", staging.display()),
        ));
    };
    let (domain, meta, level) = (first.domain, first.meta, first.cells.level);
    let mut next = 0u64;
    for (part, path) in &parts {
        if part.domain != domain || part.meta != meta || part.cells.level != level {
            return Err(Error::invalid(
                "sharded job",
                format!("{} and {} are parts of different solids", first_path.display(), path.display()),
            ));
        }
        let range = &part.cells.range;
        if range.start != next {
            let what = if range.start > next { "no part covers" } else { "two parts cover" };
            return Err(Error::invalid(
                "sharded job",
                format!(
                    "{}: {what} cells {}..{} (at {})",
                    staging.display(),
                    next.min(range.start),
                    next.max(range.start),
                    path.display()
                ),
            ));
        }
        next = range.end;
    }
    let count = Cells::count(level);
    if next != count {
        return Err(Error::invalid(
            "sharded job",
            format!("{}: no part covers cells {next}..{count}", staging.display()),
        ));
    }
    let full_cells = parts.iter().flat_map(|(p, _)| p.full.iter().copied());
    let full: Vec<NodeKey> = Cells::join_full(level, domain.depth(), full_cells);
    let shards: Vec<ShardEntry> = parts.iter().flat_map(|(p, _)| p.shards.iter().cloned()).collect();
    let nodes = full.len() as u64 + shards.iter().map(|s| s.nodes).sum::<u64>();
    let voxels = full.iter().map(|k| k.len()).sum::<u64>() + shards.iter().map(|s| s.voxels).sum::<u64>();
    let index = ShardIndex { domain, meta, level, nodes, voxels, full, shards };
    let bytes = index.encode();
    write_atomic(staging.join(INDEX_FILE), |w| w.write_all(&bytes))?;
    let layout = index.layout();
    let named: std::collections::HashSet<String> = index.shards.iter().map(|s| layout.shard_file(s.cell)).collect();
    for (_, path) in &parts {
        std::fs::remove_file(path).map_err(io(path))?;
    }
    for (path, name) in others {
        if name != INDEX_FILE && !named.contains(&name) {
            std::fs::remove_file(&path).map_err(io(&path))?;
        }
    }
    replace_folder(&staging, out)?;
    Ok(index)
}

/// Renames folder `from` to `to`, moving an earlier sharded solid at `to` aside first
/// and removing it after; refuses to replace anything else.
fn replace_folder(from: &Path, to: &Path) -> Result<()> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| Error::Io { path, source }
    };
    if to.exists() {
        let is_solid =
            to.is_dir() && (to.join(INDEX_FILE).is_file() || std::fs::read_dir(to).map_err(io(to))?.next().is_none());
        if !is_solid {
            return Err(Error::invalid(
                "output",
                format!("{}: exists and is not a sharded solid; not replaced", to.display()),
            ));
        }
        let mut name = to.file_name().map(std::ffi::OsStr::to_os_string).unwrap_or_default();
        name.push(format!(".old-{}", std::process::id()));
        let old = to.with_file_name(name);
        std::fs::rename(to, &old).map_err(io(to))?;
        std::fs::rename(from, to).map_err(io(from))?;
        std::fs::remove_dir_all(&old).map_err(io(&old))?;
    } else {
        std::fs::rename(from, to).map_err(io(from))?;
    }
    Ok(())
}
