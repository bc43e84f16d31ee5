//! The exact surface of an analytic solid, as the oracle of issue 38's mesh quality:
//! for a point, the nearest point of the solid's SURFACE, its distance, the solid's
//! outward normal there and how far that point lies from the nearest crease (sharp
//! edge); and the measurement of a mesh against it at area-weighted samples.
//!
//! A solid is a boolean tree ([`Csg`]) over primitive surfaces ([`Primitive`]: an
//! axis-aligned plane bounding a half-space, a sphere, an infinite axis-aligned
//! cylinder, a torus about z), each with its inside. Its boundary is made of
//!
//! - **faces**: points x of a primitive surface i where the tree's value depends on
//!   i's bit (the other primitives evaluated at x): flipping i's inside changes
//!   membership, so x separates inside from outside;
//! - **creases**: points of the curve where two primitive surfaces meet at which the
//!   tree depends on both bits (one flip alone changes membership for each), i.e.
//!   where two faces meet at an angle;
//! - **corners**: points where a crease meets a third surface.
//!
//! The nearest boundary point to p is the least of three kinds of candidates (the
//! distance restricted to a face region has no interior minimum but the global one,
//! since on a plane, sphere or cylinder the distance from p has one local minimum, the
//! cylinder's other critical point a saddle; else it lies on the region's border, a
//! crease, and on a crease, whose distance is unimodal for lines and circles, at a
//! local minimum along it or at the crease's own border, a corner; a torus is never
//! cut, so its projection is the answer):
//! the projection of p on each primitive surface, kept when it is a face point; the
//! nearest point of each crease curve, kept when it is a crease point; the corners.
//!
//! Crease curves are exact where the geometry is: plane & plane a line, plane & sphere
//! a circle, plane & cylinder a circle (plane across the axis) or two lines (plane
//! along it), sphere & sphere a circle. Sphere & cylinder and cylinder & cylinder
//! curves are parametrised by the angle on the cylinder, the coordinate along its
//! axis solved from the other surface (two branches, a square root). Each curve is
//! sampled at [`CURVE_SAMPLES`] parameters once (the points where a branch ends found
//! by bisection), the samples where it is a crease kept in chunks with their boxes; a
//! query takes the nearest kept sample (chunks pruned by box) and refines it by golden
//! section over the parameter on both neighbouring intervals, a refined point kept
//! only where it is still a crease. Corners are found once along the sampled curves:
//! where a third primitive's signed distance changes sign, by bisection (a curve only
//! touching a third surface, without crossing it, is missed). A torus meets nothing:
//! a solid with a torus and another primitive is refused.
//!
//! The normal at a face point is the primitive's outward normal, reversed where the
//! solid lies on the primitive's outside (a subtracted primitive). At a crease or
//! corner it is the direction from that point to p (away from the solid when p is
//! outside), the distance field's gradient; samples there are ignored by [`measure`]
//! (they lie within [`EDGE_BAND_VOXELS`] of a crease).
//!
//! [`measure`] samples a mesh ([`sample_mesh`]: triangles chosen in proportion to
//! their area, points uniform in them by the square-root map of Osada et al. 2002,
//! "Shape distributions") and reports issue 38's columns: the distance to the exact
//! surface (RMS and maximum, in voxels) at every sample, and the angle between the
//! triangle's normal (as wound: counter-clockwise seen from outside) and the exact
//! normal at the nearest surface point, median and share within 5 degrees, over the
//! samples whose nearest surface point lies at least [`EDGE_BAND_VOXELS`] from every
//! crease. Samples are measured in parallel ([`par_map`]: scoped threads, so the
//! suites of every package that include tests/common need no thread pool crate) and
//! the statistics are independent of the order.
#![allow(dead_code)]

use glam::DVec3;
use octsolid::mesh::TriangleMesh;

/// Samples of each crease curve's parameter range.
pub const CURVE_SAMPLES: usize = 4096;
/// Samples a chunk of a crease curve (one box).
const CHUNK: usize = 32;
/// Samples [`measure`] takes by default (issue 38's table).
pub const DEFAULT_SAMPLES: usize = 200_000;
/// Samples whose nearest surface point lies closer than this to a crease (in voxels)
/// are left out of the normal statistics.
pub const EDGE_BAND_VOXELS: f64 = 2.0;
/// The angle (degrees) of the "share within" column.
pub const WITHIN_DEGREES: f64 = 5.0;

