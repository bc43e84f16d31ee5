//! The boundary of a linear octree as a closed, consistently oriented, manifold
//! triangle mesh of axis-aligned faces.
//!
//! Algorithm, in lattice units (integer voxel corners, coordinates in `0..=2^depth`):
//!
//! 1. **Exposed squares.** For each full node and each of its six faces, the cube of
//!    the same size across the face is looked up in the key list (a galloping search
//!    from the node's own place, as neighbours mostly lie near in Morton order):
//!    inside a full node, the face is hidden; holding no full node, the face is
//!    emitted whole; otherwise the face splits into the four quarters facing the
//!    cube's four near children, recursively, each with its own slice of keys. Faces
//!    on the domain's faces are exposed. Only the full side of a face emits it, so the
//!    squares tile the boundary without overlap. Work follows the nodes, never a dense
//!    grid. Then coplanar squares are merged into rectangles (runs along one in-plane
//!    axis, then runs of equal runs along the other), or, with
//!    [`BoundaryOptions::unit_faces`], cut into unit squares.
//! 2. **T-junctions.** A lattice point strictly inside a rectangle's edge where another
//!    rectangle has a corner is always an end point of another rectangle's edge on the
//!    same line (the faces around the line change there, or a coplanar rectangle
//!    ends). So the edge end points on lines that hold an edge longer than one voxel
//!    are sorted once by (line, position), and each long edge takes the points
//!    strictly between its ends as extra vertices.
//! 3. **Manifold vertices.** At a lattice point the rectangles around it cover some of
//!    the twelve quarter faces between its eight voxels; each quarter face joins two of
//!    the six half-edges leaving the point. Along a half-edge with two quarter faces
//!    the surface goes on from one to the other; a half-edge with four (two voxels
//!    touching only along that edge) pairs them around the full or around the empty
//!    quarters, chosen for each such segment so that its two pairs end on different
//!    vertices at one end at least (see `sheets`). The quarter faces fall into
//!    cycles; each cycle is one mesh vertex, so a point where voxels touch only along
//!    an edge or at a corner gets one vertex a sheet and every edge ends up with
//!    exactly two faces, run in opposite directions.
//! 4. **Triangles.** A rectangle without extra vertices is two triangles; a polygon of
//!    `n` points is cut into `n - 2` by ear clipping (a corner whose neighbours are
//!    not in line with it, keeping the rest from going flat), so no triangle is
//!    degenerate and no vertex is added.
//!
//! Output: world coordinates (`domain.lattice_point`), triangles counter-clockwise seen
//! from outside, so the signed-tetrahedron volume is the octree's volume. Every step
//! runs in parallel over fixed chunks joined in order, and ties are broken by sorted
//! keys, so the mesh is the same for any number of threads. The vertices a point keeps
//! for its sheets share one position; STL, which stores positions only, gets them
//! moved apart ([`super::separate_sheets`], through [`super::write_mesh`]).

use rayon::prelude::*;
use smallvec::SmallVec;

mod sheets;

use super::TriangleMesh;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::morton;
use crate::octree::{LinearOctree, NodeKey, keys_meeting_near};
use crate::progress::{NoProgress, Progress, stop_if_cancelled};
use sheets::QuarterFace;

/// Items a parallel task handles.
const CHUNK: usize = 4096;

/// Bits a lattice coordinate takes in packed keys (coordinates go up to `2^21`).
const COORD_BITS: u32 = 22;
const COORD_MASK: u128 = (1 << COORD_BITS) - 1;

/// Estimated peak bytes per rectangle (merged) and per unit face: polygon, sort records,
/// vertex ids and the output tables.
const BYTES_PER_SQUARE: u64 = 240;
const BYTES_PER_UNIT_FACE: u64 = 160;

/// How [`boundary_mesh`] builds the mesh.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BoundaryOptions {
    /// One voxel face = two triangles; otherwise (the default) the exposed parts of
    /// node faces are merged into coplanar rectangles.
    pub unit_faces: bool,
}

