//! The exact convex hull of integer points in 3D, by quickhull (Barber, Dobkin and
//! Huhdanpaa, *The Quickhull Algorithm for Convex Hulls*, 1996).
//!
//! Points have integer coordinates of magnitude below `2^31`, so a face's normal `(b -
//! a) x (c - a)` is exact in `i128` (below `2^65`) and so is the orientation `n . (q -
//! a)` (below `2^98`): every predicate is exact, there is no tolerance, and coplanar
//! points are never "visible" (a point on a face's plane is not outside it), so a flat
//! side of the hull comes out as several coplanar triangles and points on it are
//! dropped.
//!
//! Steps: a first tetrahedron from extreme points; each other point goes to the
//! outside set of the first face it is strictly above; then, while a face has an
//! outside set, its farthest point `p` is added: the faces `p` sees are found by a
//! walk over neighbours from that face (they are connected), the horizon is their
//! edges whose other face `p` does not see, each horizon edge and `p` make a new face,
//! and the seen faces' outside points are shared among the new faces (a point outside
//! the new hull sees one of them: the faces it sees are connected and reach a seen
//! face, so some horizon edge has both its faces seen by it, and the new face on that
//! edge lies between their planes). Neighbours are found through a map from directed
//! edges to faces. Departure: no merging of coplanar faces (the caller's planes may
//! repeat).

use rustc_hash::FxHashMap;

/// A point with integer coordinates (each of magnitude below `2^31`).
pub(crate) type Point = [i64; 3];

/// A face of the hull: its corners counter-clockwise seen from outside, and its plane
/// `normal . x = offset` (the normal outward, not unit).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct HullFace {
    /// Indices of the corners into the points given.
    pub vertices: [u32; 3],
    /// `(b - a) x (c - a)`.
    pub normal: [i128; 3],
    /// `normal . a`.
    pub offset: i128,
}

impl HullFace {
    fn new(points: &[Point], vertices: [u32; 3]) -> HullFace {
        let [a, b, c] = vertices.map(|v| points[v as usize].map(i128::from));
        let (u, w) = ([b[0] - a[0], b[1] - a[1], b[2] - a[2]], [c[0] - a[0], c[1] - a[1], c[2] - a[2]]);
        let normal = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
        HullFace { vertices, normal, offset: dot(normal, a) }
    }

    /// `normal . q - offset`: positive when `q` is strictly outside the face's plane.
    pub fn height(&self, q: Point) -> i128 {
        dot(self.normal, q.map(i128::from)) - self.offset
    }
}

fn dot(a: [i128; 3], b: [i128; 3]) -> i128 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The distinct planes of `faces` (coplanar triangles of a flat side merged): each
/// as its normal divided by the gcd of its components, its offset divided likewise,
/// and a corner of a face on it.
pub(crate) fn distinct_planes(faces: &[HullFace]) -> Vec<([i128; 3], i128, u32)> {
    let mut keyed: Vec<([i128; 3], i128, u32)> = faces
        .iter()
        .map(|f| {
            let g = f.normal.iter().fold(0i128, |g, &c| gcd(g, c.abs())).max(1);
            (f.normal.map(|c| c / g), f.offset / g, f.vertices[0])
        })
        .collect();
    keyed.sort_unstable();
    keyed.dedup_by_key(|(n, o, _)| (*n, *o));
    keyed
}

fn gcd(mut a: i128, mut b: i128) -> i128 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// The largest coordinate magnitude accepted (exclusive).
pub(crate) const LIMIT: i64 = 1 << 31;

/// The faces of the convex hull of `points` (indices into `points`, which may repeat
/// points); `None` when the points are all on one plane (the hull has no volume).
///
/// # Panics
/// When a coordinate's magnitude reaches [`LIMIT`].
pub(crate) fn convex_hull(points: &[Point]) -> Option<Vec<HullFace>> {
    assert!(points.iter().flatten().all(|c| c.abs() < LIMIT), "hull coordinates must be below 2^31");
    let mut order: Vec<u32> = (0..points.len() as u32).collect();
    order.sort_by_key(|&i| points[i as usize]);
    order.dedup_by_key(|i| points[*i as usize]);
    let simplex = first_tetrahedron(points, &order)?;
    let mut hull =
        Hull { points, faces: Vec::new(), outside: Vec::new(), alive: Vec::new(), edges: FxHashMap::default() };
    let [a, b, c, d] = simplex;
    for f in [[a, b, c], [a, d, b], [b, d, c], [c, d, a]] {
        hull.add_face(f);
    }
    for &i in &order {
        if !simplex.contains(&i) {
            hull.assign(i, 0..4);
        }
    }
    let mut f = 0;
    while f < hull.faces.len() {
        if hull.alive[f] && !hull.outside[f].is_empty() {
            hull.add_point(f);
        } else {
            f += 1;
        }
    }
    Some((0..hull.faces.len()).filter(|&f| hull.alive[f]).map(|f| hull.faces[f]).collect())
}

