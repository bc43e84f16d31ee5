//! The band of a morphological step: the bricks of voxels whose phase a ball of radius
//! `D` can change, each transformed exactly with a halo read from the octree.
//!
//! A dilation by `D` adds the empty voxels whose centre lies under `D` from a full
//! voxel; an erosion removes the full voxels whose centre lies under `D` from an empty
//! one (voxels outside the domain are empty). Either changes only voxels within `R =
//! ceil(D + 1/2) - 1` voxels on each axis of a voxel of the other phase, so the domain is cut into aligned bricks of `B = 2^k >= R` voxels (at
//! least 32, at most the domain) and only these bricks are read:
//!
//! - every brick holding a key smaller than a brick (a mixed brick), and the bricks
//!   around it (within `t = ceil(R / B)` bricks, which is one unless the domain is
//!   smaller than `R`);
//! - for each key of a brick or more (a full cube of whole bricks): dilating, the
//!   shell of bricks of thickness `t` outside it; eroding, the shell inside it.
//!
//! Dilating drops the bricks already full, eroding those already empty. A brick is
//! read with its halo of `R` voxels ([`LinearOctree::occupancy`]), its squared
//! distances to the other phase computed by [`super::edt`], and the voxels that change
//! are returned as Morton runs. Coarse nodes far from the surface are never read:
//! memory and time follow the band's bricks (`(B + 2R)^3` voxels each), not the domain.
//! Bricks are processed in parallel and joined in Morton order, so the result does not
//! depend on the number of threads.

use rayon::prelude::*;

use super::edt::{Scratch, brick_distances};
use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::morton;
use crate::octree::window::keys_meeting;
use crate::octree::{LinearOctree, NodeKey};
use crate::progress::Progress;

/// Smallest brick edge, as a power of two.
const MIN_BRICK_K: u32 = 5;

/// One morphological step: grow (dilate) or shrink (erode) by a ball.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Step {
    /// The ball's radius in voxels (between voxel centres), positive.
    pub radius: f64,
    /// Dilation (add empty voxels near full ones) or erosion (the reverse).
    pub grow: bool,
}

impl Step {
    /// `R`: the most voxels a step can reach along one axis (a voxel `o` voxels away
    /// is `|o| - 1/2` away, which must be under the radius).
    fn reach(self) -> u32 {
        ((self.radius + 0.5).ceil() - 1.0).clamp(0.0, f64::from(u32::MAX / 4)) as u32
    }

    /// A voxel changes when four times its squared distance is at most this (strictly
    /// under `4 radius^2`).
    fn limit(self) -> i64 {
        ((4.0 * self.radius * self.radius).ceil() - 1.0).min(1e18) as i64
    }
}

/// The Morton runs of the voxels of `tree` that `step` changes, sorted.
pub(super) fn changed_runs(
    tree: &LinearOctree,
    step: Step,
    budget: MemoryBudget,
    progress: &dyn Progress,
) -> Result<Vec<(u64, u64)>> {
    let depth = u32::from(tree.depth());
    let r = step.reach();
    if r == 0 {
        return Ok(Vec::new());
    }
    let k = (32 - (r - 1).leading_zeros()).clamp(MIN_BRICK_K, depth.max(1)).min(depth);
    let bricks = band_bricks(tree, k, r, step.grow);
    let (b, h) = (1usize << k, (1usize << k) + 2 * r as usize);
    // Per thread: the halo (1 byte a voxel) and the passes' buffers (8 bytes a value);
    // the result: the keys in, the bricks, and a boundary layer of keys a brick face.
    let scratch = (h * h * h) as u64 + 8 * (b * h * h + b * b * h + b * b * b) as u64;
    let estimate = rayon::current_num_threads() as u64 * scratch
        + 8 * bricks.len() as u64
        + 16 * 6 * (b * b) as u64 * bricks.len() as u64
        + 3 * tree.bytes() as u64;
    budget.check(format!("offset by {} voxels", step.radius), estimate)?;
    progress.start(bricks.len() as u64);
    let limit = step.limit();
    let runs: Vec<Vec<(u64, u64)>> = bricks
        .par_iter()
        .map_init(
            || (Scratch::default(), Vec::new()),
            |(scratch, dist), &brick| {
                let runs = brick_changes(tree, brick, k, r, step.grow, limit, scratch, dist);
                progress.advance(1);
                runs
            },
        )
        .collect();
    progress.finish();
    Ok(runs.into_iter().flatten().collect())
}

