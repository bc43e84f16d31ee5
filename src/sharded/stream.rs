//! Streaming jobs over cells: a solid in memory cut into shards, shapes and meshes
//! voxelized cell by cell, and set operations of sharded solids merged cell by cell.
//!
//! A set operation restricted to an aligned range of Morton codes depends only on
//! the operands' nodes in that range (the canonical list of a voxel set is the greedy
//! cut of its runs, [`crate::octree::LinearOctree`]), so each output cell is the k-way
//! merge ([`LinearOctree::combine_all`]) of the operands' nodes in it, read through a
//! [`Cursor`] that keeps one shard of each operand in memory. Memory is bounded by a
//! few shards, whatever the solids' sizes; the output's full cells are joined once at
//! the end ([`super::join`]).

use std::ops::Range;
use std::path::Path;

use super::index::ShardIndex;
use super::job::JobHasher;
use super::layout::Layout;
use super::solid::ShardedSolid;
use super::writer::ShardWriter;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::io::oct::Metadata;
use crate::mesh::{MeshVoxelizeOptions, TriangleMesh, voxelize_mesh_cells};
use crate::octree::{
    CellNodes, CellSink, Cells, Domain, LinearOctree, NodeKey, SetOp, VoxelizeOptions, voxelize_cells,
};
use crate::progress::{NoProgress, Progress, stop_if_cancelled};
use crate::shape::Shape;
use crate::surface::HermiteData;

/// What a streaming job writes and within what.
#[derive(Clone, Copy)]
pub struct StreamOptions<'a> {
    /// The output's cell level (`None`: [`Layout::default_level`] of the depth, or for a
    /// set operation the finest of the operands').
    pub level: Option<u8>,
    /// Only these cells: one task of a job run on many machines, which writes its part
    /// and leaves the join to [`super::join`] (`None`: every cell, joined at the end).
    pub cells: Option<&'a Range<u64>>,
    /// Memory for one cell's work (shards read, nodes made); no job holds the solid.
    pub budget: MemoryBudget,
    /// Receives progress in cells.
    pub progress: &'a dyn Progress,
    /// What the job makes, as the caller tells it, for the job's identity
    /// ([`super::JobId`]): bytes that differ between jobs writing the same output
    /// (the command line passes its arguments without `--cells`). Every task of one
    /// job must pass the same.
    pub source: &'a [u8],
}

impl Default for StreamOptions<'_> {
    fn default() -> Self {
        StreamOptions { level: None, cells: None, budget: MemoryBudget::default(), progress: &NoProgress, source: b"" }
    }
}

impl StreamOptions<'_> {
    fn cells(&self, level: u8, depth: u8) -> Result<Cells> {
        if level > depth {
            return Err(Error::invalid("shard level", format!("{level} is below the voxels of depth {depth}")));
        }
        Ok(match self.cells {
            Some(range) => Cells { level, range: range.clone() },
            None => Cells::all(level),
        })
    }
}

/// A job's writer: its cells at `level` (or the default level of the depth), and
/// whether it is the whole job (no `cells` asked for) rather than a task, which
/// leaves a part even when its range is every cell. The job's identity hashes the
/// options' `source`, the domain, metadata and level, and what `input` adds (a
/// mesh's triangles, the operands of a set operation).
pub(super) struct Job {
    pub(super) writer: ShardWriter,
    pub(super) cells: Cells,
    whole: bool,
}

impl Job {
    pub(super) fn start(
        domain: Domain,
        meta: Metadata,
        level: Option<u8>,
        out: &Path,
        options: &StreamOptions,
        input: impl FnOnce(&mut JobHasher),
    ) -> Result<Job> {
        let level = level.unwrap_or_else(|| Layout::default_level(domain.depth()));
        let cells = options.cells(level, domain.depth())?;
        let whole = options.cells.is_none();
        let mut hasher = JobHasher::new(options.source, domain, meta, level);
        input(&mut hasher);
        let writer = ShardWriter::create(out, domain, meta, cells.clone(), hasher.finish(), !whole)?;
        Ok(Job { writer, cells, whole })
    }

