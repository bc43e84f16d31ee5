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
//! area). The rectangle is that of the triangles on the plane; the bent triangles a
//! crease gives the region (`regions`) are cut to it. Elements are cut from a patch's tile as from a voxel rectangle (at most
//! `elements` a side, none narrower than a voxel); each element's area and centre are
//! those of the covered part of its cell.
//!
//! Faces against other solids: where two solids of a scene touch (a wall's end against
//! the next wall, a block standing on the floor, a lamp set into the ceiling), each
//! one's surface runs on between them, where no light can come or go. A triangle whose
//! outside, half a voxel beyond its centroid along its normal, lies in a full voxel of
//! another solid faces into that solid and is left out before the regions are grown
//! ([`facing_out`]); so is one whose inside, half a voxel within, lies in an earlier
//! solid (two overlapping solids ending in one plane: the earlier keeps the face). So
//! the regions, their rectangles and the patches are the exposed surface of the
//! solids' union, each part once (to half a voxel). Kept, such a face would take a patch's share of the
//! light it receives into its elements (which receive nothing) and dim every patch that
//! crosses it: the walls' borders of a Cornell box built of overlapping boxes lost a
//! third of their light, and the colour bled off them with it.
//!
//! Departures: a cluster of a curved part is cut in the plane of its mean normal, its
//! pieces' areas corrected by their tilt (`cover`), its elements' centres moved onto
//! the shape's surface (`patches::element`); the rectangle's form factor stands in for
//! a partial patch's, scaled by what its rays find covered (`form_factor`).

use std::sync::{Arc, Mutex};

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use smallvec::SmallVec;

use super::cover::{Cover, Piece, area_and_centroid, clip_to_rect};
use super::patch::Patch;
use super::regions::{PLANAR_DISTANCE, Region, planar_regions};
use crate::budget::MemoryBudget;
use crate::error::{Number, Result};
use crate::mesh::TriangleMesh;
use crate::progress::{CancelOnly, Progress};
use crate::render::scene::Scene;
use crate::surface::{ExtractOptions, HermiteData, Style, extract};

/// A tile whose covered area is within this fraction of its own is full.
pub(crate) const FULL: f64 = 1e-3;

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
            while hull.len() >= start + 2
                && (hull[hull.len() - 1] - hull[hull.len() - 2]).perp_dot(p - hull[hull.len() - 2]) <= 0.0
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

/// What one solid's surface gives: its patches, region by region (first elements not
/// numbered), and the elements they will have.
pub(crate) struct SolidPatches {
    /// Each region's patches, as [`region_patches`] allocated them (not copied into one
    /// list that grows by doubling: the budget counted each tile once).
    pub regions: Vec<Vec<Patch>>,
    pub elements: u64,
}

impl SolidPatches {
    /// How many patches.
    pub fn count(&self) -> usize {
        self.regions.iter().map(Vec::len).sum()
    }
}

/// `mesh` (the surface of solid `index` of `scene`) less its triangles that face into
/// another solid of the scene (module doc): those whose point half a voxel of that
/// solid out of their centroid, along their normal, lies in one of its full voxels, and
/// those whose point half a voxel within lies in an earlier solid's. Triangles of no
/// area have no normal and are kept.
fn facing_out(mesh: TriangleMesh, scene: &Scene, index: usize) -> TriangleMesh {
    if scene.solids.len() < 2 {
        return mesh;
    }
    // Each other solid with the bounds of its full voxels: a point whose voxel lies
    // outside them is in none, without a search of the tree.
    let others: Vec<(usize, &crate::octree::LinearOctree, [u32; 3], [u32; 3])> = scene
        .solids
        .iter()
        .enumerate()
        .filter(|&(i, _)| i != index)
        .filter_map(|(i, o)| o.tree.voxel_bounds().map(|(lo, hi)| (i, &o.tree, lo, hi)))
        .collect();
    let contains = |tree: &crate::octree::LinearOctree, lo: [u32; 3], hi: [u32; 3], p: DVec3| {
        tree.domain()
            .voxel_of(p)
            .is_some_and(|v| (0..3).all(|a| lo[a] <= v[a] && v[a] < hi[a]) && tree.contains_voxel(v))
    };
    let hidden = |t: &[u32; 3]| {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let Some(n) = (b - a).cross(c - a).try_normalize() else { return false };
        let centroid = (a + b + c) / 3.0;
        others.iter().any(|&(i, tree, lo, hi)| {
            let half = n * (0.5 * tree.domain().voxel_size());
            contains(tree, lo, hi, centroid + half) || (i < index && contains(tree, lo, hi, centroid - half))
        })
    };
    let keep: Vec<bool> = mesh.triangles.par_iter().map(|t| !hidden(t)).collect();
    if keep.iter().all(|&k| k) {
        return mesh;
    }
    let triangles = mesh.triangles.iter().zip(&keep).filter(|(_, k)| **k).map(|(t, _)| *t).collect();
    TriangleMesh { vertices: mesh.vertices, triangles, groups: Vec::new() }
}

