//! The area of a solid's boundary, estimated from its voxels so that it converges to
//! the area of the smooth surface they digitize.
//!
//! The voxel boundary (the staircase of exposed voxel faces) over a surface patch of
//! unit normal `n` has `|n_a|` faces of axis `a` per unit area, so its area is the
//! integral of `|n|_1 = |n_x| + |n_y| + |n_z|`, not of `|n|_2 = 1`: 1.5 times a sphere's
//! area (the mean of `|n|_1` over directions), and no finer lattice helps. Weighting
//! each face of axis `a` by `|n_a|` gives the integral of `|n|_2^2 = 1`, the area
//! (Lachaud and Thibert, "Properties of Gauss digitized shapes and digital surface
//! integration", 2016: the sum over the faces of `|n . face normal|` converges with
//! a convergent normal estimator):
//!
//! ```text
//! area ~ h^2 sum_faces |n(face) . axis(face)|,   raw voxel face area = h^2 #faces
//! ```
//!
//! Normal estimator: the voxels are grouped in blocks of 4^3; for each block, the
//! faces of the 3^3 blocks around it (a window of 12 voxels) are counted by axis,
//! `U_a = #faces of axis a`, and `|n_a| ~ U_a / |U|_2`. Over a flat patch the counts are
//! proportional to `|n_a|`, so this is exact up to the window's clipping of the
//! staircase (angle errors up to about 1/12, area errors their square); unsigned
//! counts (not the area vector) keep two sheets facing away from each other inside a
//! window, such as a thin plate's, from cancelling. The faces of a block share its
//! estimate: `block area = sum_a C_a U_a / |U|_2` for its own counts `C_a`, `|C|_2`
//! when its faces are the window's (a flat patch's area vector).
//!
//! Departure, for sharp features: where the window holds no irregular edge (a lattice
//! edge with a full voxel diagonally across it from a full voxel whose face on the
//! edge is exposed: a concave step, or two voxels touching only along the edge), each
//! face counts whole. A staircase needs concave steps, so a window without them holds
//! a piece of an axis-aligned polyhedron with only convex edges and corners (a box's
//! edges and corners, taken as they are), or the terrace of a smooth surface wider
//! than the window, whose slope is then below about 1/8 (error below 1%, on a small
//! part of the surface). So an axis-aligned box's estimate is exact, while a curved
//! surface's converges.
//!
//! Error: on smooth surfaces, the normal's error (clipping, and the surface's
//! curvature across the window, `12 h kappa`) enters squared; measured, a unit sphere
//! is within 0.3% at depth 8 (123 voxels a radius) and 0.14% at depth 9, a torus of
//! radii 1 and 1/4 within 0.9% and 0.5% (tests/measure.rs). Near concave edges of
//! polyhedra the normals are smoothed over the window: faces within three blocks (12
//! voxels) of such an edge are weighted as if the surface turned gradually, which
//! loses at most `24 h` of area per unit length of edge (3.6 to 8.1 `h` measured on an
//! L-shaped prism); this vanishes with `h` but is not exact at any depth. The
//! estimate never exceeds the raw voxel face area.
//!
//! Method: the bricks of 64^3 voxels holding boundary faces ([`BoundaryBricks`]) are
//! read one at a time with a margin of 5 voxels as rows of bits ([`Rows`]); a row's
//! exposed faces and irregular edges are a few shifts and masks of it and its eight
//! neighbouring rows, counted into the blocks; then each block of the brick is
//! weighted by its window. Faces on the inner parts of big flat node faces are counted
//! in bulk, whole: nothing but their plane lies within a brick of them, and a window
//! reaches 9 voxels. Bricks run in parallel and are summed in brick order, so the
//! estimate does not depend on the number of threads.

use rayon::prelude::*;

use std::collections::BTreeMap;

use glam::DVec3;

use super::bricks::{BoundaryBricks, Pattern};
use super::rows::{MAX_SIZE, Row, Rows};
use crate::morton;
use crate::octree::{Domain, LinearOctree, Node};

