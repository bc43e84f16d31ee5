//! 2D profiles: the regions `extrude` sweeps and `revolve` turns.
//!
//! A [`Profile`] is a polygon with holes (even-odd, [`Polygon`]), a circle, a
//! rectangle, or a union or difference of profiles (the first minus the rest). Each
//! answers what the 3D shapes built on it need:
//! - [`Profile::contains`] a point;
//! - [`Profile::distance`], the signed distance to the boundary (negative inside):
//!   exact Euclidean for the leaves, and for the set operations the distance bounds
//!   of CSG (union `min`, difference `max(a, -b)`), which have the right sign and never
//!   exceed the true distance in magnitude (Hart 1996, *Sphere tracing*, §3);
//!   [`Profile::surface`] adds the outward normal of the boundary chosen;
//! - [`Profile::classify_disc`], conservatively, a disc (a 2D box through the disc
//!   around it, [`Profile::classify_box`]): a leaf's exact distance `d` at the centre
//!   says the disc of radius `r` is inside when `d < -r` and outside when `d > r` (a
//!   relative margin of `1e-9` against rounding); the set operations combine the
//!   classes by the Inside / Outside / Boundary algebra of [`super::Csg`], which is
//!   sound because each leaf's is;
//! - [`Profile::area`]: exact for the leaves (shoelace, `pi r^2`, `w h`); for a union
//!   or difference, which has no closed form, the area of the cells a quadtree of the
//!   profile's box decides inside plus those still undecided at [`AREA_LEVELS`]
//!   levels whose centre is inside (an error below the undecided cells' area, about
//!   the perimeter times `2^-AREA_LEVELS` of the box, and much less in practice: the
//!   centres err both ways);
//! - [`Profile::support`]: a point farthest along a direction, for hulls (none for a
//!   difference, whose cut may remove it).

use glam::DVec2;

use super::Class;
use super::bounds::both;
use crate::error::{Error, Result};

mod polygon;
mod spec;

pub use polygon::{Polygon, ProfileSurface};
pub use spec::{MAX_PROFILE_NESTING, ProfileSpec};

/// Quadtree levels of a set operation's [`Profile::area`].
pub const AREA_LEVELS: u32 = 11;

/// A 2D region (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Profile(Node);

#[derive(Clone, Debug, PartialEq)]
enum Node {
    Polygon(Polygon),
    Circle { center: DVec2, radius: f64 },
    Rectangle { center: DVec2, half: DVec2 },
    Union(Vec<Profile>),
    Difference(Vec<Profile>),
}

impl Profile {
    /// A polygon without holes; see [`Polygon::new`] for the checks.
    pub fn polygon(points: Vec<DVec2>) -> Result<Profile> {
        Profile::polygon_with_holes(points, Vec::new())
    }

    /// A polygon with holes (even-odd over the outline and the holes, which must be
    /// simple and apart); see [`Polygon::new`].
    pub fn polygon_with_holes(outline: Vec<DVec2>, holes: Vec<Vec<DVec2>>) -> Result<Profile> {
        let mut rings = vec![outline];
        rings.extend(holes);
        Ok(Profile(Node::Polygon(Polygon::new(rings)?)))
    }

    /// The disc of `radius` around `center`.
    pub fn circle(center: DVec2, radius: f64) -> Result<Profile> {
        if !(center.is_finite() && radius.is_finite() && radius > 0.0) {
            return Err(Error::invalid(
                "circle",
                format!("center {center} must be finite, radius {} positive", crate::error::Number(radius)),
            ));
        }
        Ok(Profile(Node::Circle { center, radius }))
    }

    /// The axis-aligned rectangle of `size` around `center`.
    pub fn rectangle(center: DVec2, size: DVec2) -> Result<Profile> {
        if !(center.is_finite() && size.is_finite() && size.min_element() > 0.0) {
            return Err(Error::invalid("rectangle", format!("center {center} must be finite, size {size} positive")));
        }
        Ok(Profile(Node::Rectangle { center, half: size * 0.5 }))
    }

    /// Points in any of `parts` (at least one).
    pub fn union(parts: Vec<Profile>) -> Result<Profile> {
        Ok(Profile(Node::Union(operands(parts)?)))
    }

    /// Points in the first of `parts` and in none of the others.
    pub fn difference(parts: Vec<Profile>) -> Result<Profile> {
        Ok(Profile(Node::Difference(operands(parts)?)))
    }

