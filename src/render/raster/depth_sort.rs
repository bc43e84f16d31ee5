//! Painter's algorithm for triangle meshes: the chapter's depth sort (section 6.2 of
//! the seed; Newell, Newell and Sancha, "A solution to the hidden surface problem",
//! 1972; Foley, van Dam, Feiner and Hughes, section 15.5.1).
//!
//! The polygons (at first the mesh's triangles) are sorted by their farthest view depth
//! `z_max`, farthest first. The head `P` of the list may be drawn (over what is drawn
//! already) when it hides no polygon `Q` still waiting whose depth extent overlaps its
//! own (`Q.z_max > P.z_min`); for each such `Q`, in this order, the first test that
//! holds settles the pair:
//! 1. the projections' x extents are disjoint;
//! 2. their y extents are disjoint;
//! 3. `P` lies wholly behind `Q`'s plane (on the side away from the eye);
//! 4. `Q` lies wholly in front of `P`'s plane (on the eye's side);
//! 5. the projections are disjoint (exactly: a separating edge direction of one of the
//!    two convex projections).
//!
//! When none holds, `P` may hide `Q`: the roles are swapped and (3) and (4) tested again
//! (`Q` wholly behind `P`'s plane, or `P` wholly in front of `Q`'s). If one holds, `Q` must
//! be drawn first: it is moved to the head and marked (a swap). A marked polygon that
//! must move again closes a cycle, and when no swap holds the two interpenetrate; in
//! both cases one polygon is split by the other's plane (`P` by `Q`'s when that plane
//! cuts `P`, else `Q` by `P`'s) and the pieces go back into the list by depth.
//!
//! A plane `a x + b y + c z + d = 0` (the seed's coefficients, as `n . p + d` with
//! `n = (b - a) x (c - a)` of the triangle's corners, normalized) has the eye on the
//! side of the sign of `n . eye + d` (perspective) or of `-n . forward` (parallel).
//!
//! Where the code departs from the book:
//! - Moved polygons wait on a stack above the sorted list (the book's "front of the
//!   list"), so the list stays sorted and the depth-overlap scan can stop at the first
//!   `Q` wholly nearer than `P`; a polygon on the stack is compared with every other one
//!   there.
//! - Side tests allow `1e-9` of the mesh's size: corners shared by neighbouring
//!   triangles lie on each other's planes, and rounding must not make them straddle.
//!   A plane through the eye (a polygon seen edge on) decides nothing by (3) or (4).
//! - A cycle whose two polygons' planes cut neither of them (the cycle runs through a
//!   third polygon) is broken by the plane of another marked polygon waiting that cuts
//!   `P`; when none does, or the polygons have grown past sixteen times the triangles,
//!   `P` is drawn as it stands and counted `unresolved`.
//! - Drawing: a piece keeps its triangle and covers the pixel centres that lie inside
//!   both the piece's projection (up to rounding) and the triangle's (the Z-buffer's
//!   exact edge test), with the triangle's barycentrics and perspective-correct depth:
//!   so the painter's fragments are the Z-buffer's wherever depths differ by more than
//!   rounding.

use glam::DVec3;

use super::projected::{Fragment, Projected, barycentric, pixel_range, project_triangles, to_pixels};
use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::mesh::TriangleMesh;
use crate::render::film::{Camera, Projection};

/// What settled the depth sort's pairs, and how often it swapped and split.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DepthSortCounts {
    /// Pairs with overlapping depth extents settled by test 1, disjoint x extents.
    pub x_extents: u64,
    /// Pairs settled by test 2, disjoint y extents.
    pub y_extents: u64,
    /// Pairs settled by test 3, `P` wholly behind `Q`'s plane.
    pub behind_plane: u64,
    /// Pairs settled by test 4, `Q` wholly in front of `P`'s plane.
    pub in_front_of_plane: u64,
    /// Pairs settled by test 5, disjoint projections.
    pub projections_disjoint: u64,
    /// Polygons moved ahead of `P` because the swapped tests (3) and (4) held.
    pub swaps: u64,
    /// Polygons split by another's plane (cycles and interpenetration).
    pub splits: u64,
    /// Polygons drawn with an order left undecided (see the module doc).
    pub unresolved: u64,
    /// Polygons drawn (triangles and pieces).
    pub drawn: u64,
}

