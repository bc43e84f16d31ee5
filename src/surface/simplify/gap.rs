//! A true bound on how far apart an edge collapse moves the surface: the largest gap
//! between the patch before and the patch after, both seen as height fields.
//!
//! Collapsing edge `a b` into `v` replaces the faces around `a` and `b` (the old patch,
//! a disk) by a fan around `v` over the same boundary polygon (the new patch). Project
//! both along `n`, the old patch's mean normal. When every old and new triangle faces
//! `n` by a margin ([`MIN_FACING`]), and the new fan's projected angles around `v` sum
//! to one turn, the boundary polygon projects to a simple polygon (star-shaped about
//! `v`), and each patch projects one to one onto it (a disk mapped with every triangle
//! kept positive and a simple boundary covers each point once). Over each cell of the
//! two projected triangulations' common refinement both patches are planar, so their
//! vertical gap is affine there and is largest at a cell corner: an interior vertex of
//! either patch (`a`, `b`, `v`) or a crossing of an old interior edge with a new one
//! (the boundary is shared, where the gap is zero). The largest of these gaps bounds
//! the distance from every point of either patch to the other (the point straight
//! above or below is that close): the two-sided Hausdorff distance.
//!
//! The points are found and the heights interpolated in floats; a relative slack of
//! [`SLACK`] times the patch's size is added for their rounding.

use glam::{DVec2, DVec3};

/// Least cosine between a triangle's normal and the projection direction.
pub(crate) const MIN_FACING: f64 = 0.2;
/// Rounding allowance, relative to the patch's largest coordinate span.
const SLACK: f64 = 1e-14;

/// The two patches of one collapse, as corner triples.
pub(crate) struct Patches<'a> {
    /// The faces around `a` and `b`, as they are.
    pub old: &'a [[DVec3; 3]],
    /// The fan around `v` that replaces them.
    pub new: &'a [[DVec3; 3]],
    /// The old patch's interior vertices, `a` and `b`.
    pub old_inside: [DVec3; 2],
    /// The new patch's interior vertex `v`.
    pub new_inside: DVec3,
}

/// The largest vertical gap between the patches, or `None` when they are not both
/// height fields over one projection (the collapse is then refused).
#[must_use]
pub(crate) fn gap_bound(p: &Patches) -> Option<f64> {
    let area = |t: &[DVec3; 3]| (t[1] - t[0]).cross(t[2] - t[0]);
    let n = p.old.iter().map(area).sum::<DVec3>().try_normalize()?;
    if !p.old.iter().chain(p.new).all(|t| {
        let a = area(t);
        a.dot(n) > MIN_FACING * a.length()
    }) {
        return None;
    }
    let u = n.any_orthonormal_vector();
    let w = n.cross(u);
    let flat = |x: DVec3| DVec2::new(x.dot(u), x.dot(w));
    let height = |x: DVec3| x.dot(n);
    // One turn around v: the signed angles of the fan's corners at v.
    let fv = flat(p.new_inside);
    let turn: f64 = p
        .new
        .iter()
        .map(|t| {
            let k = t.iter().position(|&x| x == p.new_inside).unwrap_or(0);
            let (e1, e2) = (flat(t[(k + 1) % 3]) - fv, flat(t[(k + 2) % 3]) - fv);
            e1.perp_dot(e2).atan2(e1.dot(e2))
        })
        .sum();
    if (turn - std::f64::consts::TAU).abs() > 1e-6 {
        return None;
    }
    let mut gap: f64 = 0.0;
    // Interior vertices of one patch against the other.
    for &x in &p.old_inside {
        gap = gap.max((height(x) - height_over(p.new, flat(x), &flat, &height)?).abs());
    }
    gap = gap.max((height(p.new_inside) - height_over(p.old, fv, &flat, &height)?).abs());
    // Crossings of interior edges.
    let inside_edges = |faces: &[[DVec3; 3]], inside: &[DVec3]| -> Vec<(DVec3, DVec3)> {
        let mut edges = Vec::with_capacity(faces.len() * 2);
        for t in faces {
            for k in 0..3 {
                if inside.contains(&t[k]) {
                    edges.push((t[k], t[(k + 1) % 3]));
                    edges.push((t[k], t[(k + 2) % 3]));
                }
            }
        }
        edges
    };
    let old_edges = inside_edges(p.old, &p.old_inside);
    let new_edges = inside_edges(p.new, &[p.new_inside]);
    for &(o0, o1) in &old_edges {
        let (f0, f1) = (flat(o0), flat(o1));
        for &(n0, n1) in &new_edges {
            if n1 == o0 || n1 == o1 || n0 == o0 || n0 == o1 {
                continue;
            }
            let (g0, g1) = (flat(n0), flat(n1));
            let (d, e) = (f1 - f0, g1 - g0);
            let denom = d.perp_dot(e);
            if denom == 0.0 {
                continue;
            }
            let s = (g0 - f0).perp_dot(e) / denom;
            let t = (g0 - f0).perp_dot(d) / denom;
            if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
                let ho = height(o0) + s * (height(o1) - height(o0));
                let hn = height(n0) + t * (height(n1) - height(n0));
                gap = gap.max((ho - hn).abs());
            }
        }
    }
    let span = p.old.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs().max_element()));
    Some(gap + SLACK * span.max(f64::MIN_POSITIVE))
}

/// The height over `x` of the projected triangle of `faces` that holds it (the one it
/// is deepest inside, for points on shared edges and for rounding); `None` when a
/// triangle projects reversed or `x` is outside them all.
fn height_over(
    faces: &[[DVec3; 3]],
    x: DVec2,
    flat: &impl Fn(DVec3) -> DVec2,
    height: &impl Fn(DVec3) -> f64,
) -> Option<f64> {
    let mut best: Option<(f64, [f64; 3], usize)> = None;
    for (i, t) in faces.iter().enumerate() {
        let [a, b, c] = t.map(flat);
        let det = (b - a).perp_dot(c - a);
        if det <= 0.0 {
            return None;
        }
        let la = (c - b).perp_dot(x - b) / det;
        let lb = (a - c).perp_dot(x - c) / det;
        let weights = [la, lb, 1.0 - la - lb];
        let depth = weights[0].min(weights[1]).min(weights[2]);
        if best.is_none_or(|(d, _, _)| depth > d) {
            best = Some((depth, weights, i));
        }
    }
    let (depth, weights, i) = best?;
    if depth < -1e-6 {
        return None;
    }
    Some((0..3).map(|k| weights[k] * height(faces[i][k])).sum())
}
