//! Patches and elements: the two-level hierarchy radiosity solves on, cut from the
//! octree's own boundary.
//!
//! Each solid's boundary is the set of exposed faces of its full nodes, merged into
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
//! Normals: an element's normal is its face's outward axis normal, or the source
//! shape's smooth normal at the element's centre where the solid came from a shape
//! whose surface lies within two voxels of it ([`SceneSolid::shape_surface`]), so a
//! sphere's elements are lit as the sphere is, not as its voxel staircase. Patches
//! shoot from their flat faces (their light leaves by their axis normal).
//!
//! Lookup for display: a point on a face finds its patch through a hash of the face's
//! plane and the cell of a grid of `patch_size` cells in that plane (a patch meets at
//! most four cells), then its place in the element grid.

use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::mesh::{BoundaryRect, boundary_rects};
use crate::octree::Domain;
use crate::render::scene::Scene;

/// A shooting patch: a rectangle of one face plane of one solid.
#[derive(Clone, Debug)]
pub(crate) struct Patch {
    /// The solid it belongs to.
    pub solid: u32,
    /// Its rectangle in the solid's lattice.
    pub rect: BoundaryRect,
    /// World corner at the rectangle's lowest `(u, v)`, and its world edges along `u`
    /// and `v`.
    pub corner: DVec3,
    pub du: DVec3,
    pub dv: DVec3,
    /// Outward unit axis normal.
    pub normal: DVec3,
    /// Area (world units squared).
    pub area: f64,
    /// Diffuse reflectance, `color * kd`.
    pub reflectance: DVec3,
    /// Emitted radiance.
    pub emission: DVec3,
    /// Its first element and its element grid (`nu` along `u`, `nv` along `v`; element
    /// `(i, j)` is `first + j nu + i`).
    pub first: u32,
    pub nu: u32,
    pub nv: u32,
    /// Offset off the face for rays leaving it: a thousandth of the solid's voxel.
    pub lift: f64,
}

impl Patch {
    /// The world point at fractions `(s, t)` of the patch along `u` and `v`.
    pub fn point(&self, s: f64, t: f64) -> DVec3 {
        self.corner + self.du * s + self.dv * t
    }

    /// The four corners, counter-clockwise or clockwise (the form factor takes either).
    pub fn corners(&self) -> [DVec3; 4] {
        [self.corner, self.corner + self.du, self.corner + self.du + self.dv, self.corner + self.dv]
    }

    /// The centre.
    pub fn center(&self) -> DVec3 {
        self.point(0.5, 0.5)
    }
}

/// A receiving element.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Element {
    /// Centre, on the face.
    pub center: DVec3,
    /// The point rays leave from: the centre lifted off the face along its axis normal.
    pub origin: DVec3,
    /// Unit normal: the smooth shape normal where there is one, else the axis normal.
    pub normal: DVec3,
    /// Area.
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

/// Element `cell` of patch `p` (index `patch`) at `level`: its centre on the face, the
/// smooth shape normal there (else the axis normal) and its area.
fn element(scene: &Scene, p: &Patch, patch: u32, level: u8, cell: [u32; 2]) -> Element {
    let (nu, nv) = (p.nu << level, p.nv << level);
    let [k, j] = cell;
    let center = p.point((f64::from(k) + 0.5) / f64::from(nu), (f64::from(j) + 0.5) / f64::from(nv));
    let normal = scene.solids[p.solid as usize]
        .shape_surface(center)
        .map(|s| s.normal)
        .filter(|n| n.is_finite() && n.dot(p.normal) > 0.0)
        .unwrap_or(p.normal);
    let area = p.area / f64::from(p.nu * p.nv) / f64::from(1u32 << (2 * level));
    Element { center, origin: center + p.normal * p.lift, normal, area, patch, children: 0, level, cell }
}