/// A lattice point.
pub(crate) type Point = [u32; 3];

/// An exposed rectangle of the boundary (a node face or part of one, or coplanar
/// ones merged), in lattice units.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Rect {
    /// Axis of the outward normal.
    pub axis: u8,
    /// Whether the outward normal points to `+axis`.
    pub positive: bool,
    /// Coordinate of the rectangle's plane along `axis`.
    pub plane: u32,
    /// Lowest corner along the in-plane axes `(axis + 1) % 3` and `(axis + 2) % 3`.
    pub u: u32,
    pub v: u32,
    /// Extent along the in-plane axes `(axis + 1) % 3` and `(axis + 2) % 3`.
    pub w: u32,
    pub h: u32,
}

impl Rect {
    /// The lattice point at in-plane coordinates `(u, v)`.
    fn point(&self, u: u32, v: u32) -> Point {
        let a = usize::from(self.axis);
        let mut p = [0; 3];
        p[a] = self.plane;
        p[(a + 1) % 3] = u;
        p[(a + 2) % 3] = v;
        p
    }

    /// Corners counter-clockwise seen from `+axis` (`u x v = axis`).
    fn corners(&self) -> [Point; 4] {
        let (u1, v1) = (self.u + self.w, self.v + self.h);
        [self.point(self.u, self.v), self.point(u1, self.v), self.point(u1, v1), self.point(self.u, v1)]
    }
}

/// The boundary of `tree` as a closed, manifold, outward-oriented triangle mesh in
/// world coordinates; empty (no triangles) for an empty solid. See the module doc.
///
/// # Panics
/// When the mesh would need more than `2^32` vertex indices (far beyond memory);
/// [`try_boundary_mesh`] returns an error instead.
#[must_use]
pub fn boundary_mesh(tree: &LinearOctree, options: &BoundaryOptions) -> TriangleMesh {
    match try_boundary_mesh(tree, options, MemoryBudget::unlimited(), &NoProgress) {
        Ok(mesh) => mesh,
        Err(e) => panic!("{e}"),
    }
}

/// [`boundary_mesh`], refused before anything is allocated when its estimated memory
/// exceeds `budget` (the exposed squares are first counted in a pass that allocates
/// nothing) or it would need more than `2^32` vertex indices.
/// `progress` counts the four steps of the module doc.
pub fn try_boundary_mesh(
    tree: &LinearOctree,
    options: &BoundaryOptions,
    budget: MemoryBudget,
    progress: &dyn Progress,
) -> Result<TriangleMesh> {
    let size = BoundarySize::of(tree);
    let job = format!("the boundary mesh of {} exposed voxel faces", size.unit_faces);
    budget.check(job, size.mesh_bytes(options))?;
    boundary_mesh_of_size(tree, options, size, progress)
}

/// How large the boundary of a solid is, counted in a pass over its nodes that
/// allocates nothing (step 1 of the module doc without its output).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(crate) struct BoundarySize {
    /// Exposed squares (node faces or parts of them) before merging.
    pub squares: u128,
    /// Exposed voxel faces.
    pub unit_faces: u128,
}

impl BoundarySize {
    /// Counts the exposed squares of `tree` (in parallel over chunks of its keys).
    pub(crate) fn of(tree: &LinearOctree) -> BoundarySize {
        let keys = tree.keys();
        let depth = tree.depth();
        keys.par_chunks(CHUNK)
            .enumerate()
            .map(|(c, chunk)| {
                let mut size = BoundarySize::default();
                for i in c * CHUNK..c * CHUNK + chunk.len() {
                    node_squares(keys, depth, i, &mut size);
                }
                size
            })
            .reduce(BoundarySize::default, |a, b| BoundarySize {
                squares: a.squares + b.squares,
                unit_faces: a.unit_faces + b.unit_faces,
            })
    }

