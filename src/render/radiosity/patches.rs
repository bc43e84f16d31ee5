//! Patches and elements: the two-level hierarchy radiosity solves on, cut from each
//! solid's true surface where it came from a shape, else from the octree's own
//! boundary.
//!
//! A solid made from a shape gives its patches from its true surface
//! (`surface_patches`: the planar regions of its dual contouring mesh, each cut into
//! tiles of its plane, less the faces it turns towards other solids; elements as
//! below, their areas and centres those of the surface each covers). Any other solid's
//! boundary is the set of exposed faces of its full nodes (faces against other solids
//! included: a limitation), merged into
//! coplanar rectangles (`mesh::boundary_rects`: they tile the voxel boundary without
//! overlap). A rectangle longer than `patch_size` (world units, at least one voxel) is
//! cut into the fewest equal tiles (whole voxels, the first ones a voxel longer) no
//! longer than it: the **patches**, which shoot (Cohen, Chen, Wallace and Greenberg
//! 1988: a patch's light leaves from the whole patch). Each patch is cut into
//! `elements x elements` equal **elements** (fewer along a side shorter than that many
//! voxels), which receive: an element's radiosity is the value at its centre, and a
//! patch's unshot light is the area-weighted sum of what its elements received.
//!
//! Adaptive subdivision (Cohen, Greenberg, Immel and Brock 1986, substructuring, as
//! the progressive method of Cohen et al. 1988 uses it): an element can be split into
//! four equal children ([`Patches::split`]), and those again: a quadtree over each
//! element of the base grid. Split elements stay in the list (their children follow
//! at the end, in the order they were split), so indices never move; only the leaves
//! receive and are shown. An element at level `L` is cell `(k, j)` of the patch's
//! `(nu 2^L) x (nv 2^L)` grid. Children are never narrower than a voxel.
//!
//! Normals: an element's normal is its patch's (a face's outward axis normal, a
//! tile's plane normal), or the source shape's smooth normal at the element's centre
//! where the solid came from a shape whose surface lies within two voxels of it
//! ([`SceneSolid::shape_surface`]), so a sphere's elements are lit as the sphere is,
//! not as its voxel staircase. Patches shoot from their flat rectangles (their light
//! leaves by the patch's normal).
//!
//! Elements of no area (the cells of a partly covered tile that the surface misses)
//! keep their place in the grid but receive nothing; the display shows the nearest
//! element of area of their patch in their place.
//!
//! Lookup for display: a point on a face of a voxel-boundary patch finds its patch
//! through a hash of the face's plane and the cell of a grid of `patch_size` cells in
//! that plane (a patch meets at most four cells); a point on the voxels of a solid
//! with surface patches (the staircase the renderer shows lies within a voxel of the
//! true surface) finds, among the patches registered in its cell of a 3D grid of
//! `patch_size` cells, the nearest rectangle whose normal faces the same way as the
//! voxel face (`n . face > 0`). Then its place in the element grid.

use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::mesh::{BoundaryRect, boundary_rects};
use crate::octree::Domain;
use crate::progress::Progress;
use crate::render::scene::Scene;

use super::patch::Patch;
use super::surface_patches::{TileTally, surface_patches};

/// A receiving element.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Element {
    /// Centre, on the face.
    pub center: DVec3,
    /// The point rays leave from: the centre lifted off the face along its axis normal
    /// (off a tile, along its own normal).
    pub origin: DVec3,
    /// Unit normal: the smooth shape normal where there is one, else the axis normal.
    pub normal: DVec3,
    /// Area (0 for a cell of a tile the surface misses).
    pub area: f64,
    /// Its patch.
    pub patch: u32,
    /// Its first child (the four follow in the order `(0, 0), (1, 0), (0, 1), (1, 1)`
    /// of `(k, j)`), or 0 for a leaf (element 0 is nobody's child).
    pub children: u32,
    /// Its level below the base grid (0: a base element).
    pub level: u8,
    /// Its cell `(k, j)` in the patch's grid at its level.
    pub cell: [u32; 2],
}

impl Element {
    /// Whether it receives and is shown (it is not split).
    pub fn is_leaf(&self) -> bool {
        self.children == 0
    }
}

/// Deepest level of subdivision below the base grid.
pub(crate) const MAX_LEVEL: u8 = 4;

/// Key of a lookup cell: solid, face axis, outward sign, plane, and the cell of the
/// in-plane grid.
type CellKey = (u32, u8, bool, u32, u32, u32);