/// Levels of a brick above the voxels: 64^3 voxels.
const BRICK_K: u32 = 6;
/// Voxels a side of a block, the unit that shares a normal estimate.
const BLOCK: usize = 4;
/// Voxels of context around a brick: the ring of blocks around it (the windows of its
/// own blocks) and one voxel beyond (their faces' and edges' neighbours).
const MARGIN: usize = BLOCK + 1;

/// The area of a solid's boundary ([`LinearOctree::surface_area`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceArea {
    /// The estimate of the digitized surface's area (module doc), world units squared.
    pub estimate: f64,
    /// The voxel boundary's own area: exposed voxel faces times `h^2`.
    pub voxel_faces: f64,
}

/// The row of the voxels one step along x (`dx = 1`) or back (`dx = -1`) of each voxel
/// of `row`: bit `x` is voxel `x + dx`.
fn along_x(row: Row, dx: i32) -> Row {
    if dx > 0 { row >> 1 } else { row << 1 }
}

/// The exposed faces of one block: counts by direction (`+x, -x, +y, -y, +z, -z`), and
/// whether an irregular edge lies on one of them.
#[derive(Clone, Copy, Debug, Default)]
struct BlockFaces {
    count: [u8; 6],
    irregular: bool,
}

impl BlockFaces {
    /// Faces of axis `a`.
    fn axis(&self, a: usize) -> u32 {
        u32::from(self.count[2 * a]) + u32::from(self.count[2 * a + 1])
    }
}

impl LinearOctree {
    /// The boundary's area: the estimate of the module doc and the raw voxel face area.
    #[must_use]
    pub fn surface_area(&self) -> SurfaceArea {
        let k = BRICK_K.min(u32::from(self.depth()));
        let bricks = BoundaryBricks::of(self, k);
        let per_brick: Vec<(u64, f64)> = bricks
            .read
            .par_iter()
            .map_init(Brick::default, |brick, &code| {
                brick.read(self, morton::decode(code).map(|c| c << k), (1usize << k).max(BLOCK));
                brick.area()
            })
            .collect();
        // Each pattern measured once, on a brick with the same bricks around it.
        let mut patterns: BTreeMap<Pattern, u64> = BTreeMap::new();
        bricks.patterned.iter().for_each(|&(_, pattern)| *patterns.entry(pattern).or_default() += 1);
        let per_pattern: Vec<(u64, f64)> = patterns
            .into_par_iter()
            .map(|(pattern, count)| {
                let (faces, estimate) = pattern_area(pattern, k);
                (faces * count, estimate * count as f64)
            })
            .collect();
        let faces = bricks.bulk_faces + per_brick.iter().chain(&per_pattern).map(|p| p.0).sum::<u64>();
        let estimate = bricks.bulk_faces as f64
            + per_brick.iter().map(|p| p.1).sum::<f64>()
            + per_pattern.iter().map(|p| p.1).sum::<f64>();
        let h2 = self.domain().voxel_size().powi(2);
        SurfaceArea { estimate: estimate * h2, voxel_faces: faces as f64 * h2 }
    }
}

/// The faces and estimate of a full brick of `2^k` voxels whose 27 bricks around (itself
/// included) are full as `pattern` says: read from a solid of those bricks alone, in a
/// domain of 4 bricks a side with the brick at brick `(1, 1, 1)`.
fn pattern_area(pattern: Pattern, k: u32) -> (u64, f64) {
    let domain = Domain::new(DVec3::ZERO, 1.0, k as u8 + 2).expect("a small domain");
    let size = 1 << k;
    let nodes = (0..27u32).filter(|bit| pattern & 1 << bit != 0).map(|bit| Node {
        level: 2,
        min: [bit % 3, bit / 3 % 3, bit / 9].map(|o| o * size),
        size,
    });
    let solid = LinearOctree::from_nodes(domain, nodes).expect("aligned bricks");
    let mut brick = Brick::default();
    brick.read(&solid, [size; 3], size as usize);
    brick.area()
}