/// One primitive surface and its inside.
#[derive(Clone, Copy, Debug)]
pub enum Primitive {
    /// The plane `x[axis] = at`; inside where `outward * (x[axis] - at) <= 0`
    /// (`outward` is +1 or -1: the side its normal points to).
    Plane { axis: usize, at: f64, outward: f64 },
    /// A sphere; inside within it.
    Sphere { centre: DVec3, radius: f64 },
    /// An infinite cylinder along a coordinate axis through `centre`; inside within it.
    Cylinder { axis: usize, centre: DVec3, radius: f64 },
    /// A torus about the z axis through `centre`: the tube of radius `minor` about the
    /// circle of radius `major`; inside within the tube.
    Torus { centre: DVec3, major: f64, minor: f64 },
}

/// The unit vector of a coordinate axis.
fn unit(axis: usize) -> DVec3 {
    let mut e = DVec3::ZERO;
    e[axis] = 1.0;
    e
}

/// The two axes other than `axis`, in cyclic order (so `e[u] x e[v] = e[axis]`).
fn across(axis: usize) -> (usize, usize) {
    ((axis + 1) % 3, (axis + 2) % 3)
}

/// `p` with its `axis` coordinate zeroed (the part across a cylinder's axis).
fn flatten(p: DVec3, axis: usize) -> DVec3 {
    let mut q = p;
    q[axis] = 0.0;
    q
}

/// A unit vector perpendicular to `d` (for a radial direction that is undefined).
fn any_perpendicular(d: DVec3) -> DVec3 {
    let a = if d.x.abs() < 0.9 { DVec3::X } else { DVec3::Y };
    d.cross(a).normalize()
}

impl Primitive {
    /// Signed distance to the surface: negative inside (exact for every kind).
    pub fn signed_distance(&self, p: DVec3) -> f64 {
        match *self {
            Primitive::Plane { axis, at, outward } => outward * (p[axis] - at),
            Primitive::Sphere { centre, radius } => (p - centre).length() - radius,
            Primitive::Cylinder { axis, centre, radius } => flatten(p - centre, axis).length() - radius,
            Primitive::Torus { centre, major, minor } => {
                let d = p - centre;
                (d.x.hypot(d.y) - major).hypot(d.z) - minor
            }
        }
    }

    /// The nearest point of the surface to `p` (one of them where several are).
    pub fn project(&self, p: DVec3) -> DVec3 {
        match *self {
            Primitive::Plane { axis, at, .. } => {
                let mut x = p;
                x[axis] = at;
                x
            }
            Primitive::Sphere { centre, radius } => {
                let d = p - centre;
                let dir = if d.length() > 0.0 { d.normalize() } else { DVec3::X };
                centre + radius * dir
            }
            Primitive::Cylinder { axis, centre, radius } => {
                let d = flatten(p - centre, axis);
                let dir = if d.length() > 0.0 { d.normalize() } else { unit(across(axis).0) };
                let mut x = centre + radius * dir;
                x[axis] = p[axis];
                x
            }
            Primitive::Torus { centre, major, minor } => {
                let ring = self.torus_ring_point(p, centre, major);
                let d = p - ring;
                let dir = if d.length() > 0.0 { d.normalize() } else { DVec3::Z };
                ring + minor * dir
            }
        }
    }

    /// The point of a torus's core circle nearest to `p`.
    fn torus_ring_point(&self, p: DVec3, centre: DVec3, major: f64) -> DVec3 {
        let d = DVec3::new(p.x - centre.x, p.y - centre.y, 0.0);
        let dir = if d.length() > 0.0 { d.normalize() } else { DVec3::X };
        centre + major * dir
    }

    /// The outward unit normal at a point `x` of the surface.
    pub fn normal(&self, x: DVec3) -> DVec3 {
        match *self {
            Primitive::Plane { axis, outward, .. } => outward * unit(axis),
            Primitive::Sphere { centre, .. } => (x - centre).normalize(),
            Primitive::Cylinder { axis, centre, .. } => flatten(x - centre, axis).normalize(),
            Primitive::Torus { centre, major, .. } => (x - self.torus_ring_point(x, centre, major)).normalize(),
        }
    }
}

/// A boolean tree over primitives (by their index in the solid's list).
#[derive(Clone, Debug)]
pub enum Csg {
    /// The inside of one primitive.
    Prim(usize),
    /// Inside all.
    And(Vec<Csg>),
    /// Inside any.
    Or(Vec<Csg>),
    /// Inside the first and outside the second.
    Sub(Box<Csg>, Box<Csg>),
}