/// Key of a lookup cell of the surface patches: solid and the cell of a 3D grid.
type SpaceKey = (u32, [i64; 3]);

/// The patches and elements of a scene, and the lookup from surface points to them.
#[derive(Clone, Debug)]
pub(crate) struct Patches {
    pub patches: Vec<Patch>,
    pub elements: Vec<Element>,
    /// Patch edge in voxels, for each solid (the lookup grid's cell).
    cells: Vec<u32>,
    /// Each solid's domain.
    domains: Vec<Domain>,
    lookup: FxHashMap<CellKey, SmallVec<[u32; 2]>>,
    /// The surface patches meeting each cell of each solid's 3D grid.
    space: FxHashMap<SpaceKey, SmallVec<[u32; 4]>>,
    /// Whether each solid's patches are tiles of its true surface.
    on_surface: Vec<bool>,
    /// The elements split, in order (what a `.rad` file stores to rebuild them).
    pub splits: Vec<u32>,
}

/// Estimated bytes a patch and an element take while solving (records, lookup,
/// radiosity and the shot's increments).
const BYTES_PER_PATCH: u64 = 256;
pub(crate) const BYTES_PER_ELEMENT: u64 = 160;

/// Sizes `n` equal-as-possible whole parts of `len` voxels: `(offset, size)` of each.
fn split(len: u32, n: u32) -> impl Iterator<Item = (u32, u32)> {
    let (base, extra) = (len / n, len % n);
    (0..n).map(move |i| (i * base + i.min(extra), base + u32::from(i < extra)))
}

/// Element `cell` of patch `p` (index `patch`) at `level`: its centre on the face (of
/// a partly covered tile: the centroid of the surface in its cell, moved onto the
/// shape's surface), the smooth shape normal there (else the patch's normal) and its
/// area.
fn element(scene: &Scene, p: &Patch, patch: u32, level: u8, cell: [u32; 2]) -> Element {
    let (nu, nv) = (f64::from(p.nu << level), f64::from(p.nv << level));
    let [k, j] = cell.map(f64::from);
    let cells = f64::from(p.nu * p.nv) * f64::from(1u32 << (2 * level));
    let ((s, t), area) = match &p.cover {
        None => (((k + 0.5) / nu, (j + 0.5) / nv), p.area / cells),
        Some(cover) => {
            let (fraction, c) = cover.within(k / nu, (k + 1.0) / nu, j / nv, (j + 1.0) / nv);
            ((c.x, c.y), fraction * p.rect_area())
        }
    };
    let mut center = p.point(s, t);
    let solid = &scene.solids[p.solid as usize];
    let facing = |c: DVec3| solid.shape_surface(c).filter(|s| s.normal.is_finite() && s.normal.dot(p.normal) > 0.0);
    let mut surface = facing(center);
    if p.face.is_none()
        && let Some(s) = surface
        && s.distance != 0.0
    {
        // Onto the surface, and its normal there.
        center -= s.normal * s.distance;
        surface = facing(center).or(surface);
    }
    let normal = surface.map_or(p.normal, |s| s.normal);
    let lifted = if p.face.is_some() { p.normal } else { normal };
    Element {
        center,
        origin: center + lifted * p.lift,
        normal,
        area,
        patch,
        children: 0,
        level,
        cell: [cell[0], cell[1]],
    }
}

/// Refuses a patch size that is not finite and positive, or elements a patch side
/// outside `1..=64`.
fn check_settings(patch_size: f64, elements: u32) -> Result<()> {
    if !(patch_size.is_finite() && patch_size > 0.0) {
        return Err(Error::invalid(
            "patch size",
            format!("{} must be a finite positive number", crate::error::Number(patch_size)),
        ));
    }
    if !(1..=64).contains(&elements) {
        return Err(Error::invalid("elements", format!("{elements} a patch side is outside 1..=64")));
    }
    Ok(())
}

/// Each solid's patch edge in voxels: `patch_size` in its voxels, rounded down, at
/// least 1 and at most `2^21`.
fn patch_cells(scene: &Scene, patch_size: f64) -> Vec<u32> {
    scene
        .solids
        .iter()
        .map(|s| (patch_size / s.tree.domain().voxel_size()).floor().clamp(1.0, f64::from(1u32 << 21)) as u32)
        .collect()
}

