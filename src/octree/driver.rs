//! The voxelization driver: the one top-down walk every voxelizer runs.
//!
//! A voxelizer ([`Voxelizer`]) only says how to decide a node, given the state its
//! parent handed down (nothing for a shape; the candidate triangles and an inside value
//! for a mesh solid; the candidate triangles or patch pieces for a surface). The
//! driver does the rest, the same way for all of them:
//!
//! - **Budget first.** A [`Plan`] exists only once the job's estimated peak memory has
//!   passed [`MemoryBudget::check`], and only a plan can run: no work (tables, oracles,
//!   nodes) before the check.
//! - **Order.** Children are visited in Morton order and every decided node appends
//!   its keys to one buffer, so the output comes out sorted without a sort.
//! - **Canonical merge.** A split node whose eight children all came out whole (the
//!   buffer grew by exactly eight keys, each one level below it) is replaced by itself,
//!   so the output is canonical without a pass: bottom up, a node is emitted iff it is
//!   full and its parent is not.
//! - **Parallelism.** The top [`PARALLEL_LEVELS`] levels fan out with rayon; each task
//!   fills its own buffer (and its own counters), and buffers are joined in child
//!   order, so the result never depends on the number of threads.
//! - **Progress.** The job is `8^P` units, `P = min(PARALLEL_LEVELS, depth)`: a node at
//!   level `l <= P` that is not split reports its `8^(P - l)` level-`P` nodes when
//!   decided, and a split node at level `P` reports its one unit before its subtree
//!   runs, so the units add up to `8^P` whatever the shape of the tree.
//! - **Cancel.** Every node at a level `<= P` polls [`Progress::cancelled`] before it is
//!   decided; once it says stop, the walk decides nothing more and the run returns
//!   [`crate::Error::Cancelled`].
//! - **Cells.** [`Plan::run_cells`] runs the same walk for the aligned cells `L` levels
//!   below the root in a range of their Morton numbers ([`Cells`]), handing each
//!   cell's keys to a [`CellSink`] as soon as the cell is done, so a solid larger than
//!   memory streams out cell by cell (`crate::sharded` writes each cell as a shard).
//!   The top `L` levels are walked once, only into subtrees that meet the range; each
//!   cell's subtree is the same walk as above (its top levels in parallel), and a
//!   cell's keys are exactly the whole walk's keys in its range, except that a full
//!   cell comes out as itself even where its full siblings would merge into a parent:
//!   joining those is the sink's (a canonical cut of the runs of full cells).

use std::ops::Range;

use rayon::prelude::*;

use super::domain::Domain;
use super::linear::LinearOctree;
use super::node::NodeKey;
use super::ranges;
use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::progress::{NoProgress, Progress, stop_if_cancelled};

/// Levels below the root that are split into parallel tasks (up to 8^3 = 512 tasks).
pub const PARALLEL_LEVELS: u8 = 3;

/// Options of a voxelization.
#[derive(Clone, Copy)]
pub struct VoxelizeOptions<'a> {
    /// Refuse the job when its estimated memory exceeds this.
    pub budget: MemoryBudget,
    /// Receives progress in units of level-3 subtrees.
    pub progress: &'a dyn Progress,
}

impl Default for VoxelizeOptions<'_> {
    fn default() -> Self {
        VoxelizeOptions { budget: MemoryBudget::default(), progress: &NoProgress }
    }
}

/// What a voxelizer makes of one node.
pub(crate) enum Decision<N> {
    /// No voxel of the node is in the solid.
    Empty,
    /// Every voxel of the node is in the solid.
    Full,
    /// The children (in Morton order) whose bit is set are full, the others empty:
    /// for a voxelizer that decides a node's eight children at once.
    Children(u8),
    /// Recurse: the state each child (in Morton order) starts from.
    Split([N; 8]),
}

/// Counters a voxelizer keeps while it walks, one set a parallel task, added up in
/// child order at the end.
pub(crate) trait Counters: Default + Send {
    /// Adds the counters of a finished task.
    fn add(&mut self, other: Self);
}

impl Counters for () {
    fn add(&mut self, _other: ()) {}
}

