//! A window of a sharded solid: one cell of a layout and a border of `b` voxels a
//! side (clipped to the domain), read as a whole solid of the same domain, empty
//! outside the window, with the crossings its shards carry for its voxels. The cell
//! by cell jobs that need their neighbours read through it: the offsets (a halo of
//! the distance, [`super::offset`]) and the surface's export (a border for the
//! vertices' placement, [`super::surface`]).
//!
//! The window is read from the input cells it meets, in Morton order: a cell in a
//! full node of the index is cropped from that node, a cell with a shard has the
//! shard's nodes cropped to the window (and its faces whose voxel lies in the window
//! kept), any other cell is empty. Cropping splits a node into the largest aligned
//! nodes inside the box ([`crop`]).
//!
//! Shards are read one at a time, cropped and (their faces filtered) dropped before
//! the next, so a read holds one shard besides the window: what the window needs, not
//! the shards it meets (a window near the corner of eight cells meets eight whole
//! shards; kept together, a depth-13 solid's eight shards with their crossings took
//! 1.3 to 1.7 GB to read one window of it). A caller that keeps shards for the next
//! window (neighbouring windows share most of theirs) passes a [`ShardCache`], which
//! holds whole shards up to a cap of bytes and reads the rest through as above.

use rustc_hash::FxHashMap;

use super::layout::Layout;
use super::solid::ShardedSolid;
use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::morton;
use crate::octree::{LinearOctree, NodeKey};
use crate::surface::{Crossing, FaceKey, HermiteData};

/// The voxels `lo..hi` around a cell of a sharded solid.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Window {
    /// The lowest voxel.
    pub lo: [u32; 3],
    /// One past the highest voxel.
    pub hi: [u32; 3],
    /// Whether the domain's faces cut the border.
    pub clipped: bool,
}

impl Window {
    /// The window of cell `cell` of `layout` with `border` voxels a side, clipped to a
    /// domain of `resolution` voxels a side.
    pub fn around(layout: Layout, cell: u64, border: u32, resolution: u32) -> Window {
        let lo = layout.cell_min(cell);
        let size = 1u32 << layout.cell_k();
        let (mut clipped, mut wlo, mut whi) = (false, [0; 3], [0; 3]);
        for a in 0..3 {
            wlo[a] = lo[a].saturating_sub(border);
            let hi = u64::from(lo[a]) + u64::from(size) + u64::from(border);
            whi[a] = hi.min(u64::from(resolution)) as u32;
            clipped |= u64::from(lo[a]) < u64::from(border) || hi > u64::from(resolution);
        }
        Window { lo: wlo, hi: whi, clipped }
    }

    /// Whether voxel `v` lies in the window.
    fn holds(&self, v: [u32; 3]) -> bool {
        (0..3).all(|a| v[a] >= self.lo[a] && v[a] < self.hi[a])
    }

    /// The cells of `layout` meeting the window, in Morton order.
    pub fn cells_meeting(&self, layout: Layout) -> Vec<u64> {
        let k = layout.cell_k();
        let (first, last) = (self.lo.map(|c| c >> k), self.hi.map(|c| (c - 1) >> k));
        let mut cells = Vec::new();
        for z in first[2]..=last[2] {
            for y in first[1]..=last[1] {
                for x in first[0]..=last[0] {
                    cells.push(morton::encode(x, y, z));
                }
            }
        }
        cells.sort_unstable();
        cells
    }

