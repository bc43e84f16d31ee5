//! A sharded solid on disk: its index, read on open, and its shards, read one at a
//! time and checked against the index (file kind, length, CRC-32, counts, voxel
//! bounds, every node inside its cell), so a corrupted or swapped shard is refused by
//! name. [`ShardedSolid::verify`] checks every shard, so that what is said from the
//! index alone holds.

use std::path::{Path, PathBuf};

use rayon::prelude::*;

use super::index::{ShardEntry, ShardIndex};
use super::layout::Layout;
use super::staging;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::io::oct::{self, Metadata};
use crate::octree::{CoarsenRule, Domain, LinearOctree, NodeKey};
use crate::surface::HermiteData;

/// Bytes a node takes in memory once loaded.
const NODE_BYTES: u64 = 8;

/// A sharded solid: the folder and its checked index. Opening reads only the index.
#[derive(Clone, Debug)]
pub struct ShardedSolid {
    dir: PathBuf,
    index: ShardIndex,
}

impl ShardedSolid {
    /// Opens the sharded solid in folder `dir`, reading and checking its index.
    pub fn open(dir: impl AsRef<Path>) -> Result<ShardedSolid> {
        let dir = dir.as_ref().to_path_buf();
        let index = ShardIndex::read(&dir)?;
        Ok(ShardedSolid { dir, index })
    }

    /// The folder.
    #[must_use]
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The index.
    #[must_use]
    pub fn index(&self) -> &ShardIndex {
        &self.index
    }

    /// The path of the `i`-th shard's file.
    #[must_use]
    pub fn shard_path(&self, i: usize) -> PathBuf {
        self.dir.join(self.index.layout().shard_file(self.index.shards[i].cell))
    }

    /// The bytes of the `i`-th shard's nodes once loaded.
    #[must_use]
    pub fn shard_bytes(&self, i: usize) -> u64 {
        self.index.shards[i].nodes.saturating_mul(NODE_BYTES)
    }

    /// Reads and checks the `i`-th shard: a regular file (never a FIFO or device) of
    /// the length the index records (checked before reading), its CRC-32, then the
    /// `.oct` checks, its domain and metadata equal to the index's, its counts and
    /// voxel bounds equal to the entry's, and every node inside its cell and smaller
    /// than it.
    pub fn read_shard(&self, i: usize, budget: MemoryBudget) -> Result<Vec<NodeKey>> {
        self.read_shard_and_surface(i, budget).map(|(keys, _)| keys)
    }

    /// [`ShardedSolid::read_shard`] with the shard's surface data (`None` for a shard
    /// without a surface section): the crossings of the solid's boundary faces whose
    /// voxel lies in the shard's cell, keyed in the domain's frame, checked as
    /// [`crate::io::oct::read_and_surface`] checks them.
    pub fn read_shard_and_surface(
        &self,
        i: usize,
        budget: MemoryBudget,
    ) -> Result<(Vec<NodeKey>, Option<HermiteData>)> {
        let index = &self.index;
        read_shard(&self.shard_path(i), &index.shards[i], index.domain, index.meta, index.layout(), budget)
    }

    /// Reads and checks every shard against the index ([`ShardedSolid::read_shard`]),
    /// so that what the index alone says (counts, bounds) is true of the solid.
    pub fn verify(&self, budget: MemoryBudget) -> Result<()> {
        (0..self.index.shards.len()).into_par_iter().try_for_each(|i| self.read_shard(i, budget).map(drop))
    }

    /// The whole solid in memory (refused when its nodes exceed `budget`).
    pub fn read(&self, budget: MemoryBudget) -> Result<LinearOctree> {
        let total = self.index.nodes.saturating_mul(NODE_BYTES);
        budget.check(format!("loading {}", self.dir.display()), total)?;
        let mut keys = Vec::with_capacity(self.index.nodes as usize);
        self.for_each_part(budget, |part| {
            keys.extend_from_slice(part);
            Ok(())
        })?;
        LinearOctree::from_keys(self.index.domain, keys)
            .map_err(|e| Error::invalid("sharded solid", format!("{}: {e}", self.dir.display())))
    }