    /// Estimated peak bytes of [`try_boundary_mesh`] with `options`.
    pub(crate) fn mesh_bytes(&self, options: &BoundaryOptions) -> u64 {
        let bytes = if options.unit_faces {
            self.unit_faces * u128::from(BYTES_PER_UNIT_FACE)
        } else {
            self.squares * u128::from(BYTES_PER_SQUARE)
        };
        u64::try_from(bytes).unwrap_or(u64::MAX)
    }
}

/// The boundary of a solid as voxel faces joined at their sheets' vertices, before
/// triangles: what dual contouring moves ([`crate::surface`]).
pub(crate) struct UnitFaceQuads {
    /// The unit faces, in an order that does not depend on the thread count.
    pub faces: Vec<Rect>,
    /// Each vertex's lattice point (one vertex a sheet, module doc step 3).
    pub points: Vec<Point>,
    /// Each face's four vertices, counter-clockwise seen from outside.
    pub quads: Vec<[u32; 4]>,
}

/// Steps 1 and 3 of the module doc for unit faces, without triangles; `size` is
/// [`BoundarySize::of`] `tree`.
pub(crate) fn unit_face_quads(tree: &LinearOctree, size: BoundarySize) -> Result<UnitFaceQuads> {
    if size.unit_faces * 4 > u128::from(u32::MAX) {
        return Err(Error::invalid(
            "boundary mesh",
            format!("{} faces need more than 2^32 vertices; export at a lower depth", size.unit_faces),
        ));
    }
    let faces = exposed_squares(tree).par_chunks(CHUNK).map(unit_squares).collect::<Vec<_>>().concat();
    let polygons = Polygons::concat(faces.par_chunks(CHUNK).map(|chunk| Polygons::of(chunk, &[])).collect::<Vec<_>>());
    let (points, ids) = weld_sheets(&faces, &polygons);
    let quads = ids.par_chunks_exact(4).map(|q| [q[0], q[1], q[2], q[3]]).collect();
    Ok(UnitFaceQuads { faces, points, quads })
}

/// Where the exposed squares go: a list, or a count.
trait Squares {
    fn push(&mut self, rect: Rect);
}

impl Squares for Vec<Rect> {
    fn push(&mut self, rect: Rect) {
        Vec::push(self, rect);
    }
}

impl Squares for BoundarySize {
    fn push(&mut self, rect: Rect) {
        self.squares += 1;
        self.unit_faces += u128::from(rect.w) * u128::from(rect.h);
    }
}

