//! A convex polytope: a box cut by half-spaces, its point queries answered from a
//! tree of normal cones instead of by asking every plane.
//!
//! The solid is the box `B` and the half-spaces `n_i . p <= h_i` (unit normals), the
//! same set as the CSG intersection `B & H_1 & ... & H_n`, and it answers every query
//! as that intersection does: [`Shape::contains`] is `B` and every `n_i . p <= h_i`;
//! [`Shape::surface`] is the fold of the leaves' surfaces by the farther one (the box's
//! first, then the planes' in order, the first of equally far ones kept), with each
//! leaf's own arithmetic, so the values are the same bits. Only the plane that wins is
//! found faster.
//!
//! Index (branch and bound over a bounding-cone hierarchy, as used for normal-cone
//! culling; Shirman and Abi-Ezzi, *The cone of normals technique for fast processing of
//! curved patches*, 1993): write `p = c + v` for an inner point `c`, so plane `i`'s
//! value is `f_i = n_i . v - r_i` with `r_i = h_i - n_i . c`. The planes are split in
//! halves along the widest coordinate of their normals, recursively; a node keeps the
//! axis `a` of its normals, the cone's half-angle `t` (the largest angle from `a`) and
//! the least `r_i`. If `v` makes the angle `phi` with `a`, every normal of the node has
//! `n . v <= |v| cos(max(0, phi - t))`, that is `|v|` when `phi <= t`, else `(a . v)
//! cos t + |a x v| sin t`; minus the least `r_i`, a bound on the node's `f_i`. A query
//! walks the tree nearer bound first and skips a node whose bound (plus a margin for
//! rounding) is under the best value found, so no plane that could win or tie is
//! skipped. Near the surface the walk visits `O(log n)` nodes, not `n` planes.
//!
//! Departure from the CSG intersection: [`Shape::classify`] asks the box and the plane
//! of the largest value at the box's centre, and says Inside when even that value is
//! more than the box's half-diagonal inside; sound (Outside and Inside are only said
//! when true), so voxels, decided at their centres, are the same; a box the CSG fold
//! would decide through another plane is split further instead.

use glam::DVec3;

