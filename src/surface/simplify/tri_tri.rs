//! Exact triangle-triangle intersection, as the simplifier's self-intersection test.
//!
//! Two triangles of an embedded mesh may meet only in what they share: a common corner
//! or a common edge. [`triangles_clash`] says whether two closed triangles meet anywhere
//! else. Corners are shared by *position*, not by index, so two vertices of a sheet
//! (distinct indices at one point, where voxels touch along an edge or a corner) count
//! as shared and their triangles may touch there.
//!
//! Every decision is a sign of an exact orientation predicate (`orient3d`, `orient2d`,
//! Shewchuk's adaptive arithmetic), never a rounded intersection point:
//! - no shared corner: the triangles meet iff neither lies strictly on one side of the
//!   other's plane and, when not coplanar, an edge of one meets the other (the ends of
//!   the segment two non-coplanar triangles share lie on edges of them); coplanar ones
//!   are compared in the coordinate plane their normal's largest axis projects them to
//!   (exact: dropping a coordinate keeps incidences of coplanar points);
//! - one shared corner `s`: they meet elsewhere iff the edge opposite `s` in one meets
//!   the other (their common part is convex and holds `s`; any other point of it lies
//!   on a segment from `s` that leaves one of them through its opposite edge);
//! - two shared corners (a common edge): only coplanar triangles folded onto the same
//!   side of the edge overlap;
//! - three: the same triangle twice, a clash.
//!
//! A segment meets a triangle's plane between its ends when the two `orient3d` signs
//! differ, and the line through it meets the closed triangle when the three tetrahedra
//! it spans with the triangle's edges agree in sign (Plücker coordinates' sign test).

use glam::{DVec2, DVec3};

use crate::mesh::predicates::{orient2d, orient3d};

/// Whether closed triangles `p` and `q` (non-degenerate) meet anywhere but in the
/// corners they share by position and the segment between two shared corners.
#[must_use]
pub(crate) fn triangles_clash(p: [DVec3; 3], q: [DVec3; 3]) -> bool {
    if clearly_apart(p, q) {
        return false;
    }
    let mut shared = 0;
    let (mut in_p, mut in_q) = ([false; 3], [false; 3]);
    for i in 0..3 {
        for j in 0..3 {
            if p[i] == q[j] {
                shared += 1;
                in_p[i] = true;
                in_q[j] = true;
            }
        }
    }
    match shared {
        0 => triangles_meet(p, q),
        1 => {
            let (i, j) = (in_p.iter().position(|&s| s).unwrap_or(0), in_q.iter().position(|&s| s).unwrap_or(0));
            opposite_edge_meets(p[(i + 1) % 3], p[(i + 2) % 3], q)
                || opposite_edge_meets(q[(j + 1) % 3], q[(j + 2) % 3], p)
        }
        2 => {
            let (Some(i), Some(j)) = (in_p.iter().position(|&s| !s), in_q.iter().position(|&s| !s)) else {
                return true;
            };
            let (s0, s1) = (p[(i + 1) % 3], p[(i + 2) % 3]);
            let flat = flat_axis(&[s0, s1, p[i], q[j]]);
            if flat.is_none() && orient3d(s0, s1, p[i], q[j]) != 0.0 {
                return false;
            }
            let drop = flat.unwrap_or_else(|| dominant_axis(p));
            let side_p = orient2d(project(s0, drop), project(s1, drop), project(p[i], drop));
            let side_q = orient2d(project(s0, drop), project(s1, drop), project(q[j], drop));
            side_p * side_q >= 0.0
        }
        _ => true,
    }
}

/// Whether a separating axis among the two normals and the in-plane normals of the
/// edges parts the triangles by more than the rounding of the projections: a float
/// filter that settles most pairs (coplanar neighbours of a staircase among them)
/// before any exact predicate. Any axis, however rounded, separates the true points
/// when their computed projections are apart by more than the dot products' error
/// (`3 eps |axis| |x|`, bounded by [`APART_MARGIN`]).
fn clearly_apart(p: [DVec3; 3], q: [DVec3; 3]) -> bool {
    let (np, nq) = ((p[1] - p[0]).cross(p[2] - p[0]), (q[1] - q[0]).cross(q[2] - q[0]));
    let size = size_of(p.iter().chain(&q));
    let apart = |axis: DVec3| apart_along(axis, &p, &q, size);
    apart(np)
        || apart(nq)
        || (0..3).any(|i| apart(np.cross(p[(i + 1) % 3] - p[i])) || apart(nq.cross(q[(i + 1) % 3] - q[i])))
}