/// A convex polygon of the list: a triangle or a piece of one.
struct Polygon {
    /// The mesh triangle it lies in.
    triangle: usize,
    /// Its corners, in world space.
    corners: Vec<DVec3>,
    /// Its corners in pixels.
    screen: Vec<(f64, f64)>,
    /// Its depth extent `[z_min, z_max]` along the view axis.
    z: (f64, f64),
    /// Its screen extents.
    x: (f64, f64),
    y: (f64, f64),
    /// Moved to the head once already.
    marked: bool,
}

/// A triangle's plane: unit normal, offset, and the side the eye is on (`+1`, `-1`, or
/// `0` when the plane passes through the eye).
#[derive(Clone, Copy)]
struct Plane {
    n: DVec3,
    d: f64,
    eye: f64,
}

impl Plane {
    /// Signed distance of `p`, positive on the eye's side.
    fn towards_eye(&self, p: DVec3) -> f64 {
        (self.n.dot(p) + self.d) * self.eye
    }
}

/// The sort's state: the polygons, the planes of their triangles, and the view.
struct Sorter<'a> {
    polygons: Vec<Polygon>,
    planes: Vec<Option<Plane>>,
    camera: &'a Camera,
    forward: DVec3,
    aspect: f64,
    size: (u32, u32),
    eps: f64,
    limit: usize,
    moves_again: usize,
    counts: DepthSortCounts,
}

/// What the head polygon's scan found.
enum Found {
    /// `P` hides none of the waiting polygons.
    Draw,
    /// `Q` must be drawn before `P` (swapped tests held).
    Swap(usize),
    /// `Q` must move again (a cycle) or no order exists (interpenetration).
    Split(usize, bool),
}

/// Painter's fragments: the polygons drawn far to near by the depth sort (see the
/// module doc), and its counts. Refused when the polygons (about 200 bytes each)
/// would exceed `budget`.
pub(super) fn depth_sort_fragments(
    mesh: &TriangleMesh,
    camera: &Camera,
    width: u32,
    height: u32,
    budget: MemoryBudget,
) -> Result<(Vec<Option<Fragment>>, DepthSortCounts)> {
    let projected = project_triangles(mesh, camera, width, height);
    let limit = 16 * mesh.triangles.len() + 1024;
    budget.check(format!("depth sorting {} triangles", mesh.triangles.len()), 200 * mesh.triangles.len() as u64)?;
    let mut sorter = Sorter::new(mesh, camera, width, height, &projected, limit);
    let order = sorter.sort();
    let perspective = matches!(camera.projection, Projection::Perspective { .. });
    let mut buffer: Vec<Option<Fragment>> = vec![None; width as usize * height as usize];
    for &id in &order {
        let polygon = &sorter.polygons[id];
        let p = projected[polygon.triangle].as_ref().expect("only drawable triangles are sorted");
        let whole = polygon.corners.len() == 3 && polygon.screen.iter().zip(p.screen).all(|(a, b)| *a == b);
        let (c0, c1) = pixel_range(polygon.screen.iter().map(|s| s.0), width);
        let (r0, r1) = pixel_range(polygon.screen.iter().map(|s| s.1), height);
        for r in r0..r1 {
            for c in c0..c1 {
                let (x, y) = (c as f64 + 0.5, r as f64 + 0.5);
                let Some(weights) = barycentric(p, x, y) else { continue };
                if !whole && !inside(&polygon.screen, x, y) {
                    continue;
                }
                let depth = p.depth_at(weights, perspective);
                buffer[r * width as usize + c] = Some(Fragment { triangle: polygon.triangle, weights, depth });
            }
        }
    }
    sorter.counts.drawn = order.len() as u64;
    Ok((buffer, sorter.counts))
}

