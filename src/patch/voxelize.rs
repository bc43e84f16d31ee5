//! Patch sets to octrees: the surface directly by adaptive subdivision, the solid
//! through a fine tessellation and the winding rule.
//!
//! Surface: a node keeps the pieces of patch whose control-point boxes meet it; a piece
//! larger than the node is split in four first (de Casteljau at 1/2), so pieces shrink
//! with the nodes. At a voxel, pieces are split until their boxes have a diagonal under
//! half a voxel, and the voxel is kept when one of them meets it. Every surface point
//! lies in a kept voxel (its piece's box contains it), and every kept voxel lies within
//! half a voxel of the surface (a piece's box of diagonal under h/2 meets it). The walk
//! is the octree driver's ([`crate::octree`]); a node hands its pieces to each of its
//! children. Memory: [`estimate_surface_bytes`].

use std::sync::Arc;

use glam::DVec2;

use super::BezierPatch;
use crate::aabb::Aabb;
use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::mesh::TriangleMesh;
use crate::morton;
use crate::octree::{Decision, Domain, LinearOctree, NodeKey, PARALLEL_LEVELS, Plan, VoxelizeOptions, Voxelizer};

/// The voxels the patch surfaces pass through, each within half a voxel of a surface.
///
/// Refuses (before any work) when the estimated peak memory ([`estimate_surface_bytes`])
/// exceeds `options.budget`; reports progress to `options.progress`.
pub fn voxelize_patch_surface(
    patches: &[BezierPatch],
    domain: Domain,
    options: &VoxelizeOptions,
) -> Result<LinearOctree> {
    let plan = Plan::new("voxelizing a patch surface", estimate_surface_bytes(patches, &domain), domain, options)?;
    Ok(plan.run(&PatchSurface { domain }, Arc::new(patches.to_vec()))?.0)
}

/// Pieces a node is taken to hold in [`estimate_surface_bytes`] (its parent's pieces,
/// each no larger than the parent and meeting it), away from collapsed patch sides.
const PIECES_A_NODE: f64 = 16.0;

/// Estimated peak bytes of the surface voxelization of `patches` in `domain`:
///
/// ```text
/// bytes = 16 V + 384 (16 (N + 2 (depth + 1) T) + 4 Z E) + 4096
/// V = sum over patches of (3 a + 2 p + 1)
/// N = sum over levels l <= PARALLEL_LEVELS of
///     min(8^l, sum over patches of (3 a / s^2 + 2 p / s + 1)),  s = 2^(depth - l)
/// ```
///
/// with `a` a patch's area in voxel faces and `p` its perimeter in voxels, both from
/// an 8 x 8 grid of its points (chords: a little under the true values).
///
/// - `16 V`: the surface voxels. A kept voxel meets a box of diagonal under `h/2`
///   round the surface, so the shell is about `|n|_1 + 1 <= 2.8` voxels thick, taken
///   as 3, plus a band along the patch edges and the voxel a small patch lies in; a
///   key is 8 bytes, doubled for the per-task buffers joined at the end.
/// - The rest is the pieces (a patch is 384 bytes). A node's pieces, about 16
///   (`PIECES_A_NODE`), are shared by its children until the last one starts, and
///   the running child works on its own copy. The lists alive at once are those of the
///   nodes meeting the surface on levels 0 to `PARALLEL_LEVELS`, which wait for their
///   parallel tasks (`N`: the cell count of `V` at the node size, capped by the number
///   of nodes), and, below them, two a level on the path of each running subtree, one
///   a thread (`T`, the threads of the pool it runs on: the lists grow with the
///   threads, the voxels do not).
/// - `4 Z E`: a patch side shorter than a voxel (collapsed to a point, as the
///   teapot's lid and bottom) splits into slivers that all meet the nodes at that
///   point, about `E / s` of them at node size `s` (`E`: the largest patch extent in
///   voxels); the path to such a point holds two such lists a level, `4 E` pieces
///   over the levels. `Z` counts those sides.
///
/// Clamped to `u64::MAX`.
#[must_use]
pub fn estimate_surface_bytes(patches: &[BezierPatch], domain: &Domain) -> u64 {
    let h = domain.voxel_size();
    let (area, perimeter) = patches
        .iter()
        .map(|p| area_and_perimeter(p, 8))
        .fold((0.0, 0.0), |(a, p), (b, q)| (a + b / (h * h), p + q / h));
    let count = patches.len() as f64;
    let voxels = 3.0 * area + 2.0 * perimeter + count;
    let depth = i32::from(domain.depth());
    let top: f64 = (0..=i32::from(PARALLEL_LEVELS))
        .map(|l| {
            let s = 2f64.powi(depth - l);
            (3.0 * area / (s * s) + 2.0 * perimeter / s + count).min(8f64.powi(l))
        })
        .sum();
    let threads = rayon::current_num_threads() as f64;
    let lists = top + 2.0 * f64::from(domain.depth() + 1) * threads;
    let extent = patches.iter().map(|p| p.bounds().size().max_element()).fold(0.0, f64::max) / h;
    let collapsed = patches.iter().map(|p| collapsed_sides(p, h)).sum::<usize>() as f64;
    let pieces = PIECES_A_NODE * lists + 4.0 * collapsed * extent;
    let piece = std::mem::size_of::<BezierPatch>() as f64;
    (16.0 * voxels + piece * pieces + 4096.0).min(u64::MAX as f64) as u64
}

