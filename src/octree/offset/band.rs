//! The band of a morphological step: which voxels a ball of radius `D` can change, and
//! the step's entry point (over the cubes, the sparse tiles of [`super::tiles`]; along
//! a surface, the bricks below).
//!
//! A dilation by `D` adds the empty voxels whose centre lies under `D` from a full
//! voxel; an erosion removes the full voxels whose centre lies under `D` from an empty
//! one (voxels outside the domain are empty). Either changes only voxels within `R =
//! ceil(D + 1/2) - 1` voxels on each axis of a voxel of the other phase.
//!
//! Along a surface the domain is cut into aligned bricks of `B = 2^k >= R` voxels (at
//! least 32, at most the domain) and only these bricks are read:
//!
//! - every brick holding a key smaller than a brick (a mixed brick), and the bricks
//!   around it (within `t = ceil(R / B)` bricks, which is one unless the domain is
//!   smaller than `R`);
//! - for each key of a brick or more (a full cube of whole bricks): dilating, the
//!   shell of bricks of thickness `t` outside it; eroding, the shell inside it.
//!
//! Dilating drops the bricks already full, eroding those already empty. A brick is
//! read with its halo ([`LinearOctree::occupancy`]), its squared distances to the
//! other phase computed by [`super::edt`], and the voxels that change are returned as
//! Morton runs. Coarse nodes far from the surface are never read. Bricks are
//! processed in parallel and joined in Morton order, so the result does not depend on
//! the number of threads.
//!
//! Along a surface (the sub-voxel rule of [`super::subvoxel`]) the reach is `ceil(D)`
//! (a voxel whose nearest cube lies `D + 1/2` away can still be under `D` from the
//! surface), a brick is transformed with one voxel more each side (the faces it
//! shares with its neighbours) and one beyond (its sites' own faces), its feature
//! transform names each voxel's nearest site, and the voxels whose lattice distance is
//! within `[D - 1, D + 3/2]` are measured to that site's tangent planes. The result's
//! crossing on a face between `g_full` and `g_empty` is where the distance, linear
//! between the two centres, meets `D` (a site, at `-t |n_axis|` from its old crossing).

use rayon::prelude::*;

use glam::DVec3;

use super::edt::{FAR, Scratch, brick_distances};
use super::step::Step;
use super::subvoxel::{FaceCrossings, NewCrossing, Plane, distance_to_site};
use super::tiles::TileBand;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::morton;
use crate::octree::window::keys_meeting;
use crate::octree::{LinearOctree, NodeKey};
use crate::progress::Progress;

/// Smallest brick edge, as a power of two.
const MIN_BRICK_K: u32 = 5;

/// What a step or a brick of it gives: the Morton runs of the voxels that change, and
/// along a surface the crossings of the result's faces.
pub(super) type Changes = (Vec<(u64, u64)>, Vec<NewCrossing>);

/// The bricks a step along a surface reads and the memory it is estimated to need.
pub(super) struct Band {
    /// Brick edge, as a power of two.
    k: u32,
    /// The reach `R` of the step (see the module doc).
    r: u32,
    /// The bricks to transform, as Morton codes of their corners at brick scale.
    bricks: Vec<u64>,
    /// Estimated peak memory of the step, in bytes.
    pub estimate: u64,
}

impl Band {
    /// The band of `step` along a surface on `tree`, `None` when the step reaches no
    /// voxel.
    pub(super) fn of(tree: &LinearOctree, step: Step) -> Option<Band> {
        let depth = u32::from(tree.depth());
        let r = step.reach_along_surface();
        if r == 0 {
            return None;
        }
        let k = (32 - (r - 1).leading_zeros()).clamp(MIN_BRICK_K, depth.max(1)).min(depth);
        let bricks = band_bricks(tree, k, r, step.grow);
        // A brick is read with one more voxel each side (its faces) and one more beyond
        // (its sites' faces).
        let (b, m) = (1usize << k, (1usize << k) + 2);
        let h = m + 2 * r as usize + 2;
        // Per thread: the halo (1 byte a voxel), the passes' buffers (12 bytes a value
        // with the nearest sites), each voxel's distance and direction (32 bytes); the
        // result: the keys in, the bricks, a boundary layer of keys and crossings a
        // brick face.
        let scratch =
            (h * h * h) as u64 + 12 * (m * h * h + m * m * h + 2 * m * m * m) as u64 + 32 * (m * m * m) as u64;
        let estimate = rayon::current_num_threads() as u64 * scratch
            + 8 * bricks.len() as u64
            + (16 + 24) * 6 * (b * b) as u64 * bricks.len() as u64
            + 3 * tree.bytes() as u64;
        Some(Band { k, r, bricks, estimate })
    }
}