/// One voxelization algorithm, as the driver sees it.
pub(crate) trait Voxelizer: Sync {
    /// What a node is handed by its parent.
    type Node: Send;
    /// Counters kept over the walk.
    type Counters: Counters;

    /// Decides the node `key` from the state `node` its parent handed down.
    fn decide(&self, key: NodeKey, node: Self::Node, counters: &mut Self::Counters) -> Decision<Self::Node>;
}

/// A voxelization whose memory estimate has passed the budget: the permission to start.
pub(crate) struct Plan<'a> {
    domain: Domain,
    progress: &'a dyn Progress,
}

impl<'a> Plan<'a> {
    /// Checks `estimate` (peak bytes) against `options.budget`; `job` names the work
    /// in the error (" at depth d" is added).
    pub(crate) fn new(job: &str, estimate: u64, domain: Domain, options: &VoxelizeOptions<'a>) -> Result<Self> {
        options.budget.check(format!("{job} at depth {}", domain.depth()), estimate)?;
        Ok(Plan { domain, progress: options.progress })
    }

    /// Runs `voxelizer` from the root, which starts from `root`.
    pub(crate) fn run<V: Voxelizer>(self, voxelizer: &V, root: V::Node) -> Result<(LinearOctree, V::Counters)> {
        let parallel_levels = PARALLEL_LEVELS.min(self.domain.depth());
        self.progress.start(1 << (3 * u32::from(parallel_levels)));
        let walk = Walk { voxelizer, depth: self.domain.depth(), parallel_levels, progress: self.progress };
        let (mut keys, mut counters) = (Vec::new(), V::Counters::default());
        walk.node(NodeKey::new(0, u32::from(self.domain.depth())), root, &mut keys, &mut counters);
        stop_if_cancelled(self.progress)?;
        self.progress.finish();
        Ok((LinearOctree::from_canonical(self.domain, keys), counters))
    }

    /// Runs `voxelizer` from the root (which starts from `root`) over the cells of
    /// `cells` only, handing each cell that holds a voxel to `sink` in Morton order;
    /// stops at the sink's first error. Progress counts cells.
    pub(crate) fn run_cells<V: Voxelizer>(
        self,
        voxelizer: &V,
        root: V::Node,
        cells: &Cells,
        sink: &mut dyn CellSink,
    ) -> Result<V::Counters> {
        let depth = self.domain.depth();
        let parallel_levels = cells.level.saturating_add(PARALLEL_LEVELS).min(depth);
        self.progress.start(cells.range.end.saturating_sub(cells.range.start));
        let walk = Walk { voxelizer, depth, parallel_levels, progress: &NoProgress };
        let mut top = TopWalk { walk, cells, progress: self.progress, sink, counters: V::Counters::default() };
        top.node(NodeKey::new(0, u32::from(depth)), root)?;
        self.progress.finish();
        Ok(top.counters)
    }
}

/// The aligned cells `level` levels below the root (cubes of `2^(depth - level)`
/// voxels a side), numbered `0..8^level` in Morton order, and the range of them a
/// job makes.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Cells {
    /// The cells' level: 0 is the whole domain as one cell.
    pub level: u8,
    /// The cells to make, by number.
    pub range: Range<u64>,
}

impl Cells {
    /// Every cell at `level`.
    #[must_use]
    pub fn all(level: u8) -> Cells {
        Cells { level, range: 0..Cells::count(level) }
    }

    /// How many cells there are at `level`: `8^level`.
    #[must_use]
    pub fn count(level: u8) -> u64 {
        1u64 << (3 * u32::from(level))
    }

    /// The canonical nodes of a set of full cells at `level` (cell numbers in
    /// increasing order) in a domain of depth `depth`: runs of consecutive cells cut
    /// into the largest aligned nodes, so eight full sibling cells become their parent.
    #[must_use]
    pub fn join_full(level: u8, depth: u8, full: impl IntoIterator<Item = u64>) -> Vec<NodeKey> {
        let shift = 3 * u32::from(depth - level);
        let mut runs: Vec<(u64, u64)> = Vec::new();
        for cell in full {
            let (start, end) = (cell << shift, (cell + 1) << shift);
            match runs.last_mut() {
                Some(last) if last.1 == start => last.1 = end,
                _ => runs.push((start, end)),
            }
        }
        ranges::cut_runs(runs)
    }