/// The patch and element counts of one solid's boundary rectangles, counted before
/// building.
fn face_counts(rects: &[BoundaryRect], cell: u32, elements: u32) -> (u64, u64) {
    let (mut patch_count, mut element_count) = (0u64, 0u64);
    for r in rects {
        let (nu, nv) = (r.w.div_ceil(cell), r.h.div_ceil(cell));
        patch_count += u64::from(nu) * u64::from(nv);
        // The tiles of the build below, each with up to `elements` a side.
        let side = |len: u32, n: u32| split(len, n).map(|(_, w)| u64::from(elements.min(w))).sum::<u64>();
        element_count += side(r.w, nu) * side(r.h, nv);
    }
    (patch_count, element_count)
}

/// Refuses patch and element counts whose estimated memory exceeds `budget`, or whose
/// elements cannot be numbered in a `u32`.
fn check_counts(patch_count: u64, element_count: u64, budget: MemoryBudget) -> Result<()> {
    let job = format!("radiosity on {patch_count} patches of {element_count} elements");
    budget.check(job, patch_count * BYTES_PER_PATCH + element_count * BYTES_PER_ELEMENT)?;
    if element_count > u64::from(u32::MAX) {
        return Err(Error::invalid("radiosity", format!("{element_count} elements are more than 2^32")));
    }
    Ok(())
}

/// Every boundary rectangle of solid `solid` cut into equal-as-possible patches of at
/// most `cell` voxels a side, each with up to `elements` elements a side, appended to
/// `patches`; their first elements are not numbered yet.
fn cut_into_patches(
    scene: &Scene,
    solid: usize,
    rects: &[BoundaryRect],
    cell: u32,
    elements: u32,
    patches: &mut Vec<Patch>,
) {
    {
        let s = &scene.solids[solid];
        let domain = s.tree.domain();
        let h = domain.voxel_size();
        let (reflectance, emission) = (s.material.diffuse_reflectance(), s.material.emission);
        for r in rects {
            let a = usize::from(r.axis);
            let (ua, va) = ((a + 1) % 3, (a + 2) % 3);
            let mut normal = DVec3::ZERO;
            normal[a] = if r.positive { 1.0 } else { -1.0 };
            for (dv0, hv) in split(r.h, r.h.div_ceil(cell)) {
                for (du0, wu) in split(r.w, r.w.div_ceil(cell)) {
                    let rect = BoundaryRect { u: r.u + du0, v: r.v + dv0, w: wu, h: hv, ..*r };
                    let mut lattice = [0u32; 3];
                    lattice[a] = rect.plane;
                    lattice[ua] = rect.u;
                    lattice[va] = rect.v;
                    let (mut du, mut dv) = (DVec3::ZERO, DVec3::ZERO);
                    du[ua] = f64::from(wu) * h;
                    dv[va] = f64::from(hv) * h;
                    patches.push(Patch {
                        solid: solid as u32,
                        face: Some(rect),
                        cover: None,
                        corner: domain.lattice_point(lattice),
                        du,
                        dv,
                        normal,
                        area: du[ua] * dv[va],
                        reflectance,
                        emission,
                        first: 0,
                        nu: elements.min(wu),
                        nv: elements.min(hv),
                        lift: 1e-3 * h,
                    });
                }
            }
        }
    }
}

/// Numbers each patch's first element, the patches' elements following one another;
/// returns the element count.
fn number_elements(patches: &mut [Patch]) -> u32 {
    let mut first = 0u32;
    for p in patches {
        p.first = first;
        first += p.nu * p.nv;
    }
    first
}

/// Every patch's elements at level 0, in patch order, row by row.
fn first_level_elements(scene: &Scene, patches: &[Patch]) -> Vec<Element> {
    patches
        .par_iter()
        .enumerate()
        .flat_map_iter(|(i, p)| {
            (0..p.nv).flat_map(move |j| (0..p.nu).map(move |k| element(scene, p, i as u32, 0, [k, j])))
        })
        .collect()
}

/// The lookup from each cell of each solid's face planes to the voxel-boundary
/// patches that meet it.
fn patch_lookup(patches: &[Patch], cells: &[u32]) -> FxHashMap<CellKey, SmallVec<[u32; 2]>> {
    let mut lookup: FxHashMap<CellKey, SmallVec<[u32; 2]>> = FxHashMap::default();
    for (i, p) in patches.iter().enumerate() {
        let Some(r) = &p.face else { continue };
        let c = cells[p.solid as usize];
        for cv in r.v / c..=(r.v + r.h - 1) / c {
            for cu in r.u / c..=(r.u + r.w - 1) / c {
                lookup.entry((p.solid, r.axis, r.positive, r.plane, cu, cv)).or_default().push(i as u32);
            }
        }
    }
    lookup
}