    /// Whether `p` is in the region.
    #[must_use]
    pub fn contains(&self, p: DVec2) -> bool {
        match &self.0 {
            Node::Polygon(polygon) => polygon.contains(p),
            Node::Circle { center, radius } => (p - *center).length_squared() <= radius * radius,
            Node::Rectangle { center, half } => {
                let q = (p - *center).abs();
                q.x <= half.x && q.y <= half.y
            }
            Node::Union(parts) => parts.iter().any(|part| part.contains(p)),
            Node::Difference(parts) => parts[0].contains(p) && !parts[1..].iter().any(|part| part.contains(p)),
        }
    }

    /// The signed distance to the boundary (see the module doc: exact for leaves, a
    /// bound of the right sign for set operations).
    #[must_use]
    pub fn distance(&self, p: DVec2) -> f64 {
        match &self.0 {
            Node::Polygon(polygon) => {
                let d = polygon.edge_distance(p);
                if polygon.contains(p) { -d } else { d }
            }
            Node::Circle { center, radius } => (p - *center).length() - radius,
            Node::Rectangle { center, half } => {
                let q = (p - *center).abs() - *half;
                q.max(DVec2::ZERO).length() + q.max_element().min(0.0)
            }
            Node::Union(parts) => parts.iter().map(|part| part.distance(p)).fold(f64::INFINITY, f64::min),
            Node::Difference(parts) => {
                parts[1..].iter().map(|part| -part.distance(p)).fold(parts[0].distance(p), f64::max)
            }
        }
    }

    /// [`Profile::distance`] with the outward unit normal of the boundary it measures
    /// to; `None` where that normal is undefined (a circle's centre).
    #[must_use]
    pub fn surface(&self, p: DVec2) -> Option<ProfileSurface> {
        match &self.0 {
            Node::Polygon(polygon) => Some(polygon.surface(p)),
            Node::Circle { center, radius } => {
                let r = p - *center;
                Some(ProfileSurface { distance: r.length() - radius, normal: r.try_normalize()? })
            }
            Node::Rectangle { center, half } => {
                let r = p - *center;
                let q = r.abs() - *half;
                let normal = if q.max_element() > 0.0 {
                    (q.max(DVec2::ZERO) * r.signum()).normalize()
                } else if q.x > q.y {
                    DVec2::new(r.x.signum(), 0.0)
                } else {
                    DVec2::new(0.0, r.y.signum())
                };
                Some(ProfileSurface { distance: self.distance(p), normal })
            }
            Node::Union(parts) => {
                let mut best: Option<ProfileSurface> = None;
                for part in parts {
                    let s = part.surface(p)?;
                    if best.is_none_or(|b| s.distance < b.distance) {
                        best = Some(s);
                    }
                }
                best
            }
            Node::Difference(parts) => {
                let mut best = parts[0].surface(p)?;
                for part in &parts[1..] {
                    let s = part.surface(p)?.flipped();
                    if s.distance > best.distance {
                        best = s;
                    }
                }
                Some(best)
            }
        }
    }

    /// Conservative class of the closed disc of `radius` around `center` (see the
    /// module doc).
    #[must_use]
    pub fn classify_disc(&self, center: DVec2, radius: f64) -> Class {
        if !(center.is_finite() && radius.is_finite()) {
            return Class::Boundary;
        }
        match &self.0 {
            Node::Union(parts) => {
                let mut all_outside = true;
                for part in parts {
                    match part.classify_disc(center, radius) {
                        Class::Inside => return Class::Inside,
                        Class::Boundary => all_outside = false,
                        Class::Outside => {}
                    }
                }
                if all_outside { Class::Outside } else { Class::Boundary }
            }
            Node::Difference(parts) => parts[1..].iter().fold(parts[0].classify_disc(center, radius), |acc, part| {
                if acc == Class::Outside { acc } else { both(acc, part.classify_disc(center, radius).complement()) }
            }),
            _ => {
                let d = self.distance(center);
                let margin = 1e-9 * (center.abs().max_element() + radius + self.extent());
                if d < -(radius + margin) {
                    Class::Inside
                } else if d > radius + margin {
                    Class::Outside
                } else {
                    Class::Boundary
                }
            }
        }
    }

    /// Conservative class of the closed box `[min, max]`: that of the disc around it.
    #[must_use]
    pub fn classify_box(&self, min: DVec2, max: DVec2) -> Class {
        self.classify_disc((min + max) * 0.5, (max - min).length() * 0.5)
    }

    /// The lowest and highest corners of a box holding the region.
    #[must_use]
    pub fn bounds(&self) -> (DVec2, DVec2) {
        match &self.0 {
            Node::Polygon(polygon) => polygon.bounds(),
            Node::Circle { center, radius } => (*center - *radius, *center + *radius),
            Node::Rectangle { center, half } => (*center - *half, *center + *half),
            Node::Union(parts) => parts
                .iter()
                .map(Profile::bounds)
                .fold((DVec2::INFINITY, DVec2::NEG_INFINITY), |(lo, hi), (a, b)| (lo.min(a), hi.max(b))),
            Node::Difference(parts) => parts[0].bounds(),
        }
    }