    /// The key of cell `index` in a domain of depth `depth`.
    #[must_use]
    pub fn key(&self, index: u64, depth: u8) -> NodeKey {
        let k = u32::from(depth - self.level);
        NodeKey::new(index << (3 * k), k)
    }
}

/// What a cell that holds voxels holds.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum CellNodes {
    /// Every voxel of the cell.
    Full,
    /// Some voxels: the canonical keys of the solid in the cell, none of them the
    /// cell itself.
    Nodes(Vec<NodeKey>),
}

/// Where a cell-by-cell voxelization puts each cell.
pub trait CellSink {
    /// Takes cell `index` (never empty); cells come in increasing order.
    fn cell(&mut self, index: u64, nodes: CellNodes) -> Result<()>;
}

/// The walk over the levels above the cells.
struct TopWalk<'a, 's, V: Voxelizer> {
    walk: Walk<'a, V>,
    cells: &'a Cells,
    progress: &'a dyn Progress,
    sink: &'s mut dyn CellSink,
    counters: V::Counters,
}

impl<V: Voxelizer> TopWalk<'_, '_, V> {
    /// The cells of `key` (a node at or above the cells' level) in the range.
    fn cells_of(&self, key: NodeKey) -> Range<u64> {
        let k_cell = u32::from(self.walk.depth - self.cells.level);
        let (first, last) = (key.start() >> (3 * k_cell), key.end() >> (3 * k_cell));
        first.max(self.cells.range.start)..last.min(self.cells.range.end)
    }

    fn node(&mut self, key: NodeKey, node: V::Node) -> Result<()> {
        let cells = self.cells_of(key);
        if cells.is_empty() {
            return Ok(());
        }
        stop_if_cancelled(self.progress)?;
        if key.level(self.walk.depth) == self.cells.level {
            let mut keys = Vec::new();
            self.walk.node(key, node, &mut keys, &mut self.counters);
            self.progress.advance(1);
            return match keys.as_slice() {
                [] => Ok(()),
                [one] if *one == key => self.sink.cell(cells.start, CellNodes::Full),
                _ => self.sink.cell(cells.start, CellNodes::Nodes(keys)),
            };
        }
        let decided = self.walk.voxelizer.decide(key, node, &mut self.counters);
        let full_children = match decided {
            Decision::Empty => 0,
            Decision::Full => 0xff,
            Decision::Children(full) => full,
            Decision::Split(children) => {
                for (i, child) in children.into_iter().enumerate() {
                    self.node(key.child(i as u64).expect("a split node is not a voxel"), child)?;
                }
                return Ok(());
            }
        };
        // Decided above the cells: `Children` only comes from a 2-voxel node, whose
        // children are the cells (level = depth).
        let k_cell = u32::from(self.walk.depth - self.cells.level);
        for index in cells {
            let full = full_children == 0xff
                || (key.k() == 1 && full_children >> ((index << (3 * k_cell)) - key.start()) & 1 == 1);
            if full {
                self.sink.cell(index, CellNodes::Full)?;
            }
            self.progress.advance(1);
        }
        Ok(())
    }
}

/// One running walk's fixed inputs.
struct Walk<'a, V> {
    voxelizer: &'a V,
    depth: u8,
    parallel_levels: u8,
    progress: &'a dyn Progress,
}