impl Csg {
    /// The tree's value, each primitive's inside given by `inside`.
    pub fn eval(&self, inside: &dyn Fn(usize) -> bool) -> bool {
        match self {
            Csg::Prim(i) => inside(*i),
            Csg::And(v) => v.iter().all(|c| c.eval(inside)),
            Csg::Or(v) => v.iter().any(|c| c.eval(inside)),
            Csg::Sub(a, b) => a.eval(inside) && !b.eval(inside),
        }
    }
}

/// How a crease curve maps its parameter to a point.
#[derive(Clone, Copy, Debug)]
enum CurveKind {
    /// `origin + t dir`.
    Line { origin: DVec3, dir: DVec3 },
    /// `centre + radius (cos t u + sin t v)`.
    Circle { centre: DVec3, u: DVec3, v: DVec3, radius: f64 },
    /// On the cylinder (axis, centre, radius) at angle t; the coordinate along the axis
    /// from primitive `other` (a sphere or a cylinder across), on the `branch` (+1 or
    /// -1) of its square root; none where the root is imaginary.
    OnCylinder { axis: usize, centre: DVec3, radius: f64, other: Primitive, branch: f64 },
}

impl CurveKind {
    fn point(&self, t: f64) -> Option<DVec3> {
        match *self {
            CurveKind::Line { origin, dir } => Some(origin + t * dir),
            CurveKind::Circle { centre, u, v, radius } => Some(centre + radius * (t.cos() * u + t.sin() * v)),
            CurveKind::OnCylinder { axis, centre, radius, other, branch } => {
                let (a, b) = across(axis);
                let mut x = centre + radius * (t.cos() * unit(a) + t.sin() * unit(b));
                let along = match other {
                    Primitive::Sphere { centre: c, radius: r } => {
                        let disc = r * r - flatten(x - c, axis).length_squared();
                        (disc >= 0.0).then(|| c[axis] + branch * disc.sqrt())?
                    }
                    Primitive::Cylinder { axis: axis2, centre: c, radius: r } => {
                        // The other cylinder's cross axes are `axis` and `w`.
                        let w = 3 - axis - axis2;
                        let disc = r * r - (x[w] - c[w]).powi(2);
                        (disc >= 0.0).then(|| c[axis] + branch * disc.sqrt())?
                    }
                    _ => unreachable!("OnCylinder pairs a cylinder with a sphere or a cylinder across"),
                };
                x[axis] = along;
                Some(x)
            }
        }
    }
}

/// One crease curve: the kept (crease) samples in parameter order, in chunks.
#[derive(Clone, Debug)]
struct Crease {
    /// The two primitives meeting along it.
    pair: [usize; 2],
    kind: CurveKind,
    /// The parameter spacing of the samples.
    step: f64,
    /// Kept samples: parameter and point.
    samples: Vec<(f64, DVec3)>,
    /// Each chunk's sample range and box.
    chunks: Vec<(std::ops::Range<usize>, DVec3, DVec3)>,
}

/// A boundary point with what [`ExactSolid::nearest`] knows about it.
#[derive(Clone, Copy, Debug)]
pub struct Nearest {
    /// The nearest surface point.
    pub point: DVec3,
    /// Its distance from the query point.
    pub distance: f64,
    /// The solid's outward unit normal there (see the module doc at creases).
    pub normal: DVec3,
    /// Whether the query point is inside the solid.
    pub inside: bool,
}

/// An analytic solid with its exact surface (see the module doc).
#[derive(Clone, Debug)]
pub struct ExactSolid {
    /// A short name (for tables and messages).
    pub name: String,
    /// The primitives.
    pub primitives: Vec<Primitive>,
    /// The boolean tree over them.
    pub tree: Csg,
    /// A box holding the solid (lines are sampled within it, grown by a margin).
    pub bounds: (DVec3, DVec3),
    creases: Vec<Crease>,
    /// Corners on the boundary, and whether each is on a crease.
    corners: Vec<(DVec3, bool)>,
}

