//! Polygons with holes: closed rings of points filled by the **even-odd** rule.
//!
//! A point is in the polygon when a ray from it crosses its rings an odd number of
//! times (the crossing number with the half-open rule of Shimrat 1962 / Haines 1994:
//! an edge counts when its ends lie on either side of the point's horizontal line, an
//! end on the line counted above), so a hole is a ring inside the outline, and an
//! island a ring inside a hole; the rings' directions do not matter.
//!
//! The rings are checked when the polygon is made: at least three points each, every
//! coordinate finite, no zero-length edge, no ring of zero area, and no two edges of
//! any rings meeting except consecutive edges at their shared corner (exact
//! orientation predicates, Shewchuk's, from the `robust` crate). So the rings are
//! simple and disjoint, and then the even-odd region is the one bounded by them: the
//! area is `sum_i (-1)^(k_i) |A_i|` (shoelace areas `A_i`, `k_i` the rings holding ring
//! `i`), and each edge's outward side is known (a ring at an even nesting bounds its
//! inside, an odd one its outside).
//!
//! Distances are exact: the least distance to any edge, negative inside (`O(edges)` a
//! query; no index over the edges).

use glam::DVec2;

use crate::error::{Error, Result};

/// A polygon with holes (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Polygon {
    /// The rings, each without its closing point.
    rings: Vec<Vec<DVec2>>,
    /// Per ring: `+1` when its outward side is to the right of its edges, else `-1`.
    outward: Vec<f64>,
    /// The even-odd area.
    area: f64,
}

/// The nearest boundary of a profile seen from a point: a signed distance (negative
/// inside) and the outward unit normal there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProfileSurface {
    /// Signed distance (negative inside).
    pub distance: f64,
    /// Outward unit normal of the nearest boundary.
    pub normal: DVec2,
}

impl ProfileSurface {
    /// The complement's boundary: the same, seen from the other side.
    #[must_use]
    pub fn flipped(self) -> ProfileSurface {
        ProfileSurface { distance: -self.distance, normal: -self.normal }
    }
}

impl Polygon {
    /// The polygon of `rings` (an outline, its holes, islands in them...), checked as
    /// the module doc says; a ring may repeat its first point at the end.
    pub fn new(rings: Vec<Vec<DVec2>>) -> Result<Polygon> {
        if rings.is_empty() {
            return Err(bad("a polygon needs a ring of at least 3 points"));
        }
        let mut closed = Vec::with_capacity(rings.len());
        for (r, mut ring) in rings.into_iter().enumerate() {
            if ring.len() > 3 && ring.first() == ring.last() {
                ring.pop();
            }
            if ring.len() < 3 {
                return Err(bad(format!("{} has {} points; at least 3", ring_name(r), ring.len())));
            }
            if let Some(i) = ring.iter().position(|p| !p.is_finite()) {
                return Err(bad(format!("point {i} of {} is not finite: {}", ring_name(r), ring[i])));
            }
            if let Some(i) = (0..ring.len()).find(|&i| ring[i] == ring[(i + 1) % ring.len()]) {
                return Err(bad(format!("points {i} and {} of {} are the same", (i + 1) % ring.len(), ring_name(r))));
            }
            if shoelace(&ring) == 0.0 {
                return Err(bad(format!("{} has no area", ring_name(r))));
            }
            closed.push(ring);
        }
        check_simple(&closed)?;
        let depth: Vec<usize> = (0..closed.len())
            .map(|i| (0..closed.len()).filter(|&j| j != i && in_ring(&closed[j], closed[i][0])).count())
            .collect();
        let outward = (0..closed.len())
            .map(|i| {
                let even = if depth[i].is_multiple_of(2) { 1.0 } else { -1.0 };
                shoelace(&closed[i]).signum() * even
            })
            .collect();
        let area = (0..closed.len())
            .map(|i| if depth[i].is_multiple_of(2) { shoelace(&closed[i]).abs() } else { -shoelace(&closed[i]).abs() })
            .sum();
        Ok(Polygon { rings: closed, outward, area })
    }

    /// The rings (without closing points).
    #[must_use]
    pub fn rings(&self) -> &[Vec<DVec2>] {
        &self.rings
    }