/// The Morton runs of the voxels of brick `brick` (Morton code of its brick
/// coordinates, bricks of `2^k`) that the step changes.
#[allow(clippy::too_many_arguments)]
fn brick_changes(
    tree: &LinearOctree,
    brick: u64,
    k: u32,
    r: u32,
    grow: bool,
    limit: i64,
    scratch: &mut Scratch,
    dist: &mut Vec<i64>,
) -> Vec<(u64, u64)> {
    let b = 1usize << k;
    let h = b + 2 * r as usize;
    let min = morton::decode(brick).map(|c| c << k);
    let lo = min.map(|c| i64::from(c) - i64::from(r));
    let full = tree.occupancy(lo, h as u32);
    // Sites: the phase the step spreads (full voxels when growing, empty ones else).
    let site: Vec<bool> = if grow { full } else { full.into_iter().map(|f| !f).collect() };
    if !site.contains(&true) {
        return Vec::new();
    }
    brick_distances(&site, b, r as usize, scratch, dist);
    let mut runs: Vec<(u64, u64)> = Vec::new();
    let base = brick << (3 * k);
    for i in 0..(b * b * b) as u64 {
        let [x, y, z] = morton::decode(i).map(|c| c as usize);
        let d = dist[x + b * (y + b * z)];
        // A site is at distance 0: it keeps its phase; another voxel within reach flips.
        if d > 0 && d <= limit {
            let code = base + i;
            match runs.last_mut() {
                Some(last) if last.1 == code => last.1 = code + 1,
                _ => runs.push((code, code + 1)),
            }
        }
    }
    runs
}

/// The bricks of `2^k` voxels a step of reach `r` must read, as the sorted Morton codes
/// of their brick coordinates (see the module doc).
fn band_bricks(tree: &LinearOctree, k: u32, r: u32, grow: bool) -> Vec<u64> {
    let keys = tree.keys();
    let n = (tree.domain().resolution() >> k) as i64;
    let t = i64::from(r.div_ceil(1 << k));
    let mut bricks: Vec<u64> = keys
        .par_chunks(4096)
        .flat_map_iter(|chunk| {
            let mut out = Vec::new();
            let mut last_mixed = u64::MAX;
            for key in chunk {
                let min = morton::decode(key.start()).map(|c| i64::from(c >> k));
                if key.k() < k {
                    let brick = key.start() >> (3 * k);
                    if brick != last_mixed {
                        last_mixed = brick;
                        push_shell(&mut out, [min.map(|c| c - t), min.map(|c| c + 1 + t)], None, n);
                    }
                } else {
                    let size = 1i64 << (key.k() - k);
                    let cube = [min, min.map(|c| c + size)];
                    if grow {
                        push_shell(&mut out, [min.map(|c| c - t), min.map(|c| c + size + t)], Some(cube), n);
                    } else {
                        // Within `t` bricks of the cube's outside: not in the cube shrunk by `t`.
                        push_shell(&mut out, cube, Some([min.map(|c| c + t), min.map(|c| c + size - t)]), n);
                    }
                }
            }
            out
        })
        .collect();
    bricks.par_sort_unstable();
    bricks.dedup();
    bricks.retain(|&brick| {
        let cube = NodeKey::new(brick << (3 * k), k);
        match keys_meeting(keys, cube) {
            [] => grow,
            [key] if key.k() >= k => !grow,
            _ => true,
        }
    });
    bricks
}

/// Pushes the brick codes of the box `[lo, hi)` (clipped to `0..n`) outside the box
/// `hole`, whose rows are jumped over, not visited brick by brick.
fn push_shell(out: &mut Vec<u64>, [lo, hi]: [[i64; 3]; 2], hole: Option<[[i64; 3]; 2]>, n: i64) {
    let (lo, hi) = (lo.map(|c| c.max(0)), hi.map(|c| c.min(n)));
    let hole = hole.filter(|[a, b]| (0..3).all(|i| a[i] < b[i]));
    for z in lo[2]..hi[2] {
        for y in lo[1]..hi[1] {
            let gap = hole.filter(|[a, b]| (a[1]..b[1]).contains(&y) && (a[2]..b[2]).contains(&z));
            let mut x = lo[0];
            while x < hi[0] {
                if let Some([a, b]) = gap
                    && (a[0]..b[0]).contains(&x)
                {
                    x = b[0];
                    continue;
                }
                out.push(morton::encode(x as u32, y as u32, z as u32));
                x += 1;
            }
        }
    }
}
