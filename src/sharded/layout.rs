//! The cells of a sharded solid: aligned cubes `level` levels below the root,
//! numbered in Morton order, and the names of their shard files.

use crate::morton;
use crate::octree::{Cells, NodeKey};

/// Cells `level` levels below the root of a domain of depth `depth`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// The domain's depth.
    pub depth: u8,
    /// The cells' level (0: the whole domain is one cell).
    pub level: u8,
}

impl Layout {
    /// The level a solid of depth `depth` is cut at by default: cells of `2^11` voxels
    /// a side (a few megabytes of nodes for a surface through a cell), one cell up to
    /// depth 11.
    #[must_use]
    pub fn default_level(depth: u8) -> u8 {
        depth.saturating_sub(11)
    }

    /// How many levels a cell sits above the voxels.
    #[must_use]
    pub fn cell_k(&self) -> u8 {
        self.depth - self.level
    }

    /// How many cells there are: `8^level`.
    #[must_use]
    pub fn cell_count(&self) -> u64 {
        Cells::count(self.level)
    }

    /// Cell `cell`'s node.
    #[must_use]
    pub fn cell_key(&self, cell: u64) -> NodeKey {
        let k = u32::from(self.cell_k());
        NodeKey::new(cell << (3 * k), k)
    }

    /// Cell `cell`'s lowest voxel.
    #[must_use]
    pub fn cell_min(&self, cell: u64) -> [u32; 3] {
        morton::decode(self.cell_key(cell).start())
    }

    /// The cell holding the voxel of Morton code `code`.
    #[must_use]
    pub fn cell_of(&self, code: u64) -> u64 {
        code >> (3 * u32::from(self.cell_k()))
    }

    /// The shard file of cell `cell`: `c` and the cell's number in hexadecimal, as
    /// many digits as the largest number needs, then `.oct`.
    #[must_use]
    pub fn shard_file(&self, cell: u64) -> String {
        let digits = (3 * usize::from(self.level)).div_ceil(4).max(1);
        format!("c{cell:0digits$x}.oct")
    }
}