use super::{Class, Cuboid, HalfSpace, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::Result;

/// Planes a leaf of the cone tree holds at most.
const LEAF_PLANES: usize = 8;

/// A box cut by half-spaces (see the module doc).
pub(super) struct Polytope {
    cuboid: Cuboid,
    bounds: Aabb,
    planes: Vec<HalfSpace>,
    /// The planes' indices in `planes`, in the tree's order.
    order: Vec<u32>,
    nodes: Vec<Cone>,
    inner: DVec3,
    /// Rounding allowance on a bound.
    margin: f64,
}

/// A node of the cone tree: the planes `order[start..end]`, its children (none for a
/// leaf), the axis, `cos t`, `sin t` and the least `r_i`.
struct Cone {
    start: u32,
    end: u32,
    children: Option<[u32; 2]>,
    axis: DVec3,
    cos: f64,
    sin: f64,
    least_reach: f64,
}

impl Polytope {
    /// The box `cuboid` cut by the half-spaces `n . p <= h` of `planes` (unit normals),
    /// `inner` a point inside them all (any point gives the same answers; one inside
    /// gives the tightest bounds).
    pub(super) fn new(cuboid: Cuboid, planes: &[(DVec3, f64)], inner: DVec3) -> Result<Polytope> {
        let halves = planes.iter().map(|&(n, h)| HalfSpace::new(n, h)).collect::<Result<Vec<_>>>()?;
        let bounds = cuboid.bounds().expect("a box has bounds");
        let mut order: Vec<u32> = (0..planes.len() as u32).collect();
        let mut nodes = Vec::new();
        if !planes.is_empty() {
            build(planes, inner, &mut order, 0, planes.len(), &mut nodes);
        }
        let scale =
            planes.iter().map(|p| p.1.abs()).fold(inner.abs().max_element(), f64::max) + bounds.size().max_element();
        Ok(Polytope { cuboid, bounds, planes: halves, order, nodes, inner, margin: 1e-9 * (scale + 1.0) })
    }

    /// The first plane of the largest value `n_i . p - h_i` (as [`HalfSpace::surface`]
    /// measures it) and that surface, among those whose value could reach `floor`;
    /// `None` when none does.
    fn farthest_plane(&self, p: DVec3, floor: f64) -> Option<(u32, Surface)> {
        let v = p - self.inner;
        let length = v.length();
        let mut best: Option<(u32, Surface)> = None;
        let mut stack: Vec<u32> = Vec::with_capacity(64);
        if !self.nodes.is_empty() {
            stack.push(0);
        }
        while let Some(at) = stack.pop() {
            let node = &self.nodes[at as usize];
            let bound = self.bound(node, v, length);
            let beat = best.map_or(floor, |(_, s)| s.distance.max(floor));
            if bound + self.margin < beat {
                continue;
            }
            match node.children {
                Some([a, b]) => {
                    // The nearer bound last, so it is walked first.
                    let (ba, bb) = (
                        self.bound(&self.nodes[a as usize], v, length),
                        self.bound(&self.nodes[b as usize], v, length),
                    );
                    if ba >= bb {
                        stack.extend([b, a]);
                    } else {
                        stack.extend([a, b]);
                    }
                }
                None => {
                    for j in node.start..node.end {
                        let i = self.order[j as usize];
                        let Some(s) = self.planes[i as usize].surface(p) else { continue };
                        let better = match best {
                            None => true,
                            Some((bi, bs)) => s.distance > bs.distance || (s.distance == bs.distance && i < bi),
                        };
                        if better {
                            best = Some((i, s));
                        }
                    }
                }
            }
        }
        best
    }

    /// An upper bound of `n_i . v - r_i` over `node`'s planes (see the module doc).
    fn bound(&self, node: &Cone, v: DVec3, length: f64) -> f64 {
        let along = node.axis.dot(v);
        let reach =
            if along >= length * node.cos { length } else { along * node.cos + node.axis.cross(v).length() * node.sin };
        reach - node.least_reach
    }
}

/// Builds the cone tree over `order[start..end]`, returning its node's index.
fn build(
    planes: &[(DVec3, f64)],
    inner: DVec3,
    order: &mut [u32],
    start: usize,
    end: usize,
    nodes: &mut Vec<Cone>,
) -> u32 {
    let members = &order[start..end];
    let sum: DVec3 = members.iter().map(|&i| planes[i as usize].0).sum();
    let axis = if sum.length_squared() > 1e-24 { sum.normalize() } else { planes[members[0] as usize].0.normalize() };
    // The cone a little wider than its members (rounding), never past the sphere.
    let cos = members.iter().map(|&i| axis.dot(planes[i as usize].0.normalize())).fold(1.0, f64::min) - 1e-9;
    let cos = cos.max(-1.0);
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let least_reach =
        members.iter().map(|&i| planes[i as usize].1 - planes[i as usize].0.dot(inner)).fold(f64::INFINITY, f64::min);
    let at = nodes.len() as u32;
    nodes.push(Cone { start: start as u32, end: end as u32, children: None, axis, cos, sin, least_reach });
    if end - start > LEAF_PLANES {
        // Split at the median of the normals' widest coordinate.
        let (lo, hi) = members.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &i| {
            (lo.min(planes[i as usize].0), hi.max(planes[i as usize].0))
        });
        let spread = hi - lo;
        let c = if spread.x >= spread.y && spread.x >= spread.z {
            0
        } else if spread.y >= spread.z {
            1
        } else {
            2
        };
        let mid = (end - start) / 2;
        order[start..end].select_nth_unstable_by(mid, |&a, &b| {
            planes[a as usize].0[c].total_cmp(&planes[b as usize].0[c]).then(a.cmp(&b))
        });
        let a = build(planes, inner, order, start, start + mid, nodes);
        let b = build(planes, inner, order, start + mid, end, nodes);
        nodes[at as usize].children = Some([a, b]);
    }
    at
}