/// Four points not on one plane, oriented so that `d` is below `a, b, c`.
fn first_tetrahedron(points: &[Point], order: &[u32]) -> Option<[u32; 4]> {
    let p = |i: u32| points[i as usize];
    let (&a, &b) = (order.first()?, order.last()?);
    if a == b {
        return None;
    }
    let (pa, pb) = (p(a).map(i128::from), p(b).map(i128::from));
    let u = [pb[0] - pa[0], pb[1] - pa[1], pb[2] - pa[2]];
    let off_line = |i: u32| {
        let q = p(i).map(i128::from);
        let w = [q[0] - pa[0], q[1] - pa[1], q[2] - pa[2]];
        let n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
        n.iter().map(|x| x.abs()).max().unwrap_or(0)
    };
    let c = *order.iter().max_by_key(|&&i| off_line(i))?;
    if off_line(c) == 0 {
        return None;
    }
    let base = HullFace::new(points, [a, b, c]);
    let d = *order.iter().max_by_key(|&&i| base.height(p(i)).abs())?;
    match base.height(p(d)) {
        0 => None,
        h if h > 0 => Some([a, c, b, d]),
        _ => Some([a, b, c, d]),
    }
}

struct Hull<'a> {
    points: &'a [Point],
    faces: Vec<HullFace>,
    outside: Vec<Vec<u32>>,
    alive: Vec<bool>,
    /// Directed edge `(from, to)` -> the face holding it.
    edges: FxHashMap<(u32, u32), u32>,
}

impl Hull<'_> {
    fn add_face(&mut self, vertices: [u32; 3]) -> u32 {
        let id = self.faces.len() as u32;
        self.faces.push(HullFace::new(self.points, vertices));
        self.outside.push(Vec::new());
        self.alive.push(true);
        for k in 0..3 {
            self.edges.insert((vertices[k], vertices[(k + 1) % 3]), id);
        }
        id
    }

    /// Puts point `i` in the outside set of the first face of `faces` it is strictly
    /// above; drops it when there is none.
    fn assign(&mut self, i: u32, faces: std::ops::Range<usize>) {
        let q = self.points[i as usize];
        if let Some(f) = faces.into_iter().find(|&f| self.alive[f] && self.faces[f].height(q) > 0) {
            self.outside[f].push(i);
        }
    }

    /// Adds the farthest point of face `start`'s outside set.
    fn add_point(&mut self, start: usize) {
        let face = self.faces[start];
        let points = self.points;
        let &p =
            self.outside[start].iter().max_by_key(|&&i| face.height(points[i as usize])).expect("an outside point");
        let q = points[p as usize];
        // The faces p sees, by a walk over neighbours.
        let mut seen = vec![start as u32];
        let mut visible = rustc_hash::FxHashSet::default();
        visible.insert(start as u32);
        let mut horizon = Vec::new();
        let mut k = 0;
        while k < seen.len() {
            let f = seen[k];
            k += 1;
            let v = self.faces[f as usize].vertices;
            for e in 0..3 {
                let (from, to) = (v[e], v[(e + 1) % 3]);
                let other = self.edges[&(to, from)];
                if visible.contains(&other) {
                    continue;
                }
                if self.faces[other as usize].height(q) > 0 {
                    visible.insert(other);
                    seen.push(other);
                } else {
                    horizon.push((from, to));
                }
            }
        }
        let mut orphans = Vec::new();
        for &f in &seen {
            let f = f as usize;
            self.alive[f] = false;
            orphans.append(&mut self.outside[f]);
            let v = self.faces[f].vertices;
            for e in 0..3 {
                let key = (v[e], v[(e + 1) % 3]);
                if self.edges.get(&key) == Some(&(f as u32)) {
                    self.edges.remove(&key);
                }
            }
        }
        let first = self.faces.len();
        for (from, to) in horizon {
            self.add_face([from, to, p]);
        }
        let new = first..self.faces.len();
        for i in orphans {
            if i != p {
                self.assign(i, new.clone());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Brute force: a face's plane is a hull plane iff no point is strictly above it,
    /// and every point is on or below every face.
    #[test]
    fn hulls_of_random_and_lattice_points_are_the_brute_force_hulls() {
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = |m: i64| {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed % (2 * m as u64 + 1)) as i64 - m
        };
        for (n, m) in [(50, 1_000_000_000), (400, 3), (200, 1)] {
            let points: Vec<Point> = (0..n).map(|_| [next(m), next(m), next(m)]).collect();
            let faces = convex_hull(&points).unwrap();
            for f in &faces {
                assert!(points.iter().all(|&q| f.height(q) <= 0));
            }
            // Every point that is a strict extreme in some axis direction is a vertex.
            for axis in 0..3 {
                let top = points.iter().map(|q| q[axis]).max().unwrap();
                assert!(faces.iter().any(|f| f.vertices.iter().any(|&v| points[v as usize][axis] == top)));
            }
            // Closed: every directed edge has its reverse.
            let edges: std::collections::HashSet<(u32, u32)> =
                faces.iter().flat_map(|f| (0..3).map(move |k| (f.vertices[k], f.vertices[(k + 1) % 3]))).collect();
            assert!(edges.iter().all(|&(a, b)| edges.contains(&(b, a))));
        }
        assert!(convex_hull(&[[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]).is_none());
    }
}