/// `step` over the cubes with a radius no larger than the domain needs: every voxel
/// centre lies within `sqrt 3 n` of every voxel, so radii of `2n + 2` and more all
/// flip the same voxels (and the squared distances stay small).
fn clamped(tree: &LinearOctree, step: Step) -> Step {
    let n = f64::from(tree.domain().resolution());
    Step { radius: step.radius.min(2.0 * n + 2.0), ..step }
}

/// The memory `step` (along a surface when `along_surface`) is estimated to need; 0
/// when it reaches no voxel.
pub(super) fn estimate(tree: &LinearOctree, step: Step, along_surface: bool) -> u64 {
    if along_surface {
        return Band::of(tree, step).map_or(0, |band| band.estimate);
    }
    let step = clamped(tree, step);
    match step.reach() {
        0 => 0,
        r => TileBand::of(tree, step, r).estimate,
    }
}

/// The Morton runs of the voxels of `tree` that `step` changes, sorted, and, along a
/// surface, the crossings of the result's boundary faces in the band from its
/// distance field (in brick order; a face two bricks meet comes twice).
pub(super) fn changed_runs(
    tree: &LinearOctree,
    step: Step,
    surface: Option<&dyn FaceCrossings>,
    budget: MemoryBudget,
    progress: &dyn Progress,
) -> Result<Changes> {
    let Some(surface) = surface else {
        // Over the cubes: the sparse tiles of [`super::tiles`].
        let step = clamped(tree, step);
        let r = step.reach();
        if r == 0 {
            return Ok((Vec::new(), Vec::new()));
        }
        if step.limit() >= i64::from(u32::MAX) {
            return Err(Error::invalid(
                "offset distance",
                format!("{} voxels is more than the band transform holds on this domain", step.radius),
            ));
        }
        let band = TileBand::of(tree, step, r);
        budget.check(format!("offset by {} voxels", step.radius), band.estimate)?;
        return Ok((band.changed_runs(tree, step, step.limit(), progress), Vec::new()));
    };
    let Some(Band { k, r, bricks, estimate }) = Band::of(tree, step) else {
        return Ok((Vec::new(), Vec::new()));
    };
    budget.check(format!("offset by {} voxels", step.radius), estimate)?;
    progress.start(bricks.len() as u64);
    let parts: Vec<Changes> = bricks
        .par_iter()
        .map_init(
            || (Scratch::default(), Vec::new(), Vec::new()),
            |(scratch, dist, nearest), &brick| {
                let part = brick_along_surface(tree, brick, k, r, step, surface, scratch, dist, nearest);
                progress.advance(1);
                part
            },
        )
        .collect();
    progress.finish();
    let crossings = parts.iter().map(|p| p.1.len()).sum();
    let (mut runs, mut faces) = (Vec::new(), Vec::with_capacity(crossings));
    for (r, f) in parts {
        runs.extend(r);
        faces.extend(f);
    }
    Ok((runs, faces))
}

