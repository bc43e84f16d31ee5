//! One polygon of a mesh file (an OBJ or PLY face) cut into triangles, by ear clipping
//! in its plane.
//!
//! The plane: the polygon's Newell normal `N = sum (p_i - p_{i+1}) x (p_i + p_{i+1}) / 2`
//! (its vector area, exact for planar polygons and a fair average for warped ones); the
//! corners are projected by dropping the coordinate along `N`'s largest component,
//! keeping the other two in cyclic order (mirrored when that component is negative), so
//! the projection is counter-clockwise and a triangle cut from it keeps the face's
//! orientation.
//!
//! Ear clipping (Meisters, "Polygons have ears", 1975; the bookkeeping of Eberly,
//! "Triangulation by Ear Clipping", 2002): a corner is an ear when it is convex and no
//! other corner that is not strictly convex lies in or on the triangle it makes with its
//! two neighbours. Cutting an ear leaves a simple polygon with one corner fewer in which
//! only the two neighbours can change, so the ears live in a priority queue with a
//! version a corner, and n - 2 cuts, each checking the few reflex corners, triangulate
//! the polygon in O(n r) for r reflex corners. Orientation signs are exact (`robust`).
//!
//! Departures from the textbook: the ear cut next is the one with the shortest new
//! diagonal, not the first found, and corners on a straight line are cut last. A fan
//! (or first-ear order, which on a convex polygon is the same fan) makes a 1000-gon
//! into 998 slivers all as long as the polygon, every one of them a candidate in every
//! octree node near the fan's centre; shortest-diagonal-first cuts every other corner
//! of a regular polygon, then every other of the rest, so its edges total about
//! `perimeter x log2 n` instead of `n x diameter`. Ties go to the corner after the
//! first, so a square becomes the fan `0 1 2`, `0 2 3` that tobj made. When clipping
//! cannot go on (the projection is not a simple polygon: a self-crossing or strongly
//! warped face), the polygon has no area, or it is too large for O(n r) ([`WORK_LIMIT`]),
//! the corners left are fanned and the caller is told why.

use std::cmp::{Ordering, Reverse};
use std::collections::BinaryHeap;
use std::path::Path;

use glam::{DVec2, DVec3};

use super::predicates::orient2d;
use crate::warning::{Place, Tally, Warning};

/// Most `corners x reflex corners` ear tests a polygon may take before it is fanned.
pub const WORK_LIMIT: usize = 1 << 26;

/// How a polygon was triangulated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Triangulation {
    /// By ear clipping (a triangle as it is).
    EarClipped,
    /// As a fan, because the polygon has no area.
    FanNoArea,
    /// Ear clipping stopped: the polygon is not simple in its plane; the corners left
    /// were fanned.
    FanNotSimple,
    /// As a fan, because ear clipping would take more than [`WORK_LIMIT`] tests.
    FanTooLarge,
}

/// An ear waiting in the queue: cut the shortest diagonal first, straight corners last,
/// ties to the corner after the first.
#[derive(Clone, Copy, Debug)]
struct Ear {
    straight: bool,
    diagonal: f64,
    rank: usize,
    corner: usize,
    version: u32,
}

impl Ear {
    fn key(&self) -> (Reverse<bool>, Reverse<OrderedF64>, Reverse<usize>) {
        (Reverse(self.straight), Reverse(OrderedF64(self.diagonal)), Reverse(self.rank))
    }
}

