//! The convex hull of shapes, from their support points, to a stated tolerance.
//!
//! Method: the outer approximation by support functions (the "cutting plane" or
//! Kelley scheme; for convex bodies see Lopez and Reisner, *Hausdorff approximation of
//! convex polygons*, 2005): the hull `K` of shapes `S_1..S_n` has the support function
//! `h(n) = max_i max_{p in S_i} n . p`, and each shape answers [`Shape::support`], a
//! point reaching it. Start from the supports in 256 directions spread over the sphere
//! (a Fibonacci lattice), take their exact convex hull `P` ([`super::convex_hull`],
//! the points snapped to a lattice of `2^-30` of their box, which moves them by less
//! than a ten-millionth of the tolerance), and for each face of `P` (unit outward
//! normal `n`, plane `n . x = c`) ask the support in `n`: where `h(n) - c` exceeds the
//! tolerance, that point joins and the hull is taken again; stop when no face's gap
//! exceeds it.
//!
//! Result and error bound: the solid is `Q`, the intersection of the supporting
//! half-spaces `n . x <= h(n)` of `P`'s face normals (merged where faces share a
//! plane) and of the hull's bounding box (itself from the six axis supports). Every
//! such half-space holds `K`, so `K` is inside `Q`; and each plane is within the
//! tolerance of `P`'s face on it, with `P` inside `K` (its corners are points of the
//! shapes), so `Q` reaches beyond `K` only where its planes, pushed out by at most the
//! tolerance from `P`'s faces, meet. The tolerance defaults to `2^-11` of the hull's
//! largest extent ([`HullOptions`]): a quarter voxel at depth 9 in a domain the hull
//! fills.
//!
//! The solid is the intersection of those half-spaces and a [`Cuboid`], a
//! [`super::polytope`] leaf: its surface is the planes' (the farthest plane's distance
//! and normal; exact inside), the same bits as the CSG intersection of the
//! [`super::HalfSpace`]s gives, but each point query walks a tree of the planes' normal
//! cones instead of asking every plane (a ball of radius `R` in a hull of extent `E`
//! makes about `5 R 2048 / E` of them): the crossings of the hull of two balls and a
//! box in `scenes/profiles.toml` at depth 9, which cost `O(planes)` a boundary face
//! (14 s of CPU), take about a second.

use glam::DVec3;

use super::convex_hull::{LIMIT, Point, convex_hull, distinct_planes};
use super::polytope::Polytope;
use super::{Csg, Cuboid, Shape};
use crate::error::{Error, Result};

/// Options of [`Hull::new`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HullOptions {
    /// The largest gap allowed between a face and the supporting plane parallel to
    /// it, in world units; `None` for `2^-11` of the hull's largest extent.
    pub tolerance: Option<f64>,
    /// Refine at most this many rounds (each takes the hull anew).
    pub rounds: usize,
}

impl Default for HullOptions {
    fn default() -> Self {
        HullOptions { tolerance: None, rounds: 64 }
    }
}

/// The convex hull of shapes (see the module doc).
pub struct Hull {
    tree: Csg,
    planes: usize,
    points: usize,
    tolerance: f64,
}

/// Directions of the first supports.
const FIRST_DIRECTIONS: usize = 256;