/// The patches of solid `index` of `scene`, which has a source shape, cut from its true
/// surface where no other solid covers it (module doc).
pub(crate) fn surface_patches(
    scene: &Scene,
    index: u32,
    patch_size: f64,
    elements: u32,
    budget: MemoryBudget,
    tally: &TileTally,
    stop: &dyn Progress,
) -> Result<SolidPatches> {
    let solid = &scene.solids[index as usize];
    let shape = solid.shape().expect("a solid with a shape");
    let hermite = HermiteData::from_shape(shape, &solid.tree);
    let options = ExtractOptions { style: Style::Smooth, tolerance: 0.0, budget, ..ExtractOptions::default() };
    let surface = extract(&solid.tree, &hermite, &options, &CancelOnly(stop))?;
    let mesh = &facing_out(surface.mesh, scene, index as usize);
    let voxel = solid.tree.domain().voxel_size();
    let regions = planar_regions(mesh, voxel, patch_size);
    let (reflectance, emission) = (solid.material.diffuse_reflectance(), solid.material.emission);
    let mut out = SolidPatches { regions: Vec::with_capacity(regions.len()), elements: 0 };
    for region in &regions {
        let mut patches = region_patches(mesh, region, voxel, patch_size, elements, budget, tally)?;
        for p in &mut patches {
            p.solid = index;
            p.reflectance = reflectance;
            p.emission = emission;
            out.elements += u64::from(p.nu) * u64::from(p.nv);
        }
        out.regions.push(patches);
    }
    Ok(out)
}

/// The tiles counted so far over the regions of every solid, which are cut side by side:
/// the budget bounds their sum (a count a solid let each of the solids on the cores take
/// a whole budget).
#[derive(Default)]
pub(crate) struct TileTally(Mutex<f64>);

impl TileTally {
    /// Adds `tiles`; the total so far, these included.
    fn add(&self, tiles: f64) -> f64 {
        let mut total = self.0.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        *total += tiles;
        *total
    }
}

