//! Planar regions of a closed triangle mesh: the faces of the true surface that
//! radiosity cuts into patches.
//!
//! Region growing (the classic segmentation of a mesh into planes, as in Hoppe's
//! surface reconstruction and the "planar region" passes of mesh simplifiers): the
//! lowest unassigned triangle of positive area seeds a region with its plane (unit
//! normal `n`, a point `o` on it), and a breadth-first walk over edge-adjacent
//! triangles takes each one whose normal is within [`PLANAR_DEGREES`] of `n` and
//! whose three corners lie within [`PLANAR_DISTANCE`] voxels of the plane. Triangles
//! of (next to) no area join a growing region whenever their corners lie on its
//! plane, as they have no normal of their own. The seed's plane is kept (not refitted
//! as the region grows): dual contouring puts the vertices of a flat face exactly on
//! its plane (their QEF has one plane), so the seed's plane is the face's.
//!
//! A region is kept as planar only with [`MIN_AREA`] and a mean width of
//! [`MIN_WIDTH`] voxels: where a crease crosses the lattice at an angle, dual
//! contouring's quads span it (their corners lie on the crease and on either face), and
//! along a straight crease their triangles can make a plane of their own, one voxel
//! wide. Then these bent triangles: an unassigned triangle edge-adjacent to a planar
//! region joins the one whose plane its corners lie nearest, within [`BENT_DISTANCE`]
//! voxels, layer after layer; the distance keeps a curved part next to a flat face
//! from being eaten into beyond its first voxel.
//!
//! What is left (triangles of curved parts, and the bent ones where a crease crosses
//! the lattice at an angle) is grouped by a second, looser walk: a **cluster** takes
//! edge-adjacent triangles whose normals are within [`CLUSTER_DEGREES`] of its seed's
//! and whose corners lie in the cube of edge `cluster_size` centred on the seed's first
//! corner; its plane is the area-weighted mean of its triangles' (normal and
//! centroid), and its triangles lie only near that plane. So a sphere becomes patches
//! of about `cluster_size`, and a crease's bent triangles thin strips along it.
//!
//! Departures: no refit of the plane (see above), no merging of coplanar regions that
//! do not touch (two block faces in one plane stay two regions, which is what patches
//! want anyway), and the order of seeds is the triangle order, so the regions depend
//! only on the mesh.

use std::collections::VecDeque;

use glam::DVec3;
use rayon::prelude::*;

use crate::mesh::TriangleMesh;

/// Most angle between a planar region's seed normal and a member's, degrees.
pub(crate) const PLANAR_DEGREES: f64 = 1.0;
/// Most distance of a member's corner from a planar region's plane, in voxels.
pub(crate) const PLANAR_DISTANCE: f64 = 0.02;
/// Most angle between a cluster's seed normal and a member's, degrees.
pub(crate) const CLUSTER_DEGREES: f64 = 30.0;
/// Least area of a planar region, in square voxels.
const MIN_AREA: f64 = 2.0;
/// Least mean width of a planar region (its area over its box's diagonal), in voxels.
const MIN_WIDTH: f64 = 1.5;
/// Most distance of a bent triangle's corner from the plane of the region it joins, in
/// voxels.
pub(crate) const BENT_DISTANCE: f64 = 1.0;
/// Triangles of at most this area (in square voxels) have no normal of their own.
const SLIVER_AREA: f64 = 1e-9;

/// A set of edge-connected triangles and the plane they lie on (or near).
#[derive(Clone, Debug)]
pub(crate) struct Region {
    /// Unit normal of its plane, outward (the triangles' side).
    pub normal: DVec3,
    /// A point of its plane.
    pub point: DVec3,
    /// Its triangles (indices into the mesh), in the order the walk took them, the
    /// bent ones it took in last.
    pub triangles: Vec<u32>,
    /// How many of `triangles` lie on its plane (the rest are bent triangles, within
    /// [`BENT_DISTANCE`] voxels of it).
    pub own: usize,
    /// Whether every triangle lies on the plane (a planar region), not only near it (a
    /// cluster of a curved part).
    pub planar: bool,
}

