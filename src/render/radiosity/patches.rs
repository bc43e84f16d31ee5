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
}

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
}

/// Estimated bytes a patch and an element take while solving (records, lookup,
/// radiosity and the shot's increments).
const BYTES_PER_PATCH: u64 = 256;
const BYTES_PER_ELEMENT: u64 = 160;

/// Sizes `n` equal-as-possible whole parts of `len` voxels: `(offset, size)` of each.
fn split(len: u32, n: u32) -> impl Iterator<Item = (u32, u32)> {
    let (base, extra) = (len / n, len % n);
    (0..n).map(move |i| (i * base + i.min(extra), base + u32::from(i < extra)))
}

impl Patches {
    /// The patches of every solid of `scene` no longer than `patch_size` (world units)
    /// with up to `elements x elements` elements each; refused when their estimated
    /// memory exceeds `budget`.
    pub fn build(scene: &Scene, patch_size: f64, elements: u32, budget: MemoryBudget) -> Result<Patches> {
        if !(patch_size.is_finite() && patch_size > 0.0) {
            return Err(Error::invalid("patch size", format!("{patch_size} must be a finite positive number")));
        }
        if !(1..=64).contains(&elements) {
            return Err(Error::invalid("elements", format!("{elements} a patch side is outside 1..=64")));
        }
        let rects: Vec<Vec<BoundaryRect>> = scene.solids.iter().map(|s| boundary_rects(&s.tree)).collect();
        let cells: Vec<u32> = scene
            .solids
            .iter()
            .map(|s| (patch_size / s.tree.domain().voxel_size()).floor().clamp(1.0, f64::from(1u32 << 21)) as u32)
            .collect();
        // Count before building.
        let (mut patch_count, mut element_count) = (0u64, 0u64);
        for (rects, &cell) in rects.iter().zip(&cells) {
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
        let mut patches = Vec::with_capacity(patch_count as usize);
        for (solid, (rects, &cell)) in rects.iter().zip(&cells).enumerate() {
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
        let mut first = 0u32;
        for p in &mut patches {
            p.first = first;
            first += p.nu * p.nv;
        }
        debug_assert_eq!(u64::from(first), element_count, "the count before building is the build's");
        let elements: Vec<Element> = patches
            .par_iter()
            .enumerate()
            .flat_map_iter(|(i, p)| {
                let solid = &scene.solids[p.solid as usize];
                let area = p.area / f64::from(p.nu * p.nv);
                (0..p.nv).flat_map(move |j| {
                    (0..p.nu).map(move |k| {
                        let center =
                            p.point((f64::from(k) + 0.5) / f64::from(p.nu), (f64::from(j) + 0.5) / f64::from(p.nv));
                        let normal = solid
                            .shape_surface(center)
                            .map(|s| s.normal)
                            .filter(|n| n.is_finite() && n.dot(p.normal) > 0.0)
                            .unwrap_or(p.normal);
                        Element { center, origin: center + p.normal * p.lift, normal, area, patch: i as u32 }
                    })
                })
            })
            .collect();
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
        let domains = scene.solids.iter().map(|s| *s.tree.domain()).collect();
        Ok(Patches { patches, elements, cells, domains, lookup })
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