/// [`try_boundary_mesh`] after its budget check, `size` being [`BoundarySize::of`] `tree`.
pub(crate) fn boundary_mesh_of_size(
    tree: &LinearOctree,
    options: &BoundaryOptions,
    size: BoundarySize,
    progress: &dyn Progress,
) -> Result<TriangleMesh> {
    progress.start(4);
    // Polygon corners (4 a rectangle, more with T-junctions) must fit u32 vertex indices.
    let count = if options.unit_faces { size.unit_faces } else { size.squares };
    if count * 4 > u128::from(u32::MAX) {
        return Err(Error::invalid(
            "boundary mesh",
            format!("{count} faces need more than 2^32 vertices; export at a lower depth"),
        ));
    }
    // 1. Exposed squares, then merged or cut.
    let mut rects = exposed_squares(tree);
    if options.unit_faces {
        rects = rects.par_chunks(CHUNK).map(unit_squares).collect::<Vec<_>>().concat();
    } else {
        rects = merge_coplanar(rects);
    }

    progress.advance(1);
    stop_if_cancelled(progress)?;
    // 2. Polygons with the extra vertices that T-junctions need.
    let polygons = if options.unit_faces {
        rects.par_chunks(CHUNK).map(|chunk| Polygons::of(chunk, &[])).collect::<Vec<_>>()
    } else {
        let ends = edge_ends(&rects);
        rects.par_chunks(CHUNK).map(|chunk| Polygons::of(chunk, &ends)).collect::<Vec<_>>()
    };
    let polygons = Polygons::concat(polygons);
    if polygons.points.len() + rects.len() > u32::MAX as usize {
        return Err(Error::invalid(
            "boundary mesh",
            format!("{} polygon points need more than 2^32 vertices; export at a lower depth", polygons.points.len()),
        ));
    }

    progress.advance(1);
    stop_if_cancelled(progress)?;
    // 3. One vertex a sheet at each lattice point.
    let (points, ids) = weld_sheets(&rects, &polygons);
    let domain = tree.domain();
    let vertices: Vec<_> = points.par_iter().map(|&p| domain.lattice_point(p)).collect();

    progress.advance(1);
    stop_if_cancelled(progress)?;
    // 4. Triangles.
    let triangles = (0..rects.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .flat_map_iter(|s| triangulate(usize::from(rects[s].axis), polygons.get(s), &ids[polygons.range(s)]))
        .collect();
    progress.advance(1);
    stop_if_cancelled(progress)?;
    progress.finish();
    Ok(TriangleMesh { vertices, triangles, groups: Vec::new() })
}

/// The exposed squares of the faces of `tree`'s full nodes (step 1 of the module doc,
/// before merging), in key order.
pub(crate) fn exposed_squares(tree: &LinearOctree) -> Vec<Rect> {
    let keys = tree.keys();
    let depth = tree.depth();
    keys.par_chunks(CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut out = Vec::new();
            for i in c * CHUNK..c * CHUNK + chunk.len() {
                node_squares(keys, depth, i, &mut out);
            }
            out
        })
        .collect::<Vec<_>>()
        .concat()
}

/// The boundary of `tree` as coplanar rectangles in lattice units (the exposed parts
/// of its full nodes' faces, merged; step 1 of the module doc): they tile the voxel
/// boundary without overlap, in an order that does not depend on the thread count.
/// Radiosity's patches are cut from them.
pub(crate) fn boundary_rects(tree: &LinearOctree) -> Vec<Rect> {
    merge_coplanar(exposed_squares(tree))
}

/// Appends the exposed squares of the six faces of node `keys[index]` to `out`.
fn node_squares(keys: &[NodeKey], depth: u8, index: usize, out: &mut impl Squares) {
    let key = keys[index];
    let node = key.node(depth);
    let resolution = 1u32 << depth;
    for axis in 0..3 {
        let (u_axis, v_axis) = ((axis + 1) % 3, (axis + 2) % 3);
        for positive in [false, true] {
            let plane = if positive { node.min[axis] + node.size } else { node.min[axis] };
            let rect = Rect {
                axis: axis as u8,
                positive,
                plane,
                u: node.min[u_axis],
                v: node.min[v_axis],
                w: node.size,
                h: node.size,
            };
            if (positive && plane == resolution) || (!positive && plane == 0) {
                out.push(rect);
                continue;
            }
            // The same-size cube across the face (aligned: the plane is a multiple of the size).
            let mut across = node.min;
            across[axis] = if positive { plane } else { plane - node.size };
            let cube = NodeKey::new(morton::encode(across[0], across[1], across[2]), key.k());
            expose(keys_meeting_near(keys, index, cube), cube, rect, out);
        }
    }
}