/// Each triangle's edge neighbours (up to three; a closed manifold mesh has exactly
/// three), `u32::MAX` where an edge has no other triangle or more than one.
fn neighbours(mesh: &TriangleMesh) -> Vec<[u32; 3]> {
    let mut edges: Vec<(u64, u32)> = mesh
        .triangles
        .par_iter()
        .enumerate()
        .flat_map_iter(|(t, tri)| {
            (0..3).map(move |k| {
                let (a, b) = (tri[k], tri[(k + 1) % 3]);
                ((u64::from(a.min(b)) << 32) | u64::from(a.max(b)), (t as u32) * 3 + k as u32)
            })
        })
        .collect();
    edges.par_sort_unstable();
    let mut out = vec![[u32::MAX; 3]; mesh.triangles.len()];
    let mut i = 0;
    while i < edges.len() {
        let mut j = i + 1;
        while j < edges.len() && edges[j].0 == edges[i].0 {
            j += 1;
        }
        if j == i + 2 {
            let (x, y) = (edges[i].1, edges[i + 1].1);
            out[(x / 3) as usize][(x % 3) as usize] = y / 3;
            out[(y / 3) as usize][(y % 3) as usize] = x / 3;
        }
        i = j;
    }
    out
}

/// Each triangle's unit normal (zero for a sliver) and area.
fn normals_and_areas(mesh: &TriangleMesh, sliver: f64) -> Vec<(DVec3, f64)> {
    mesh.triangles
        .par_iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
            let cross = (b - a).cross(c - a);
            let area = 0.5 * cross.length();
            if area <= sliver { (DVec3::ZERO, area) } else { (cross / (2.0 * area), area) }
        })
        .collect()
}

/// The planar regions of `mesh` (closed, oriented, in world units, voxels of `voxel`),
/// then clusters of at most `cluster_size` across of what is left (module doc).
pub(crate) fn planar_regions(mesh: &TriangleMesh, voxel: f64, cluster_size: f64) -> Vec<Region> {
    let around = neighbours(mesh);
    let normals = normals_and_areas(mesh, SLIVER_AREA * voxel * voxel);
    let corners = |t: u32| mesh.triangles[t as usize].map(|i| mesh.vertices[i as usize]);
    let mut region_of = vec![u32::MAX; mesh.triangles.len()];
    let mut regions = Vec::new();
    let (planar_cos, distance) = (PLANAR_DEGREES.to_radians().cos(), PLANAR_DISTANCE * voxel);
    // Planar regions.
    let mut queue = VecDeque::new();
    for seed in 0..mesh.triangles.len() as u32 {
        let (n, area) = normals[seed as usize];
        if region_of[seed as usize] != u32::MAX || area <= 0.0 || n == DVec3::ZERO {
            continue;
        }
        let point = corners(seed)[0];
        let fits = |t: u32| {
            let (m, _) = normals[t as usize];
            (m == DVec3::ZERO || m.dot(n) >= planar_cos)
                && corners(t).iter().all(|&p| n.dot(p - point).abs() <= distance)
        };
        let id = regions.len() as u32;
        let triangles = grow(seed, id, &around, &mut region_of, &mut queue, fits);
        let own = triangles.len();
        regions.push(Region { normal: n, point, triangles, own, planar: true });
    }
    // A region is planar only with some area of its own and some width: lone
    // triangles and strips (a crease's bent triangles, one voxel wide) are released.
    let min_area = MIN_AREA * voxel * voxel;
    let mut kept = Vec::with_capacity(regions.len());
    for r in regions {
        let area: f64 = r.triangles.iter().map(|&t| normals[t as usize].1).sum();
        let (mut lo, mut hi) = (DVec3::MAX, DVec3::MIN);
        for &t in &r.triangles {
            for p in corners(t) {
                lo = lo.min(p);
                hi = hi.max(p);
            }
        }
        if area >= min_area && area >= MIN_WIDTH * voxel * (hi - lo).length() {
            let id = kept.len() as u32;
            for &t in &r.triangles {
                region_of[t as usize] = id;
            }
            kept.push(r);
        } else {
            for &t in &r.triangles {
                region_of[t as usize] = u32::MAX;
            }
        }
    }
    let mut regions = kept;
    absorb_bent(mesh, &around, &mut regions, &mut region_of, voxel);
    // Clusters of the rest.
    let cluster_cos = CLUSTER_DEGREES.to_radians().cos();
    let half = 0.5 * cluster_size.max(voxel);
    for seed in 0..mesh.triangles.len() as u32 {
        if region_of[seed as usize] != u32::MAX {
            continue;
        }
        let (n, _) = normals[seed as usize];
        let center = corners(seed)[0];
        let fits = |t: u32| {
            let (m, _) = normals[t as usize];
            (n == DVec3::ZERO || m == DVec3::ZERO || m.dot(n) >= cluster_cos)
                && corners(t).iter().all(|&p| (p - center).abs().max_element() <= half)
        };
        let id = regions.len() as u32;
        let triangles = grow(seed, id, &around, &mut region_of, &mut queue, fits);
        let (mut normal, mut point, mut area) = (DVec3::ZERO, DVec3::ZERO, 0.0);
        for &t in &triangles {
            let (m, a) = normals[t as usize];
            let [p, q, r] = corners(t);
            normal += m * a;
            point += (p + q + r) * (a / 3.0);
            area += a;
        }
        let normal = normal.try_normalize().unwrap_or(if n == DVec3::ZERO { DVec3::Z } else { n });
        let point = if area > 0.0 { point / area } else { center };
        let own = triangles.len();
        regions.push(Region { normal, point, triangles, own, planar: false });
    }
    regions
}