impl ExactSolid {
    /// The solid of `tree` over `primitives`, inside `bounds`; finds its creases and
    /// corners (panics on a pair it cannot intersect: a torus with anything, parallel
    /// cylinders).
    pub fn new(name: &str, primitives: Vec<Primitive>, tree: Csg, bounds: (DVec3, DVec3)) -> Self {
        let mut solid =
            ExactSolid { name: name.to_string(), primitives, tree, bounds, creases: Vec::new(), corners: Vec::new() };
        let margin = (bounds.1 - bounds.0).max_element() * 0.25;
        let (lo, hi) = (bounds.0 - DVec3::splat(margin), bounds.1 + DVec3::splat(margin));
        let n = solid.primitives.len();
        let mut curves = Vec::new();
        for i in 0..n {
            for j in i + 1..n {
                for (kind, closed, range) in crease_curves(solid.primitives[i], solid.primitives[j], lo, hi) {
                    curves.push(([i, j], kind, closed, range));
                }
            }
        }
        for ([i, j], kind, closed, (t0, t1)) in curves {
            solid.add_crease([i, j], kind, closed, t0, t1);
        }
        solid
    }

    /// Whether `p` is inside (closed: surface points count as inside).
    pub fn contains(&self, p: DVec3) -> bool {
        self.tree.eval(&|i| self.primitives[i].signed_distance(p) <= 0.0)
    }

    /// On how many of the primitives `bits` the tree's value at `x` depends: for each
    /// bit, whether some choice of the others among `bits` makes flipping it change the
    /// value (the primitives not in `bits` evaluated at `x`).
    fn dependence(&self, x: DVec3, bits: &[usize]) -> usize {
        let sides: Vec<bool> = self.primitives.iter().map(|p| p.signed_distance(x) <= 0.0).collect();
        let eval = |mask: u32| {
            self.tree.eval(&|i| match bits.iter().position(|&b| b == i) {
                Some(k) => mask >> k & 1 == 1,
                None => sides[i],
            })
        };
        (0..bits.len()).filter(|&k| (0..1u32 << bits.len()).any(|mask| eval(mask) != eval(mask ^ (1 << k)))).count()
    }