impl PartialEq for Ear {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Ear {}
impl PartialOrd for Ear {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ear {
    /// The best ear is the greatest (the queue is a max-heap).
    fn cmp(&self, other: &Self) -> Ordering {
        self.key().cmp(&other.key())
    }
}

/// An `f64` ordered by [`f64::total_cmp`].
#[derive(Clone, Copy, Debug, PartialEq)]
struct OrderedF64(f64);
impl Eq for OrderedF64 {}
impl PartialOrd for OrderedF64 {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for OrderedF64 {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0.total_cmp(&other.0)
    }
}

/// Cuts polygons into triangles, keeping its buffers from one polygon to the next.
#[derive(Default)]
pub struct EarClipper {
    /// The projected corners.
    points: Vec<DVec2>,
    /// The corners' neighbours in the polygon left to cut.
    prev: Vec<usize>,
    next: Vec<usize>,
    /// Whether a corner is still in that polygon.
    alive: Vec<bool>,
    /// Bumped whenever a corner's neighbours change, to drop its stale ears.
    version: Vec<u32>,
    /// The corners that are not strictly convex (the only ones that can block an ear).
    reflex: Vec<usize>,
    queue: BinaryHeap<Ear>,
}

impl EarClipper {
    /// Appends the triangles of the polygon `polygon` (indices into `vertices`, in
    /// order) to `out`, as index triples in the polygon's orientation: n - 2 of them.
    pub fn triangulate(&mut self, vertices: &[DVec3], polygon: &[u32], out: &mut Vec<[u32; 3]>) -> Triangulation {
        let n = polygon.len();
        if n < 3 {
            return Triangulation::EarClipped;
        }
        if n == 3 {
            out.push([polygon[0], polygon[1], polygon[2]]);
            return Triangulation::EarClipped;
        }
        if !self.project(vertices, polygon) {
            fan(polygon.iter().copied(), out);
            return Triangulation::FanNoArea;
        }
        self.start();
        // Before any ear is looked for: queueing the ears alone is n tests of r corners.
        if n.saturating_mul(self.reflex.len()) > WORK_LIMIT {
            fan(polygon.iter().copied(), out);
            return Triangulation::FanTooLarge;
        }
        self.queue.clear();
        for i in 0..n {
            self.queue_if_ear(i);
        }
        let mut left = n;
        while left > 3 {
            let Some(ear) = self.queue.pop() else { break };
            if !self.alive[ear.corner] || ear.version != self.version[ear.corner] {
                continue;
            }
            let (p, i, q) = (self.prev[ear.corner], ear.corner, self.next[ear.corner]);
            out.push([polygon[p], polygon[i], polygon[q]]);
            self.cut(i);
            left -= 1;
        }
        let first = (0..n).find(|&i| self.alive[i]).expect("three corners are left");
        if left == 3 {
            let (second, third) = (self.next[first], self.next[self.next[first]]);
            out.push([polygon[first], polygon[second], polygon[third]]);
            return Triangulation::EarClipped;
        }
        let ring = std::iter::successors(Some(first), |&i| Some(self.next[i]).filter(|&j| j != first));
        fan(ring.map(|i| polygon[i]), out);
        Triangulation::FanNotSimple
    }

    /// Projects the corners onto the plane of the polygon, counter-clockwise; false
    /// when the polygon has no area.
    fn project(&mut self, vertices: &[DVec3], polygon: &[u32]) -> bool {
        let corner = |k: usize| vertices[polygon[k % polygon.len()] as usize];
        let normal: DVec3 =
            (0..polygon.len()).map(|k| (corner(k) - corner(k + 1)).cross(corner(k) + corner(k + 1))).sum();
        let axis = normal.abs().max_position();
        if normal[axis] == 0.0 || !normal.is_finite() {
            return false;
        }
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let (u, v) = if normal[axis] > 0.0 { (u, v) } else { (v, u) };
        self.points.clear();
        self.points.extend((0..polygon.len()).map(|k| DVec2::new(corner(k)[u], corner(k)[v])));
        true
    }

    /// Links the corners in a ring and finds the reflex ones.
    fn start(&mut self) {
        let n = self.points.len();
        self.prev.clear();
        self.prev.extend((0..n).map(|i| (i + n - 1) % n));
        self.next.clear();
        self.next.extend((0..n).map(|i| (i + 1) % n));
        self.alive.clear();
        self.alive.resize(n, true);
        self.version.clear();
        self.version.resize(n, 0);
        let mut reflex = std::mem::take(&mut self.reflex);
        reflex.clear();
        reflex.extend((0..n).filter(|&i| self.turn(i) <= 0.0));
        self.reflex = reflex;
    }

    /// Removes ear `i`; its neighbours may stop being reflex and become ears.
    fn cut(&mut self, i: usize) {
        let (p, q) = (self.prev[i], self.next[i]);
        self.alive[i] = false;
        self.next[p] = q;
        self.prev[q] = p;
        for j in [p, q] {
            self.version[j] += 1;
            if self.turn(j) > 0.0 {
                self.reflex.retain(|&r| r != j);
            }
        }
        self.reflex.retain(|&r| r != i);
        self.queue_if_ear(p);
        self.queue_if_ear(q);
    }

    /// The exact sign of the turn at corner `i`: positive when convex.
    fn turn(&self, i: usize) -> f64 {
        orient2d(self.points[self.prev[i]], self.points[i], self.points[self.next[i]])
    }

    /// Queues corner `i` when it is an ear: convex (or straight, between its
    /// neighbours) with no corner of `reflex` in or on its triangle.
    fn queue_if_ear(&mut self, i: usize) {
        let (p, q) = (self.prev[i], self.next[i]);
        let [a, b, c] = [p, i, q].map(|k| self.points[k]);
        let turn = self.turn(i);
        let straight = turn == 0.0;
        if turn < 0.0 || (straight && (a - b).dot(c - b) > 0.0) {
            return;
        }
        let blocks = |&r: &usize| {
            let x = self.points[r];
            r != p
                && r != i
                && r != q
                && x != a
                && x != b
                && x != c
                && orient2d(a, b, x) >= 0.0
                && orient2d(b, c, x) >= 0.0
                && orient2d(c, a, x) >= 0.0
        };
        if self.reflex.iter().any(blocks) {
            return;
        }
        let n = self.points.len();
        let ear = Ear {
            straight,
            diagonal: a.distance_squared(c),
            rank: (i + n - 1) % n,
            corner: i,
            version: self.version[i],
        };
        self.queue.push(ear);
    }
}

/// The polygons of a file that had to be fanned, for a warning a reason.
#[derive(Default)]
pub(super) struct FanTally {
    not_simple: Tally,
    too_large: Tally,
}

impl FanTally {
    /// Counts the polygon at `place` if it was fanned for a reason worth a warning (a
    /// polygon without area is fanned silently: any cut of it is as good).
    pub(super) fn add(&mut self, how: Triangulation, place: Place) {
        match how {
            Triangulation::EarClipped | Triangulation::FanNoArea => {}
            Triangulation::FanNotSimple => self.not_simple.add(place),
            Triangulation::FanTooLarge => self.too_large.add(place),
        }
    }