    /// The window of `solid` as a solid of its domain (empty outside the window), and
    /// the crossings its shards carry for the window's voxels (module doc; none unless
    /// `faces`); shards through `cache` when given (which then keeps this window's for the
    /// next), else each read and dropped in turn, within `budget`.
    pub fn read(
        &self,
        solid: &ShardedSolid,
        faces: bool,
        mut cache: Option<&mut ShardCache>,
        budget: MemoryBudget,
    ) -> Result<(LinearOctree, HermiteData)> {
        let index = solid.index();
        let (layout, depth) = (index.layout(), index.domain.depth());
        let meeting = self.cells_meeting(layout);
        if let Some(cache) = cache.as_deref_mut() {
            let wanted: Vec<usize> = meeting.iter().filter_map(|&c| shard_of(solid, c)).collect();
            cache.keep(&wanted);
        }
        let (mut keys, mut kept) = (Vec::new(), Vec::new());
        for c in meeting {
            if is_full(solid, c) {
                crop(layout.cell_key(c), depth, &self.lo, &self.hi, &mut keys);
            } else if let Some(i) = shard_of(solid, c) {
                let fresh = match cache.as_deref().and_then(|cache| cache.shards.get(&i)) {
                    Some(_) => None,
                    None => Some(solid.read_shard_and_surface(i, budget)?),
                };
                let (nodes, surface) = match &fresh {
                    Some(shard) => shard,
                    None => cache.as_deref().and_then(|cache| cache.shards.get(&i)).expect("kept above"),
                };
                for &node in nodes {
                    crop(node, depth, &self.lo, &self.hi, &mut keys);
                }
                if faces && let Some(surface) = surface {
                    kept.extend(surface.faces().iter().filter(|(f, _)| self.holds(f.voxel())).copied());
                }
                if let (Some(shard), Some(cache)) = (fresh, cache.as_deref_mut()) {
                    cache.offer(i, shard);
                }
            }
        }
        let window = LinearOctree::from_keys_unsorted(index.domain, keys);
        Ok((window, HermiteData::from_faces(kept)))
    }
}

/// Whether cell `cell` of `solid`'s layout lies in a full node of its index.
pub(super) fn is_full(solid: &ShardedSolid, cell: u64) -> bool {
    let index = solid.index();
    let start = index.layout().cell_key(cell).start();
    let at = index.full.partition_point(|k| k.end() <= start);
    index.full.get(at).is_some_and(|k| k.start() <= start)
}

/// The shard of cell `cell` of `solid`, if it has one.
pub(super) fn shard_of(solid: &ShardedSolid, cell: u64) -> Option<usize> {
    solid.index().shards.binary_search_by_key(&cell, |s| s.cell).ok()
}

/// Appends the parts of node `key` inside the box `lo..hi` (voxels) to `out`, split
/// into the largest aligned nodes inside it, in Morton order.
fn crop(key: NodeKey, depth: u8, lo: &[u32; 3], hi: &[u32; 3], out: &mut Vec<NodeKey>) {
    let node = key.node(depth);
    let (min, size) = (node.min, node.size);
    if (0..3).any(|a| min[a] >= hi[a] || min[a] + size <= lo[a]) {
        return;
    }
    if (0..3).all(|a| min[a] >= lo[a] && min[a] + size <= hi[a]) {
        out.push(key);
        return;
    }
    for c in 0..8 {
        if let Some(child) = key.child(c) {
            crop(child, depth, lo, hi, out);
        }
    }
}

/// Shards read for the last window, kept for the next (neighbouring cells share most),
/// whole, as long as their bytes stay within a cap.
pub(super) struct ShardCache {
    shards: FxHashMap<usize, Shard>,
    /// The bytes the kept shards take.
    bytes: u64,
    /// The most bytes to keep.
    cap: u64,
}

/// A shard's nodes and crossings.
type Shard = (Vec<NodeKey>, Option<HermiteData>);

/// The bytes a shard takes in memory.
fn shard_bytes((nodes, surface): &Shard) -> u64 {
    let face = std::mem::size_of::<(FaceKey, Crossing)>();
    (nodes.capacity() * std::mem::size_of::<NodeKey>() + surface.as_ref().map_or(0, |s| s.len() * face)) as u64
}

impl ShardCache {
    /// A cache keeping at most `cap` bytes of shards.
    pub fn with_cap(cap: u64) -> ShardCache {
        ShardCache { shards: FxHashMap::default(), bytes: 0, cap }
    }

    /// The bytes the kept shards take.
    pub fn bytes(&self) -> u64 {
        self.bytes
    }

    /// Drops every shard.
    pub fn clear(&mut self) {
        self.shards.clear();
        self.bytes = 0;
    }

    /// Drops every shard but `wanted`.
    fn keep(&mut self, wanted: &[usize]) {
        self.shards.retain(|i, _| wanted.contains(i));
        self.bytes = self.shards.values().map(shard_bytes).sum();
    }

    /// Keeps shard `i` when it fits under the cap.
    fn offer(&mut self, i: usize, shard: Shard) {
        let bytes = shard_bytes(&shard);
        if self.bytes + bytes <= self.cap {
            self.bytes += bytes;
            self.shards.insert(i, shard);
        }
    }
}