    /// Samples a crease curve over `[t0, t1]`, keeps its crease points in chunks, and
    /// records the corners where a third primitive crosses it.
    fn add_crease(&mut self, pair: [usize; 2], kind: CurveKind, closed: bool, t0: f64, t1: f64) {
        let step = (t1 - t0) / CURVE_SAMPLES as f64;
        // Parameters: the uniform ones, plus the ends of each branch (bisected).
        let mut params: Vec<f64> = (0..=CURVE_SAMPLES).map(|k| t0 + step * k as f64).collect();
        if closed {
            params.pop();
        }
        let mut all: Vec<(f64, DVec3)> = Vec::with_capacity(params.len() + 8);
        for w in 0..params.len() {
            let t = params[w];
            let here = kind.point(t);
            if let Some(x) = here {
                all.push((t, x));
            }
            if let Some(&next) = params.get(w + 1) {
                let there = kind.point(next);
                if here.is_some() != there.is_some() {
                    // Bisect to the branch's end, keeping the defined side.
                    let (mut a, mut b) = if here.is_some() { (t, next) } else { (next, t) };
                    for _ in 0..100 {
                        let m = 0.5 * (a + b);
                        if kind.point(m).is_some() { a = m } else { b = m }
                    }
                    all.push((a, kind.point(a).expect("kept defined")));
                }
            }
        }
        all.sort_by(|a, b| a.0.total_cmp(&b.0));
        // Corners: a third primitive's sign change between consecutive samples.
        for k in 0..self.primitives.len() {
            if pair.contains(&k) {
                continue;
            }
            let prim = self.primitives[k];
            let count = all.len();
            let pairs = if closed { count } else { count.saturating_sub(1) };
            for w in 0..pairs {
                let (ta, xa) = all[w];
                let (mut tb, xb) = all[(w + 1) % count];
                if w + 1 == count {
                    tb += std::f64::consts::TAU;
                }
                // Only neighbours on one piece of the curve (not across a gap).
                if tb - ta > 1.5 * step {
                    continue;
                }
                let (sa, sb) = (prim.signed_distance(xa), prim.signed_distance(xb));
                if (sa <= 0.0) == (sb <= 0.0) {
                    continue;
                }
                let (mut a, mut b) = (ta, tb);
                for _ in 0..100 {
                    let m = 0.5 * (a + b);
                    let Some(x) = kind.point(m) else { break };
                    if (prim.signed_distance(x) <= 0.0) == (sa <= 0.0) { a = m } else { b = m }
                }
                if let Some(x) = kind.point(0.5 * (a + b)) {
                    let d = self.dependence(x, &[pair[0], pair[1], k]);
                    if d >= 1 {
                        self.corners.push((x, d >= 2));
                    }
                }
            }
        }
        let samples: Vec<(f64, DVec3)> = all.into_iter().filter(|&(_, x)| self.dependence(x, &pair) == 2).collect();
        if samples.is_empty() {
            return;
        }
        let chunks = samples
            .chunks(CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let lo = chunk.iter().fold(DVec3::INFINITY, |m, s| m.min(s.1));
                let hi = chunk.iter().fold(DVec3::NEG_INFINITY, |m, s| m.max(s.1));
                (c * CHUNK..c * CHUNK + chunk.len(), lo, hi)
            })
            .collect();
        self.creases.push(Crease { pair, kind, step, samples, chunks });
    }

    /// The nearest crease point to `p` and its distance, searched below `limit`
    /// (`(limit, p)` when there is none nearer).
    fn nearest_crease(&self, p: DVec3, limit: f64) -> (f64, DVec3) {
        let mut best = (limit, p);
        for crease in &self.creases {
            // Step 1: the nearest kept sample, chunks pruned by their boxes.
            let mut found: Option<(f64, usize)> = None;
            for (range, lo, hi) in &crease.chunks {
                let gap = (*lo - p).max(p - *hi).max(DVec3::ZERO).length();
                if gap >= best.0.min(found.map_or(f64::INFINITY, |f| f.0)) {
                    continue;
                }
                for k in range.clone() {
                    let d = (crease.samples[k].1 - p).length();
                    if found.is_none_or(|f| d < f.0) {
                        found = Some((d, k));
                    }
                }
            }
            let Some((d, k)) = found else { continue };
            if d < best.0 {
                best = (d, crease.samples[k].1);
            }
            // Step 2: golden section on both intervals next to it.
            let t = crease.samples[k].0;
            for neighbour in [t - crease.step, t + crease.step] {
                let (a, b) = if neighbour < t { (neighbour, t) } else { (t, neighbour) };
                if let Some((d, x)) = golden(&crease.kind, p, a, b)
                    && d < best.0
                    && self.dependence(x, &crease.pair) == 2
                {
                    best = (d, x);
                }
            }
        }
        for &(x, on_crease) in &self.corners {
            let d = (x - p).length();
            if on_crease && d < best.0 {
                best = (d, x);
            }
        }
        best
    }

    /// The nearest surface point to `p` (see the module doc).
    pub fn nearest(&self, p: DVec3) -> Nearest {
        let inside = self.contains(p);
        let mut best: Option<Nearest> = None;
        for (i, prim) in self.primitives.iter().enumerate() {
            let x = prim.project(p);
            if self.dependence(x, &[i]) != 1 {
                continue;
            }
            let d = (x - p).length();
            if best.is_none_or(|b| d < b.distance) {
                // The solid lies on the primitive's inside where it contains points
                // just inside it: then the outward normals agree.
                let sides: Vec<bool> = self.primitives.iter().map(|q| q.signed_distance(x) <= 0.0).collect();
                let solid_inside = self.tree.eval(&|k| if k == i { true } else { sides[k] });
                let n = prim.normal(x);
                best = Some(Nearest { point: x, distance: d, normal: if solid_inside { n } else { -n }, inside });
            }
        }
        let limit = best.map_or(f64::INFINITY, |b| b.distance);
        let (d, x) = self.nearest_crease(p, limit);
        let from_corner = self
            .corners
            .iter()
            .map(|&(c, _)| ((c - p).length(), c))
            .filter(|&(dc, _)| dc < d.min(limit))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        let (d, x) = from_corner.unwrap_or((d, x));
        if d < limit {
            let away = p - x;
            let normal = if away.length() > 1e-12 {
                let n = away.normalize();
                if inside { -n } else { n }
            } else {
                // On the crease itself: the mean of the two faces' normals.
                best.map_or(DVec3::Z, |b| b.normal)
            };
            return Nearest { point: x, distance: d, normal, inside };
        }
        best.expect("a solid with a surface")
    }

    /// The distance from a surface point `x` to the nearest crease (infinite when the
    /// solid has none).
    pub fn crease_distance(&self, x: DVec3) -> f64 {
        self.nearest_crease(x, f64::INFINITY).0
    }

    /// Whether the solid has creases at all.
    pub fn has_creases(&self) -> bool {
        !self.creases.is_empty()
    }

    /// The solid's crease corners (where three surfaces meet with a sharp edge).
    pub fn corners(&self) -> Vec<DVec3> {
        self.corners.iter().filter(|c| c.1).map(|c| c.0).collect()
    }

    // ---- The solids of issue 38's table and tests ----

    /// A sphere.
    pub fn sphere(centre: DVec3, radius: f64) -> Self {
        let r = DVec3::splat(radius);
        ExactSolid::new("sphere", vec![Primitive::Sphere { centre, radius }], Csg::Prim(0), (centre - r, centre + r))
    }

    /// A torus about the z axis.
    pub fn torus(centre: DVec3, major: f64, minor: f64) -> Self {
        let r = DVec3::new(major + minor, major + minor, minor);
        ExactSolid::new(
            "torus",
            vec![Primitive::Torus { centre, major, minor }],
            Csg::Prim(0),
            (centre - r, centre + r),
        )
    }

    /// The six planes of the box `[min, max]` (as primitives, in the order -x, +x, -y,
    /// +y, -z, +z) and their intersection.
    fn box_primitives(min: DVec3, max: DVec3, first: usize) -> (Vec<Primitive>, Csg) {
        let mut prims = Vec::new();
        for axis in 0..3 {
            prims.push(Primitive::Plane { axis, at: min[axis], outward: -1.0 });
            prims.push(Primitive::Plane { axis, at: max[axis], outward: 1.0 });
        }
        (prims, Csg::And((first..first + 6).map(Csg::Prim).collect()))
    }

    /// An axis-aligned box.
    pub fn cuboid(min: DVec3, max: DVec3) -> Self {
        let (prims, tree) = Self::box_primitives(min, max, 0);
        ExactSolid::new("cube", prims, tree, (min, max))
    }

    /// A ball minus an axis-aligned box (a concave corner where the box's corner lies
    /// inside the ball).
    pub fn sphere_minus_box(centre: DVec3, radius: f64, min: DVec3, max: DVec3) -> Self {
        let (mut prims, cut) = Self::box_primitives(min, max, 1);
        prims.insert(0, Primitive::Sphere { centre, radius });
        let r = DVec3::splat(radius);
        ExactSolid::new(
            "sphere minus cube",
            prims,
            Csg::Sub(Box::new(Csg::Prim(0)), Box::new(cut)),
            (centre - r, centre + r),
        )
    }

    /// The classic CSG part: a cube of side 2 centred at the origin & a ball of radius
    /// 1.3, minus three cylinders of radius 0.6 along x, y and z through the origin.
    pub fn classic() -> Self {
        let (mut prims, cube) = Self::box_primitives(DVec3::splat(-1.0), DVec3::splat(1.0), 0);
        prims.push(Primitive::Sphere { centre: DVec3::ZERO, radius: 1.3 });
        for axis in 0..3 {
            prims.push(Primitive::Cylinder { axis, centre: DVec3::ZERO, radius: 0.6 });
        }
        let Csg::And(mut body) = cube else { unreachable!() };
        body.push(Csg::Prim(6));
        let tree =
            Csg::Sub(Box::new(Csg::And(body)), Box::new(Csg::Or(vec![Csg::Prim(7), Csg::Prim(8), Csg::Prim(9)])));
        ExactSolid::new("classic part", prims, tree, (DVec3::splat(-1.0), DVec3::splat(1.0)))
    }

    /// The solids by name, as the measurement program knows them: `classic`, `sphere`
    /// (radius 1), `torus` (1 and 0.4 about z), `cube` (side 2), `sphere-minus-cube`
    /// (radius 1 minus the box `[0, 2]^3`: a concave corner at the origin); all
    /// centred at the origin.
    pub fn by_name(name: &str) -> Option<Self> {
        Some(match name {
            "classic" => Self::classic(),
            "sphere" => Self::sphere(DVec3::ZERO, 1.0),
            "torus" => Self::torus(DVec3::ZERO, 1.0, 0.4),
            "cube" => Self::cuboid(DVec3::splat(-1.0), DVec3::splat(1.0)),
            "sphere-minus-cube" => Self::sphere_minus_box(DVec3::ZERO, 1.0, DVec3::ZERO, DVec3::splat(2.0)),
            _ => return None,
        })
    }
}