/// Whether the edge `d, e` of one triangle, opposite the corner it shares with `t`,
/// meets `t`: first a float filter like [`clearly_apart`] (the segment and `t` parted
/// along `t`'s normal, the in-plane normals of its edges, or the crosses of the
/// segment with them), then [`segment_meets_triangle`]. The filter settles the faces
/// of one fan, which touch at their shared corner, so [`clearly_apart`] never parts
/// them and the exact predicates, near zero on a nearly flat fan, took their slow
/// path (5 million of them merging the classic part's cells at depth 9).
fn opposite_edge_meets(d: DVec3, e: DVec3, t: [DVec3; 3]) -> bool {
    let (u, v) = (t[1] - t[0], t[2] - t[0]);
    let n = u.cross(v);
    // A triangle whose corners may be collinear is left to the exact predicates
    // (which find any segment in its plane meeting it, as the merge's check relies
    // on): only a normal far above its rounding proves it is not.
    if n.length_squared() <= DEGENERATE_AREA * u.length_squared() * v.length_squared() {
        return segment_meets_triangle(d, e, t);
    }
    let size = size_of([d, e].iter().chain(&t));
    let segment = [d, e];
    let apart = |axis: DVec3| apart_along(axis, &segment, &t, size);
    let parted = apart(n)
        || (0..3).any(|k| {
            let edge = t[(k + 1) % 3] - t[k];
            apart(n.cross(edge)) || apart((e - d).cross(edge))
        });
    !parted && segment_meets_triangle(d, e, t)
}

/// The largest coordinate's magnitude among `points`, times `sqrt 3` (a bound on
/// their lengths), for [`apart_along`]'s margin.
fn size_of<'a>(points: impl Iterator<Item = &'a DVec3>) -> f64 {
    points.fold(0.0f64, |m, x| m.max(x.abs().max_element())) * 3f64.sqrt()
}

/// Whether the computed projections of point sets `p` and `q` on `axis` are apart by
/// more than the dot products' rounding (`APART_MARGIN |axis| size`): then some
/// plane separates the true points strictly, however rounded `axis` is.
fn apart_along(axis: DVec3, p: &[DVec3], q: &[DVec3], size: f64) -> bool {
    let span = |s: &[DVec3]| {
        s.iter().map(|x| axis.dot(*x)).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| (lo.min(d), hi.max(d)))
    };
    let ((lo_p, hi_p), (lo_q, hi_q)) = (span(p), span(q));
    let margin = APART_MARGIN * axis.length() * size;
    hi_p + margin < lo_q || hi_q + margin < lo_p
}

/// Relative error allowance of a float dot product in [`clearly_apart`] (far above
/// `3 eps`).
const APART_MARGIN: f64 = 1e-13;
/// Squared sine of a triangle's corner angle below which [`opposite_edge_meets`]
/// (and the merge's flat fans) take its corners as possibly collinear (far above the
/// cross product's rounding).
pub(crate) const DEGENERATE_AREA: f64 = 1e-20;

/// Whether closed triangles `p` and `q` have a common point.
#[must_use]
pub(crate) fn triangles_meet(p: [DVec3; 3], q: [DVec3; 3]) -> bool {
    if let Some(drop) = flat_axis(&[p[0], p[1], p[2], q[0], q[1], q[2]]) {
        return coplanar_triangles_meet(p, q, drop);
    }
    let dp = p.map(|x| orient3d(q[0], q[1], q[2], x));
    if strictly_one_side(dp) {
        return false;
    }
    let dq = q.map(|x| orient3d(p[0], p[1], p[2], x));
    if strictly_one_side(dq) {
        return false;
    }
    if dp.iter().all(|&d| d == 0.0) {
        return coplanar_triangles_meet(p, q, dominant_axis(q));
    }
    (0..3).any(|i| segment_meets_triangle(p[i], p[(i + 1) % 3], q))
        || (0..3).any(|j| segment_meets_triangle(q[j], q[(j + 1) % 3], p))
}