impl<V: Voxelizer> Walk<'_, V> {
    /// Appends the canonical nodes of the solid inside `key` to `out`.
    fn node(&self, key: NodeKey, node: V::Node, out: &mut Vec<NodeKey>, counters: &mut V::Counters) {
        let level = key.level(self.depth);
        if level <= self.parallel_levels && self.progress.cancelled() {
            return; // `Plan::run` returns `Cancelled`.
        }
        match self.voxelizer.decide(key, node, counters) {
            Decision::Empty => self.report(level),
            Decision::Full => {
                self.report(level);
                out.push(key);
            }
            Decision::Children(full) => {
                self.report(level);
                if full == 0xff {
                    out.push(key); // Eight full children are their parent.
                } else {
                    let set = (0..8u64).filter(|i| full >> i & 1 == 1);
                    out.extend(set.map(|i| key.child(i).expect("a node with children")));
                }
            }
            Decision::Split(children) => {
                let before = out.len();
                if level < self.parallel_levels {
                    self.fan_out(key, children, out, counters);
                } else {
                    self.report(level);
                    for (i, child) in children.into_iter().enumerate() {
                        self.node(key.child(i as u64).expect("a split node is not a voxel"), child, out, counters);
                    }
                }
                // Eight full children are their parent.
                if out.len() == before + 8 && out[before..].iter().all(|c| c.k() + 1 == key.k()) {
                    out.truncate(before);
                    out.push(key);
                }
            }
        }
    }

    /// The children of `key` as parallel tasks, each with its own buffer and counters,
    /// joined in child order.
    fn fan_out(&self, key: NodeKey, children: [V::Node; 8], out: &mut Vec<NodeKey>, counters: &mut V::Counters) {
        let parts: Vec<(Vec<NodeKey>, V::Counters)> = children
            .into_par_iter()
            .enumerate()
            .map(|(i, child)| {
                let (mut part, mut c) = (Vec::new(), V::Counters::default());
                self.node(key.child(i as u64).expect("a split node is not a voxel"), child, &mut part, &mut c);
                (part, c)
            })
            .collect();
        out.reserve(parts.iter().map(|(p, _)| p.len()).sum());
        for (part, c) in parts {
            out.extend(part);
            counters.add(c);
        }
    }

    /// Reports a decided node at `level`: its share of the level-`parallel_levels` grid.
    fn report(&self, level: u8) {
        if level <= self.parallel_levels {
            self.progress.advance(1 << (3 * u32::from(self.parallel_levels - level)));
        }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::atomic::{AtomicU64, Ordering};

    use glam::DVec3;

    use super::*;
    use crate::error::Error;
    use crate::morton;

    /// A voxelizer of a ball of voxels (centres within `radius` voxels of `center`)
    /// that decides each node by looking at all its voxels: the node it is handed must
    /// be its own key (checks that states reach the right children), and 2-voxel nodes
    /// are decided eight children at once.
    struct Ball {
        center: [f64; 3],
        radius: f64,
    }

    impl Ball {
        fn contains(&self, v: [u32; 3]) -> bool {
            (0..3).map(|a| (f64::from(v[a]) + 0.5 - self.center[a]).powi(2)).sum::<f64>() < self.radius.powi(2)
        }
    }

    /// Decisions made.
    #[derive(Default, Debug, PartialEq)]
    struct Decided(u64);

    impl Counters for Decided {
        fn add(&mut self, other: Decided) {
            self.0 += other.0;
        }
    }

    impl Voxelizer for Ball {
        type Node = NodeKey;
        type Counters = Decided;

        fn decide(&self, key: NodeKey, node: NodeKey, counters: &mut Decided) -> Decision<NodeKey> {
            assert_eq!(key, node, "a child was handed another child's state");
            counters.0 += 1;
            if key.k() == 1 {
                let full = (0..8).filter(|&i| self.contains(morton::decode(key.child(i).unwrap().start())));
                return Decision::Children(full.fold(0, |m, i| m | 1 << i));
            }
            let inside = (key.start()..key.end()).filter(|&c| self.contains(morton::decode(c))).count() as u64;
            match inside {
                0 => Decision::Empty,
                n if n == key.len() => Decision::Full,
                _ => Decision::Split(std::array::from_fn(|i| key.child(i as u64).unwrap())),
            }
        }
    }

    #[derive(Default)]
    struct Units {
        total: AtomicU64,
        done: AtomicU64,
    }

    impl Progress for Units {
        fn start(&self, total: u64) {
            self.total.store(total, Ordering::SeqCst);
        }
        fn advance(&self, n: u64) {
            self.done.fetch_add(n, Ordering::SeqCst);
        }
    }

    #[test]
    fn walk_gives_the_canonical_voxel_set_with_progress_adding_up_on_any_thread_count() {
        for depth in 1..=6u8 {
            let domain = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
            let n = f64::from(domain.resolution());
            let ball = Ball { center: [0.45 * n, 0.5 * n, 0.55 * n], radius: 0.4 * n + 0.3 };
            // Oracle: every voxel tested, canonicalized by the greedy cut of runs.
            let voxels = (0..domain.voxel_total()).map(morton::decode).filter(|&v| ball.contains(v));
            let want = LinearOctree::from_voxels(domain, voxels).unwrap();
            let mut first = None;
            for threads in [1, 2, 3] {
                let units = Units::default();
                let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &units };
                let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
                let (tree, decided) = pool.install(|| {
                    let plan = Plan::new("test", 0, domain, &options).unwrap();
                    plan.run(&ball, NodeKey::new(0, u32::from(depth))).unwrap()
                });
                assert_eq!(tree, want, "depth {depth}, {threads} threads");
                let total = 1 << (3 * u32::from(depth.min(PARALLEL_LEVELS)));
                assert_eq!(units.total.load(Ordering::SeqCst), total, "depth {depth}");
                assert_eq!(units.done.load(Ordering::SeqCst), total, "depth {depth}, {threads} threads");
                assert_eq!(*first.get_or_insert(decided.0), decided.0, "decisions counted on {threads} threads");
            }
        }
    }

    /// Collects cells, checking their order.
    #[derive(Default)]
    struct Collect(Vec<(u64, CellNodes)>);

    impl CellSink for Collect {
        fn cell(&mut self, index: u64, nodes: CellNodes) -> Result<()> {
            assert!(self.0.last().is_none_or(|(last, _)| *last < index), "cells out of order");
            self.0.push((index, nodes));
            Ok(())
        }
    }

    #[test]
    fn cells_in_any_split_of_their_range_give_the_whole_walks_keys() {
        for depth in 1..=5u8 {
            let domain = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
            let n = f64::from(domain.resolution());
            // A ball large enough that whole cells are inside at every level.
            let ball = Ball { center: [0.5 * n, 0.45 * n, 0.5 * n], radius: 0.47 * n };
            let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), progress: &NoProgress };
            let root = NodeKey::new(0, u32::from(depth));
            let whole = Plan::new("test", 0, domain, &options).unwrap().run(&ball, root).unwrap().0;
            for level in 0..=depth {
                let total = Cells::count(level);
                // One job, and the range cut in three uneven jobs.
                for cuts in [vec![0, total], vec![0, total / 3, total / 2 + 1, total]] {
                    let mut sink = Collect::default();
                    for w in cuts.windows(2) {
                        let cells = Cells { level, range: w[0]..w[1] };
                        let plan = Plan::new("test", 0, domain, &options).unwrap();
                        plan.run_cells(&ball, NodeKey::new(0, u32::from(depth)), &cells, &mut sink).unwrap();
                    }
                    let full = sink.0.iter().filter(|(_, c)| *c == CellNodes::Full).map(|(i, _)| *i);
                    let mut keys = Cells::join_full(level, depth, full);
                    for (index, nodes) in &sink.0 {
                        if let CellNodes::Nodes(nodes) = nodes {
                            let cell = Cells::all(level).key(*index, depth);
                            assert!(nodes.iter().all(|k| k.start() >= cell.start() && k.end() <= cell.end()));
                            assert!(!nodes.contains(&cell), "a full cell came as its nodes");
                            keys.extend_from_slice(nodes);
                        }
                    }
                    keys.sort_unstable();
                    assert_eq!(keys, whole.keys(), "depth {depth}, level {level}, cuts {cuts:?}");
                }
            }
        }
    }

    #[test]
    fn a_plan_over_budget_is_refused_naming_the_job() {
        let domain = Domain::new(DVec3::ZERO, 1.0, 9).unwrap();
        let options = VoxelizeOptions { budget: MemoryBudget(1000), progress: &NoProgress };
        assert!(Plan::new("test", 1000, domain, &options).is_ok());
        match Plan::new("voxelizing a test", 1001, domain, &options) {
            Err(Error::OverBudget { job, estimate: 1001, budget: 1000 }) => {
                assert_eq!(job, "voxelizing a test at depth 9");
            }
            Err(e) => panic!("{e}"),
            Ok(_) => panic!("a plan over budget was made"),
        }
    }
}