impl Shape for Polytope {
    fn classify(&self, b: &Aabb) -> Class {
        let cuboid = self.cuboid.classify(b);
        if cuboid == Class::Outside {
            return Class::Outside;
        }
        let c = b.center();
        let Some((i, s)) = self.farthest_plane(c, f64::NEG_INFINITY) else { return cuboid };
        let plane = self.planes[i as usize].classify(b);
        if plane == Class::Outside {
            return Class::Outside;
        }
        // Every plane's value at the centre is at most `s`, and moves by at most the
        // half-diagonal over the box.
        if cuboid == Class::Inside && s.distance + (b.size() * 0.5).length() + self.margin < 0.0 {
            Class::Inside
        } else {
            Class::Boundary
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        // Some plane with `n . p > h`: a value above zero (the sign of `n . p - h`).
        self.cuboid.contains(p) && self.farthest_plane(p, 0.0).is_none_or(|(_, s)| s.distance <= 0.0)
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(self.bounds)
    }

    /// The box's surface, or the first farthest plane's when strictly farther (the CSG
    /// intersection's fold).
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let cuboid = self.cuboid.surface(p)?;
        match self.farthest_plane(p, cuboid.distance) {
            Some((_, s)) if s.distance > cuboid.distance => Some(s),
            _ => Some(cuboid),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::Csg;
    use crate::test_util::Rng;

    /// Planes tangent to a ball of radius about 1 around `c`, random, and the axis and
    /// diagonal ones at distance 1 (their values tie exactly at points of a dyadic grid).
    fn planes(rng: &mut Rng, c: DVec3, n: usize) -> Vec<(DVec3, f64)> {
        let mut out: Vec<(DVec3, f64)> = (0..n)
            .map(|_| {
                let d = loop {
                    let d = rng.vec(-1.0, 1.0);
                    if d.length_squared() > 0.01 && d.length_squared() <= 1.0 {
                        break d.normalize();
                    }
                };
                (d, d.dot(c) + rng.range(0.9, 1.1))
            })
            .collect();
        for d in [DVec3::X, DVec3::NEG_X, DVec3::Y, DVec3::NEG_Y, DVec3::Z, DVec3::NEG_Z, DVec3::new(1.0, 1.0, 0.0)] {
            let d = d.normalize();
            out.insert(rng.below(out.len() as u64) as usize, (d, d.dot(c) + 1.0));
        }
        out
    }

    #[test]
    fn points_get_the_bits_of_the_csg_intersection_and_boxes_sound_classes() {
        let mut rng = Rng(39);
        for round in 0..6 {
            let c = DVec3::new(0.5, -0.25, 0.0) * f64::from(round);
            let planes = planes(&mut rng, c, [3, 40, 700][round as usize % 3]);
            let cuboid = Cuboid::new(c, DVec3::splat(2.05)).unwrap();
            let mut oracle = Csg::leaf(cuboid.clone());
            for &(n, h) in &planes {
                oracle = oracle & Csg::leaf(HalfSpace::new(n, h).unwrap());
            }
            let inner = c + rng.vec(-0.3, 0.3);
            let polytope = Polytope::new(cuboid, &planes, inner).unwrap();
            for i in 0..4000 {
                // Dyadic points (exact ties between the axis planes) and random ones.
                let p = if i % 2 == 0 {
                    c + DVec3::new(rng.below(33) as f64, rng.below(33) as f64, rng.below(33) as f64) / 8.0 - 2.0
                } else {
                    c + rng.vec(-2.0, 2.0)
                };
                assert_eq!(polytope.contains(p), oracle.contains(p), "{p}");
                let (a, b) = (polytope.surface(p).unwrap(), oracle.surface(p).unwrap());
                assert_eq!(a.distance.to_bits(), b.distance.to_bits(), "{p}");
                assert_eq!(a.normal.to_array().map(f64::to_bits), b.normal.to_array().map(f64::to_bits), "{p}");
                let q = c + rng.vec(-2.0, 2.0);
                let bx = Aabb::from_center_half(q, DVec3::splat(rng.range(0.0, 0.4)));
                let samples = (0..64).map(|_| bx.min + bx.size() * DVec3::new(rng.unit(), rng.unit(), rng.unit()));
                let inside: Vec<bool> = samples.map(|s| oracle.contains(s)).collect();
                match polytope.classify(&bx) {
                    Class::Inside => assert!(inside.iter().all(|&x| x), "{bx:?}"),
                    Class::Outside => assert!(!inside.iter().any(|&x| x), "{bx:?}"),
                    Class::Boundary => {}
                }
            }
        }
    }
}