    /// The solid at the finest depth whose nodes fit `budget` (estimated at a quarter
    /// of the nodes a level coarser, a surface's rate), at least the cell level's;
    /// each shard is coarsened on its own as it is read ([`CoarsenRule::Any`]: the
    /// result holds the solid), so only one shard at a time is held at full depth.
    /// Returns the solid and its depth.
    pub fn read_within(&self, budget: MemoryBudget) -> Result<LinearOctree> {
        let depth = self.index.domain.depth();
        let mut target = depth;
        let mut nodes = self.index.nodes as f64;
        while target > self.index.level.max(1) && nodes * NODE_BYTES as f64 > budget.0 as f64 {
            target -= 1;
            nodes /= 4.0;
        }
        if target == depth {
            return self.read(budget);
        }
        let coarse = self.index.domain.with_depth(target)?;
        let shift = 3 * u32::from(depth - target);
        // Each shard read and coarsened on its own, on every thread (one shard a
        // thread in memory at full depth), the coarse keys kept in shard order.
        let shards: Vec<Vec<NodeKey>> = (0..self.index.shards.len())
            .into_par_iter()
            .map(|i| {
                let fine = LinearOctree::from_canonical(self.index.domain, self.read_shard(i, budget)?);
                Ok(fine.coarsen(target, CoarsenRule::Any)?.into_keys())
            })
            .collect::<Result<_>>()?;
        // The full nodes map whole (they are at least a cell, and the target at least
        // the cell level); merged with the shards' coarse keys by position.
        let layout = self.index.layout();
        let mut runs: Vec<(u64, u64)> = Vec::new();
        let mut push = |start: u64, end: u64| match runs.last_mut() {
            Some(last) if last.1 >= start => last.1 = last.1.max(end),
            _ => runs.push((start, end)),
        };
        let mut full = self.index.full.iter().peekable();
        for (entry, keys) in self.index.shards.iter().zip(&shards) {
            let start = layout.cell_key(entry.cell).start();
            while let Some(key) = full.next_if(|k| k.start() < start) {
                push(key.start() >> shift, key.end() >> shift);
            }
            keys.iter().for_each(|k| push(k.start(), k.end()));
        }
        full.for_each(|k| push(k.start() >> shift, k.end() >> shift));
        let tree = LinearOctree::from_sorted_runs(coarse, runs);
        budget.check(
            format!("loading {} at depth {target}", self.dir.display()),
            tree.node_count() as u64 * NODE_BYTES,
        )?;
        Ok(tree)
    }

    /// Hands the solid's nodes to `f` in Morton order, a full node or a shard at a time.
    fn for_each_part(&self, budget: MemoryBudget, mut f: impl FnMut(&[NodeKey]) -> Result<()>) -> Result<()> {
        let layout = self.index.layout();
        let mut full = self.index.full.iter().peekable();
        for (i, shard) in self.index.shards.iter().enumerate() {
            let start = layout.cell_key(shard.cell).start();
            while let Some(key) = full.next_if(|k| k.start() < start) {
                f(std::slice::from_ref(key))?;
            }
            f(&self.read_shard(i, budget)?)?;
        }
        for key in full {
            f(std::slice::from_ref(key))?;
        }
        Ok(())
    }

    /// A reader of the solid's nodes range by range ([`Cursor::nodes_in`]).
    #[must_use]
    pub fn cursor(&self, budget: MemoryBudget) -> Cursor<'_> {
        Cursor { solid: self, budget, cached: None }
    }
}

/// Reads a sharded solid's nodes in aligned ranges, keeping the last shard read.
pub struct Cursor<'a> {
    solid: &'a ShardedSolid,
    budget: MemoryBudget,
    cached: Option<(usize, Vec<NodeKey>)>,
}