/// Whether `(x, y)` lies in the convex polygon `screen` (either winding), edges
/// included up to a millionth of a pixel.
fn inside(screen: &[(f64, f64)], x: f64, y: f64) -> bool {
    let (mut positive, mut negative) = (false, false);
    for k in 0..screen.len() {
        let (a, b) = (screen[k], screen[(k + 1) % screen.len()]);
        let length = (b.0 - a.0).hypot(b.1 - a.1);
        if length == 0.0 {
            continue;
        }
        let e = ((b.0 - a.0) * (y - a.1) - (b.1 - a.1) * (x - a.0)) / length;
        positive |= e > 1e-6;
        negative |= e < -1e-6;
    }
    !(positive && negative)
}

impl<'a> Sorter<'a> {
    fn new(
        mesh: &TriangleMesh,
        camera: &'a Camera,
        width: u32,
        height: u32,
        projected: &[Option<Projected>],
        limit: usize,
    ) -> Self {
        let forward = (camera.target - camera.eye).normalize();
        let (lo, hi) =
            mesh.vertices.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(lo, hi), &v| (lo.min(v), hi.max(v)));
        let eps = 1e-9 * (hi - lo).length().max(f64::MIN_POSITIVE);
        let planes = (0..mesh.triangles.len())
            .map(|i| {
                projected[i].as_ref()?;
                let [a, b, c] = mesh.corners(i);
                let n = (b - a).cross(c - a).normalize_or_zero();
                let d = -n.dot(a);
                let eye = match camera.projection {
                    Projection::Perspective { .. } => n.dot(camera.eye) + d,
                    Projection::Orthographic { .. } => -n.dot(forward) * (hi - lo).length(),
                };
                let eye = if eye.abs() <= eps { 0.0 } else { eye.signum() };
                Some(Plane { n, d, eye })
            })
            .collect();
        let mut sorter = Sorter {
            polygons: Vec::new(),
            planes,
            camera,
            forward,
            aspect: f64::from(width) / f64::from(height),
            size: (width, height),
            eps,
            limit,
            moves_again: 0,
            counts: DepthSortCounts::default(),
        };
        for (i, p) in projected.iter().enumerate() {
            if p.is_some() {
                let polygon = sorter.polygon(i, mesh.corners(i).to_vec());
                sorter.polygons.push(polygon);
            }
        }
        sorter
    }

    /// The polygon of `corners` in triangle `triangle`, with its projection and extents.
    fn polygon(&self, triangle: usize, corners: Vec<DVec3>) -> Polygon {
        let (w, h) = self.size;
        let screen: Vec<(f64, f64)> = corners
            .iter()
            .map(|&p| to_pixels(self.camera.project(p, self.aspect).unwrap_or((0.0, 0.0)), w, h))
            .collect();
        let extent = |values: &mut dyn Iterator<Item = f64>| {
            values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)))
        };
        Polygon {
            triangle,
            z: extent(&mut corners.iter().map(|&p| (p - self.camera.eye).dot(self.forward))),
            x: extent(&mut screen.iter().map(|s| s.0)),
            y: extent(&mut screen.iter().map(|s| s.1)),
            corners,
            screen,
            marked: false,
        }
    }

    /// The drawing order, farthest first (ids into `polygons`).
    fn sort(&mut self) -> Vec<usize> {
        // `list`: ascending by z_max, the head at the end; `stack`: moved polygons, the
        // head on top.
        let mut list: Vec<usize> = (0..self.polygons.len()).collect();
        list.sort_by(|&a, &b| self.polygons[a].z.1.total_cmp(&self.polygons[b].z.1).then(b.cmp(&a)));
        let mut stack: Vec<usize> = Vec::new();
        let mut order = Vec::with_capacity(list.len());
        while let Some(p) = stack.last().or(list.last()).copied() {
            let on_stack = !stack.is_empty();
            match self.scan(p, on_stack, &list, &stack) {
                Found::Draw => {
                    order.push(p);
                    if on_stack {
                        stack.pop()
                    } else {
                        list.pop()
                    };
                }
                Found::Swap(q) => {
                    self.counts.swaps += 1;
                    self.polygons[q].marked = true;
                    remove(&mut list, &mut stack, q);
                    stack.push(q);
                }
                Found::Split(q, cycle) => {
                    let cut = if self.polygons.len() >= self.limit {
                        None
                    } else if let Some(pieces) = self.split(p, q) {
                        Some((p, pieces))
                    } else if let Some(pieces) = self.split(q, p) {
                        Some((q, pieces))
                    } else if cycle {
                        self.cut_in_cycle(p, q, &stack)
                    } else {
                        None
                    };
                    if let Some((gone, pieces)) = cut {
                        self.counts.splits += 1;
                        remove(&mut list, &mut stack, gone);
                        for piece in pieces {
                            let id = self.polygons.len();
                            let z = piece.z.1;
                            self.polygons.push(piece);
                            let at = list.partition_point(|&o| self.polygons[o].z.1 < z);
                            list.insert(at, id);
                        }
                    } else if cycle && self.moves_again < self.limit {
                        // No plane of the chain cuts another: move Q again.
                        self.moves_again += 1;
                        self.counts.swaps += 1;
                        remove(&mut list, &mut stack, q);
                        stack.push(q);
                    } else {
                        self.counts.unresolved += 1;
                        order.push(p);
                        remove(&mut list, &mut stack, p);
                    }
                }
            }
        }
        order
    }

    /// Compares the head `p` with the waiting polygons whose depth extents overlap its
    /// own: the stack's (all of them) and the list's (nearest last, until one lies wholly
    /// nearer).
    fn scan(&mut self, p: usize, on_stack: bool, list: &[usize], stack: &[usize]) -> Found {
        let z_min = self.polygons[p].z.0;
        let waiting_stack = stack.iter().rev().skip(usize::from(on_stack)).copied();
        let overlapping_stack = waiting_stack.filter(|&q| self.polygons[q].z.1 > z_min).collect::<Vec<_>>();
        let waiting_list = list.iter().rev().skip(usize::from(!on_stack)).copied();
        let overlapping_list = waiting_list.take_while(|&q| self.polygons[q].z.1 > z_min);
        let mut settled = [0u64; 6];
        let mut found = Found::Draw;
        for q in overlapping_stack.into_iter().chain(overlapping_list) {
            if let Some(test) = self.settles(p, q) {
                settled[usize::from(test)] += 1;
                continue;
            }
            // P may hide Q: the swapped tests (3) and (4).
            found = if !(self.behind(q, p) || self.in_front(p, q)) {
                Found::Split(q, false)
            } else if self.polygons[q].marked {
                Found::Split(q, true)
            } else {
                Found::Swap(q)
            };
            break;
        }
        let c = &mut self.counts;
        for (count, add) in [
            &mut c.x_extents,
            &mut c.y_extents,
            &mut c.behind_plane,
            &mut c.in_front_of_plane,
            &mut c.projections_disjoint,
        ]
        .into_iter()
        .zip(&settled[1..])
        {
            *count += add;
        }
        found
    }

    /// The five tests in order: the first (1 to 5) showing that `p` does not hide `q`.
    fn settles(&self, p: usize, q: usize) -> Option<u8> {
        let (a, b) = (&self.polygons[p], &self.polygons[q]);
        if a.x.1 < b.x.0 || b.x.1 < a.x.0 {
            Some(1)
        } else if a.y.1 < b.y.0 || b.y.1 < a.y.0 {
            Some(2)
        } else if self.behind(p, q) {
            Some(3)
        } else if self.in_front(q, p) {
            Some(4)
        } else if disjoint(&a.screen, &b.screen) {
            Some(5)
        } else {
            None
        }
    }

    /// Whether polygon `a` lies wholly behind the plane of polygon `b` (away from the eye).
    fn behind(&self, a: usize, b: usize) -> bool {
        let Some(plane) = self.planes[self.polygons[b].triangle] else { return false };
        plane.eye != 0.0 && self.polygons[a].corners.iter().all(|&v| plane.towards_eye(v) <= self.eps)
    }

    /// Whether polygon `a` lies wholly in front of the plane of polygon `b` (the eye's side).
    fn in_front(&self, a: usize, b: usize) -> bool {
        let Some(plane) = self.planes[self.polygons[b].triangle] else { return false };
        plane.eye != 0.0 && self.polygons[a].corners.iter().all(|&v| plane.towards_eye(v) >= -self.eps)
    }

    /// A cycle's cut: among `p`, `q` and the moved polygons on the stack (the chain
    /// that led to the cycle, its top sixteen), the first polygon another's plane cuts,
    /// with its pieces.
    fn cut_in_cycle(&self, p: usize, q: usize, stack: &[usize]) -> Option<(usize, [Polygon; 2])> {
        let mut chain: Vec<usize> = vec![p, q];
        chain.extend(stack.iter().rev().take(16).filter(|&&s| s != p && s != q));
        chain.iter().find_map(|&a| {
            chain.iter().find_map(|&b| if a == b { None } else { self.split(a, b) }).map(|pieces| (a, pieces))
        })
    }

    /// Whether the plane of polygon `b` has corners of `a` strictly on both sides.
    fn cuts(&self, b: usize, a: usize) -> bool {
        let plane = self.planes[self.polygons[b].triangle].expect("sorted polygons have planes");
        let sides = self.polygons[a].corners.iter().map(|&v| plane.n.dot(v) + plane.d);
        let (mut above, mut below) = (false, false);
        for s in sides {
            above |= s > self.eps;
            below |= s < -self.eps;
        }
        above && below
    }

    /// Polygon `a` cut by the plane of polygon `b` (Sutherland-Hodgman against both
    /// half-spaces), `None` when the plane does not cut it.
    fn split(&self, a: usize, b: usize) -> Option<[Polygon; 2]> {
        if !self.cuts(b, a) {
            return None;
        }
        let plane = self.planes[self.polygons[b].triangle].expect("sorted polygons have planes");
        let corners = &self.polygons[a].corners;
        let side = |v: DVec3| {
            let s = plane.n.dot(v) + plane.d;
            if s.abs() <= self.eps { 0.0 } else { s }
        };
        let (mut above, mut below) = (Vec::new(), Vec::new());
        for k in 0..corners.len() {
            let (u, v) = (corners[k], corners[(k + 1) % corners.len()]);
            let (su, sv) = (side(u), side(v));
            if su >= 0.0 {
                above.push(u);
            }
            if su <= 0.0 {
                below.push(u);
            }
            if su * sv < 0.0 {
                let t = su / (su - sv);
                let x = u + (v - u) * t;
                above.push(x);
                below.push(x);
            }
        }
        let triangle = self.polygons[a].triangle;
        Some([self.polygon(triangle, above), self.polygon(triangle, below)])
    }
}