/// Emits the parts of square `rect` (a face of a full node) that the cube `across` beyond it
/// leaves uncovered; `keys` are the full nodes meeting `across` as `keys_meeting`
/// gives them (the covering node alone when one covers it).
fn expose(keys: &[NodeKey], across: NodeKey, rect: Rect, out: &mut impl Squares) {
    match keys {
        [] => out.push(rect),
        [key] if key.k() >= across.k() => {}
        _ => {
            // Partly full: recurse into the four children touching the square (on its
            // side of `across` along the axis), each with its slice of keys.
            let a = usize::from(rect.axis);
            let near = u64::from(!rect.positive);
            let half = rect.w / 2;
            let mut rest = keys;
            for c in (0..8u64).filter(|c| (c >> a) & 1 == near) {
                let Some(child) = across.child(c) else { return };
                rest = &rest[rest.partition_point(|k| k.start() < child.start())..];
                let inside = rest.partition_point(|k| k.start() < child.end());
                let du = ((c >> ((a + 1) % 3)) & 1) as u32 * half;
                let dv = ((c >> ((a + 2) % 3)) & 1) as u32 * half;
                let sub = Rect { u: rect.u + du, v: rect.v + dv, w: half, h: half, ..rect };
                expose(&rest[..inside], child, sub, out);
                rest = &rest[inside..];
            }
        }
    }
}

/// Coplanar rectangles merged: first runs along `u` with the same `v` and height, then
/// runs of those along `v` with the same `u` and width. Sorting by unique keys keeps the
/// order independent of the thread count.
fn merge_coplanar(mut rects: Vec<Rect>) -> Vec<Rect> {
    let plane = |r: &Rect| (r.axis, r.positive, r.plane);
    rects.par_sort_unstable_by_key(|r| (plane(r), r.v, r.h, r.u));
    let rows = merge_runs(
        rects,
        |a, b| plane(a) == plane(b) && (a.v, a.h) == (b.v, b.h) && a.u + a.w == b.u,
        |a, b| {
            a.w += b.w;
        },
    );
    let mut rows = rows;
    rows.par_sort_unstable_by_key(|r| (plane(r), r.u, r.w, r.v));
    merge_runs(rows, |a, b| plane(a) == plane(b) && (a.u, a.w) == (b.u, b.w) && a.v + a.h == b.v, |a, b| a.h += b.h)
}

/// Folds each run of consecutive items that `joins` links into its first (`grow`).
fn merge_runs(items: Vec<Rect>, joins: impl Fn(&Rect, &Rect) -> bool, grow: impl Fn(&mut Rect, &Rect)) -> Vec<Rect> {
    let mut out: Vec<Rect> = Vec::with_capacity(items.len());
    for item in items {
        match out.last_mut() {
            Some(last) if joins(last, &item) => grow(last, &item),
            _ => out.push(item),
        }
    }
    out
}

/// The unit squares of `rects`, in order, each rectangle's row by row.
fn unit_squares(rects: &[Rect]) -> Vec<Rect> {
    let mut out = Vec::new();
    for s in rects {
        for dv in 0..s.h {
            for du in 0..s.w {
                out.push(Rect { u: s.u + du, v: s.v + dv, w: 1, h: 1, ..*s });
            }
        }
    }
    out
}

/// A point on the axis-`d` line through `p`, packed so that sorting groups points by
/// line (axis, the two other coordinates) and orders them along it.
fn line_point(d: usize, p: Point) -> u128 {
    let (b, c) = ((d + 1) % 3, (d + 2) % 3);
    (d as u128) << (3 * COORD_BITS)
        | u128::from(p[b]) << (2 * COORD_BITS)
        | u128::from(p[c]) << COORD_BITS
        | u128::from(p[d])
}

/// The axis along which two lattice points on an axis-parallel edge differ.
fn edge_axis(a: Point, b: Point) -> usize {
    (0..3).find(|&d| a[d] != b[d]).unwrap_or(0)
}

/// A rectangle's four edges counter-clockwise seen from `+axis`: axis, start, end.
fn edges(s: &Rect) -> impl Iterator<Item = (usize, Point, Point)> {
    let c = s.corners();
    (0..4).map(move |i| (edge_axis(c[i], c[(i + 1) % 4]), c[i], c[(i + 1) % 4]))
}