/// Margin, in voxels, around a tile's rectangle within which points find it: the
/// staircase lies within a voxel of the true surface.
const SPACE_MARGIN: f64 = 2.0;

/// The cell of `p` in the 3D lookup grid of cells `cell` voxels across of `domain`.
fn space_cell(domain: &Domain, cell: u32, p: DVec3) -> [i64; 3] {
    let q = (p - domain.min()) / (domain.voxel_size() * f64::from(cell));
    [q.x, q.y, q.z].map(|c| c.floor().clamp(-1e15, 1e15) as i64)
}

/// The lookup from each cell of each solid's 3D grid to the surface patches whose
/// rectangle (grown by [`SPACE_MARGIN`] voxels and, for a partly covered tile, by half
/// its longer side: a curved cluster's surface bulges off its plane) meets it.
fn space_lookup(patches: &[Patch], cells: &[u32], domains: &[Domain]) -> FxHashMap<SpaceKey, SmallVec<[u32; 4]>> {
    let mut lookup: FxHashMap<SpaceKey, SmallVec<[u32; 4]>> = FxHashMap::default();
    for (i, p) in patches.iter().enumerate() {
        if p.face.is_some() {
            continue;
        }
        let domain = &domains[p.solid as usize];
        let bulge = if p.cover.is_some() { 0.5 * p.du.length().max(p.dv.length()) } else { 0.0 };
        let margin = DVec3::splat(SPACE_MARGIN * domain.voxel_size() + bulge);
        let corners = p.corners();
        let lo = corners.iter().fold(DVec3::MAX, |a, &c| a.min(c)) - margin;
        let hi = corners.iter().fold(DVec3::MIN, |a, &c| a.max(c)) + margin;
        let cell = cells[p.solid as usize];
        let (a, b) = (space_cell(domain, cell, lo), space_cell(domain, cell, hi));
        for z in a[2]..=b[2] {
            for y in a[1]..=b[1] {
                for x in a[0]..=b[0] {
                    lookup.entry((p.solid, [x, y, z])).or_default().push(i as u32);
                }
            }
        }
    }
    lookup
}

impl Patches {
    /// The patches of every solid of `scene` no longer than `patch_size` (world units)
    /// with up to `elements x elements` elements each; refused when their estimated
    /// memory exceeds `budget`. A solid's true surface is extracted only while `stop`
    /// does not ask to stop ([`Progress::cancelled`]; then `Cancelled`).
    pub fn build(
        scene: &Scene,
        patch_size: f64,
        elements: u32,
        budget: MemoryBudget,
        stop: &dyn Progress,
    ) -> Result<Patches> {
        check_settings(patch_size, elements)?;
        let cells = patch_cells(scene, patch_size);
        // Each solid's true surface tiles (a solid made from a shape), or its boundary
        // rectangles, counted before any element is made.
        enum Part {
            Surface(Vec<Vec<Patch>>),
            Faces(Vec<BoundaryRect>),
        }
        // The solids side by side (each surface's extraction is within `budget`, their
        // tiles together).
        let tally = TileTally::default();
        let found: Vec<(Part, u64, u64)> = scene
            .solids
            .par_iter()
            .enumerate()
            .map(|(i, solid)| {
                Ok(if solid.shape().is_some() {
                    let found = surface_patches(scene, i as u32, patch_size, elements, budget, &tally, stop)?;
                    let count = found.count() as u64;
                    (Part::Surface(found.regions), count, found.elements)
                } else {
                    let rects = boundary_rects(&solid.tree);
                    let (p, e) = face_counts(&rects, cells[i], elements);
                    (Part::Faces(rects), p, e)
                })
            })
            .collect::<Result<_>>()?;
        let (mut patch_count, mut element_count) = (0u64, 0u64);
        let mut parts = Vec::with_capacity(scene.solids.len());
        for (part, p, e) in found {
            patch_count += p;
            element_count += e;
            parts.push(part);
        }
        check_counts(patch_count, element_count, budget)?;
        let mut patches = Vec::with_capacity(patch_count as usize);
        let on_surface = parts.iter().map(|p| matches!(p, Part::Surface(_))).collect();
        for (solid, part) in parts.into_iter().enumerate() {
            match part {
                Part::Surface(regions) => patches.extend(regions.into_iter().flatten()),
                Part::Faces(rects) => cut_into_patches(scene, solid, &rects, cells[solid], elements, &mut patches),
            }
        }
        let first = number_elements(&mut patches);
        debug_assert_eq!(u64::from(first), element_count, "the count before building is the build's");
        let elements = first_level_elements(scene, &patches);
        let lookup = patch_lookup(&patches, &cells);
        let domains: Vec<Domain> = scene.solids.iter().map(|s| *s.tree.domain()).collect();
        let space = space_lookup(&patches, &cells, &domains);
        Ok(Patches { patches, elements, cells, domains, lookup, space, on_surface, splits: Vec::new() })
    }