    /// The area (see the module doc: exact for leaves, within the undecided cells of
    /// a quadtree for set operations).
    #[must_use]
    pub fn area(&self) -> f64 {
        match &self.0 {
            Node::Polygon(polygon) => polygon.area(),
            Node::Circle { radius, .. } => std::f64::consts::PI * radius * radius,
            Node::Rectangle { half, .. } => 4.0 * half.x * half.y,
            Node::Union(_) | Node::Difference(_) => {
                let (lo, hi) = self.bounds();
                self.cell_area(lo, hi, AREA_LEVELS)
            }
        }
    }

    /// The area in the box `[lo, hi]` by a quadtree `levels` deep (undecided leaves
    /// counted by their centre).
    fn cell_area(&self, lo: DVec2, hi: DVec2, levels: u32) -> f64 {
        let size = hi - lo;
        match self.classify_box(lo, hi) {
            Class::Inside => size.x * size.y,
            Class::Outside => 0.0,
            Class::Boundary if levels == 0 => {
                if self.contains((lo + hi) * 0.5) {
                    size.x * size.y
                } else {
                    0.0
                }
            }
            Class::Boundary => {
                let mid = (lo + hi) * 0.5;
                [
                    (lo, mid),
                    (DVec2::new(mid.x, lo.y), DVec2::new(hi.x, mid.y)),
                    (DVec2::new(lo.x, mid.y), DVec2::new(mid.x, hi.y)),
                    (mid, hi),
                ]
                .iter()
                .map(|&(a, b)| self.cell_area(a, b, levels - 1))
                .sum()
            }
        }
    }

    /// A point of the region farthest along `d`; `None` for a difference (see the
    /// module doc).
    #[must_use]
    pub fn support(&self, d: DVec2) -> Option<DVec2> {
        match &self.0 {
            Node::Polygon(polygon) => Some(polygon.support(d)),
            Node::Circle { center, radius } => Some(*center + d.normalize_or_zero() * *radius),
            Node::Rectangle { center, half } => Some(*center + DVec2::new(half.x.copysign(d.x), half.y.copysign(d.y))),
            Node::Union(parts) => {
                let mut best: Option<DVec2> = None;
                for part in parts {
                    let s = part.support(d)?;
                    if best.is_none_or(|b| s.dot(d) > b.dot(d)) {
                        best = Some(s);
                    }
                }
                best
            }
            Node::Difference(_) => None,
        }
    }

    /// The largest coordinate magnitude of the region's box (the scale of rounding).
    fn extent(&self) -> f64 {
        let (lo, hi) = self.bounds();
        lo.abs().max(hi.abs()).max_element()
    }
}

fn operands(parts: Vec<Profile>) -> Result<Vec<Profile>> {
    if parts.is_empty() {
        return Err(Error::invalid("profile", "a union or difference needs at least one profile"));
    }
    Ok(parts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_operations_classify_soundly_and_their_area_is_close() {
        let plate = Profile::rectangle(DVec2::ZERO, DVec2::new(4.0, 2.0)).unwrap();
        let hole = Profile::circle(DVec2::ZERO, 0.5).unwrap();
        let cut = Profile::difference(vec![plate, hole]).unwrap();
        let want = 8.0 - std::f64::consts::PI * 0.25;
        assert!((cut.area() / want - 1.0).abs() < 1e-3, "{}", cut.area());
        // A dense check: every decided disc agrees with the points in it.
        for i in 0..40 {
            for j in 0..20 {
                let c = DVec2::new(-2.2 + 0.11 * f64::from(i), -1.1 + 0.11 * f64::from(j));
                let class = cut.classify_disc(c, 0.08);
                for k in 0..16 {
                    let a = f64::from(k) * std::f64::consts::TAU / 16.0;
                    let p = c + DVec2::new(a.cos(), a.sin()) * 0.079;
                    match class {
                        Class::Inside => assert!(cut.contains(p), "{p}"),
                        Class::Outside => assert!(!cut.contains(p), "{p}"),
                        Class::Boundary => {}
                    }
                }
            }
        }
        let s = cut.surface(DVec2::new(0.6, 0.0)).unwrap();
        assert!((s.distance + 0.1).abs() < 1e-12 && (s.normal - DVec2::NEG_X).length() < 1e-12, "{s:?}");
        assert_eq!(cut.support(DVec2::X), None);
    }
}