/// One brick with its margin: the rows, and the faces of its blocks and of the ring of
/// blocks around them (the windows of its own blocks).
#[derive(Clone, Debug, Default)]
struct Brick {
    rows: Rows,
    /// Voxels a side of the rows: the brick (at least a block) and two margins.
    size: usize,
    /// Blocks a side of `blocks`: the brick's and the ring's.
    side: usize,
    blocks: Vec<BlockFaces>,
}

/// The first voxel of the ring of blocks in the rows (one voxel of context before it).
const RING: usize = MARGIN - BLOCK;

impl Brick {
    /// Reads the brick of `core` voxels a side with lowest voxel `min` and counts the
    /// faces of its blocks and of the ring of blocks around them.
    fn read(&mut self, tree: &LinearOctree, min: [u32; 3], core: usize) {
        self.size = core + 2 * MARGIN;
        debug_assert!(self.size <= MAX_SIZE);
        self.side = core / BLOCK + 2;
        let lo = min.map(|c| i64::from(c) - MARGIN as i64);
        self.rows.read(tree, lo, self.size);
        self.blocks.clear();
        self.blocks.resize(self.side.pow(3), BlockFaces::default());
        let (first, last) = (RING, self.size - RING);
        let valid: Row = ((1 << (last - first)) - 1) << first;
        // Rows of the same state as all their neighbours, in and just around the
        // counted voxels, have no faces: full ones are skipped here, empty ones below.
        let wide = (valid << 1 | valid >> 1) & (Row::MAX >> (MAX_SIZE - self.size));
        for z in first..last {
            for y in first..last {
                let r = self.rows.row(y, z);
                if r & valid != 0 && !(r & wide == wide && self.solid_around(y, z, wide)) {
                    self.count_row(y, z, valid);
                }
            }
        }
    }

    /// Whether the eight rows around `(y, z)` are full at bits `wide`.
    fn solid_around(&self, y: usize, z: usize, wide: Row) -> bool {
        (z - 1..=z + 1).all(|zz| (y - 1..=y + 1).all(|yy| self.rows.row(yy, zz) & wide == wide))
    }

    /// Counts the exposed faces and irregular edges of the full voxels of row `(y, z)`
    /// (bits `valid`) into their blocks.
    fn count_row(&mut self, y: usize, z: usize, valid: Row) {
        let at = |dy: isize, dz: isize| self.rows.row(y.wrapping_add_signed(dy), z.wrapping_add_signed(dz));
        let r = at(0, 0);
        let (ym, yp, zm, zp) = (at(-1, 0), at(1, 0), at(0, -1), at(0, 1));
        let faces = [r & !along_x(r, 1), r & !along_x(r, -1), r & !yp, r & !ym, r & !zp, r & !zm];
        // Irregular: an exposed face towards v + d with v + d + e full (e a unit step
        // across d): the edge between is concave, or a pinch.
        let [xp_ym, xp_yp, xp_zm, xp_zp] = [ym, yp, zm, zp].map(|row| along_x(row, 1));
        let [xm_ym, xm_yp, xm_zm, xm_zp] = [ym, yp, zm, zp].map(|row| along_x(row, -1));
        let [ymzm, ymzp, ypzm, ypzp] = [at(-1, -1), at(-1, 1), at(1, -1), at(1, 1)];
        let irregular = faces[0] & (xp_ym | xp_yp | xp_zm | xp_zp)
            | faces[1] & (xm_ym | xm_yp | xm_zm | xm_zp)
            | faces[2] & (xp_yp | xm_yp | ypzm | ypzp)
            | faces[3] & (xp_ym | xm_ym | ymzm | ymzp)
            | faces[4] & (xp_zp | xm_zp | ymzp | ypzp)
            | faces[5] & (xp_zm | xm_zm | ymzm | ypzm);
        // Bit i of a mask shifted by RING is voxel i of the ring's first block.
        let base = self.side * ((y - RING) / BLOCK + self.side * ((z - RING) / BLOCK));
        for (d, mask) in faces.into_iter().enumerate() {
            let mut m = (mask & valid) >> RING;
            while m != 0 {
                self.blocks[base + m.trailing_zeros() as usize / BLOCK].count[d] += 1;
                m &= m - 1;
            }
        }
        let mut m = (irregular & valid) >> RING;
        while m != 0 {
            let bx = m.trailing_zeros() as usize / BLOCK;
            self.blocks[base + bx].irregular = true;
            m &= !(0xf << (BLOCK * bx));
        }
    }

