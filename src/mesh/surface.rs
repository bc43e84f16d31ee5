//! Surface (shell) voxelization of triangle meshes.
//!
//! - [`SurfaceKind::Conservative`]: every voxel a triangle touches (exact
//!   separating-axis test): 26-separating, a thick shell.
//! - [`SurfaceKind::Thin`]: the voxels whose centre cross (the three axis-parallel
//!   segments of one voxel length through the centre) a triangle meets. It is
//!   6-separating: a 6-connected path of voxels that crosses the surface steps along
//!   those segments, so it meets the surface on some voxel's cross, and that voxel is
//!   in the set. It is about a third as thick as the conservative shell.

use glam::DVec3;

use super::TriangleMesh;
use super::tri_box::triangle_box_overlap;
use crate::error::Result;
use crate::morton;
use crate::octree::{Domain, LinearOctree, NodeKey};

/// Which surface voxels to keep.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceKind {
    /// Every voxel the surface touches.
    Conservative,
    /// A thin, 6-separating shell.
    Thin,
}

/// Voxelizes the surface of `mesh` (no inside).
pub fn voxelize_surface(mesh: &TriangleMesh, domain: Domain, kind: SurfaceKind) -> Result<LinearOctree> {
    mesh.check()?;
    let all: Vec<u32> = (0..mesh.triangles.len() as u32).collect();
    let mut out = Vec::new();
    node(mesh, &domain, kind, NodeKey::new(0, u32::from(domain.depth())), &all, &mut out);
    Ok(LinearOctree::from_keys_unsorted(domain, out))
}

fn node(mesh: &TriangleMesh, d: &Domain, kind: SurfaceKind, key: NodeKey, tris: &[u32], out: &mut Vec<NodeKey>) {
    let min = morton::decode(key.start());
    let b = d.cube_box(min, 1 << key.k());
    let half = b.size() * 0.5;
    let mine: Vec<u32> =
        tris.iter().copied().filter(|&t| triangle_box_overlap(&mesh.corners(t as usize), b.center(), half)).collect();
    if mine.is_empty() {
        return;
    }
    if key.k() > 0 {
        for i in 0..8 {
            node(mesh, d, kind, key.child(i).expect("k > 0"), &mine, out);
        }
        return;
    }
    let keep = match kind {
        SurfaceKind::Conservative => true,
        SurfaceKind::Thin => {
            let c = b.center();
            mine.iter().any(|&t| {
                let tri = mesh.corners(t as usize);
                DVec3::AXES.iter().any(|&axis| segment_meets_triangle(c - axis * half, c + axis * half, &tri))
            })
        }
    };
    if keep {
        out.push(key);
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