/// Whether coplanar closed triangles `p` and `q` meet, seen with coordinate `drop`
/// left out.
fn coplanar_triangles_meet(p: [DVec3; 3], q: [DVec3; 3], drop: usize) -> bool {
    let (p2, q2) = (p.map(|x| project(x, drop)), q.map(|x| project(x, drop)));
    (0..3).any(|i| (0..3).any(|j| segments_meet(p2[i], p2[(i + 1) % 3], q2[j], q2[(j + 1) % 3])))
        || point_in_triangle(p2[0], q2)
        || point_in_triangle(q2[0], p2)
}

/// The axis along which all `points` have the same coordinate, if any: they are then
/// coplanar exactly, in a plane that coordinate's projection keeps one to one (the
/// flats of a staircase and of a box, settled without the adaptive predicates).
fn flat_axis(points: &[DVec3]) -> Option<usize> {
    (0..3).find(|&k| points.iter().all(|x| x[k] == points[0][k]))
}

/// Whether the closed segment `d, e` meets the closed triangle `t`.
#[must_use]
pub(crate) fn segment_meets_triangle(d: DVec3, e: DVec3, t: [DVec3; 3]) -> bool {
    let flat = flat_axis(&[d, e, t[0], t[1], t[2]]);
    let (sd, se) = match flat {
        Some(_) => (0.0, 0.0),
        None => (orient3d(t[0], t[1], t[2], d), orient3d(t[0], t[1], t[2], e)),
    };
    if sd * se > 0.0 {
        return false;
    }
    if sd == 0.0 && se == 0.0 {
        let drop = flat.unwrap_or_else(|| dominant_axis(t));
        let (d2, e2, t2) = (project(d, drop), project(e, drop), t.map(|x| project(x, drop)));
        return point_in_triangle(d2, t2)
            || point_in_triangle(e2, t2)
            || (0..3).any(|i| segments_meet(d2, e2, t2[i], t2[(i + 1) % 3]));
    }
    let s = [orient3d(d, e, t[0], t[1]), orient3d(d, e, t[1], t[2]), orient3d(d, e, t[2], t[0])];
    s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
}

/// Whether all three signs are positive, or all negative.
fn strictly_one_side(d: [f64; 3]) -> bool {
    d.iter().all(|&x| x > 0.0) || d.iter().all(|&x| x < 0.0)
}

/// The axis along which the triangle's normal is largest: dropping it projects the
/// triangle's plane one to one.
fn dominant_axis(t: [DVec3; 3]) -> usize {
    let n = (t[1] - t[0]).cross(t[2] - t[0]).abs();
    if n.x >= n.y && n.x >= n.z {
        0
    } else if n.y >= n.z {
        1
    } else {
        2
    }
}

/// `x` without its coordinate `drop`.
fn project(x: DVec3, drop: usize) -> DVec2 {
    match drop {
        0 => DVec2::new(x.y, x.z),
        1 => DVec2::new(x.z, x.x),
        _ => DVec2::new(x.x, x.y),
    }
}

/// Whether the closed segments `a, b` and `c, d` meet.
fn segments_meet(a: DVec2, b: DVec2, c: DVec2, d: DVec2) -> bool {
    let (d1, d2) = (orient2d(a, b, c), orient2d(a, b, d));
    let (d3, d4) = (orient2d(c, d, a), orient2d(c, d, b));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return true;
    }
    (d1 == 0.0 && within(a, b, c))
        || (d2 == 0.0 && within(a, b, d))
        || (d3 == 0.0 && within(c, d, a))
        || (d4 == 0.0 && within(c, d, b))
}

/// Whether `p`, collinear with `a, b`, lies in the box of `a, b` (so on the segment).
fn within(a: DVec2, b: DVec2, p: DVec2) -> bool {
    a.min(b).cmple(p).all() && p.cmple(a.max(b)).all()
}

