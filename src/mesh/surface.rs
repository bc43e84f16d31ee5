//! Surface (shell) voxelization of triangle meshes.
//!
//! - [`SurfaceKind::Conservative`]: every voxel a triangle touches (exact
//!   separating-axis test): 26-separating, a thick shell.
//! - [`SurfaceKind::Thin`]: the voxels whose centre cross (the three axis-parallel
//!   segments of one voxel length through the centre) a triangle meets. It is
//!   6-separating: a 6-connected path of voxels that crosses the surface steps along
//!   those segments, so it meets the surface on some voxel's cross, and that voxel is
//!   in the set. It is about a third as thick as the conservative shell.
//!
//! Walk: the octree driver's ([`crate::octree`]), top down; a node is handed the
//! triangles that overlap its box (exact separating-axis test, made by the parent for
//! each child), and a node with none is empty. Memory: [`estimate_surface_bytes`].

use glam::DVec3;
use smallvec::SmallVec;

use super::TriangleMesh;
use super::tri_box::triangle_box_overlap;
use crate::aabb::Aabb;
use crate::error::Result;
use crate::morton;
use crate::octree::{Decision, Domain, LinearOctree, NodeKey, Plan, VoxelizeOptions, Voxelizer};

/// Which surface voxels to keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceKind {
    /// Every voxel the surface touches.
    Conservative,
    /// A thin, 6-separating shell.
    Thin,
}

/// Voxelizes the surface of `mesh` (no inside).
///
/// Refuses (before any work) when the estimated peak memory ([`estimate_surface_bytes`])
/// exceeds `options.budget`; reports progress to `options.progress`.
pub fn voxelize_surface(
    mesh: &TriangleMesh,
    domain: Domain,
    kind: SurfaceKind,
    options: &VoxelizeOptions,
) -> Result<LinearOctree> {
    mesh.validate()?;
    let plan = Plan::new("voxelizing a mesh surface", estimate_surface_bytes(mesh, &domain), domain, options)?;
    let job = Surface { mesh, domain, kind };
    let all: Vec<u32> = (0..mesh.triangles.len() as u32).collect();
    let root = job.meeting(&all, &domain.cube_box([0; 3], domain.resolution()));
    Ok(plan.run(&job, root)?.0)
}

/// Estimated peak bytes of the surface voxelization of `mesh` in `domain`:
///
/// ```text
/// bytes = 16 V + 4 L + 4096
/// V = sum over triangles of (2 a + 2 p + 1)
/// L = sum over triangles of (8/3 a + 4 p + depth + 1)
/// ```
///
/// with `a` a triangle's area in voxel faces (`area / h^2`) and `p` its perimeter in
/// voxels. `V` counts the surface voxels: a plane meets about `|n|_1 <= sqrt(3)` unit
/// cells a unit of area, taken as 2 (a triangle on a lattice plane touches the two
/// layers beside it), plus a band of about two cells a unit of edge and the cell a
/// small triangle lies in. A key is 8 bytes, doubled for the per-task buffers joined
/// at the end. `L` counts the candidate lists: the same count of cells a triangle
/// meets, with cells the node size `s` at every level (`a / s^2 + ...`), summed over
/// the levels `s = 1, 2, 4, ...` (geometric: `4/3` of the area term, twice the edge
/// term, one cell a level): every (triangle, node) pair the walk ever makes, so more
/// than the lists alive at once, at 4 bytes an entry. Clamped to `u64::MAX`.
#[must_use]
pub fn estimate_surface_bytes(mesh: &TriangleMesh, domain: &Domain) -> u64 {
    let h = domain.voxel_size();
    let levels = f64::from(domain.depth()) + 1.0;
    let (mut voxels, mut lists) = (0.0, 0.0);
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let area = 0.5 * (b - a).cross(c - a).length() / (h * h);
        let perimeter = (a.distance(b) + b.distance(c) + c.distance(a)) / h;
        voxels += 2.0 * area + 2.0 * perimeter + 1.0;
        lists += 8.0 / 3.0 * area + 4.0 * perimeter + levels;
    }
    (16.0 * voxels + 4.0 * lists + 4096.0).min(u64::MAX as f64) as u64
}

/// One surface voxelization's fixed inputs.
struct Surface<'a> {
    mesh: &'a TriangleMesh,
    domain: Domain,
    kind: SurfaceKind,
}

