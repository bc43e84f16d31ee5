//! Offsets, shells and rounds of a sharded solid, cell by cell with a halo: memory
//! follows one window, never the solid ([`morph`]).
//!
//! Every morphological step is local: whether a voxel flips under an offset by `D`
//! depends only on the voxels within `D + 1/2` of its centre (the exact rule of
//! [`crate::octree::LinearOctree::offset`]: a voxel of the phase the step spreads into
//! flips when its centre lies under `D` from a cube of the other phase; along a surface
//! the nearest site's tangent planes, a voxel farther at most). So an output cell is
//! computed from a **window**: the cell and a halo of `h` voxels a side read from the
//! input cells it meets (each neighbour's shard read, cropped to the window; full cells
//! cropped from the index), the window offset as a whole solid of the same domain (the
//! same aligned tiles, the same band transform), and the result clipped to the cell.
//! Outside the window the window is empty, so the result is wrong only within `D` (and
//! a voxel) of the window's faces, which the halo keeps out of the cell: for one step
//! `h = ceil(|D|) + 4` (the reach of the step, the voxel one beyond the cell whose face
//! the cell's crossings describe, and a site's own faces one beyond that). A shell is
//! one step and a set operation of the window (local too); a round is two or four
//! steps done on one window whose halo is the sum of the steps' (each step wrong only
//! within its reach of the previous one's wrong voxels). The cells are the same bits as
//! the single-file result's ([`super::stream`]'s canonical cut), so the output is
//! the merged solid's operation bit for bit, crossings included when the input's
//! shards carry them (the along-surface steps of [`crate::surface`]'s
//! `offset_with_surface` and kin, the crossings kept for the faces of the cell's
//! voxels, as the shards of [`super::voxelize_shape`] keep them).
//!
//! Departures from the sketch of one pass a step: a round takes one pass with the
//! summed halo instead of a pass (and an intermediate sharded solid) a step: cells are
//! thousands of voxels a side and radii tens, so a window grows by little. Cells far
//! from the surface are decided from the index alone: a window with no solid voxel
//! gives an empty cell (no step makes voxels from nothing), a window all full inside the
//! domain gives a full cell for an offset or a round and an empty one for a shell. The
//! window's crop leaves nodes smaller than a tile on its faces, so the band transform
//! also reads the tiles along the window's faces where the solid meets them (at most
//! the window's surface again).
//!
//! Memory: before any cell is written the largest window (by the bytes its shards take
//! once loaded) is read and every step's estimate taken on it
//! ([`crate::octree::LinearOctree::check_offset_steps`]); each window is checked again
//! as its shards are read and as each step starts.

use std::path::Path;

use super::index::ShardIndex;
use super::layout::Layout;
use super::solid::ShardedSolid;
use super::stream::{Job, StreamOptions};
use super::window::{ShardCache, Window, is_full, shard_of};
use crate::error::{Error, Result};
use crate::octree::{CellNodes, CellSink, LinearOctree, NodeKey, OffsetOptions};
use crate::progress::NoProgress;
use crate::surface::{FaceKey, HermiteData, offset_with_surface, round_with_surface, shell_with_surface};

/// A morphological operation, distances in voxels (see [`crate::octree::LinearOctree`]'s
/// `offset`, `shell` and `round`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Morph {
    /// Grow (positive) or shrink (negative) by a ball of this radius.
    Offset(f64),
    /// The wall of this thickness inside the surface, or outside it when `outward`.
    Shell {
        /// The wall's thickness.
        thickness: f64,
        /// Outside the surface.
        outward: bool,
    },
    /// Convex edges (an opening) and concave edges (a closing) rounded by `radius`.
    Round {
        /// The ball's radius.
        radius: f64,
        /// Round the convex edges.
        convex: bool,
        /// Round the concave edges.
        concave: bool,
    },
}

impl Morph {
    /// The offset steps the operation makes, in order.
    #[must_use]
    pub fn steps(self) -> Vec<f64> {
        match self {
            Morph::Offset(d) => vec![d],
            Morph::Shell { thickness, outward } => vec![if outward { thickness } else { -thickness }],
            Morph::Round { radius, convex, concave } => {
                let mut steps = Vec::new();
                if convex {
                    steps.extend([-radius, radius]);
                }
                if concave {
                    steps.extend([radius, -radius]);
                }
                steps
            }
        }
    }

    /// Fails unless the distances are finite (and positive for a shell or a round).
    fn check(self) -> Result<()> {
        let (what, value, positive) = match self {
            Morph::Offset(d) => ("offset distance", d, false),
            Morph::Shell { thickness, .. } => ("shell thickness", thickness, true),
            Morph::Round { radius, .. } => ("round radius", radius, true),
        };
        if value.is_finite() && (!positive || value > 0.0) {
            Ok(())
        } else {
            Err(Error::invalid(
                what,
                format!("{value} is not a finite{} number of voxels", if positive { " positive" } else { "" }),
            ))
        }
    }