impl Hull {
    /// The hull of `shapes` (at least one); fails for a shape without
    /// [`Shape::support`] (naming its place in the list) and for a flat hull.
    pub fn new(shapes: &[Csg], options: HullOptions) -> Result<Hull> {
        if shapes.is_empty() {
            return Err(Error::invalid("hull", "a hull needs at least one shape"));
        }
        let support = |d: DVec3| -> Result<DVec3> {
            let mut best: Option<DVec3> = None;
            for (i, shape) in shapes.iter().enumerate() {
                let p = shape.support(d).filter(|p| p.is_finite()).ok_or_else(|| no_support(i))?;
                if best.is_none_or(|b| p.dot(d) > b.dot(d)) {
                    best = Some(p);
                }
            }
            Ok(best.expect("a shape"))
        };
        let axes = [DVec3::X, DVec3::Y, DVec3::Z, DVec3::NEG_X, DVec3::NEG_Y, DVec3::NEG_Z];
        let mut points = Vec::new();
        for d in axes.into_iter().chain(fibonacci(FIRST_DIRECTIONS)) {
            points.push(support(d)?);
        }
        let hi = DVec3::new(support(DVec3::X)?.x, support(DVec3::Y)?.y, support(DVec3::Z)?.z);
        let lo = DVec3::new(support(DVec3::NEG_X)?.x, support(DVec3::NEG_Y)?.y, support(DVec3::NEG_Z)?.z);
        let extent = (hi - lo).max_element();
        if !(extent > 0.0 && extent.is_finite()) {
            return Err(flat());
        }
        let tolerance = options.tolerance.unwrap_or(extent / 2048.0);
        if !(tolerance > 0.0 && tolerance.is_finite()) {
            return Err(Error::invalid(
                "hull tolerance",
                format!("{} must be positive", crate::error::Number(tolerance)),
            ));
        }
        // The snapping lattice: 2^30 steps over the box, centred.
        let unit = extent / f64::from(1u32 << 30);
        let centre = (lo + hi) * 0.5;
        let snap = |p: DVec3| -> Point {
            let q = ((p - centre) / unit).round();
            [q.x as i64, q.y as i64, q.z as i64].map(|c| c.clamp(1 - LIMIT, LIMIT - 1))
        };
        let unsnap = |q: Point| centre + DVec3::new(q[0] as f64, q[1] as f64, q[2] as f64) * unit;
        let mut lattice: Vec<Point> = points.iter().map(|&p| snap(p)).collect();
        for _ in 0..options.rounds {
            let faces = convex_hull(&lattice).ok_or_else(flat)?;
            let planes = distinct_planes(&faces);
            let mut added = false;
            let mut cut = Vec::with_capacity(planes.len());
            for (normal, _, corner) in planes {
                let n = DVec3::new(normal[0] as f64, normal[1] as f64, normal[2] as f64).normalize();
                let s = support(n)?;
                let face = n.dot(unsnap(lattice[corner as usize]));
                if s.dot(n) - face > tolerance {
                    lattice.push(snap(s));
                    added = true;
                }
                cut.push((n, s.dot(n)));
            }
            if !added {
                let cuboid = Cuboid::new(centre, (hi - lo).max(DVec3::splat(unit)))?;
                let inner = lattice.iter().map(|&q| unsnap(q)).sum::<DVec3>() / lattice.len() as f64;
                let tree = Csg::leaf(Polytope::new(cuboid, &cut, inner)?);
                return Ok(Hull { tree, planes: cut.len(), points: lattice.len(), tolerance });
            }
        }
        Err(Error::invalid(
            "hull",
            format!("not within the tolerance {tolerance} after {} rounds; give a larger tolerance", options.rounds),
        ))
    }

    /// The solid: the supporting half-spaces and the box (see the module doc).
    #[must_use]
    pub fn tree(&self) -> &Csg {
        &self.tree
    }

    /// The planes of the solid (besides its box's).
    #[must_use]
    pub fn planes(&self) -> usize {
        self.planes
    }

    /// The support points its polytope was taken over.
    #[must_use]
    pub fn points(&self) -> usize {
        self.points
    }

    /// The tolerance it was refined to.
    #[must_use]
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }
}

impl From<Hull> for Csg {
    fn from(hull: Hull) -> Csg {
        hull.tree
    }
}

/// `n` directions spread evenly over the sphere (a Fibonacci lattice).
fn fibonacci(n: usize) -> impl Iterator<Item = DVec3> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..n).map(move |i| {
        let z = 1.0 - (2.0 * i as f64 + 1.0) / n as f64;
        let r = (1.0 - z * z).sqrt();
        let a = golden * i as f64;
        DVec3::new(r * a.cos(), r * a.sin(), z)
    })
}

fn no_support(i: usize) -> Error {
    Error::invalid(
        "hull",
        format!(
            "shape {i} of the hull has no support point (spheres, ellipsoids, boxes, cylinders, cones, tori, \
             sponges, untwisted extrusions, full revolutions, their transforms, patterns and unions have one; \
             intersections, differences, complements and half-spaces do not)"
        ),
    )
}

fn flat() -> Error {
    Error::invalid("hull", "the hull is flat: the shapes lie in one plane")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::Sphere;

    #[test]
    fn the_hull_of_two_balls_holds_them_and_stays_within_the_tolerance_of_the_capsule() {
        let balls = [Sphere::new(DVec3::new(-1.0, 0.0, 0.0), 1.0).unwrap(), Sphere::new(DVec3::X, 1.0).unwrap()];
        let hull = Hull::new(&balls.map(Csg::leaf), HullOptions::default()).unwrap();
        let tree = hull.tree();
        let capsule = |p: DVec3| DVec3::new(p.x.clamp(-1.0, 1.0), 0.0, 0.0).distance(p) - 1.0;
        let mut seed = 7u64;
        for _ in 0..20_000 {
            let mut r = || {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 * 5.0 - 2.5
            };
            let p = DVec3::new(r(), r(), r());
            if capsule(p) <= 0.0 {
                assert!(tree.contains(p), "{p}");
            }
            if capsule(p) > 2.0 * hull.tolerance() {
                assert!(!tree.contains(p), "{p}");
            }
        }
    }
}