    /// Ends the job: the join when it made every cell (the index), else the task's part.
    pub(super) fn finish(self) -> Result<Option<ShardIndex>> {
        if self.whole { self.writer.finish().map(Some) } else { self.writer.finish_part().map(|()| None) }
    }
}

/// Writes `tree` as the sharded solid `out` (the index when every cell was asked for).
/// The job's identity is the options' `source` with the domain, metadata and level
/// (not the nodes): a task must say what it cuts.
pub fn write(tree: &LinearOctree, meta: Metadata, out: &Path, options: &StreamOptions) -> Result<Option<ShardIndex>> {
    let mut job = Job::start(*tree.domain(), meta, options.level, out, options, |_| {})?;
    let (cells, writer) = (job.cells.clone(), &mut job.writer);
    let layout = Layout { depth: tree.depth(), level: cells.level };
    options.progress.start(cells.range.end - cells.range.start);
    let keys = tree.keys();
    let mut i = keys.partition_point(|k| k.end() <= layout.cell_key(cells.range.start).start());
    let mut done = cells.range.start;
    while i < keys.len() && layout.cell_of(keys[i].start()) < cells.range.end {
        let key = keys[i];
        let cell = layout.cell_of(key.start());
        if key.k() >= u32::from(layout.cell_k()) {
            // A node of a cell or more: each of its cells in the range is full.
            let last = layout.cell_of(key.end() - 1).min(cells.range.end - 1);
            for c in cell.max(cells.range.start)..=last {
                writer.cell(c, CellNodes::Full)?;
            }
            i += 1;
        } else {
            let end = layout.cell_key(cell).end();
            let n = keys[i..].partition_point(|k| k.start() < end);
            writer.cell(cell, CellNodes::Nodes(keys[i..i + n].to_vec()))?;
            i += n;
        }
        let reached = layout.cell_of(key.end() - 1) + 1;
        options.progress.advance(reached.min(cells.range.end).saturating_sub(done));
        stop_if_cancelled(options.progress)?;
        done = done.max(reached);
    }
    options.progress.finish();
    job.finish()
}

/// Voxelizes `shape` in `domain` into the sharded solid `out`, a cell at a time
/// ([`voxelize_cells`]): the same solid as [`crate::octree::voxelize`]. Each shard
/// carries the exact crossings of the solid's boundary faces in its cell, seams
/// included, in a surface section ([`HermiteData::from_shape_in_cell`]).
pub fn voxelize_shape(
    shape: &dyn Shape,
    domain: Domain,
    meta: Metadata,
    out: &Path,
    options: &StreamOptions,
) -> Result<Option<ShardIndex>> {
    let mut job = Job::start(domain, meta, options.level, out, options, |_| {})?;
    let voxelize = VoxelizeOptions { budget: options.budget, progress: options.progress };
    let layout = Layout { depth: domain.depth(), level: job.cells.level };
    let mut sink = WithSurface { shape, layout, writer: &mut job.writer };
    voxelize_cells(shape, domain, &voxelize, &job.cells, &mut sink)?;
    job.finish()
}

/// A shape's cells written as shards with their surface data: the exact crossings of
/// the whole solid's boundary faces in each cell ([`HermiteData::from_shape_in_cell`]).
struct WithSurface<'a> {
    shape: &'a dyn Shape,
    layout: Layout,
    writer: &'a mut ShardWriter,
}

impl CellSink for WithSurface<'_> {
    fn cell(&mut self, index: u64, nodes: CellNodes) -> Result<()> {
        let cell = self.layout.cell_key(index);
        let shape = self.shape;
        self.writer.cell_with_surface(index, nodes, |tree| Some(HermiteData::from_shape_in_cell(shape, tree, cell)))
    }
}