/// The tiles of one region (module doc), with their covers, counted in `tally`.
///
/// # Errors
/// When the tiles of every region so far would take more than `budget` (a patch size
/// far under the solids' size), before this region's are allocated.
fn region_patches(
    mesh: &TriangleMesh,
    region: &Region,
    voxel: f64,
    patch_size: f64,
    elements: u32,
    budget: MemoryBudget,
    tally: &TileTally,
) -> Result<Vec<Patch>> {
    let n = region.normal;
    let (e1, e2) = plane_basis(n);
    let flat = |p: DVec3| DVec2::new((p - region.point).dot(e1), (p - region.point).dot(e2));
    // The rectangle of the corners on the plane (those of the bent triangles a crease
    // adds lie on the crease, or off the plane): the bent triangles are cut to it.
    let on_plane = PLANAR_DISTANCE * voxel;
    let corners: Vec<DVec3> = region
        .triangles
        .iter()
        .enumerate()
        .flat_map(|(k, &t)| mesh.triangles[t as usize].map(|i| (k < region.own, mesh.vertices[i as usize])))
        .filter(|&(own, p)| own || (p - region.point).dot(n).abs() <= on_plane)
        .map(|(_, p)| p)
        .collect();
    let dir = smallest_rectangle_direction(&convex_hull(corners.iter().map(|&p| flat(p)).collect()));
    let u = e1 * dir.x + e2 * dir.y;
    let v = n.cross(u);
    let frame = |p: DVec3| DVec2::new((p - region.point).dot(u), (p - region.point).dot(v));
    let (mut lo, mut hi) = (DVec2::splat(f64::MAX), DVec2::splat(f64::MIN));
    for &p in &corners {
        let q = frame(p);
        lo = lo.min(q);
        hi = hi.max(q);
    }
    let size = (hi - lo).max(DVec2::splat(1e-9 * voxel));
    // (A side a hair over a whole number of patches, by rounding, is that number.)
    let tiles = |len: f64| (len / patch_size - 1e-6).ceil().max(1.0);
    // Each tile holds its two areas and its list of pieces while it is cut, and may
    // become a patch: checked before any is allocated, in floats (a tiny patch size
    // overflows any integer), with the solid's tiles so far.
    let tile_bytes =
        (std::mem::size_of::<(f64, f64)>() + std::mem::size_of::<Vec<Piece>>() + 1 + std::mem::size_of::<Patch>())
            as f64;
    let tiles_so_far = tally.add(tiles(size.x) * tiles(size.y));
    let estimate = tiles_so_far * tile_bytes;
    budget.check(
        format!("{tiles_so_far:.0} patches of side {}", Number(patch_size)),
        if estimate < u64::MAX as f64 { estimate as u64 } else { u64::MAX },
    )?;
    let (tu, tv) = (tiles(size.x) as usize, tiles(size.y) as usize);
    let tile = DVec2::new(size.x / tu as f64, size.y / tv as f64);
    // Each triangle clipped to the tiles its box meets, in tile coordinates: first
    // each tile's areas (covered in its plane, and true), then the pieces of the tiles
    // covered only in part, which alone keep theirs.
    let clipped_pieces = |keep: &dyn Fn(usize) -> bool, found: &mut dyn FnMut(usize, Piece)| {
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
                    if !keep(j * tu + i) {
                        continue;
                    }
                    let local: SmallVec<[DVec2; 8]> =
                        grid.iter().map(|&g| g - DVec2::new(i as f64, j as f64)).collect();
                    let inside = local.iter().all(|p| (0.0..=1.0).contains(&p.x) && (0.0..=1.0).contains(&p.y));
                    let clipped = if inside { local } else { clip_to_rect(&local, 0.0, 1.0, 0.0, 1.0) };
                    if clipped.len() >= 3 {
                        found(j * tu + i, Piece { points: clipped, scale });
                    }
                }
            }
        }
    };
    let mut areas = vec![(0.0, 0.0); tu * tv];
    clipped_pieces(&|_| true, &mut |k, piece| {
        let a = area_and_centroid(&piece.points).0;
        areas[k].0 += a;
        areas[k].1 += a * piece.scale;
    });
    let full = |&(plane, _): &(f64, f64)| region.planar && plane >= 1.0 - FULL;
    let partial: Vec<bool> = areas.iter().map(|a| a.1 > 0.0 && !full(a)).collect();
    let mut pieces: Vec<Vec<Piece>> = vec![Vec::new(); tu * tv];
    clipped_pieces(&|k| partial[k], &mut |k, piece| {
        if area_and_centroid(&piece.points).0 > 0.0 {
            pieces[k].push(piece);
        }
    });
    let tile_area = tile.x * tile.y;
    let mut patches = Vec::with_capacity(tu * tv);
    for (k, tile_pieces) in pieces.into_iter().enumerate() {
        let (i, j) = (k % tu, k / tu);
        let covered = areas[k].1;
        if covered <= 0.0 {
            continue;
        }
        let full = full(&areas[k]);
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
    Ok(patches)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box of `size` turned `degrees` about z and then 9 degrees about x (no face on
    /// the lattice), voxelized at depth 6 in [-1, 1]^3, as a scene solid.
    fn turned_box(size: DVec3, degrees: f64) -> (crate::render::Scene, glam::DAffine3) {
        use crate::octree::{Domain, VoxelizeOptions, voxelize};
        use crate::shape::{Cuboid, Transformed};
        let map = glam::DAffine3::from_rotation_x(9f64.to_radians())
            * glam::DAffine3::from_rotation_z(degrees.to_radians())
            * glam::DAffine3::from_translation(DVec3::new(0.013, -0.021, 0.007));
        let shape = Transformed::new(Cuboid::new(DVec3::ZERO, size).unwrap(), map).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
        let tree = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
        let mut scene = crate::render::Scene::new();
        scene.add_shaped("box", tree, crate::render::Material::default(), Arc::new(shape));
        (scene, map)
    }

    #[test]
    fn a_turned_box_is_six_planar_regions_of_its_faces_areas_each_one_tile_a_patch_size() {
        let size = DVec3::new(0.9, 0.6, 0.45);
        let (scene, map) = turned_box(size, 17.0);
        let solid = &scene.solids[0];
        let shape = solid.shape().unwrap();
        let surface = extract(
            &solid.tree,
            &HermiteData::from_shape(shape, &solid.tree),
            &ExtractOptions::default(),
            &crate::NoProgress,
        )
        .unwrap();
        let voxel = solid.tree.domain().voxel_size();
        let regions = planar_regions(&surface.mesh, voxel, 1.0);
        assert_eq!(regions.len(), 6, "{:?}", regions.iter().map(|r| (r.normal, r.triangles.len())).collect::<Vec<_>>());
        // Each region is a face: its normal the turned axis, its one patch (the patch
        // size is above the faces') of the face's area.
        let mut faces: Vec<(DVec3, f64)> = Vec::new();
        for a in 0..3 {
            for sign in [-1.0, 1.0] {
                let mut axis = DVec3::ZERO;
                axis[a] = sign;
                let (u, v) = ((a + 1) % 3, (a + 2) % 3);
                faces.push((map.matrix3 * axis, size[u] * size[v]));
            }
        }
        for r in &regions {
            assert!(r.planar);
            let (normal, area) = *faces.iter().find(|f| f.0.dot(r.normal) > 1.0 - 1e-9).expect("a face's normal");
            let patches =
                region_patches(&surface.mesh, r, voxel, 1.0, 4, MemoryBudget::unlimited(), &TileTally::default())
                    .unwrap();
            assert_eq!(patches.len(), 1, "{normal}");
            let got = patches[0].area;
            // Exact for a tile the face fills; within half a percent where the bent
            // triangles of a crease leave slivers of it uncovered.
            assert!((got - area).abs() < 5e-3 * area, "face {normal}: area {got}, want {area}");
        }
    }

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