    /// The brick's exposed voxel faces and their estimated area (voxel units), summed
    /// over its blocks in order.
    fn area(&self) -> (u64, f64) {
        let (first, last) = (1, self.side - 1);
        let mut faces = 0;
        let mut estimate = 0.0;
        for bz in first..last {
            for by in first..last {
                for bx in first..last {
                    let own = self.blocks[bx + self.side * (by + self.side * bz)];
                    let c = [0, 1, 2].map(|a| own.axis(a));
                    let total: u32 = c.iter().sum();
                    if total > 0 {
                        faces += u64::from(total);
                        estimate += self.weighted(c, [bx, by, bz]);
                    }
                }
            }
        }
        (faces, estimate)
    }

    /// The estimated area of faces `c` (by axis) of block `b`, from its window.
    fn weighted(&self, c: [u32; 3], b: [usize; 3]) -> f64 {
        let mut u = [0u32; 3];
        let mut irregular = false;
        for z in b[2] - 1..=b[2] + 1 {
            for y in b[1] - 1..=b[1] + 1 {
                for x in b[0] - 1..=b[0] + 1 {
                    let w = self.blocks[x + self.side * (y + self.side * z)];
                    (0..3).for_each(|a| u[a] += w.axis(a));
                    irregular |= w.irregular;
                }
            }
        }
        if !irregular {
            return f64::from(c[0] + c[1] + c[2]);
        }
        let u = u.map(f64::from);
        let norm = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
        (0..3).map(|a| f64::from(c[a]) * u[a]).sum::<f64>() / norm
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::{VoxelizeOptions, voxelize};
    use crate::shape::Sphere;
    use crate::test_util::Rng;

    /// The estimator of the module doc straight from a dense grid: per block of 4^3
    /// (from the lattice's origin), faces by axis and irregular edges voxel by voxel;
    /// the windows clipped to the domain.
    fn dense_estimate(tree: &LinearOctree) -> (u64, f64) {
        let n = tree.domain().resolution() as i64;
        let mut grid = vec![false; (n * n * n) as usize];
        for node in tree.nodes() {
            let s = i64::from(node.size);
            let m = node.min.map(i64::from);
            for (x, y, z) in (0..s).flat_map(|x| (0..s).flat_map(move |y| (0..s).map(move |z| (x, y, z)))) {
                grid[(m[0] + x + n * (m[1] + y + n * (m[2] + z))) as usize] = true;
            }
        }
        let full =
            |v: [i64; 3]| v.iter().all(|&c| (0..n).contains(&c)) && grid[(v[0] + n * (v[1] + n * v[2])) as usize];
        let nb = (n as usize).div_ceil(BLOCK);
        let block = |v: [i64; 3]| v.map(|c| c as usize / BLOCK);
        let index = |b: [usize; 3]| b[0] + nb * (b[1] + nb * b[2]);
        let mut count = vec![[0u32; 3]; nb * nb * nb];
        let mut irregular = vec![false; nb * nb * nb];
        let step = |v: [i64; 3], axis: usize, by: i64| {
            let mut w = v;
            w[axis] += by;
            w
        };
        for v in (0..n * n * n).map(|i| [i % n, i / n % n, i / (n * n)]).filter(|&v| full(v)) {
            for (axis, by) in [(0, 1), (0, -1), (1, 1), (1, -1), (2, 1), (2, -1)] {
                let w = step(v, axis, by);
                if full(w) {
                    continue;
                }
                count[index(block(v))][axis] += 1;
                for e in (0..3).filter(|&e| e != axis) {
                    if full(step(w, e, 1)) || full(step(w, e, -1)) {
                        irregular[index(block(v))] = true;
                    }
                }
            }
        }
        let (mut faces, mut estimate) = (0, 0.0);
        for (bx, by, bz) in (0..nb).flat_map(|x| (0..nb).flat_map(move |y| (0..nb).map(move |z| (x, y, z)))) {
            let c = count[index([bx, by, bz])];
            if c == [0; 3] {
                continue;
            }
            let (mut u, mut irr) = ([0.0f64; 3], false);
            let around = |b: usize| b.saturating_sub(1)..(b + 2).min(nb);
            for (x, y, z) in around(bx).flat_map(|x| around(by).flat_map(move |y| around(bz).map(move |z| (x, y, z)))) {
                (0..3).for_each(|a| u[a] += f64::from(count[index([x, y, z])][a]));
                irr |= irregular[index([x, y, z])];
            }
            faces += u64::from(c[0] + c[1] + c[2]);
            let norm = (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]).sqrt();
            estimate += if irr {
                (0..3).map(|a| f64::from(c[a]) * u[a]).sum::<f64>() / norm
            } else {
                f64::from(c[0] + c[1] + c[2])
            };
        }
        (faces, estimate)
    }