    /// One warning a reason.
    pub(super) fn warnings(&self, path: &Path) -> Vec<Warning> {
        let not_simple = self.not_simple.warning(path, |n| {
            format!("faces that are not simple polygons in their plane, fanned where ear clipping stopped: {n}")
        });
        let too_large = self
            .too_large
            .warning(path, |n| format!("faces with too many reflex corners to ear-clip quickly, fanned: {n}"));
        not_simple.into_iter().chain(too_large).collect()
    }
}

/// The fan from the first corner.
fn fan(corners: impl Iterator<Item = u32>, out: &mut Vec<[u32; 3]>) {
    let corners: Vec<u32> = corners.collect();
    out.extend(corners.windows(2).skip(1).map(|w| [corners[0], w[0], w[1]]));
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Twice the signed area of a triangle in the xy plane.
    fn area2(v: &[DVec3], t: [u32; 3]) -> f64 {
        let [a, b, c] = t.map(|i| v[i as usize]);
        (b - a).cross(c - a).z
    }

    #[test]
    fn squares_fan_and_concave_polygons_keep_their_area_and_orientation() {
        let square = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let mut out = Vec::new();
        let mut clipper = EarClipper::default();
        assert_eq!(clipper.triangulate(&square, &[0, 1, 2, 3], &mut out), Triangulation::EarClipped);
        assert_eq!(out, [[0, 1, 2], [0, 2, 3]]);
        // An L of six corners, area 3, whose fan from its reflex-adjacent corner would
        // cover the notch; and the same L clockwise.
        let l = [(0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (1.0, 1.0), (1.0, 2.0), (0.0, 2.0)]
            .map(|(x, y)| DVec3::new(x, y, 0.0));
        for order in [[1u32, 2, 3, 4, 5, 0], [0, 5, 4, 3, 2, 1]] {
            out.clear();
            assert_eq!(clipper.triangulate(&l, &order, &mut out), Triangulation::EarClipped);
            assert_eq!(out.len(), 4);
            let sign = if order[1] == 2 { 1.0 } else { -1.0 };
            assert!(out.iter().all(|&t| sign * area2(&l, t) > 0.0), "{out:?}");
            assert_eq!(out.iter().map(|&t| area2(&l, t).abs()).sum::<f64>(), 6.0);
        }
    }

    #[test]
    fn a_polygon_too_large_to_clip_is_fanned_before_any_ear_is_looked_for() {
        // One OBJ face of 40 000 corners on the same vertex (what a fuzzer made of a
        // face line): every corner is straight, so not strictly convex, and each ear
        // test would scan all of them. Queueing the ears before the work limit was
        // checked took n^2 tests (5.6 s) and then fanned anyway.
        let v = [DVec3::ZERO, DVec3::Y, DVec3::X];
        let polygon: Vec<u32> = [0, 1].into_iter().chain(std::iter::repeat_n(2, 40_000)).collect();
        let mut clipper = EarClipper::default();
        let mut out = Vec::new();
        assert_eq!(clipper.triangulate(&v, &polygon, &mut out), Triangulation::FanTooLarge);
        assert_eq!(out.len(), polygon.len() - 2);
        assert!(clipper.queue.is_empty(), "{} ears were queued before the limit was checked", clipper.queue.len());
    }

    #[test]
    fn a_polygon_that_winds_round_three_times_is_fanned_and_says_so() {
        // A square gone round three times (an OBJ face of assimp's tests does this):
        // ear clipping cuts some ears, then none is free of the other rounds' corners;
        // the rest is fanned, still n - 2 triangles.
        let v = [DVec3::ZERO, DVec3::X, DVec3::new(1.0, 1.0, 0.0), DVec3::Y];
        let polygon: Vec<u32> = (0..12).map(|i| i % 4).collect();
        let mut out = Vec::new();
        assert_eq!(EarClipper::default().triangulate(&v, &polygon, &mut out), Triangulation::FanNotSimple);
        assert_eq!(out.len(), 10);
    }
}