/// The sides of `patch` whose four control points lie within `h` of each other.
fn collapsed_sides(patch: &BezierPatch, h: f64) -> usize {
    let q = &patch.p;
    let sides = [q[0], q[3], std::array::from_fn(|i| q[i][0]), std::array::from_fn(|i| q[i][3])];
    sides.iter().filter(|side| side.iter().all(|c| c.distance(side[0]) < h)).count()
}

/// Area and perimeter of the `n x n` grid of points of `patch`.
fn area_and_perimeter(patch: &BezierPatch, n: u32) -> (f64, f64) {
    let at = |i: u32, j: u32| patch.eval(f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
    let mut area = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            area += 0.5 * ((b - a).cross(c - a).length() + (c - a).cross(d - a).length());
        }
    }
    let perimeter = (0..n)
        .map(|k| {
            at(k, 0).distance(at(k + 1, 0))
                + at(k, n).distance(at(k + 1, n))
                + at(0, k).distance(at(0, k + 1))
                + at(n, k).distance(at(n, k + 1))
        })
        .sum();
    (area, perimeter)
}

/// One patch-surface voxelization's fixed input.
struct PatchSurface {
    domain: Domain,
}

impl Voxelizer for PatchSurface {
    /// The parent's pieces (the patches at the root), shared by the eight children;
    /// each copies them when it starts (the last one takes them), so one copy is
    /// alive at a time on a path, as in a plain recursion.
    type Node = Arc<Vec<BezierPatch>>;
    type Counters = ();

    // Inlined into the driver's walk (callgrind, the teapot's surface at depth 8 on one
    // thread: 3.020 G instructions called, 2.987 G inlined).
    #[inline(always)]
    fn decide(&self, key: NodeKey, pieces: Self::Node, _: &mut ()) -> Decision<Self::Node> {
        let pieces = Arc::try_unwrap(pieces).unwrap_or_else(|shared| shared.as_ref().clone());
        let mine = self.pieces_meeting(key, pieces);
        if mine.is_empty() {
            Decision::Empty
        } else if key.k() == 0 {
            Decision::Full
        } else {
            let mine = Arc::new(mine);
            Decision::Split(std::array::from_fn(|_| Arc::clone(&mine)))
        }
    }
}

impl PatchSurface {
    /// The pieces of `pieces` that meet the node `key`, split until they are no larger
    /// than the node (at a voxel: until their diagonal is under `h/2`, and one is enough).
    fn pieces_meeting(&self, key: NodeKey, pieces: Vec<BezierPatch>) -> Vec<BezierPatch> {
        let d = &self.domain;
        let size = 1u32 << key.k();
        let b = d.cube_box(morton::decode(key.start()), size);
        // Pieces may not be larger than the node; at a voxel, their diagonal < h/2.
        let limit = if key.k() == 0 { 0.5 * d.voxel_size() } else { f64::from(size) * d.voxel_size() };
        let meets = |a: &Aabb| a.min.cmple(b.max).all() && a.max.cmpge(b.min).all();
        let mut mine = Vec::new();
        let mut stack = pieces;
        while let Some(p) = stack.pop() {
            let pb = p.bounds();
            if !meets(&pb) {
                continue;
            }
            let too_big = if key.k() == 0 { pb.size().length() >= limit } else { pb.size().max_element() > limit };
            if too_big {
                stack.extend(p.split4());
            } else {
                mine.push(p);
                if key.k() == 0 {
                    break; // one piece is enough to keep the voxel
                }
            }
        }
        mine
    }
}

/// Estimated peak bytes of [`tessellate`]`(patches, n)` for `patches` patches:
///
/// ```text
/// bytes = patches * (92 V + 12 T),  V = (n + 1)^2,  T = 2 n^2
/// ```
///
/// A grid vertex is 24 bytes, held twice while welding, with a 4-byte remap entry
/// and a hash entry of about 40 bytes; a triangle is 12 bytes. A patch file is a few
/// hundred bytes a patch and its tessellation up to 2 MB a patch at `n = 128`, so
/// this is checked before tessellating. Saturates at `u64::MAX`.
#[must_use]
pub fn estimate_tessellation_bytes(patches: usize, n: u32) -> u64 {
    let n = u64::from(n.max(1));
    let per_patch = 92 * (n + 1) * (n + 1) + 12 * 2 * n * n;
    (patches as u64).saturating_mul(per_patch)
}