    /// The window's halo in voxels (module doc).
    #[must_use]
    pub fn halo(self) -> u32 {
        let sum: f64 = self.steps().iter().map(|d| d.abs().ceil() + 4.0).sum();
        sum.min(f64::from(u32::MAX / 4)) as u32
    }

    /// What a window all full (and inside the domain) gives: full for an offset or a
    /// round, empty for a shell.
    fn full_stays_full(self) -> bool {
        !matches!(self, Morph::Shell { .. })
    }

    /// The operation on a whole solid, along its surface when it has one.
    fn apply(
        self,
        tree: &LinearOctree,
        surface: Option<&HermiteData>,
        options: &OffsetOptions,
    ) -> Result<(LinearOctree, Option<HermiteData>)> {
        Ok(match (self, surface) {
            (Morph::Offset(d), None) => (tree.offset(d, options)?, None),
            (Morph::Shell { thickness, outward }, None) => (tree.shell(thickness, outward, options)?, None),
            (Morph::Round { radius, convex, concave }, None) => (tree.round(radius, convex, concave, options)?, None),
            (Morph::Offset(d), Some(data)) => {
                let (tree, data) = offset_with_surface(tree, data, d, options)?;
                (tree, Some(data))
            }
            (Morph::Shell { thickness, outward }, Some(data)) => {
                let (tree, data) = shell_with_surface(tree, data, thickness, outward, options)?;
                (tree, Some(data))
            }
            (Morph::Round { radius, convex, concave }, Some(data)) => {
                let (tree, data) = round_with_surface(tree, data, radius, convex, concave, options)?;
                (tree, Some(data))
            }
        })
    }
}

impl std::fmt::Display for Morph {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match *self {
            Morph::Offset(d) => write!(f, "offset by {d} voxels"),
            Morph::Shell { thickness, outward } => {
                write!(f, "shell of {thickness} voxels {}", if outward { "outward" } else { "inward" })
            }
            Morph::Round { radius, convex, concave } => {
                let edges = match (convex, concave) {
                    (true, true) => "every edge",
                    (true, false) => "convex edges",
                    (false, true) => "concave edges",
                    (false, false) => "no edge",
                };
                write!(f, "round of {edges} by {radius} voxels")
            }
        }
    }
}

/// `morph` of the sharded solid `solid` into the sharded solid `out`, cell by cell
/// (module doc): the same solid (and crossings, when the shards carry them) as the
/// operation on the merged solid, cut into cells at the options' level (default: the
/// input's). `options.progress` counts output cells.
///
/// # Errors
/// A distance that is not finite (or not positive for a shell or round); the largest
/// window or any of its steps over the budget (before any cell is written); a shard
/// that fails its checks (named); writing fails.
pub fn morph(solid: &ShardedSolid, morph: Morph, out: &Path, options: &StreamOptions) -> Result<Option<ShardIndex>> {
    morph.check()?;
    let index = solid.index();
    let (domain, meta) = (index.domain, index.meta);
    let level = options.level.unwrap_or(index.level);
    let input = index.layout();
    let output = Layout { depth: domain.depth(), level: level.min(domain.depth()) };
    let halo = morph.halo();
    let steps = morph.steps();
    let windows = Windows { solid, input, output, halo };
    let all = 0..output.cell_count();
    let range = options.cells.cloned().unwrap_or(all);
    // The largest window checked before any cell is written.
    let largest = range
        .clone()
        .filter(|&c| windows.kind(c) == Kind::Mixed)
        .max_by_key(|&c| windows.shards_meeting(c).iter().map(|&i| solid.shard_bytes(i)).sum::<u64>());
    // First from the index alone: the window's shards held and the window cut from them.
    if let Some(cell) = largest {
        let bytes: u64 = windows.shards_meeting(cell).iter().map(|&i| solid.shard_bytes(i)).sum();
        options.budget.check(
            format!("the {morph} of {} (the window of cell {cell}: its shards and their crop)", solid.dir().display()),
            bytes.saturating_mul(2),
        )?;
    }
    // Surface data goes through when the input's shards carry it (all of a solid's do
    // or none do; the first tells).
    let along =
        if index.shards.is_empty() { false } else { solid.read_shard_and_surface(0, options.budget)?.1.is_some() };
    let mut cache = ShardCache::default();
    if let Some(cell) = largest {
        let (window, _) = windows.read(cell, along, &mut cache, options)?;
        window.check_offset_steps(
            format!("{morph} of {} (the window of cell {cell})", solid.dir().display()),
            &steps,
            along,
            options.budget,
        )?;
    }
    let mut job = Job::start(domain, meta, Some(output.level), out, options, |h| {
        h.bytes(format!("{morph:?}").as_bytes());
        let index = index.encode();
        h.u64(index.len() as u64);
        h.bytes(&index);
    })?;
    let writer = &mut job.writer;
    let step_options = OffsetOptions { budget: options.budget, progress: &NoProgress };
    options.progress.start(range.end - range.start);
    for cell in range {
        match windows.kind(cell) {
            Kind::Empty => {}
            Kind::Full => {
                if morph.full_stays_full() {
                    writer.cell(cell, CellNodes::Full)?;
                }
            }
            Kind::Mixed => {
                let (window, surface) = windows.read(cell, along, &mut cache, options)?;
                let (result, data) =
                    morph.apply(&window, surface.as_ref(), &step_options).map_err(|e| in_cell(e, solid, cell))?;
                let key = output.cell_key(cell);
                match clip(&result, key) {
                    None => {}
                    Some(CellNodes::Full) => writer.cell(cell, CellNodes::Full)?,
                    Some(nodes) => writer.cell_with_surface(cell, nodes, |_| {
                        data.map(|data| {
                            HermiteData::from_faces(
                                data.faces().iter().filter(|(f, _)| face_in(*f, key)).copied().collect(),
                            )
                        })
                    })?,
                }
            }
        }
        options.progress.advance(1);
    }
    options.progress.finish();
    job.finish()
}