/// The voxels of brick `brick` that `step` changes along `surface`, by the sub-voxel
/// rule of [`super::subvoxel`], as Morton runs, and the crossings of the result's
/// faces that touch the brick (interpolated where the distance field meets the radius;
/// see the module doc).
#[allow(clippy::too_many_arguments)]
fn brick_along_surface(
    tree: &LinearOctree,
    brick: u64,
    k: u32,
    r: u32,
    step: Step,
    surface: &dyn FaceCrossings,
    scratch: &mut Scratch,
    dist: &mut Vec<i64>,
    nearest: &mut Vec<u32>,
) -> Changes {
    let (b, grow, radius) = (1usize << k, step.grow, step.radius);
    // The region: the brick and one voxel each side; its halo: the reach and one more.
    let (m, o) = (b + 2, r as usize + 1);
    let h = m + 2 * o;
    let min = morton::decode(brick).map(|c| i64::from(c << k));
    let lo = min.map(|c| c - 1 - o as i64);
    let full = tree.occupancy(lo, h as u32);
    let site: Vec<bool> = if grow { full } else { full.into_iter().map(|f| !f).collect() };
    if !site.contains(&true) {
        return (Vec::new(), Vec::new());
    }
    // Values over this are never read: a voxel that flips lies under `radius + 1/2`
    // from its nearest cube, and a face's far end one voxel farther.
    let cap = (2.0 * radius + 3.0).powi(2).ceil().min(1e18) as i64;
    brick_distances(&site, m, o, cap, scratch, dist, Some(nearest));
    let n = i64::from(tree.domain().resolution());
    let window = |c: [usize; 3]| c[0] + h * (c[1] + h * c[2]);
    let crossing = |voxel: [i64; 3], direction: u8| {
        let code = morton::encode(voxel[0] as u32, voxel[1] as u32, voxel[2] as u32);
        let (t, normal) = surface.face_crossing(code, direction).unwrap_or_else(|| {
            let mut axis = [0.0; 3];
            axis[usize::from(direction / 2)] = if direction & 1 == 1 { 1.0 } else { -1.0 };
            (0.5, axis)
        });
        (f64::from(t), DVec3::from(normal.map(f64::from)))
    };
    // Four times the squared lattice distance where the sub-voxel distance is needed:
    // it lies within [d_cube - 1/2, d_cube + sqrt 3 / 2], and a face's far end is a
    // voxel farther.
    let exact_lo = if radius > 1.0 { (2.0 * radius - 2.0).powi(2) } else { 0.0 };
    let exact_hi = (2.0 * radius + 3.0).powi(2);
    // The distance of each voxel of the region (a site: minus infinity) and the
    // direction from its foot point on the surface.
    let mut g = vec![f64::INFINITY; m * m * m];
    let mut away = vec![DVec3::ZERO; m * m * m];
    let mut planes: Vec<Plane> = Vec::with_capacity(6);
    for z in 0..m {
        for y in 0..m {
            for x in 0..m {
                let i = x + m * (y + m * z);
                let p = [x + o, y + o, z + o];
                if site[window(p)] {
                    g[i] = f64::NEG_INFINITY;
                    continue;
                }
                let cost = dist[i];
                if cost >= FAR {
                    continue;
                }
                let c = cost as f64;
                let d_cube = c.sqrt() / 2.0;
                if c >= exact_hi {
                    g[i] = d_cube - 0.5;
                    continue;
                }
                if c < exact_lo {
                    g[i] = d_cube;
                    continue;
                }
                let s = nearest[i] as usize;
                let sc = [s % h, s / h % h, s / (h * h)];
                let rel =
                    DVec3::new(sc[0] as f64 - p[0] as f64, sc[1] as f64 - p[1] as f64, sc[2] as f64 - p[2] as f64);
                planes.clear();
                for direction in 0..6u8 {
                    let (axis, positive) = (usize::from(direction / 2), direction & 1 == 1);
                    let mut nc = sc;
                    if positive {
                        nc[axis] += 1;
                    } else if nc[axis] == 0 {
                        continue;
                    } else {
                        nc[axis] -= 1;
                    }
                    if nc[axis] >= h || site[window(nc)] {
                        continue;
                    }
                    let mut e = DVec3::ZERO;
                    e[axis] = if positive { 1.0 } else { -1.0 };
                    let lattice = |c: [usize; 3]| -> [i64; 3] { std::array::from_fn(|a| lo[a] + c[a] as i64) };
                    let plane = if grow {
                        let (t, normal) = crossing(lattice(sc), direction);
                        Plane { point: rel + e * t, normal }
                    } else {
                        // The face belongs to the full neighbour, seen from its side.
                        let (t, normal) = crossing(lattice(nc), direction ^ 1);
                        Plane { point: rel + e * (1.0 - t), normal: -normal }
                    };
                    planes.push(plane);
                }
                let (d, foot) = distance_to_site(&planes, d_cube);
                g[i] = d;
                away[i] = -foot;
            }
        }
    }
    let flips = |i: usize| g[i] > f64::NEG_INFINITY && g[i] < radius;
    let mut runs: Vec<(u64, u64)> = Vec::new();
    let base = brick << (3 * k);
    for code in 0..(b * b * b) as u64 {
        let [x, y, z] = morton::decode(code).map(|c| c as usize + 1);
        if flips(x + m * (y + m * z)) {
            let code = base + code;
            match runs.last_mut() {
                Some(last) if last.1 == code => last.1 = code + 1,
                _ => runs.push((code, code + 1)),
            }
        }
    }
    // The result's faces that touch the brick: voxel `v` and `v + e_axis`, the first
    // from one voxel before the brick, both inside the domain.
    let result_full = |i: usize| if g[i] == f64::NEG_INFINITY { grow } else { flips(i) == grow };
    let mut faces = Vec::new();
    for axis in 0..3 {
        let stride = [1, m, m * m][axis];
        for z in 0..m {
            for y in 0..m {
                for x in 0..m {
                    let v = [x, y, z];
                    if (0..3).any(|a| if a == axis { v[a] > b } else { v[a] == 0 || v[a] > b }) {
                        continue;
                    }
                    let lattice: [i64; 3] = std::array::from_fn(|a| min[a] - 1 + v[a] as i64);
                    if lattice.iter().any(|&c| c < 0 || c >= n) || lattice[axis] + 1 >= n {
                        continue;
                    }
                    let (i, j) = (x + m * (y + m * z), x + m * (y + m * z) + stride);
                    let (fi, fj) = (result_full(i), result_full(j));
                    if fi == fj {
                        continue;
                    }
                    let (f, e, direction) = if fi { (i, j, 2 * axis as u8 + 1) } else { (j, i, 2 * axis as u8) };
                    let mut fv = lattice;
                    if !fi {
                        fv[axis] += 1;
                    }
                    // A site's value: minus its distance to the original crossing
                    // between the two, along the normal.
                    let value = |at: usize| {
                        if g[at] > f64::NEG_INFINITY {
                            return g[at];
                        }
                        let (t, normal) = crossing(fv, direction);
                        let along = if at == f { t } else { 1.0 - t };
                        -along * normal[axis].abs()
                    };
                    let (gf, ge) = (value(f), value(e));
                    let t = if grow { (radius - gf) / (ge - gf) } else { (gf - radius) / (gf - ge) };
                    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.5 };
                    // The normal: the direction from the foot point (to the voxel
                    // growing, from it shrinking) of the end whose direction is the
                    // nearer the face's own (the other end may have a different
                    // surface nearest, as an edge voxel has two faces equally near).
                    let mut axis_normal = DVec3::ZERO;
                    axis_normal[axis] = if fi { 1.0 } else { -1.0 };
                    let sign = if grow { 1.0 } else { -1.0 };
                    let normal = [f, e]
                        .into_iter()
                        .map(|at| away[at] * sign)
                        .filter(|a| a.length_squared() > 1e-18)
                        .map(DVec3::normalize)
                        .max_by(|a, b| a.dot(axis_normal).total_cmp(&b.dot(axis_normal)))
                        .unwrap_or(axis_normal)
                        .as_vec3()
                        .to_array();
                    let voxel = morton::encode(fv[0] as u32, fv[1] as u32, fv[2] as u32);
                    faces.push(NewCrossing { voxel, direction, t: t as f32, normal });
                }
            }
        }
    }
    (runs, faces)
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