    #[test]
    fn bricks_rows_and_bulk_give_the_dense_estimate() {
        let mut rng = Rng(11);
        let mut trees = Vec::new();
        for depth in [1u8, 2, 3, 6, 7] {
            let domain = Domain::new(DVec3::new(-1.0, 0.5, 2.0), 3.0, depth).unwrap();
            let res = u64::from(domain.resolution());
            let mut nodes: Vec<Node> = (0..rng.below(12) + 1)
                .map(|_| {
                    let k = rng.below(u64::from(depth)) as u32;
                    let min = [0; 3].map(|_| (rng.below(res >> k) as u32) << k);
                    Node { level: depth - k as u8, min, size: 1 << k }
                })
                .collect();
            nodes.extend((0..rng.below(300)).map(|_| Node {
                level: depth,
                min: [0; 3].map(|_| rng.below(res) as u32),
                size: 1,
            }));
            trees.push(LinearOctree::from_nodes(domain, nodes).unwrap());
            // A ball cut by the domain's faces, and one far inside.
            for (centre, radius) in [(rng.vec(-1.0, 2.0), 1.3), (DVec3::new(0.6, 2.1, 3.4), 0.9)] {
                let ball = Sphere::new(centre, radius).unwrap();
                trees.push(voxelize(&ball, domain, &VoxelizeOptions::default()).unwrap());
            }
        }
        // Big aligned nodes with flat faces counted in bulk, beside ragged ones.
        let domain = Domain::new(DVec3::ZERO, 1.0, 9).unwrap();
        let cube = |min, size| Node { level: 0, min, size };
        let blocks = [cube([0, 0, 0], 256), cube([256, 0, 0], 128), cube([384, 128, 0], 64), cube([0, 256, 256], 256)];
        let ragged = (0..500).map(|i| cube([260 + i % 13, 130 + i / 13 % 7, 70 + i % 11], 1));
        trees.push(LinearOctree::from_nodes(domain, blocks.into_iter().chain(ragged)).unwrap());
        // A ball of brick-sized voxels (depth 3 refined to 9): every boundary brick is
        // measured by its pattern, staircases and concave steps included.
        let coarse = Domain::new(DVec3::ZERO, 1.0, 3).unwrap();
        let ball =
            voxelize(&Sphere::new(DVec3::splat(0.45), 0.4).unwrap(), coarse, &VoxelizeOptions::default()).unwrap();
        let fine = ball.nodes().map(|n| Node { level: n.level, min: n.min.map(|c| c << 6), size: n.size << 6 });
        trees.push(LinearOctree::from_nodes(domain, fine).unwrap());
        for tree in &trees {
            let (faces, estimate) = dense_estimate(tree);
            let area = tree.surface_area();
            let h2 = tree.domain().voxel_size().powi(2);
            assert_eq!(area.voxel_faces, faces as f64 * h2, "{}", tree.domain());
            assert!((area.estimate - estimate * h2).abs() <= 1e-9 * area.estimate, "{}", tree.domain());
            assert!(area.estimate <= area.voxel_faces);
        }
    }
}
