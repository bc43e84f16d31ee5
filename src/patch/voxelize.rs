//! Patch sets to octrees: the surface directly by adaptive subdivision, the solid
//! through a fine tessellation and the winding rule.
//!
//! Surface: a node keeps the pieces of patch whose control-point boxes meet it; a piece
//! larger than the node is split in four first (de Casteljau at 1/2), so pieces shrink
//! with the nodes. At a voxel, pieces are split until their boxes have a diagonal under
//! half a voxel, and the voxel is kept when one of them meets it. Every surface point
//! lies in a kept voxel (its piece's box contains it), and every kept voxel lies within
//! half a voxel of the surface (a piece's box of diagonal under h/2 meets it).

use rayon::prelude::*;

use super::BezierPatch;
use crate::aabb::Aabb;
use crate::error::Result;
use crate::mesh::TriangleMesh;
use crate::morton;
use crate::octree::{Domain, LinearOctree, NodeKey, PARALLEL_LEVELS};

/// The voxels the patch surfaces pass through, each within half a voxel of a surface.
pub fn voxelize_patch_surface(patches: &[BezierPatch], domain: Domain) -> Result<LinearOctree> {
    let mut out = Vec::new();
    surface_node(&domain, NodeKey::new(0, u32::from(domain.depth())), patches.to_vec(), &mut out);
    Ok(LinearOctree::from_keys_unsorted(domain, out))
}

fn surface_node(d: &Domain, key: NodeKey, pieces: Vec<BezierPatch>, out: &mut Vec<NodeKey>) {
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
    if mine.is_empty() {
        return;
    }
    if key.k() == 0 {
        out.push(key);
        return;
    }
    let level = key.level(d.depth());
    if level < PARALLEL_LEVELS {
        let parts: Vec<Vec<NodeKey>> = (0..8)
            .into_par_iter()
            .map(|i| {
                let mut part = Vec::new();
                surface_node(d, key.child(i).expect("k > 0"), mine.clone(), &mut part);
                part
            })
            .collect();
        parts.into_iter().for_each(|p| out.extend(p));
    } else {
        for i in 0..8 {
            surface_node(d, key.child(i).expect("k > 0"), mine.clone(), out);
        }
    }
}

/// Triangles on an `n x n` grid of every patch, welded, oriented so the enclosed
/// signed volume is positive (the winding rule then reads 1 inside).
#[must_use]
pub fn tessellate(patches: &[BezierPatch], n: u32) -> TriangleMesh {
    let n = n.max(1);
    let mut mesh = TriangleMesh::default();
    for patch in patches {
        let base = mesh.vertices.len() as u32;
        for i in 0..=n {
            for j in 0..=n {
                mesh.vertices.push(patch.eval(f64::from(i) / f64::from(n), f64::from(j) / f64::from(n)));
            }
        }
        let at = |i: u32, j: u32| base + i * (n + 1) + j;
        for i in 0..n {
            for j in 0..n {
                mesh.triangles.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                mesh.triangles.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    mesh.weld();
    // Drop triangles that collapsed where a patch degenerates to a point (the lid's top).
    mesh.triangles.retain(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0]);
    let volume: f64 = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            a.dot(b.cross(c))
        })
        .sum();
    if volume < 0.0 {
        mesh.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    }
    mesh
}

/// Segments a patch side needs so the tessellation's chords stay within `tolerance`
/// of the surface for a patch of extent `extent` (a conservative rule of thumb).
#[must_use]
pub fn segments_for(extent: f64, tolerance: f64) -> u32 {
    ((extent / tolerance.max(1e-12)).sqrt() * 2.0).ceil().clamp(4.0, 128.0) as u32
}
