//! Patches from the true surface: a solid made from a shape is extracted by dual
//! contouring of its exact Hermite data ([`crate::surface::extract`], smooth, no
//! simplification), its triangles grouped into planar regions and clusters of curved
//! parts (`regions`), and each region cut into rectangular tiles of its plane.
//!
//! A region's rectangle is the smallest-area rectangle around its corners in its plane
//! (Freeman and Shapira 1975: one side lies along an edge of the convex hull, so every
//! hull edge is tried), so a face of a turned block is its own rectangle, exactly, and
//! not a staircase of one-voxel strips. The rectangle is cut into the fewest equal
//! tiles no longer than `patch_size` a side; each tile the region's triangles meet is a
//! **patch**, its triangles clipped to it its [`Cover`] unless they fill it (a tile
//! whose covered area is within [`FULL`] of its own is taken as full, with its exact
//! area). Elements are cut from a patch's tile as from a voxel rectangle (at most
//! `elements` a side, none narrower than a voxel); each element's area and centre are
//! those of the covered part of its cell.
//!
//! Departures: a cluster of a curved part is cut in the plane of its mean normal, its
//! pieces' areas corrected by their tilt (`cover`), its elements' centres moved onto
//! the shape's surface (`patches::element`); the rectangle's form factor stands in for
//! a partial patch's, scaled by what its rays find covered (`form_factor`).

use std::sync::Arc;

use glam::{DVec2, DVec3};
use smallvec::SmallVec;

use super::cover::{Cover, Piece, area_and_centroid, clip_to_rect};
use super::patches::Patch;
use super::regions::{Region, planar_regions};
use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::render::scene::SceneSolid;
use crate::surface::{ExtractOptions, HermiteData, Style, extract};

/// A tile whose covered area is within this fraction of its own is full.
pub(crate) const FULL: f64 = 1e-6;

/// Two unit vectors spanning the plane of unit normal `n`.
fn plane_basis(n: DVec3) -> (DVec3, DVec3) {
    let helper = if n.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    let u = (helper - n * helper.dot(n)).normalize();
    (u, n.cross(u))
}

/// The convex hull of `points` (Andrew's monotone chain), counter-clockwise.
fn convex_hull(mut points: Vec<DVec2>) -> Vec<DVec2> {
    points.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    points.dedup();
    if points.len() < 3 {
        return points;
    }
    let mut hull: Vec<DVec2> = Vec::with_capacity(2 * points.len());
    for pass in 0..2 {
        let start = hull.len();
        let order: Box<dyn Iterator<Item = &DVec2>> =
            if pass == 0 { Box::new(points.iter()) } else { Box::new(points.iter().rev()) };
        for &p in order {
            while hull.len() >= start + 2 && (hull[hull.len() - 1] - hull[hull.len() - 2]).perp_dot(p - hull[hull.len() - 2]) <= 0.0
            {
                hull.pop();
            }
            hull.push(p);
        }
        hull.pop();
    }
    hull
}