/// The end points of rectangle edges, as sorted, distinct [`line_point`]s, on the lines
/// that hold an edge longer than one voxel (only those edges have lattice points
/// strictly inside). The lines are kept in a hashed bit set; a false hit only adds a
/// point no long edge asks for.
fn edge_ends(rects: &[Rect]) -> Vec<u128> {
    // Fibonacci hash of the line (the point without its position along the line, 46 bits).
    let line_hash = |p: u128| ((p >> COORD_BITS) as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15) >> 20;
    let long_lines: Vec<u64> = rects
        .par_iter()
        .filter(|s| s.w > 1 || s.h > 1)
        .flat_map_iter(|s| {
            edges(s).filter(|(d, a, b)| a[*d].abs_diff(b[*d]) > 1).map(|(d, a, _)| line_hash(line_point(d, a)))
        })
        .collect();
    let bits = (long_lines.len() * 16).next_power_of_two().max(64);
    let mut set = vec![0u64; bits / 64];
    for h in long_lines {
        let b = h as usize & (bits - 1);
        set[b / 64] |= 1 << (b % 64);
    }
    let on_long_line = |p: u128| {
        let b = line_hash(p) as usize & (bits - 1);
        set[b / 64] & (1 << (b % 64)) != 0
    };
    let mut ends: Vec<u128> = rects
        .par_chunks(CHUNK)
        .flat_map_iter(|chunk| {
            let mut out = Vec::new();
            for s in chunk {
                for (d, a, b) in edges(s) {
                    let start = line_point(d, a);
                    if on_long_line(start) {
                        out.extend([start, line_point(d, b)]);
                    }
                }
            }
            out
        })
        .collect();
    ends.par_sort_unstable();
    ends.dedup();
    ends
}

/// Polygons as one flat point list with offsets: rectangle `s` is
/// `points[offsets[s]..offsets[s + 1]]`, counter-clockwise seen from outside,
/// starting at a corner.
struct Polygons {
    points: Vec<Point>,
    offsets: Vec<usize>,
}

impl Polygons {
    /// The polygons of `rects`: corners plus the points of `ends` strictly inside
    /// each edge (`ends` empty: corners only).
    fn of(rects: &[Rect], ends: &[u128]) -> Polygons {
        let mut points = Vec::with_capacity(4 * rects.len());
        let mut offsets = Vec::with_capacity(rects.len() + 1);
        offsets.push(0);
        for s in rects {
            let start = points.len();
            let c = s.corners();
            for i in 0..4 {
                let (a, b) = (c[i], c[(i + 1) % 4]);
                points.push(a);
                let d = edge_axis(a, b);
                if a[d].abs_diff(b[d]) == 1 || ends.is_empty() {
                    continue;
                }
                let (la, lb) = (line_point(d, a), line_point(d, b));
                let (lo, hi) = (la.min(lb), la.max(lb));
                let first = ends.partition_point(|&e| e <= lo);
                let last = first + ends[first..].partition_point(|&e| e < hi);
                let mut at = |e: &u128| {
                    let mut p = a;
                    p[d] = (e & COORD_MASK) as u32;
                    points.push(p);
                };
                if la < lb {
                    ends[first..last].iter().for_each(&mut at);
                } else {
                    ends[first..last].iter().rev().for_each(&mut at);
                }
            }
            if !s.positive {
                // Clockwise seen from +axis is counter-clockwise seen from outside.
                points[start + 1..].reverse();
            }
            offsets.push(points.len());
        }
        Polygons { points, offsets }
    }

    /// Joins per-chunk polygon lists in order.
    fn concat(parts: Vec<Polygons>) -> Polygons {
        let mut points = Vec::with_capacity(parts.iter().map(|p| p.points.len()).sum());
        let mut offsets = vec![0];
        for part in parts {
            let base = points.len();
            offsets.extend(part.offsets[1..].iter().map(|o| o + base));
            points.extend(part.points);
        }
        Polygons { points, offsets }
    }

    fn range(&self, s: usize) -> std::ops::Range<usize> {
        self.offsets[s]..self.offsets[s + 1]
    }

    fn get(&self, s: usize) -> &[Point] {
        &self.points[self.range(s)]
    }