/// Names the input and the cell in an error of a window's steps.
fn in_cell(e: Error, solid: &ShardedSolid, cell: u64) -> Error {
    match e {
        Error::InvalidArgument { what, reason } => Error::InvalidArgument {
            what,
            reason: format!("{} (the window of cell {cell}): {reason}", solid.dir().display()),
        },
        e => e,
    }
}

/// The nodes of `tree` in the aligned node `cell`: `None` when none, full, or the nodes.
fn clip(tree: &LinearOctree, cell: NodeKey) -> Option<CellNodes> {
    let keys = tree.keys();
    let first = keys.partition_point(|k| k.end() <= cell.start());
    let inside: Vec<NodeKey> = keys[first..].iter().take_while(|k| k.start() < cell.end()).copied().collect();
    match inside.as_slice() {
        [] => None,
        [one] if one.start() <= cell.start() && one.end() >= cell.end() => Some(CellNodes::Full),
        _ => Some(CellNodes::Nodes(inside)),
    }
}

/// What the index says of a window.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    /// No input cell it meets holds a voxel.
    Empty,
    /// Every input cell it meets is full, and the window lies inside the domain.
    Full,
    /// Anything else: read and computed.
    Mixed,
}

/// The windows of the output cells over the input's cells.
struct Windows<'a> {
    solid: &'a ShardedSolid,
    input: Layout,
    output: Layout,
    halo: u32,
}

impl Windows<'_> {
    /// The window of output cell `cell`: the halo around it.
    fn window(&self, cell: u64) -> Window {
        Window::around(self.output, cell, self.halo, self.solid.index().domain.resolution())
    }

    /// The shards meeting the window of `cell`.
    fn shards_meeting(&self, cell: u64) -> Vec<usize> {
        self.window(cell).cells_meeting(self.input).into_iter().filter_map(|c| shard_of(self.solid, c)).collect()
    }

    /// What the index says of the window of `cell`.
    fn kind(&self, cell: u64) -> Kind {
        let window = self.window(cell);
        let (mut any, mut all) = (false, true);
        for c in window.cells_meeting(self.input) {
            let full = is_full(self.solid, c);
            let shard = shard_of(self.solid, c).is_some();
            any |= full || shard;
            all &= full;
        }
        match (any, all && !window.clipped) {
            (false, _) => Kind::Empty,
            (true, true) => Kind::Full,
            (true, false) => Kind::Mixed,
        }
    }

    /// The window of `cell` as a solid of the domain (empty outside it), and the
    /// crossings the shards carry for its voxels when `along`; shards come through
    /// `cache`, which keeps those of this window for the next.
    fn read(
        &self,
        cell: u64,
        along: bool,
        cache: &mut ShardCache,
        options: &StreamOptions,
    ) -> Result<(LinearOctree, Option<HermiteData>)> {
        let (window, crossings) = self.window(cell).read(self.solid, along, Some(cache), options.budget)?;
        Ok((window, along.then_some(crossings)))
    }
}

/// Whether a face's voxel lies in `cell`.
fn face_in(face: FaceKey, cell: NodeKey) -> bool {
    (cell.start()..cell.end()).contains(&face.voxel)
}