    /// The even-odd area.
    #[must_use]
    pub fn area(&self) -> f64 {
        self.area
    }

    /// Whether `p` is inside (even-odd crossing number).
    #[must_use]
    pub fn contains(&self, p: DVec2) -> bool {
        self.rings.iter().fold(false, |inside, ring| inside ^ in_ring(ring, p))
    }

    /// The least distance from `p` to an edge, unsigned.
    #[must_use]
    pub fn edge_distance(&self, p: DVec2) -> f64 {
        self.nearest(p).0.sqrt()
    }

    /// Exact signed distance and the outward normal (from the nearest edge point
    /// towards `p` outside, away from it inside; the edge's own normal on the edge).
    #[must_use]
    pub fn surface(&self, p: DVec2) -> ProfileSurface {
        let (squared, q, edge_normal) = self.nearest(p);
        let distance = squared.sqrt();
        let inside = self.contains(p);
        let away = (p - q).try_normalize();
        let normal = match away {
            Some(n) if inside => -n,
            Some(n) => n,
            None => edge_normal,
        };
        ProfileSurface { distance: if inside { -distance } else { distance }, normal }
    }

    /// The lowest and highest corners of the points' box.
    #[must_use]
    pub fn bounds(&self) -> (DVec2, DVec2) {
        let all = self.rings.iter().flatten();
        (all.clone().fold(DVec2::INFINITY, |a, &p| a.min(p)), all.fold(DVec2::NEG_INFINITY, |a, &p| a.max(p)))
    }

    /// A vertex farthest along `d` (the region's hull is its vertices' hull).
    #[must_use]
    pub fn support(&self, d: DVec2) -> DVec2 {
        let mut best = self.rings[0][0];
        for &p in self.rings.iter().flatten() {
            if p.dot(d) > best.dot(d) {
                best = p;
            }
        }
        best
    }

    /// The squared distance to the nearest edge, the nearest point and that edge's
    /// outward unit normal.
    fn nearest(&self, p: DVec2) -> (f64, DVec2, DVec2) {
        let mut best = (f64::INFINITY, p, DVec2::X);
        for (ring, &side) in self.rings.iter().zip(&self.outward) {
            for i in 0..ring.len() {
                let (a, b) = (ring[i], ring[(i + 1) % ring.len()]);
                let ab = b - a;
                let t = ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0);
                let q = a + ab * t;
                let squared = (p - q).length_squared();
                if squared < best.0 {
                    best = (squared, q, DVec2::new(ab.y, -ab.x).normalize() * side);
                }
            }
        }
        best
    }
}

fn ring_name(r: usize) -> String {
    if r == 0 { "the outline".to_string() } else { format!("ring {r}") }
}

fn bad(reason: impl Into<String>) -> Error {
    Error::invalid("polygon", reason)
}

/// The signed area (positive counter-clockwise) by the shoelace formula.
fn shoelace(ring: &[DVec2]) -> f64 {
    let n = ring.len();
    0.5 * (0..n).map(|i| ring[i].perp_dot(ring[(i + 1) % n])).sum::<f64>()
}

/// Whether `p` is inside the ring (crossing number, half-open rule).
fn in_ring(ring: &[DVec2], p: DVec2) -> bool {
    let mut inside = false;
    let mut a = ring[ring.len() - 1];
    for &b in ring {
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
        a = b;
    }
    inside
}

/// Exact sign of the turn `a -> b -> c` (positive counter-clockwise).
fn orient(a: DVec2, b: DVec2, c: DVec2) -> f64 {
    let k = |v: DVec2| robust::Coord { x: v.x, y: v.y };
    robust::orient2d(k(a), k(b), k(c))
}

/// Whether the closed segments `ab` and `cd` share a point (exactly).
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (o1, o2, o3, o4) = (orient(a, b, c), orient(a, b, d), orient(c, d, a), orient(c, d, b));
    let on = |p: DVec2, q: DVec2, r: DVec2| r.cmpge(p.min(q)).all() && r.cmple(p.max(q)).all();
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    (o1 == 0.0 && on(a, b, c)) || (o2 == 0.0 && on(a, b, d)) || (o3 == 0.0 && on(c, d, a)) || (o4 == 0.0 && on(c, d, b))
}

