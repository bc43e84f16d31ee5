//! Occupancy windows: a cube of up to 17 voxels a side of an octree's occupancy as
//! bit rows (`Window`, the input of the normal estimate in `normal_field`), read
//! straight from the octree or through `Bricks`, a cache of 16^3 bricks of the same bit
//! rows that neighbouring windows share.
//!
//! A window of `size` voxels a side with lowest voxel `lo` has `size^2` rows along x;
//! row `y + size z` bit `x` is voxel `lo + (x, y, z)`. A brick is the same for the
//! aligned cube of 16 voxels at `16 b`; a window of at most 17 voxels meets at most two
//! bricks an axis, so each of its rows is at most two brick rows, shifted and joined.
//! Voxels outside the domain are empty. Why bricks: the octree is read fastest over
//! aligned cubes (`LinearOctree::occupancy_rows` descends from the smallest node
//! holding the cube, which for an unaligned window can be far larger than it).

use dashmap::DashMap;
use rustc_hash::FxBuildHasher;

use crate::octree::LinearOctree;

/// Largest window edge in voxels.
pub(crate) const MAX_WINDOW: usize = 17;

/// Occupancy of a cube of voxels with lowest voxel `lo`: `rows[y + size z]` bit `x` is
/// voxel `lo + (x, y, z)`.
#[derive(Clone, Copy)]
pub(crate) struct Window {
    /// Voxels a side, at most [`MAX_WINDOW`].
    pub size: usize,
    /// The rows along x.
    pub rows: [u32; MAX_WINDOW * MAX_WINDOW],
}

impl Window {
    /// The window of `size` voxels a side (at most [`MAX_WINDOW`]) at `lo`, read
    /// straight from `tree`.
    #[cfg(test)]
    pub(crate) fn read(tree: &LinearOctree, lo: [i64; 3], size: usize) -> Self {
        let size = size.min(MAX_WINDOW);
        let mut window = Window { size, rows: [0; MAX_WINDOW * MAX_WINDOW] };
        tree.occupancy_rows(lo, size as u32, &mut window.rows);
        window
    }
}

/// Voxels a side of a cached brick.
const BRICK: i64 = 16;

/// A brick's occupancy: `rows[y + 16 z]` bit `x`.
type Brick = [u16; 256];

/// The occupancy of one octree in 16^3 bricks, each read from the octree on first use.
/// Safe to share between threads; windows read through it equal [`Window::read`]'s.
#[derive(Debug, Default)]
pub(crate) struct Bricks {
    bricks: DashMap<[i64; 3], Brick, FxBuildHasher>,
}

impl Bricks {
    /// The window of `size` voxels a side (at most [`MAX_WINDOW`]) at `lo` of `tree`,
    /// filled a brick at a time (one or two an axis).
    pub(crate) fn window(&self, tree: &LinearOctree, lo: [i64; 3], size: usize) -> Window {
        let size = size.min(MAX_WINDOW);
        let mut window = Window { size, rows: [0; MAX_WINDOW * MAX_WINDOW] };
        let first = lo.map(|c| c.div_euclid(BRICK));
        let last = lo.map(|c| (c + size as i64 - 1).div_euclid(BRICK));
        for i in 0..8 {
            let b: [i64; 3] = std::array::from_fn(|a| first[a] + ((i >> a) & 1) as i64);
            if (0..3).all(|a| b[a] <= last[a])
                && let Some(brick) = self.brick(tree, b)
            {
                fill(&mut window, lo, b, &brick);
            }
        }
        window
    }

    /// The brick at brick coordinates `b`, read on first use; `None` outside the domain.
    fn brick(&self, tree: &LinearOctree, b: [i64; 3]) -> Option<Brick> {
        let n = i64::from(tree.domain().resolution());
        if b.iter().any(|&c| c < 0 || c * BRICK >= n) {
            return None;
        }
        if let Some(brick) = self.bricks.get(&b) {
            return Some(*brick);
        }
        let mut rows = [0u32; 256];
        tree.occupancy_rows(b.map(|c| c * BRICK), BRICK as u32, &mut rows);
        let brick = rows.map(|r| r as u16);
        self.bricks.insert(b, brick);
        Some(brick)
    }
}

/// Ors into `window` (lowest voxel `lo`) its rows' parts that lie in `brick`, the brick
/// at brick coordinates `b`.
fn fill(window: &mut Window, lo: [i64; 3], b: [i64; 3], brick: &Brick) {
    let size = window.size as i64;
    // The window's voxels inside the brick, a range an axis (window indices).
    let range = |a: usize| (b[a] * BRICK - lo[a]).max(0)..(b[a] * BRICK + BRICK - lo[a]).min(size);
    let mask = (1u64 << size) - 1;
    // Window x index i is brick bit i + shift (a negative shift: the brick starts
    // inside the window).
    let shift = lo[0] - b[0] * BRICK;
    for z in range(2) {
        let bz = (lo[2] + z - b[2] * BRICK) as usize;
        for y in range(1) {
            let by = (lo[1] + y - b[1] * BRICK) as usize;
            let row = u64::from(brick[by + 16 * bz]);
            let bits = if shift >= 0 { row >> shift } else { row << -shift };
            window.rows[(y + size * z) as usize] |= (bits & mask) as u32;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::{Domain, VoxelizeOptions, voxelize};
    use crate::shape::Sphere;
    use crate::test_util::Rng;
    use glam::DVec3;

    #[test]
    fn windows_read_through_bricks_equal_windows_read_from_the_octree() {
        // A ball reaching past the domain's faces, at a depth where windows straddle
        // bricks and the domain's boundary; every window size.
        let ball = Sphere::new(DVec3::new(0.3, -0.2, 0.1), 0.9).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
        let tree = voxelize(&ball, domain, &VoxelizeOptions::default()).unwrap();
        let bricks = Bricks::default();
        let mut rng = Rng(4);
        for _ in 0..3_000 {
            let lo: [i64; 3] = std::array::from_fn(|_| rng.below(84) as i64 - 10);
            let size = 1 + rng.below(MAX_WINDOW as u64) as usize;
            let (want, got) = (Window::read(&tree, lo, size), bricks.window(&tree, lo, size));
            assert_eq!(got.rows, want.rows, "at {lo:?}, size {size}");
        }
    }

    #[test]
    fn windows_hold_the_octree_occupancy_as_bits() {
        // A ball reaching past the domain's faces: windows across the boundary, of
        // every size, against the octree's flag a voxel.
        let ball = Sphere::new(DVec3::new(0.3, -0.2, 0.1), 0.9).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
        let tree = voxelize(&ball, domain, &VoxelizeOptions::default()).unwrap();
        let mut rng = Rng(3);
        for _ in 0..3_000 {
            let lo: [i64; 3] = std::array::from_fn(|_| rng.below(84) as i64 - 10);
            let size = 1 + rng.below(MAX_WINDOW as u64) as usize;
            let window = Window::read(&tree, lo, size);
            for (i, full) in tree.occupancy(lo, size as u32).into_iter().enumerate() {
                assert_eq!(window.rows[i / size] >> (i % size) & 1 == 1, full, "at {lo:?}, size {size}, voxel {i}");
            }
            assert!(window.rows[size * size..].iter().all(|&r| r == 0));
        }
    }
}