/// The direction (unit, in the plane's 2D basis) of the smallest-area rectangle
/// around `hull`.
fn smallest_rectangle_direction(hull: &[DVec2]) -> DVec2 {
    let mut best = (f64::MAX, DVec2::X);
    for (i, &a) in hull.iter().enumerate() {
        let Some(u) = (hull[(i + 1) % hull.len()] - a).try_normalize() else { continue };
        let v = u.perp();
        let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
        for &p in hull {
            let q = DVec2::new(p.dot(u), p.dot(v));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let area = (hi - lo).x * (hi - lo).y;
        if area < best.0 * (1.0 - 1e-12) {
            best = (area, u);
        }
    }
    best.1
}

/// What one solid's surface gives: its patches (first elements not numbered) and the
/// elements they will have.
pub(crate) struct SolidPatches {
    pub patches: Vec<Patch>,
    pub elements: u64,
}

/// The patches of `solid` (index `index`), which has a source shape, cut from its true
/// surface (module doc).
pub(crate) fn surface_patches(
    solid: &SceneSolid,
    index: u32,
    patch_size: f64,
    elements: u32,
    budget: MemoryBudget,
) -> Result<SolidPatches> {
    let shape = solid.shape().expect("a solid with a shape");
    let hermite = HermiteData::from_shape(shape, &solid.tree);
    let options = ExtractOptions { style: Style::Smooth, tolerance: 0.0, budget, ..ExtractOptions::default() };
    let surface = extract(&solid.tree, &hermite, &options, &crate::NoProgress)?;
    let mesh = &surface.mesh;
    let voxel = solid.tree.domain().voxel_size();
    let regions = planar_regions(mesh, voxel, patch_size);
    let (reflectance, emission) = (solid.material.diffuse_reflectance(), solid.material.emission);
    let mut out = SolidPatches { patches: Vec::new(), elements: 0 };
    for region in &regions {
        for mut p in region_patches(mesh, region, voxel, patch_size, elements) {
            p.solid = index;
            p.reflectance = reflectance;
            p.emission = emission;
            out.elements += u64::from(p.nu) * u64::from(p.nv);
            out.patches.push(p);
        }
    }
    Ok(out)
}

/// The tiles of one region (module doc), with their covers.
fn region_patches(
    mesh: &crate::mesh::TriangleMesh,
    region: &Region,
    voxel: f64,
    patch_size: f64,
    elements: u32,
) -> Vec<Patch> {
    let n = region.normal;
    let (e1, e2) = plane_basis(n);
    let flat = |p: DVec3| DVec2::new((p - region.point).dot(e1), (p - region.point).dot(e2));
    let corners: Vec<DVec2> =
        region.triangles.iter().flat_map(|&t| mesh.triangles[t as usize]).map(|i| flat(mesh.vertices[i as usize])).collect();
    let dir = smallest_rectangle_direction(&convex_hull(corners));
    let u = e1 * dir.x + e2 * dir.y;
    let v = n.cross(u);
    let frame = |p: DVec3| DVec2::new((p - region.point).dot(u), (p - region.point).dot(v));
    let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
    for &t in &region.triangles {
        for i in mesh.triangles[t as usize] {
            let q = frame(mesh.vertices[i as usize]);
            lo = lo.min(q);
            hi = hi.max(q);
        }
    }
    let size = (hi - lo).max(DVec2::splat(1e-9 * voxel));
    let tiles = |len: f64| ((len / patch_size) * (1.0 - 1e-12)).ceil().max(1.0) as usize;
    let (tu, tv) = (tiles(size.x), tiles(size.y));
    let tile = DVec2::new(size.x / tu as f64, size.y / tv as f64);
    // Each triangle clipped to the tiles its box meets, in tile coordinates.
    let mut pieces: Vec<Vec<Piece>> = vec![Vec::new(); tu * tv];
    for &t in &region.triangles {
        let [a, b, c] = mesh.triangles[t as usize].map(|i| mesh.vertices[i as usize]);
        let tilt = (b - a).cross(c - a).normalize_or_zero().dot(n).abs();
        let scale = if region.planar || tilt <= 0.0 { 1.0 } else { 1.0 / tilt.max(0.2) };
        let grid: [DVec2; 3] = [a, b, c].map(|p| (frame(p) - lo) / tile);
        let (glo, ghi) = (grid[0].min(grid[1]).min(grid[2]), grid[0].max(grid[1]).max(grid[2]));
        let range = |a: f64, b: f64, n: usize| {
            let first = (a.floor().max(0.0) as usize).min(n - 1);
            let last = (b.ceil() as usize).clamp(first + 1, n);
            first..last
        };
        for j in range(glo.y, ghi.y, tv) {
            for i in range(glo.x, ghi.x, tu) {
                let local: SmallVec<[DVec2; 8]> = grid.iter().map(|&g| g - DVec2::new(i as f64, j as f64)).collect();
                let clipped = clip_to_rect(&local, 0.0, 1.0, 0.0, 1.0);
                if clipped.len() >= 3 && area_and_centroid(&clipped).0 > 0.0 {
                    pieces[j * tu + i].push(Piece { points: clipped, scale });
                }
            }
        }
    }
    let tile_area = tile.x * tile.y;
    let mut patches = Vec::new();
    for (k, tile_pieces) in pieces.into_iter().enumerate() {
        if tile_pieces.is_empty() {
            continue;
        }
        let (i, j) = (k % tu, k / tu);
        let covered: f64 = tile_pieces.iter().map(|p| area_and_centroid(&p.points).0 * p.scale).sum();
        let plane: f64 = tile_pieces.iter().map(|p| area_and_centroid(&p.points).0).sum();
        if covered <= 0.0 {
            continue;
        }
        let full = region.planar && plane >= 1.0 - FULL;
        let corner = region.point + u * (lo.x + i as f64 * tile.x) + v * (lo.y + j as f64 * tile.y);
        let side = |len: f64| elements.min((len / voxel * (1.0 + 1e-9)).floor().max(1.0) as u32);
        let lift = (0.5 * n.abs().element_sum() + 0.05) * voxel;
        patches.push(Patch {
            solid: 0,
            face: None,
            cover: (!full).then(|| Arc::new(Cover::new(tile_pieces))),
            corner,
            du: u * tile.x,
            dv: v * tile.y,
            normal: n,
            area: if full { tile_area } else { covered * tile_area },
            reflectance: DVec3::ZERO,
            emission: DVec3::ZERO,
            first: 0,
            nu: side(tile.x),
            nv: side(tile.y),
            lift,
        });
    }
    patches
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_smallest_rectangle_of_a_turned_square_lies_along_its_sides() {
        let turn = 0.3f64;
        let (c, s) = (turn.cos(), turn.sin());
        let square: Vec<DVec2> = [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0), (0.5, 0.0), (0.5, 0.5)]
            .iter()
            .map(|&(x, y)| DVec2::new(c * x - s * y, s * x + c * y))
            .collect();
        let hull = convex_hull(square);
        assert_eq!(hull.len(), 4);
        let d = smallest_rectangle_direction(&hull);
        // Along one of the square's sides (any of the four).
        let along = d.dot(DVec2::new(c, s)).abs().max(d.dot(DVec2::new(-s, c)).abs());
        assert!((along - 1.0).abs() < 1e-12, "{d}");
    }
}