/// The crease curves where the surfaces of `a` and `b` meet, with whether each closes
/// and its parameter range (lines within the box `[lo, hi]`).
fn crease_curves(a: Primitive, b: Primitive, lo: DVec3, hi: DVec3) -> Vec<(CurveKind, bool, (f64, f64))> {
    use Primitive::*;
    let full = (0.0, std::f64::consts::TAU);
    let circle = |centre: DVec3, axis: DVec3, radius: f64| {
        let u = any_perpendicular(axis);
        (CurveKind::Circle { centre, u, v: axis.normalize().cross(u), radius }, true, full)
    };
    match (a, b) {
        (Plane { axis: pa, at: aa, .. }, Plane { axis: pb, at: ab, .. }) => {
            if pa == pb {
                return vec![];
            }
            let c = 3 - pa - pb;
            let mut origin = DVec3::ZERO;
            origin[pa] = aa;
            origin[pb] = ab;
            vec![(CurveKind::Line { origin, dir: unit(c) }, false, (lo[c], hi[c]))]
        }
        (Plane { axis, at, .. }, Sphere { centre, radius }) | (Sphere { centre, radius }, Plane { axis, at, .. }) => {
            let h = at - centre[axis];
            if h.abs() >= radius {
                return vec![];
            }
            let mut c = centre;
            c[axis] = at;
            vec![circle(c, unit(axis), (radius * radius - h * h).sqrt())]
        }
        (Plane { axis: pa, at, .. }, Cylinder { axis, centre, radius })
        | (Cylinder { axis, centre, radius }, Plane { axis: pa, at, .. }) => {
            if pa == axis {
                let mut c = centre;
                c[axis] = at;
                return vec![circle(c, unit(axis), radius)];
            }
            let other = 3 - pa - axis;
            let h = at - centre[pa];
            if h.abs() >= radius {
                return vec![];
            }
            let s = (radius * radius - h * h).sqrt();
            [-1.0, 1.0]
                .into_iter()
                .map(|sign| {
                    let mut origin = DVec3::ZERO;
                    origin[pa] = at;
                    origin[other] = centre[other] + sign * s;
                    (CurveKind::Line { origin, dir: unit(axis) }, false, (lo[axis], hi[axis]))
                })
                .collect()
        }
        (Sphere { centre: c1, radius: r1 }, Sphere { centre: c2, radius: r2 }) => {
            let d = (c2 - c1).length();
            if d == 0.0 || d >= r1 + r2 || d <= (r1 - r2).abs() {
                return vec![];
            }
            let n = (c2 - c1) / d;
            let h = (d * d + r1 * r1 - r2 * r2) / (2.0 * d);
            vec![circle(c1 + h * n, n, (r1 * r1 - h * h).sqrt())]
        }
        (Sphere { .. }, Cylinder { axis, centre, radius }) | (Cylinder { axis, centre, radius }, Sphere { .. }) => {
            let other = if matches!(a, Sphere { .. }) { a } else { b };
            [-1.0, 1.0]
                .into_iter()
                .map(|branch| (CurveKind::OnCylinder { axis, centre, radius, other, branch }, true, full))
                .collect()
        }
        (Cylinder { axis, centre, radius }, Cylinder { axis: axis2, .. }) => {
            assert_ne!(axis, axis2, "parallel cylinders are not supported");
            [-1.0, 1.0]
                .into_iter()
                .map(|branch| (CurveKind::OnCylinder { axis, centre, radius, other: b, branch }, true, full))
                .collect()
        }
        _ => panic!("a torus meets no other primitive in this oracle"),
    }
}