/// Voxelizes the solid bounded by `mesh` into the sharded solid `out`, a cell at a
/// time ([`voxelize_mesh_cells`]): the same solid as [`crate::mesh::voxelize_mesh`].
pub fn voxelize_mesh(
    mesh: &TriangleMesh,
    domain: Domain,
    meta: Metadata,
    mesh_options: &MeshVoxelizeOptions,
    out: &Path,
    options: &StreamOptions,
) -> Result<Option<ShardIndex>> {
    let mut job = Job::start(domain, meta, options.level, out, options, |h| {
        h.u64(mesh.vertices.len() as u64);
        for v in &mesh.vertices {
            v.to_array().iter().for_each(|c| h.u64(c.to_bits()));
        }
        for t in &mesh.triangles {
            t.iter().for_each(|&i| h.u64(u64::from(i)));
        }
        h.bytes(format!("{:?}", mesh_options.inside).as_bytes());
    })?;
    let mesh_options = MeshVoxelizeOptions { budget: options.budget, progress: options.progress, ..*mesh_options };
    voxelize_mesh_cells(mesh, domain, &mesh_options, &job.cells, &mut job.writer)?;
    job.finish()
}

/// `op` over the sharded solids `operands` (one domain), merged cell by cell into the
/// sharded solid `out`: the same solid as [`LinearOctree::combine_all`] of them.
pub fn combine(
    operands: &[ShardedSolid],
    op: SetOp,
    out: &Path,
    options: &StreamOptions,
) -> Result<Option<ShardIndex>> {
    let first = operands.first().ok_or_else(|| Error::invalid("operands", "a set operation needs a solid"))?;
    let (domain, meta) = (first.index().domain, first.index().meta);
    if let Some(other) = operands.iter().find(|s| s.index().domain != domain) {
        return Err(Error::invalid(
            "operands",
            format!(
                "{} is over {}, {} over {}: sharded solids combine over one domain (bring them into one with `csg` in memory or `transform`)",
                first.dir().display(),
                domain,
                other.dir().display(),
                other.index().domain
            ),
        ));
    }
    let level = options.level.unwrap_or_else(|| operands.iter().map(|s| s.index().level).max().unwrap_or(0));
    // Memory: for each operand its largest shard (held) and a copy of a cell's nodes,
    // and as much again for the output.
    let largest: u64 =
        operands.iter().map(|s| (0..s.index().shards.len()).map(|i| s.shard_bytes(i)).max().unwrap_or(0)).sum();
    options.budget.check(format!("merging cells at level {level}"), largest.saturating_mul(4))?;
    let mut job = Job::start(domain, meta, Some(level), out, options, |h| {
        h.bytes(format!("{op:?}").as_bytes());
        for solid in operands {
            let index = solid.index().encode();
            h.u64(index.len() as u64);
            h.bytes(&index);
        }
    })?;
    let (cells, writer) = (job.cells.clone(), &mut job.writer);
    let layout = Layout { depth: domain.depth(), level };
    let mut cursors: Vec<_> = operands.iter().map(|s| s.cursor(options.budget)).collect();
    options.progress.start(cells.range.end - cells.range.start);
    for cell in cells.range.clone() {
        let key = layout.cell_key(cell);
        let mut parts = Vec::with_capacity(cursors.len());
        for cursor in &mut cursors {
            parts.push(cursor.nodes_in(key)?);
        }
        options.progress.advance(1);
        stop_if_cancelled(options.progress)?;
        let keys = merge_cell(parts, op, domain)?;
        match keys.as_slice() {
            [] => {}
            [one] if *one == key => writer.cell(cell, CellNodes::Full)?,
            _ => writer.cell(cell, CellNodes::Nodes(keys))?,
        }
    }
    options.progress.finish();
    job.finish()
}

/// `op` over one cell's nodes of each operand.
fn merge_cell(parts: Vec<Vec<NodeKey>>, op: SetOp, domain: Domain) -> Result<Vec<NodeKey>> {
    let nonempty = parts.iter().filter(|p| !p.is_empty()).count();
    let trivially_empty = match op {
        SetOp::Union | SetOp::SymmetricDifference => nonempty == 0,
        SetOp::Intersection => nonempty < parts.len(),
        SetOp::Difference => parts[0].is_empty(),
    };
    if trivially_empty {
        return Ok(Vec::new());
    }
    let trees: Vec<LinearOctree> = parts.into_iter().map(|p| LinearOctree::from_canonical(domain, p)).collect();
    Ok(LinearOctree::combine_all(&trees.iter().collect::<Vec<_>>(), op)?.into_keys())
}