/// Removes `id` from whichever of the list and the stack holds it.
fn remove(list: &mut Vec<usize>, stack: &mut Vec<usize>, id: usize) {
    if let Some(k) = stack.iter().position(|&o| o == id) {
        stack.remove(k);
    } else if let Some(k) = list.iter().rposition(|&o| o == id) {
        list.remove(k);
    }
}

/// Pixels by which two projections may overlap and still count as disjoint: pieces and
/// neighbours that share a corner or an edge only touch.
const TOUCH: f64 = 1e-7;

/// Whether two convex polygons in the plane are disjoint: some edge direction of one
/// separates their projections onto its normal, up to [`TOUCH`].
fn disjoint(a: &[(f64, f64)], b: &[(f64, f64)]) -> bool {
    let separates = |poly: &[(f64, f64)]| {
        (0..poly.len()).any(|k| {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            let length = (p.1 - q.1).hypot(q.0 - p.0);
            if length == 0.0 {
                return false;
            }
            let axis = ((p.1 - q.1) / length, (q.0 - p.0) / length);
            let project = |s: &[(f64, f64)]| {
                s.iter()
                    .map(|v| v.0 * axis.0 + v.1 * axis.1)
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| (lo.min(x), hi.max(x)))
            };
            let ((a0, a1), (b0, b1)) = (project(a), project(b));
            a1 < b0 + TOUCH || b1 < a0 + TOUCH
        })
    };
    separates(a) || separates(b)
}