/// Whether `p` lies in the closed triangle `t` (non-degenerate).
fn point_in_triangle(p: DVec2, t: [DVec2; 3]) -> bool {
    let s = [orient2d(t[0], t[1], p), orient2d(t[1], t[2], p), orient2d(t[2], t[0], p)];
    s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    type I3 = [i64; 3];

    fn sub(a: I3, b: I3) -> I3 {
        [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
    }
    fn cross(a: I3, b: I3) -> I3 {
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    }
    fn dot(a: I3, b: I3) -> i64 {
        a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    }

    /// Oracle: the separating axis theorem in integers. Two convex point sets (a
    /// triangle, a segment, flat or not) are disjoint iff some axis among the face
    /// normals, the edge-edge cross products and the in-plane edge normals (normal x
    /// edge) separates their projections strictly.
    fn sat_meet(p: &[I3], q: &[I3]) -> bool {
        let edges = |s: &[I3]| -> Vec<I3> {
            (0..s.len()).flat_map(|i| (i + 1..s.len()).map(move |j| (i, j))).map(|(i, j)| sub(s[j], s[i])).collect()
        };
        let (ep, eq) = (edges(p), edges(q));
        let normal = |s: &[I3], e: &[I3]| if s.len() == 3 { cross(e[0], e[1]) } else { [0; 3] };
        let (np, nq) = (normal(p, &ep), normal(q, &eq));
        let mut axes = vec![np, nq];
        for &a in &ep {
            for &b in &eq {
                axes.push(cross(a, b));
            }
        }
        for &n in &[np, nq] {
            for &e in ep.iter().chain(&eq) {
                axes.push(cross(n, e));
            }
        }
        // A segment and a triangle, or two collinear-ish sets: also the normals of the
        // planes through the segment and each edge's direction are among the crosses;
        // add the segment's own perpendiculars within the other's plane above.
        !axes.iter().filter(|a| **a != [0; 3]).any(|&a| {
            let (lo_p, hi_p) = span(p, a);
            let (lo_q, hi_q) = span(q, a);
            hi_p < lo_q || hi_q < lo_p
        })
    }

    fn span(s: &[I3], a: I3) -> (i64, i64) {
        let d: Vec<i64> = s.iter().map(|&x| dot(x, a)).collect();
        (*d.iter().min().unwrap(), *d.iter().max().unwrap())
    }

    fn to_f(x: I3) -> DVec3 {
        DVec3::new(x[0] as f64, x[1] as f64, x[2] as f64)
    }

    fn random_triangle(rng: &mut Rng, n: u64) -> [I3; 3] {
        loop {
            let t: [I3; 3] = std::array::from_fn(|_| std::array::from_fn(|_| rng.below(n) as i64));
            if cross(sub(t[1], t[0]), sub(t[2], t[0])) != [0; 3] {
                return t;
            }
        }
    }

    #[test]
    fn triangles_meet_as_the_separating_axis_oracle_says() {
        // Coordinates in 0..4: coplanar, touching and collinear cases abound.
        let mut rng = Rng(38);
        let (mut met, mut missed) = (0, 0);
        for _ in 0..40_000 {
            let (p, q) = (random_triangle(&mut rng, 4), random_triangle(&mut rng, 4));
            let expected = sat_meet(&p, &q);
            assert_eq!(triangles_meet(p.map(to_f), q.map(to_f)), expected, "{p:?} {q:?}");
            let shares = p.iter().any(|x| q.contains(x));
            if !shares {
                assert_eq!(triangles_clash(p.map(to_f), q.map(to_f)), expected, "{p:?} {q:?}");
                assert!(!(expected && clearly_apart(p.map(to_f), q.map(to_f))));
            }
            met += usize::from(expected);
            missed += usize::from(!expected);
        }
        assert!(met > 5000 && missed > 5000, "{met} meet, {missed} miss");
    }

    #[test]
    fn segments_meet_triangles_as_the_separating_axis_oracle_says() {
        let mut rng = Rng(7);
        let (mut met, mut missed) = (0, 0);
        for _ in 0..40_000 {
            let t = random_triangle(&mut rng, 4);
            let s: [I3; 2] = std::array::from_fn(|_| std::array::from_fn(|_| rng.below(4) as i64));
            if s[0] == s[1] {
                continue;
            }
            let expected = sat_meet(&s, &t);
            assert_eq!(segment_meets_triangle(to_f(s[0]), to_f(s[1]), t.map(to_f)), expected, "{s:?} {t:?}");
            assert_eq!(opposite_edge_meets(to_f(s[0]), to_f(s[1]), t.map(to_f)), expected, "{s:?} {t:?}");
            met += usize::from(expected);
            missed += usize::from(!expected);
        }
        assert!(met > 5000 && missed > 5000, "{met} meet, {missed} miss");
    }

    /// Oracle for one shared corner `s` (generic, non-coplanar triangles): the two
    /// triangles cut the line their planes share in intervals from `s`; they clash
    /// iff both intervals leave `s` the same way. Computed in floats on triangles far
    /// from degenerate.
    #[test]
    fn one_shared_corner_clashes_iff_the_triangles_overlap_beyond_it() {
        let mut rng = Rng(99);
        let (mut clash, mut apart, mut cases) = (0, 0, 0);
        while cases < 20_000 {
            let s = rng.vec(-1.0, 1.0);
            let p = [s, rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0)];
            let q = [s, rng.vec(-1.0, 1.0), rng.vec(-1.0, 1.0)];
            let (np, nq) = ((p[1] - s).cross(p[2] - s), (q[1] - s).cross(q[2] - s));
            let dir = np.cross(nq);
            if np.length() < 0.05 || nq.length() < 0.05 || dir.length() < 0.05 * np.length() * nq.length() {
                continue;
            }
            // The interval of a triangle (corner s at 0) along the line s + t dir.
            let interval = |t: [DVec3; 3], n: DVec3| {
                // Points s + t dir in the triangle: barycentric in its plane.
                let in_plane = |t0: f64| {
                    let x = s + dir * t0;
                    let e = |a: DVec3, b: DVec3| (b - a).cross(x - a).dot(n);
                    e(t[0], t[1]) >= -1e-12 && e(t[1], t[2]) >= -1e-12 && e(t[2], t[0]) >= -1e-12
                };
                (in_plane(1e-6), in_plane(-1e-6))
            };
            let (fp, bp) = interval(p, np);
            let (fq, bq) = interval(q, nq);
            let expected = (fp && fq) || (bp && bq);
            cases += 1;
            // Skip the near-tangent cases where 1e-6 steps cannot decide.
            let got = triangles_clash(p, q);
            assert_eq!(got, expected, "{p:?} {q:?}");
            clash += usize::from(got);
            apart += usize::from(!got);
        }
        assert!(clash > 1000 && apart > 1000, "{clash} clash, {apart} apart");
    }

    /// The float filter of one shared corner against the exact predicates alone, on
    /// fans of a sphere of radius 300 with edges of a few units (a dual mesh's curved
    /// patch, where the predicates are near zero), shifted off the origin so the
    /// coordinates round.
    #[test]
    fn nearly_flat_fans_clash_as_the_exact_predicates_say() {
        let mut rng = Rng(41);
        let (mut clash, mut apart) = (0, 0);
        let centre = DVec3::new(1000.3, -207.1, 55.7);
        let on_sphere = |x: DVec3| centre + (x - centre).normalize() * 300.0;
        for _ in 0..20_000 {
            let s = on_sphere(centre + rng.vec(-1.0, 1.0));
            let near = |rng: &mut Rng| on_sphere(s + rng.vec(-3.0, 3.0));
            let p = [s, near(&mut rng), near(&mut rng)];
            let q = [s, near(&mut rng), near(&mut rng)];
            let exact = segment_meets_triangle(p[1], p[2], q) || segment_meets_triangle(q[1], q[2], p);
            assert_eq!(triangles_clash(p, q), exact, "{p:?} {q:?}");
            clash += usize::from(exact);
            apart += usize::from(!exact);
        }
        assert!(clash > 1000 && apart > 1000, "{clash} clash, {apart} apart");
    }

    #[test]
    fn shared_edges_and_sheet_corners_are_allowed_folds_are_not() {
        let (o, x, y, z) = (DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z);
        // A shared edge, bent: fine; coplanar on opposite sides: fine; folded: clash.
        assert!(!triangles_clash([o, x, y], [x, o, z]));
        assert!(!triangles_clash([o, x, y], [x, o, -y]));
        assert!(triangles_clash([o, x, y], [x, o, y * 0.5 + x * 0.2]));
        // Two voxels' faces touching at one corner (a sheet vertex): fine.
        assert!(!triangles_clash([o, x, y], [o, -x, -z]));
        // Sharing a corner, crossing through each other: clash.
        assert!(triangles_clash([o, x + z, x - z], [o, x + y, x - y]));
        // The same corners twice: clash.
        assert!(triangles_clash([o, x, y], [o, y, x]));
    }
}