    fn len(&self) -> usize {
        self.offsets.len() - 1
    }
}

/// Welds the polygons' points into vertices, one a sheet at each lattice point
/// (module doc, step 3). Returns the vertices' lattice points and each polygon
/// point's vertex index.
fn weld_sheets(rects: &[Rect], polygons: &Polygons) -> (Vec<Point>, Vec<u32>) {
    // One record a polygon point: where it is, which quarter faces its rectangle covers there.
    let records: Vec<u128> = (0..polygons.len())
        .into_par_iter()
        .with_min_len(CHUNK)
        .flat_map_iter(|s| {
            let rect = &rects[s];
            let a = usize::from(rect.axis);
            let low = rect.point(rect.u, rect.v);
            let range = polygons.range(s);
            let poly = polygons.get(s);
            let n = poly.len();
            (0..n).map(move |i| {
                let (p, prev, next) = (poly[i], poly[(i + n - 1) % n], poly[(i + 1) % n]);
                let (hp, hn) = (sheets::half_edge(p, prev), sheets::half_edge(p, next));
                let faces = if hp / 2 == hn / 2 {
                    // A point inside an edge: two quarter faces either side of the inward half-edge.
                    let w = 3 - a - usize::from(hp / 2);
                    let inward = 2 * w as u8 + u8::from(p[w] == low[w]);
                    [QuarterFace::new(a, hp, inward, rect.positive), QuarterFace::new(a, inward, hn, rect.positive)]
                } else {
                    [QuarterFace::new(a, hp, hn, rect.positive), QuarterFace::NONE]
                };
                sheets::record(p, faces, range.start + i)
            })
        })
        .collect();
    // The polygon neighbour of point `i` in the direction of half-edge `h`.
    let along = |i: usize, h: u8| {
        let s = polygons.offsets.partition_point(|&o| o <= i) - 1;
        let poly = polygons.get(s);
        let (k, n) = (i - polygons.offsets[s], poly.len());
        let next = poly[(k + 1) % n];
        if sheets::half_edge(poly[k], next) == h { next } else { poly[(k + n - 1) % n] }
    };
    sheets::weld(records, polygons.points.len(), along)
}

/// The triangles of one polygon (module doc, step 4) in the plane normal to `axis`;
/// `ids` are its points' vertex indices.
fn triangulate(axis: usize, poly: &[Point], ids: &[u32]) -> SmallVec<[[u32; 3]; 2]> {
    if poly.len() == 4 {
        return SmallVec::from_buf([[ids[0], ids[1], ids[2]], [ids[0], ids[2], ids[3]]]);
    }
    // Ear clipping of a weakly convex polygon: cut off a corner whose neighbours are
    // not in line with it, unless all the other points are in line with those
    // neighbours (the rest would be flat; one of the line's two ends serves then).
    let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
    let cross = |a: Point, b: Point, c: Point| {
        let d = |p: Point, q: Point, k: usize| i64::from(q[k]) - i64::from(p[k]);
        d(a, b, u) * d(b, c, v) - d(a, b, v) * d(b, c, u)
    };
    let mut ring: SmallVec<[usize; 16]> = (0..poly.len()).collect();
    let mut out = SmallVec::new();
    while ring.len() > 3 {
        let n = ring.len();
        let around = |k: usize| (ring[(k + n - 1) % n], ring[k], ring[(k + 1) % n]);
        let ear = (0..n)
            .find(|&k| {
                let (a, b, c) = around(k);
                cross(poly[a], poly[b], poly[c]) != 0
                    && ring.iter().any(|&j| j != b && cross(poly[a], poly[c], poly[j]) != 0)
            })
            .unwrap_or(0);
        let (a, b, c) = around(ear);
        out.push([ids[a], ids[b], ids[c]]);
        ring.remove(ear);
    }
    out.push([ids[ring[0]], ids[ring[1]], ids[ring[2]]]);
    out
}