impl Cursor<'_> {
    /// The solid's canonical nodes in the aligned node `range` (a node of the solid
    /// holding all of it comes back as `range` itself).
    pub fn nodes_in(&mut self, range: NodeKey) -> Result<Vec<NodeKey>> {
        let index = &self.solid.index;
        let layout: Layout = index.layout();
        let (lo, hi) = (range.start(), range.end());
        let mut out = Vec::new();
        // Full nodes meeting the range: one holding it, or several inside it.
        let first = index.full.partition_point(|k| k.end() <= lo);
        for key in index.full[first..].iter().take_while(|k| k.start() < hi) {
            if key.start() <= lo && key.end() >= hi {
                return Ok(vec![range]);
            }
            out.push(*key);
        }
        // Shards meeting the range.
        let (cell_lo, cell_hi) = (layout.cell_of(lo), layout.cell_of(hi - 1));
        let first = index.shards.partition_point(|s| s.cell < cell_lo);
        for i in (first..index.shards.len()).take_while(|&i| index.shards[i].cell <= cell_hi) {
            if self.cached.as_ref().is_none_or(|(c, _)| *c != i) {
                self.cached = Some((i, self.solid.read_shard(i, self.budget)?));
            }
            let keys = &self.cached.as_ref().expect("just loaded").1;
            let from = keys.partition_point(|k| k.end() <= lo);
            for key in keys[from..].iter().take_while(|k| k.start() < hi) {
                if key.start() <= lo && key.end() >= hi {
                    return Ok(vec![range]);
                }
                out.push(*key);
            }
        }
        out.sort_unstable_by_key(|k| k.start());
        Ok(out)
    }
}

/// Reads and checks the shard file `path` of `entry`: a regular file of the length
/// the entry records (checked before reading), its CRC-32, then the `.oct` checks,
/// its domain and metadata equal to the index's, its counts and voxel bounds equal
/// to the entry's, and every node inside its cell and smaller than it. Returns its
/// nodes and its surface data, if it carries any.
pub(crate) fn read_shard(
    path: &Path,
    entry: &ShardEntry,
    domain: Domain,
    meta: Metadata,
    layout: Layout,
    budget: MemoryBudget,
) -> Result<(Vec<NodeKey>, Option<HermiteData>)> {
    let fail = |offset: u64, reason: String| Error::Format { path: path.to_path_buf(), offset, reason };
    budget.check(
        format!("reading shard {}", path.display()),
        entry.bytes.saturating_add(entry.nodes.saturating_mul(NODE_BYTES)),
    )?;
    let bytes = staging::read_exact_len(path, entry.bytes, "the index")?;
    let crc = crc32fast::hash(&bytes);
    if crc != entry.crc32 {
        return Err(fail(0, format!("checksum mismatch with the index: file {crc:08x}, index {:08x}", entry.crc32)));
    }
    let (tree, shard_meta, surface) = oct::decode_and_surface(&bytes, path, budget)?;
    if *tree.domain() != domain || shard_meta != meta {
        return Err(fail(12, "the shard's domain or metadata differ from the index's".into()));
    }
    if tree.node_count() as u64 != entry.nodes || tree.voxel_count() != entry.voxels {
        return Err(fail(
            48,
            format!(
                "{} nodes of {} voxels, the index says {} of {}",
                tree.node_count(),
                tree.voxel_count(),
                entry.nodes,
                entry.voxels
            ),
        ));
    }
    let cell = layout.cell_key(entry.cell);
    if let Some((n, key)) =
        tree.keys().iter().enumerate().find(|(_, k)| k.start() < cell.start() || k.end() > cell.end() || **k == cell)
    {
        let reason = if *key == cell {
            "is the whole cell (a full cell belongs in the index)"
        } else {
            "reaches beyond its cell"
        };
        return Err(fail(
            oct::HEADER_BYTES as u64,
            format!("node {n} (start {}, k {}) {reason}", key.start(), key.k()),
        ));
    }
    let bounds = tree.voxel_bounds().map(|(lo, hi)| (lo, hi.map(|c| c - 1)));
    if bounds != Some((entry.min, entry.max)) {
        return Err(fail(
            oct::HEADER_BYTES as u64,
            format!(
                "the shard's voxels span {bounds:?}, the index says {:?}..={:?} (lowest and highest voxel)",
                entry.min, entry.max
            ),
        ));
    }
    Ok((tree.into_keys(), surface))
}