/// Refuses a patch size that is not finite and positive, or elements a patch side
/// outside `1..=64`.
fn check_settings(patch_size: f64, elements: u32) -> Result<()> {
    if !(patch_size.is_finite() && patch_size > 0.0) {
        return Err(Error::invalid("patch size", format!("{patch_size} must be a finite positive number")));
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

/// The patch and element counts, counted before building, once their estimated
/// memory fits `budget` and the elements can be numbered in a `u32`.
fn counts_within_budget(
    rects: &[Vec<BoundaryRect>],
    cells: &[u32],
    elements: u32,
    budget: MemoryBudget,
) -> Result<(u64, u64)> {
    let (mut patch_count, mut element_count) = (0u64, 0u64);
    for (rects, &cell) in rects.iter().zip(cells) {
        for r in rects {
            let (nu, nv) = (r.w.div_ceil(cell), r.h.div_ceil(cell));
            patch_count += u64::from(nu) * u64::from(nv);
            // The tiles of the build below, each with up to `elements` a side.
            let side = |len: u32, n: u32| split(len, n).map(|(_, w)| u64::from(elements.min(w))).sum::<u64>();
            element_count += side(r.w, nu) * side(r.h, nv);
        }
    }
    let job = format!("radiosity on {patch_count} patches of {element_count} elements");
    budget.check(job, patch_count * BYTES_PER_PATCH + element_count * BYTES_PER_ELEMENT)?;
    if element_count > u64::from(u32::MAX) {
        return Err(Error::invalid("radiosity", format!("{element_count} elements are more than 2^32")));
    }
    Ok((patch_count, element_count))
}

/// Every boundary rectangle of every solid cut into equal-as-possible patches of at
/// most its solid's cell a side, each with up to `elements` elements a side; their
/// first elements are not numbered yet.
fn cut_into_patches(
    scene: &Scene,
    rects: &[Vec<BoundaryRect>],
    cells: &[u32],
    elements: u32,
    patch_count: u64,
) -> Vec<Patch> {
    let mut patches = Vec::with_capacity(patch_count as usize);
    for (solid, (rects, &cell)) in rects.iter().zip(cells).enumerate() {
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
                        rect,
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
    patches
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

/// The lookup from each cell of each solid's face planes to the patches that meet it.
fn patch_lookup(patches: &[Patch], cells: &[u32]) -> FxHashMap<CellKey, SmallVec<[u32; 2]>> {
    let mut lookup: FxHashMap<CellKey, SmallVec<[u32; 2]>> = FxHashMap::default();
    for (i, p) in patches.iter().enumerate() {
        let c = cells[p.solid as usize];
        let r = &p.rect;
        for cv in r.v / c..=(r.v + r.h - 1) / c {
            for cu in r.u / c..=(r.u + r.w - 1) / c {
                lookup.entry((p.solid, r.axis, r.positive, r.plane, cu, cv)).or_default().push(i as u32);
            }
        }
    }
    lookup
}

impl Patches {
    /// The patches of every solid of `scene` no longer than `patch_size` (world units)
    /// with up to `elements x elements` elements each; refused when their estimated
    /// memory exceeds `budget`.
    pub fn build(scene: &Scene, patch_size: f64, elements: u32, budget: MemoryBudget) -> Result<Patches> {
        check_settings(patch_size, elements)?;
        let rects: Vec<Vec<BoundaryRect>> = scene.solids.iter().map(|s| boundary_rects(&s.tree)).collect();
        let cells = patch_cells(scene, patch_size);
        let (patch_count, element_count) = counts_within_budget(&rects, &cells, elements, budget)?;
        let mut patches = cut_into_patches(scene, &rects, &cells, elements, patch_count);
        let first = number_elements(&mut patches);
        debug_assert_eq!(u64::from(first), element_count, "the count before building is the build's");
        let elements = first_level_elements(scene, &patches);
        let lookup = patch_lookup(&patches, &cells);
        let domains = scene.solids.iter().map(|s| *s.tree.domain()).collect();
        Ok(Patches { patches, elements, cells, domains, lookup, splits: Vec::new() })
    }

    /// Most elements (split ones included) whose estimated memory, with the patches',
    /// fits `budget`.
    pub fn elements_within(&self, budget: MemoryBudget) -> usize {
        let patches = self.patches.len() as u64 * BYTES_PER_PATCH;
        (budget.0.saturating_sub(patches) / BYTES_PER_ELEMENT).min(u64::from(u32::MAX)) as usize
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
    /// solid `solid`, and `p`'s fractions along its `u` and `v` edges.
    pub fn find(&self, solid: usize, p: DVec3, face: DVec3) -> Option<(usize, f64, f64)> {
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
            let r = &self.patches[i as usize].rect;
            let s = (q[ua] - f64::from(r.u)) / f64::from(r.w);
            let t = (q[va] - f64::from(r.v)) / f64::from(r.h);
            let inside = (-tolerance..=1.0 + tolerance).contains(&s) && (-tolerance..=1.0 + tolerance).contains(&t);
            inside.then_some((i as usize, s.clamp(0.0, 1.0), t.clamp(0.0, 1.0)))
        })
    }
}