impl Voxelizer for Surface<'_> {
    /// The triangles overlapping the node. Lists near the voxels hold a few, and the
    /// eight of a split node are moved together: four inline are the cheapest
    /// (callgrind, Spot at depth 8 `--fill thin` on one thread: 644 M instructions
    /// with 16 inline, 641 M with 8, 637 M with 4).
    type Node = SmallVec<[u32; 4]>;
    type Counters = ();

    fn decide(&self, key: NodeKey, mine: Self::Node, _: &mut ()) -> Decision<Self::Node> {
        // Step 1: no triangle overlaps the node.
        if mine.is_empty() {
            return Decision::Empty;
        }
        let min = morton::decode(key.start());
        // Step 2: a voxel with triangles is kept (conservative), or kept when one of
        // them meets its centre cross (thin).
        if key.k() == 0 {
            let keep = match self.kind {
                SurfaceKind::Conservative => true,
                SurfaceKind::Thin => {
                    let b = self.domain.cube_box(min, 1);
                    let (c, half) = (b.center(), b.size() * 0.5);
                    mine.iter().any(|&t| {
                        let tri = self.mesh.corners(t as usize);
                        DVec3::AXES.iter().any(|&axis| segment_meets_triangle(c - axis * half, c + axis * half, &tri))
                    })
                }
            };
            return if keep { Decision::Full } else { Decision::Empty };
        }
        // Step 3: each child gets the triangles overlapping its box.
        let size = 1u32 << (key.k() - 1);
        Decision::Split(std::array::from_fn(|i| {
            let child = morton::decode(key.child(i as u64).expect("k > 0").start());
            self.meeting(&mine, &self.domain.cube_box(child, size))
        }))
    }
}

impl Surface<'_> {
    /// The triangles of `candidates` that overlap the box `b` (exact test).
    fn meeting(&self, candidates: &[u32], b: &Aabb) -> SmallVec<[u32; 4]> {
        let (center, half) = (b.center(), b.size() * 0.5);
        candidates
            .iter()
            .copied()
            .filter(|&t| triangle_box_overlap(&self.mesh.corners(t as usize), center, half))
            .collect()
    }
}

/// Whether the closed segment `a b` meets the closed triangle `t` (with a relative
/// tolerance, so touching counts).
fn segment_meets_triangle(a: DVec3, b: DVec3, t: &[DVec3; 3]) -> bool {
    // Moller-Trumbore on the segment's parameter range [0, 1].
    let dir = b - a;
    let (e1, e2) = (t[1] - t[0], t[2] - t[0]);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    let tol = 1e-9;
    if det.abs() < 1e-300 {
        return false; // parallel: a grazing segment is covered by the other two axes
    }
    let s = a - t[0];
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    let w = e2.dot(q) / det;
    u >= -tol && v >= -tol && u + v <= 1.0 + tol && (-tol..=1.0 + tol).contains(&w)
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::mesh::generate::{icosphere, torus};

    #[test]
    fn estimate_covers_the_keys_made_and_is_within_a_few_times_them_for_large_triangles() {
        let tri = |c: [DVec3; 3]| TriangleMesh::new(c.to_vec(), vec![[0, 1, 2]]).unwrap();
        let large = [
            ("triangle on a lattice plane", tri([DVec3::ZERO, DVec3::X, DVec3::Y])),
            ("triangle along a face diagonal", tri([DVec3::ZERO, DVec3::X, DVec3::new(0.0, 1.0, 1.0)])),
            ("triangle across the cube", tri([DVec3::X, DVec3::Y, DVec3::Z])),
        ];
        let small = [("icosphere", icosphere(DVec3::ZERO, 1.0, 3)), ("torus", torus(1.0, 0.35, 48, 24))];
        for (name, mesh) in large.iter().chain(&small) {
            for depth in [4, 6, 8] {
                let d = Domain::around(&mesh.bounds(), 0.03, depth).unwrap();
                let estimate = estimate_surface_bytes(mesh, &d);
                for kind in [SurfaceKind::Conservative, SurfaceKind::Thin] {
                    let shell = voxelize_surface(mesh, d, kind, &VoxelizeOptions::default()).unwrap();
                    let keys = 16 * shell.voxel_count();
                    assert!(estimate >= keys, "{name} {kind:?} at depth {depth}: {estimate} < {keys}");
                }
            }
        }
        for (name, mesh) in &large {
            let d = Domain::around(&mesh.bounds(), 0.03, 9).unwrap();
            let shell = voxelize_surface(mesh, d, SurfaceKind::Conservative, &VoxelizeOptions::default()).unwrap();
            let (estimate, keys) = (estimate_surface_bytes(mesh, &d), 16 * shell.voxel_count());
            assert!(estimate < 3 * keys, "{name}: {estimate} vs {keys}");
        }
    }
}