/// Gives each unassigned triangle edge-adjacent to a planar region's triangle to the
/// adjacent region whose plane its corners lie nearest (within [`BENT_DISTANCE`]
/// voxels), layer after layer while any joins: the bent (and the few folded)
/// triangles where a crease crosses the lattice at an angle (their corners lie on the
/// crease and on either face) join a face, so the faces tile the surface up to their
/// creases. The distance keeps it to the voxel next to a face.
fn absorb_bent(mesh: &TriangleMesh, around: &[[u32; 3]], regions: &mut [Region], region_of: &mut [u32], voxel: f64) {
    let corners = |t: u32| mesh.triangles[t as usize].map(|i| mesh.vertices[i as usize]);
    let limit = BENT_DISTANCE * voxel;
    let mut open: Vec<u32> = (0..mesh.triangles.len() as u32).filter(|&t| region_of[t as usize] == u32::MAX).collect();
    loop {
        let before = open.len();
        let layer = region_of.to_vec();
        open.retain(|&t| {
            let mut best: Option<(f64, u32)> = None;
            for &n in &around[t as usize] {
                let Some(&id) = layer.get(n as usize) else { continue };
                if id == u32::MAX {
                    continue;
                }
                let r = &regions[id as usize];
                let d = corners(t).iter().map(|&p| r.normal.dot(p - r.point).abs()).fold(0.0, f64::max);
                if d <= limit && best.is_none_or(|b| d < b.0) {
                    best = Some((d, id));
                }
            }
            let Some((_, id)) = best else { return true };
            region_of[t as usize] = id;
            regions[id as usize].triangles.push(t);
            false
        });
        if open.len() == before || open.is_empty() {
            break;
        }
    }
}

/// Breadth-first from `seed` over edge neighbours that are unassigned and `fit`,
/// marking each `id`; the triangles taken, in order.
fn grow(
    seed: u32,
    id: u32,
    around: &[[u32; 3]],
    region_of: &mut [u32],
    queue: &mut VecDeque<u32>,
    fits: impl Fn(u32) -> bool,
) -> Vec<u32> {
    let mut taken = vec![seed];
    region_of[seed as usize] = id;
    queue.clear();
    queue.push_back(seed);
    while let Some(t) = queue.pop_front() {
        for &m in &around[t as usize] {
            if m != u32::MAX && region_of[m as usize] == u32::MAX && fits(m) {
                region_of[m as usize] = id;
                taken.push(m);
                queue.push_back(m);
            }
        }
    }
    taken
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The closed box `[0, 1] x [0, 2] x [0, 3]` as 12 triangles, outward.
    fn box_mesh() -> TriangleMesh {
        let size = DVec3::new(1.0, 2.0, 3.0);
        let vertices: Vec<DVec3> =
            (0..8).map(|i| DVec3::new(f64::from(i & 1), f64::from((i >> 1) & 1), f64::from(i >> 2)) * size).collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let triangles = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        TriangleMesh::new(vertices, triangles).unwrap()
    }

    #[test]
    fn a_box_is_six_planar_regions_of_two_triangles_with_outward_normals() {
        let mesh = box_mesh();
        let regions = planar_regions(&mesh, 0.1, 1.0);
        assert_eq!(regions.len(), 6);
        let centre = DVec3::new(0.5, 1.0, 1.5);
        for r in &regions {
            assert!(r.planar && r.triangles.len() == 2);
            assert_eq!(r.normal.abs().max_element(), 1.0);
            assert!(r.normal.dot(r.point - centre) > 0.0, "outward");
        }
    }
}