    /// A patch's sides in its solid's voxels.
    pub fn sides_in_voxels(&self, i: usize) -> (f64, f64) {
        let p = &self.patches[i];
        let h = self.domains[p.solid as usize].voxel_size();
        (p.du.length() / h, p.dv.length() / h)
    }

    /// The leaf to show at `(s, t)` of patch `i`: the leaf holding it, or where that
    /// has no area (a cell of a tile the surface misses), the base element of area
    /// nearest to it (its leaf at the element's centre).
    pub fn shown_leaf(&self, i: usize, s: f64, t: f64) -> usize {
        let leaf = self.leaf_at(i, s, t);
        if self.elements[leaf].area > 0.0 {
            return leaf;
        }
        let p = &self.patches[i];
        let (w, h) = (p.du.length(), p.dv.length());
        let mut best = (f64::MAX, leaf);
        for e in p.first..p.first + p.nu * p.nv {
            let el = &self.elements[e as usize];
            if el.area <= 0.0 {
                continue;
            }
            let [k, j] = el.cell;
            let (cs, ct) = ((f64::from(k) + 0.5) / f64::from(p.nu), (f64::from(j) + 0.5) / f64::from(p.nv));
            let d = ((cs - s) * w).powi(2) + ((ct - t) * h).powi(2);
            if d < best.0 {
                best = (d, self.leaf_at(i, cs, ct));
            }
        }
        best.1
    }

    /// Most elements (split ones included) whose estimated memory, with the patches',
    /// fits `budget`.
    pub fn elements_within(&self, budget: MemoryBudget) -> usize {
        let patches = self.patches.len() as u64 * BYTES_PER_PATCH;
        (budget.0.saturating_sub(patches) / BYTES_PER_ELEMENT).min(u64::from(u32::MAX)) as usize
    }

    /// The base element (level 0) element `e` lies in.
    pub fn base_element(&self, e: usize) -> usize {
        let el = &self.elements[e];
        let p = &self.patches[el.patch as usize];
        let [k, j] = el.cell.map(|c| c >> el.level);
        (p.first + j * p.nu + k) as usize
    }

    /// Elements that receive and are shown (not split).
    pub fn leaf_count(&self) -> usize {
        self.elements.len() - self.splits.len()
    }

    /// The leaf element holding `(s, t)` of patch `i`.
    pub fn leaf_at(&self, i: usize, s: f64, t: f64) -> usize {
        let p = &self.patches[i];
        let k = ((s * f64::from(p.nu)) as u32).min(p.nu - 1);
        let j = ((t * f64::from(p.nv)) as u32).min(p.nv - 1);
        let mut e = (p.first + j * p.nu + k) as usize;
        while !self.elements[e].is_leaf() {
            let child = &self.elements[e];
            let level = u32::from(child.level) + 1;
            let (nu, nv) = (p.nu << level, p.nv << level);
            let k = ((s * f64::from(nu)) as u32).min(nu - 1);
            let j = ((t * f64::from(nv)) as u32).min(nv - 1);
            e = (child.children + (k & 1) + 2 * (j & 1)) as usize;
        }
        e
    }