/// The minimum of the distance from `p` to the curve over `[a, b]` by golden section
/// (the distance taken unimodal there), with its point; none where the curve is not
/// defined at the result.
fn golden(kind: &CurveKind, p: DVec3, a: f64, b: f64) -> Option<(f64, DVec3)> {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let f = |t: f64| kind.point(t).map_or(f64::INFINITY, |x| (x - p).length_squared());
    let (mut a, mut b) = (a, b);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..60 {
        if fc < fd {
            b = d;
            d = c;
            fd = fc;
            c = b - g * (b - a);
            fc = f(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    let x = kind.point(0.5 * (a + b))?;
    Some(((x - p).length(), x))
}

// ---- Sampling a mesh and measuring it ----

/// A point sampled on a mesh, with its triangle's unit normal (as wound).
#[derive(Clone, Copy, Debug)]
pub struct MeshSample {
    /// The point.
    pub point: DVec3,
    /// The unit normal of its triangle: `(b - a) x (c - a)`, normalized.
    pub normal: DVec3,
    /// The triangle's index.
    pub triangle: usize,
}

/// `n` points on the mesh, area-weighted (see the module doc), seeded (xorshift64, the
/// tests' generator); degenerate triangles are never chosen.
pub fn sample_mesh(mesh: &TriangleMesh, n: usize, seed: u64) -> Vec<MeshSample> {
    let mut cumulative = Vec::with_capacity(mesh.triangles.len());
    let mut total = 0.0;
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        total += 0.5 * (b - a).cross(c - a).length();
        cumulative.push(total);
    }
    assert!(total > 0.0, "a mesh with area");
    let mut state = seed.max(1);
    let mut unit = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| {
            let target = unit() * total;
            let t = cumulative.partition_point(|&c| c <= target).min(cumulative.len() - 1);
            let [a, b, c] = mesh.corners(t);
            let (r1, r2) = (unit().sqrt(), unit());
            let point = (1.0 - r1) * a + r1 * (1.0 - r2) * b + r1 * r2 * c;
            MeshSample { point, normal: (b - a).cross(c - a).normalize(), triangle: t }
        })
        .collect()
}

/// Issue 38's columns for one mesh against one exact solid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quality {
    /// The mesh's triangles.
    pub triangles: usize,
    /// Samples taken.
    pub samples: usize,
    /// Distance from the samples to the exact surface, root mean square, in voxels.
    pub rms: f64,
    /// Its maximum over the samples, in voxels.
    pub max: f64,
    /// The median angle (degrees) between a sample's triangle normal and the exact
    /// normal at its nearest surface point, over the samples away from creases.
    pub median_normal_deg: f64,
    /// The share (0..1) of those samples within [`WITHIN_DEGREES`].
    pub share_within_5deg_away_from_edges: f64,
    /// The share of samples away from creases (the area the normal columns describe).
    pub share_away_from_edges: f64,
}

