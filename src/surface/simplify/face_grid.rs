//! A uniform grid over a block's box whose cells list the faces whose boxes meet
//! them, for the self-intersection tests of `block`: a face is tested only against
//! the faces listed in the cells its box meets.
//!
//! Cells are cubes of twice the faces' mean edge (so a face meets a few cells), at
//! most [`GRID_CELLS`] an axis; what lies outside the box is clamped into its border
//! cells.

use glam::DVec3;

/// Most cells of a grid along an axis.
const GRID_CELLS: usize = 64;

/// Face lists by cell over the box from `min`, in cells of side `cell`, `dims` along
/// the axes (stale entries are the caller's to skip or drop).
pub(crate) struct FaceGrid {
    min: DVec3,
    cell: f64,
    dims: [usize; 3],
    /// Face ids by cell index (`cell_index`).
    pub lists: Vec<Vec<u32>>,
}

/// The cells of a grid a box meets: the lowest and highest cell along each axis.
pub(crate) type CellRange = ([usize; 3], [usize; 3]);

impl FaceGrid {
    /// An empty grid over the box `min..max` for faces of mean edge `mean_edge`.
    pub fn new(min: DVec3, max: DVec3, mean_edge: f64) -> Self {
        let side = (max - min).max_element();
        let mut cell = (2.0 * mean_edge).max(side / GRID_CELLS as f64);
        if cell.is_nan() || cell <= 0.0 {
            cell = side.max(f64::MIN_POSITIVE);
        }
        let n = ((max - min) / cell).ceil();
        let dims = [n.x, n.y, n.z].map(|c| (c as usize).clamp(1, GRID_CELLS));
        FaceGrid { min, cell, dims, lists: vec![Vec::new(); dims[0] * dims[1] * dims[2]] }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.lists.len()
    }

    /// The cells the box `lo..hi` meets, clamped to the grid.
    pub fn cells_between(&self, lo: DVec3, hi: DVec3) -> CellRange {
        let index = |p: DVec3| {
            let c = ((p - self.min) / self.cell).floor();
            [0, 1, 2].map(|k| (c[k].max(0.0) as usize).min(self.dims[k] - 1))
        };
        (index(lo), index(hi))
    }

    /// The cells a triangle's box meets, clamped to the grid.
    pub fn cells_of(&self, t: [DVec3; 3]) -> CellRange {
        self.cells_between(t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))
    }

    /// `range` grown by `margin` cells each way, clamped to the grid.
    pub fn grown(&self, (first, last): CellRange, margin: usize) -> CellRange {
        (first.map(|c| c.saturating_sub(margin)), [0, 1, 2].map(|k| (last[k] + margin).min(self.dims[k] - 1)))
    }

    /// The indices of the cells of `range`, x fastest.
    pub fn cells(&self, range: CellRange) -> impl Iterator<Item = usize> + use<> {
        let dims = self.dims;
        let (first, last) = range;
        (first[2]..=last[2]).flat_map(move |z| {
            (first[1]..=last[1]).flat_map(move |y| (first[0]..=last[0]).map(move |x| (z * dims[1] + y) * dims[0] + x))
        })
    }

    /// Lists face `id` in the cells of `range`.
    pub fn insert(&mut self, id: u32, range: CellRange) {
        for cell in self.cells(range) {
            self.lists[cell].push(id);
        }
    }
}