    /// The leaves just beyond the middle of each edge of element `e`, on its face
    /// plane (in the coplanar patch there across a patch border; none off the face).
    pub fn edge_neighbours(&self, e: usize) -> impl Iterator<Item = usize> + '_ {
        let el = &self.elements[e];
        let i = el.patch as usize;
        let p = &self.patches[i];
        let (nu, nv) = (f64::from(p.nu << el.level), f64::from(p.nv << el.level));
        let [k, j] = el.cell;
        let (cs, ct) = ((f64::from(k) + 0.5) / nu, (f64::from(j) + 0.5) / nv);
        [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)].into_iter().filter_map(move |(dk, dj)| {
            let (s, t) = (cs + dk / nu, ct + dj / nv);
            if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
                return Some(self.leaf_at(i, s, t));
            }
            let (n, ns, nt) = self.find(p.solid as usize, p.point(s, t), p.normal)?;
            Some(self.leaf_at(n, ns, nt))
        })
    }

    /// Whether element `e` may be split: a leaf above [`MAX_LEVEL`] whose children are
    /// at least a voxel wide.
    pub fn can_split(&self, e: usize) -> bool {
        let el = &self.elements[e];
        let p = &self.patches[el.patch as usize];
        let h = self.domains[p.solid as usize].voxel_size();
        let scale = f64::from(1u32 << (el.level + 1));
        el.is_leaf()
            && el.area > 0.0
            && el.level < MAX_LEVEL
            && p.du.length() / (f64::from(p.nu) * scale) >= h * (1.0 - 1e-9)
            && p.dv.length() / (f64::from(p.nv) * scale) >= h * (1.0 - 1e-9)
    }

    /// Splits leaf `e` into its four children (appended); returns the first child's
    /// index. `e` must pass [`Patches::can_split`].
    pub fn split(&mut self, scene: &Scene, e: usize) -> u32 {
        debug_assert!(self.can_split(e), "element {e} cannot be split");
        let el = self.elements[e];
        let p = &self.patches[el.patch as usize];
        let first = self.elements.len() as u32;
        let [k, j] = el.cell;
        for (dk, dj) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
            self.elements.push(element(scene, p, el.patch, el.level + 1, [2 * k + dk, 2 * j + dj]));
        }
        self.elements[e].children = first;
        self.splits.push(e as u32);
        first
    }

    /// The patch holding the point `p` on the face of outward axis normal `face` of
    /// solid `solid` (see the module doc for surface patches), and `p`'s fractions
    /// along its `u` and `v` edges.
    pub fn find(&self, solid: usize, p: DVec3, face: DVec3) -> Option<(usize, f64, f64)> {
        if *self.on_surface.get(solid)? {
            return self.find_on_surface(solid, p, face);
        }
        let a = (0..3).find(|&a| face[a] != 0.0)?;
        let positive = face[a] > 0.0;
        let domain = self.domains.get(solid)?;
        let q = (p - domain.min()) / domain.voxel_size();
        let (ua, va) = ((a + 1) % 3, (a + 2) % 3);
        let plane = q[a].round();
        let c = f64::from(*self.cells.get(solid)?);
        if !(plane >= 0.0 && q[ua] >= 0.0 && q[va] >= 0.0 && plane < 4.3e9) {
            return None;
        }
        let (cu, cv) = ((q[ua] / c).floor().min(4.2e9) as u32, (q[va] / c).floor().min(4.2e9) as u32);
        let key = (solid as u32, a as u8, positive, plane as u32, cu, cv);
        let tolerance = 1e-6;
        self.lookup.get(&key)?.iter().find_map(|&i| {
            let r = self.patches[i as usize].face.as_ref()?;
            let s = (q[ua] - f64::from(r.u)) / f64::from(r.w);
            let t = (q[va] - f64::from(r.v)) / f64::from(r.h);
            let inside = (-tolerance..=1.0 + tolerance).contains(&s) && (-tolerance..=1.0 + tolerance).contains(&t);
            inside.then_some((i as usize, s.clamp(0.0, 1.0), t.clamp(0.0, 1.0)))
        })
    }

    /// [`Patches::find`] on a solid with surface patches: the nearest rectangle of the
    /// patches registered in `p`'s cell whose normal faces the way `face` does.
    fn find_on_surface(&self, solid: usize, p: DVec3, face: DVec3) -> Option<(usize, f64, f64)> {
        let domain = self.domains.get(solid)?;
        if !p.is_finite() {
            return None;
        }
        let key = (solid as u32, space_cell(domain, self.cells[solid], p));
        let mut best: Option<(f64, usize, f64, f64)> = None;
        for &i in self.space.get(&key)? {
            let patch = &self.patches[i as usize];
            if patch.normal.dot(face) <= 1e-9 {
                continue;
            }
            let q = p - patch.corner;
            let (s, t) = (q.dot(patch.du) / patch.du.length_squared(), q.dot(patch.dv) / patch.dv.length_squared());
            let (cs, ct) = (s.clamp(0.0, 1.0), t.clamp(0.0, 1.0));
            let off = q.dot(patch.normal);
            let d = off * off + ((s - cs) * patch.du.length()).powi(2) + ((t - ct) * patch.dv.length()).powi(2);
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, i as usize, cs, ct));
            }
        }
        best.map(|(_, i, s, t)| (i, s, t))
    }
}