/// Refuses rings whose edges meet anywhere but at consecutive edges' shared corner
/// (edges sorted by their lowest x, each compared with those whose x ranges overlap).
fn check_simple(rings: &[Vec<DVec2>]) -> Result<()> {
    struct Edge {
        ring: usize,
        index: usize,
        a: DVec2,
        b: DVec2,
    }
    let mut edges: Vec<Edge> = rings
        .iter()
        .enumerate()
        .flat_map(|(r, ring)| {
            (0..ring.len()).map(move |i| Edge { ring: r, index: i, a: ring[i], b: ring[(i + 1) % ring.len()] })
        })
        .collect();
    edges.sort_by(|e, f| e.a.x.min(e.b.x).total_cmp(&f.a.x.min(f.b.x)));
    for (i, e) in edges.iter().enumerate() {
        let right = e.a.x.max(e.b.x);
        for f in edges[i + 1..].iter().take_while(|f| f.a.x.min(f.b.x) <= right) {
            let n = rings[e.ring].len();
            let consecutive = e.ring == f.ring && ((e.index + 1) % n == f.index || (f.index + 1) % n == e.index);
            let meet = if consecutive {
                // They share a corner; they must not fold back along each other.
                let (shared, p, q) = if e.b == f.a { (e.b, e.a, f.b) } else { (e.a, e.b, f.a) };
                orient(p, shared, q) == 0.0 && (p - shared).dot(q - shared) > 0.0
            } else {
                segments_meet(e.a, e.b, f.a, f.b)
            };
            if meet {
                let what = |g: &Edge| format!("edge {} of {}", g.index, ring_name(g.ring));
                return Err(bad(format!(
                    "{} and {} cross or touch: the rings must be simple and apart",
                    what(e),
                    what(f)
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(c: f64, h: f64) -> Vec<DVec2> {
        vec![DVec2::new(c - h, c - h), DVec2::new(c + h, c - h), DVec2::new(c + h, c + h), DVec2::new(c - h, c + h)]
    }

    #[test]
    fn a_square_with_a_hole_and_an_island_has_even_odd_area_and_points() {
        let p = Polygon::new(vec![square(0.0, 3.0), square(0.0, 2.0), square(0.0, 1.0)]).unwrap();
        assert_eq!(p.area(), 36.0 - 16.0 + 4.0);
        assert!(p.contains(DVec2::new(2.5, 0.0)) && !p.contains(DVec2::new(1.5, 0.0)) && p.contains(DVec2::ZERO));
        let s = p.surface(DVec2::new(1.5, 0.2));
        assert!((s.distance - 0.5).abs() < 1e-15 && (s.normal - DVec2::NEG_X).length() < 1e-12, "{s:?}");
        let s = p.surface(DVec2::new(2.75, 0.0));
        assert!((s.distance + 0.25).abs() < 1e-15 && (s.normal - DVec2::X).length() < 1e-12, "{s:?}");
    }

    #[test]
    fn crossing_rings_few_points_and_nan_are_refused() {
        let bowtie = vec![DVec2::ZERO, DVec2::new(2.0, 2.0), DVec2::new(2.0, 0.0), DVec2::new(0.0, 1.0)];
        assert!(Polygon::new(vec![bowtie]).unwrap_err().to_string().contains("cross"));
        let e = Polygon::new(vec![vec![DVec2::ZERO, DVec2::X]]).unwrap_err().to_string();
        assert!(e.contains("2 points"), "{e}");
        let e = Polygon::new(vec![vec![DVec2::ZERO, DVec2::X, DVec2::NAN]]).unwrap_err().to_string();
        assert!(e.contains("not finite"), "{e}");
        assert!(Polygon::new(vec![square(0.0, 1.0), square(1.0, 1.0)]).is_err());
        let flat = vec![DVec2::ZERO, DVec2::X, DVec2::new(2.0, 0.0)];
        assert!(Polygon::new(vec![flat]).is_err());
    }
}