/// [`tessellate`], refused (before any work) when [`estimate_tessellation_bytes`]
/// exceeds `budget`.
pub fn tessellate_within(patches: &[BezierPatch], n: u32, budget: MemoryBudget) -> Result<TriangleMesh> {
    budget.check("tessellating patches", estimate_tessellation_bytes(patches.len(), n))?;
    Ok(tessellate(patches, n))
}

/// Triangles on an `n x n` grid of every patch, welded, oriented so the enclosed
/// signed volume is positive (the winding rule then reads 1 inside).
#[must_use]
pub fn tessellate(patches: &[BezierPatch], n: u32) -> TriangleMesh {
    tessellate_with_params(patches, n).0
}

/// Where a triangle of a tessellation lies on its patches: the patch's index and the
/// `(u, v)` of each corner, in the triangle's corner order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleParams {
    /// Index of the patch the triangle was cut from.
    pub patch: u32,
    /// Each corner's `(u, v)` on that patch.
    pub uv: [DVec2; 3],
}

/// [`tessellate`], with each triangle's patch and its corners' parameters.
#[must_use]
pub fn tessellate_with_params(patches: &[BezierPatch], n: u32) -> (TriangleMesh, Vec<TriangleParams>) {
    let n = n.max(1);
    let mut mesh = TriangleMesh::default();
    let mut params = Vec::new();
    let uv = |i: u32, j: u32| DVec2::new(f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
    for (index, patch) in patches.iter().enumerate() {
        let base = mesh.vertices.len() as u32;
        for i in 0..=n {
            for j in 0..=n {
                let [u, v] = uv(i, j).to_array();
                mesh.vertices.push(patch.eval(u, v));
            }
        }
        let at = |i: u32, j: u32| base + i * (n + 1) + j;
        let patch = index as u32;
        for i in 0..n {
            for j in 0..n {
                mesh.triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                params.push(TriangleParams { patch, uv: [uv(i, j), uv(i + 1, j), uv(i + 1, j + 1)] });
                mesh.triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
                params.push(TriangleParams { patch, uv: [uv(i, j), uv(i + 1, j + 1), uv(i, j + 1)] });
            }
        }
    }
    mesh.weld();
    // Drop triangles that collapsed where a patch degenerates to a point (the lid's top).
    let collapsed = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
    let keep: Vec<bool> = mesh.triangles.iter().map(|t| !collapsed(t)).collect();
    let mut k = keep.iter();
    mesh.triangles.retain(|_| *k.next().expect("one flag a triangle"));
    let mut k = keep.iter();
    params.retain(|_| *k.next().expect("one flag a triangle"));
    let volume: f64 = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            a.dot(b.cross(c))
        })
        .sum();
    if volume < 0.0 {
        mesh.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        params.iter_mut().for_each(|p| p.uv.swap(1, 2));
    }
    (mesh, params)
}

/// Segments a patch side needs so the tessellation's chords stay within `tolerance`
/// of the surface for a patch of extent `extent` (a conservative rule of thumb).
#[must_use]
pub fn segments_for(extent: f64, tolerance: f64) -> u32 {
    ((extent / tolerance.max(1e-12)).sqrt() * 2.0).ceil().clamp(4.0, 128.0) as u32
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::patch::read_patches;

    fn domain(patches: &[BezierPatch], depth: u8) -> Domain {
        let b = patches.iter().map(BezierPatch::bounds).reduce(|a, b| a.union(&b)).expect("patches");
        Domain::around(&b, 0.02, depth).unwrap()
    }

    #[test]
    fn estimate_covers_the_keys_made_and_is_within_a_few_times_them_for_large_patches() {
        let teapot = read_patches("models/teapot.patches").unwrap();
        // One patch tilted across all three axes, its odd control rows lifted.
        let p = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let (u, v) = (i as f64 / 3.0, j as f64 / 3.0);
                DVec3::new(u, v, 0.5 * (u + v) + 0.1 * (i % 2) as f64)
            })
        });
        let one = vec![BezierPatch { p }];
        for (name, patches) in [("teapot", &teapot), ("one patch", &one)] {
            for depth in [4, 6, 8, 9] {
                let d = domain(patches, depth);
                let keys = 16 * voxelize_patch_surface(patches, d, &VoxelizeOptions::default()).unwrap().voxel_count();
                // The lists' term grows with the threads: counted for two.
                let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
                let estimate = two.install(|| estimate_surface_bytes(patches, &d));
                assert!(estimate >= keys, "{name} at depth {depth}: {estimate} < {keys}");
                if depth == 9 {
                    assert!(estimate < 6 * keys, "{name} at depth {depth}: {estimate} vs {keys}");
                }
            }
        }
        // The teapot's lid and bottom close in four patch sides each.
        assert_eq!(teapot.iter().map(|p| collapsed_sides(p, domain(&teapot, 9).voxel_size())).sum::<usize>(), 8);
    }
}