/// [`measure_with`] at [`DEFAULT_SAMPLES`] and seed 1.
pub fn measure(mesh: &TriangleMesh, solid: &ExactSolid, voxel: f64) -> Quality {
    measure_with(mesh, solid, voxel, DEFAULT_SAMPLES, 1)
}

/// The mesh's quality against the solid's exact surface at `n` area-weighted samples
/// (see the module doc); distances in units of `voxel`.
pub fn measure_with(mesh: &TriangleMesh, solid: &ExactSolid, voxel: f64, n: usize, seed: u64) -> Quality {
    let samples = sample_mesh(mesh, n, seed);
    let band = EDGE_BAND_VOXELS * voxel;
    let measured: Vec<(f64, Option<f64>)> = par_map(&samples, |s| {
        let near = solid.nearest(s.point);
        let away = solid.nearest_crease(near.point, band).0 >= band;
        let angle = s.normal.dot(near.normal).clamp(-1.0, 1.0).acos().to_degrees();
        (near.distance / voxel, away.then_some(angle))
    });
    let rms = (measured.iter().map(|m| m.0 * m.0).sum::<f64>() / n as f64).sqrt();
    let max = measured.iter().map(|m| m.0).fold(0.0, f64::max);
    let mut angles: Vec<f64> = measured.iter().filter_map(|m| m.1).collect();
    angles.sort_by(f64::total_cmp);
    let median = if angles.is_empty() { f64::NAN } else { angles[angles.len() / 2] };
    let within = angles.iter().filter(|&&a| a <= WITHIN_DEGREES).count();
    Quality {
        triangles: mesh.triangles.len(),
        samples: n,
        rms,
        max,
        median_normal_deg: median,
        share_within_5deg_away_from_edges: within as f64 / angles.len().max(1) as f64,
        share_away_from_edges: angles.len() as f64 / n as f64,
    }
}

/// `f` of every item, in order, on all cores: the items cut into one run a thread
/// (`std::thread::available_parallelism`), each run mapped by a scoped thread.
pub fn par_map<T: Sync, R: Send>(items: &[T], f: impl Fn(&T) -> R + Sync) -> Vec<R> {
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let run = items.len().div_ceil(threads).max(1);
    std::thread::scope(|scope| {
        let handles: Vec<_> =
            items.chunks(run).map(|chunk| scope.spawn(|| chunk.iter().map(&f).collect::<Vec<R>>())).collect();
        handles.into_iter().flat_map(|h| h.join().expect("a measuring thread panicked")).collect()
    })
}
