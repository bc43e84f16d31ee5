//! Solid voxelization of triangle meshes into a canonical linear octree.
//!
//! Adaptive and top-down like shape voxelization, with the triangles handed down the
//! tree: a node keeps the triangles that overlap its box (exact separating-axis test,
//! [`super::tri_box`], in large nodes; a plane test in small ones, see
//! [`SAT_MIN_SIZE`]); a node with none is wholly inside or outside and is decided by
//! one point query at its first voxel's centre; a voxel with triangles is decided at
//! its centre. Work follows the surface. The walk itself (Morton order, the merge of
//! eight full children, the parallel top levels, progress, the budget check before the
//! tables are built) is the octree driver's ([`crate::octree`]); this file says how a
//! node is decided and what it hands its children ([`MeshNode`]).
//!
//! Inside rules: [`InsideRule::Parity`] counts crossings of a `+x` ray (watertight
//! meshes); [`InsideRule::Winding`] thresholds the generalized winding number at 1/2
//! (holes, cracks, self-overlap); [`InsideRule::Auto`] takes parity when the mesh is
//! watertight, else winding.
//!
//! Coherence: below nodes of [`REFERENCE_SIZE`] voxels a side, queries are not made from
//! scratch. Such a node's centre is queried once; every node below gets the value at
//! its centre (and a voxel or a node without triangles at its sample point) from its
//! parent's centre value plus the signed crossings of the segment between the two
//! points. The parent's centre is a corner of the child, so the segment stays in the
//! child and only the child's own triangles can cross it: a child without triangles
//! just inherits the value.
//! That is exact for parity and for closed parts of a mesh; near a hole the winding
//! number also varies smoothly, and this carries it over less than one small node.
//!
//! Points on the surface: node centres are lattice points and voxel centres half-way
//! between, so a mesh whose faces, edges or vertices lie on the lattice (an
//! axis-aligned box on voxel planes) puts them on the surface. Every crossing count
//! then perturbs all points alike ([`super::crossing`]): a point on the surface is
//! decided as the point a hair toward `+x`, then `+y`, then `+z` (for a box, `lo <= c
//! < hi` on each axis). A query from scratch is never made at a point on the plane of
//! one of its node's triangles (the oracles have no such rule, and the winding number
//! is undefined there): it is made at a point of the node off all of them and carried
//! to the point like any reference value.

use smallvec::SmallVec;

use glam::DVec3;

use super::TriangleMesh;
use super::crossing::{Plane, signed_crossing, signed_crossing_sides};
use super::parity::ParityGrid;
use super::tri_box::triangle_box_overlap;
use super::winding::WindingNumber;
use crate::aabb::Aabb;
use crate::budget::MemoryBudget;
use crate::error::Result;
use crate::morton;
use crate::octree::{
    CellSink, Cells, Counters, Decision, Domain, LinearOctree, NodeKey, Plan, VoxelizeOptions, Voxelizer, check_level,
};
use crate::progress::{NoProgress, Progress};

/// Children of at least this many voxels a side get the exact separating-axis test;
/// smaller ones get every triangle whose bounding box meets them and whose plane may
/// meet them (`|n . (c - a)| <= |n|_1 h`, a few instructions). Below [`REFERENCE_SIZE`]
/// a list only has to hold every triangle that meets the child (an extra triangle
/// crosses no segment inside it, so values and voxels stay the same) and the full test
/// costs more than the visits it saves; at and above it, an empty list means a query
/// from scratch, so those lists stay exact. Bunny, `valgrind --tool=callgrind`,
/// instructions of load and voxelization: full test for children smaller than the
/// triangle's box 1.13 G (depth 8) and 7.56 G (depth 10); plane test 1.05 G and 7.29 G.
pub const SAT_MIN_SIZE: u32 = REFERENCE_SIZE;

/// Nodes of this many voxels a side carry a reference query for their subtree.
pub const REFERENCE_SIZE: u32 = 16;

/// How a point is decided inside a mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InsideRule {
    /// Parity for watertight meshes, winding otherwise.
    Auto,
    /// Odd number of crossings of a ray (watertight meshes only).
    Parity,
    /// Generalized winding number at least 1/2.
    Winding,
}

impl InsideRule {
    /// Every rule, in the order help lists them.
    pub const ALL: [InsideRule; 3] = [InsideRule::Auto, InsideRule::Parity, InsideRule::Winding];

    /// The rule's one spelling (`auto`, `parity`, `winding`).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            InsideRule::Auto => "auto",
            InsideRule::Parity => "parity",
            InsideRule::Winding => "winding",
        }
    }
}

crate::spelling::spelled!(InsideRule);

/// Options of a mesh voxelization.
#[derive(Clone, Copy)]
pub struct MeshVoxelizeOptions<'a> {
    /// The inside rule.
    pub inside: InsideRule,
    /// Refuse when the estimated memory exceeds this.
    pub budget: MemoryBudget,
    /// Receives progress in units of level-3 subtrees.
    pub progress: &'a dyn Progress,
}

impl Default for MeshVoxelizeOptions<'_> {
    fn default() -> Self {
        MeshVoxelizeOptions { inside: InsideRule::Auto, budget: MemoryBudget::default(), progress: &NoProgress }
    }
}

/// What a mesh voxelization did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MeshVoxelizeStats {
    /// The rule used (never `Auto`).
    pub rule: Option<InsideRule>,
    /// Octree nodes visited.
    pub nodes_visited: u64,
    /// Triangle-box overlap tests.
    pub triangle_box_tests: u64,
    /// Point queries made from scratch (ray casts or winding numbers).
    pub point_queries: u64,
    /// Triangles left out because they bound nothing ([`TriangleMesh::solid_boundary`]).
    pub void_triangles: usize,
}

impl Counters for MeshVoxelizeStats {
    fn add(&mut self, o: MeshVoxelizeStats) {
        self.nodes_visited += o.nodes_visited;
        self.triangle_box_tests += o.triangle_box_tests;
        self.point_queries += o.point_queries;
    }
}

/// The point query of one rule.
enum Oracle {
    Parity(ParityGrid),
    Winding(WindingNumber),
}

impl Oracle {
    fn value(&self, p: DVec3) -> f64 {
        match self {
            Oracle::Parity(g) => f64::from(g.crossings(p) % 2),
            Oracle::Winding(w) => w.at(p),
        }
    }

    /// The value past `crossings` signed surface crossings from a point of value `vq`.
    fn carry(&self, vq: f64, crossings: i32) -> f64 {
        let k = f64::from(crossings);
        match self {
            Oracle::Parity(_) => (vq + k).rem_euclid(2.0),
            Oracle::Winding(_) => vq + k,
        }
    }

    fn inside(&self, v: f64) -> bool {
        match self {
            Oracle::Parity(_) => v > 0.5,
            Oracle::Winding(_) => v >= 0.5,
        }
    }
}

/// Estimated peak bytes: nodes near the surface of the mesh's box, the triangle
/// lists handed down (a few per surface voxel), and the inside oracle (the parity
/// grid's bound, [`ParityGrid::max_bytes`], when the rule may be parity; the winding
/// hierarchy is within the 200 bytes a triangle).
fn estimate_bytes(mesh: &TriangleMesh, domain: &Domain, inside: InsideRule) -> u64 {
    estimate_bytes_capped(mesh, domain, inside, f64::INFINITY)
}

/// [`estimate_bytes`] with the surface capped at `max_faces` voxel faces.
fn estimate_bytes_capped(mesh: &TriangleMesh, domain: &Domain, inside: InsideRule, max_faces: f64) -> u64 {
    let area = mesh.bounds().intersection(&domain.aabb()).map_or(0.0, |b| b.area());
    let faces = (area / domain.voxel_size().powi(2)).min(max_faces);
    let oracle = match inside {
        InsideRule::Winding => 0.0,
        InsideRule::Parity | InsideRule::Auto => ParityGrid::max_bytes(mesh.triangles.len()) as f64,
    };
    (faces * 32.0 + mesh.triangles.len() as f64 * 200.0 + oracle).min(u64::MAX as f64) as u64
}

/// Voxelizes the solid bounded by `mesh` into `domain`.
pub fn voxelize_mesh(
    mesh: &TriangleMesh,
    domain: Domain,
    options: &MeshVoxelizeOptions,
) -> Result<(LinearOctree, MeshVoxelizeStats)> {
    mesh.validate()?;
    let (mesh, void_triangles, copied) = solid_triangles(mesh);
    let driver = VoxelizeOptions { budget: options.budget, progress: options.progress };
    let plan = Plan::new("voxelizing a mesh", estimate_bytes(&mesh, &domain, options.inside), domain, &driver)?;
    if mesh.triangles.is_empty() {
        let stats = MeshVoxelizeStats { rule: Some(InsideRule::Winding), void_triangles, ..Default::default() };
        return Ok((LinearOctree::empty(domain), stats));
    }
    let (rule, job, root) = prepare(&mesh, domain, options.inside, copied);
    let (tree, mut stats) = plan.run(&job, root)?;
    stats.rule = Some(rule);
    stats.void_triangles = void_triangles;
    Ok((tree, stats))
}

/// Voxelizes the solid bounded by `mesh` in `domain` cell by cell: the cells of
/// `cells` that hold voxels go to `sink` in Morton order, with exactly the keys
/// [`voxelize_mesh`] gives in each cell (see [`crate::octree::Cells`]). The estimate
/// checked against the budget is one cell's (its surface capped at the cell's box)
/// plus the mesh's tables and inside oracle, which every cell shares.
pub fn voxelize_mesh_cells(
    mesh: &TriangleMesh,
    domain: Domain,
    options: &MeshVoxelizeOptions,
    cells: &Cells,
    sink: &mut dyn CellSink,
) -> Result<MeshVoxelizeStats> {
    mesh.validate()?;
    check_level(cells, &domain)?;
    let (mesh, void_triangles, copied) = solid_triangles(mesh);
    let driver = VoxelizeOptions { budget: options.budget, progress: options.progress };
    let cell_edge = f64::from(domain.resolution() >> cells.level);
    let estimate = estimate_bytes_capped(&mesh, &domain, options.inside, 6.0 * cell_edge * cell_edge);
    let plan = Plan::new("voxelizing a cell of a mesh", estimate, domain, &driver)?;
    if mesh.triangles.is_empty() {
        return Ok(MeshVoxelizeStats { rule: Some(InsideRule::Winding), void_triangles, ..Default::default() });
    }
    let (rule, job, root) = prepare(&mesh, domain, options.inside, copied);
    let mut stats = plan.run_cells(&job, root, cells, sink)?;
    stats.rule = Some(rule);
    stats.void_triangles = void_triangles;
    Ok(stats)
}

/// The triangles that bound the solid ([`TriangleMesh::solid_boundary`]), how many were
/// left out, and whether some set of corners is still copied. One sort of the corner
/// sets answers the usual mesh, every triangle on corners of its own.
pub(crate) fn solid_triangles(mesh: &TriangleMesh) -> (std::borrow::Cow<'_, TriangleMesh>, usize, bool) {
    let void = |t: &[u32; 3]| t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
    if !mesh.triangles.iter().any(void) && super::all_distinct(&super::corner_sets(&mesh.triangles)) {
        return (std::borrow::Cow::Borrowed(mesh), 0, false);
    }
    let (kept, void_triangles) = mesh.solid_boundary();
    (kept, void_triangles, true)
}

/// The rule `inside` resolves to, the job (tables and inside oracle) and the root's
/// state.
fn prepare(mesh: &TriangleMesh, domain: Domain, inside: InsideRule, copied: bool) -> (InsideRule, Job<'_>, MeshNode) {
    // The oracle (and the watertight check it may need) and the per-triangle tables
    // are independent: built side by side.
    let oracle = || {
        let rule = match inside {
            InsideRule::Auto if mesh.is_watertight() => InsideRule::Parity,
            InsideRule::Auto => InsideRule::Winding,
            r => r,
        };
        let oracle = match rule {
            InsideRule::Parity => Oracle::Parity(ParityGrid::new(mesh)),
            _ => Oracle::Winding(WindingNumber::new(mesh)),
        };
        (rule, oracle)
    };
    let tables = || {
        let corners: Vec<[DVec3; 3]> = (0..mesh.triangles.len()).map(|t| mesh.corners(t)).collect();
        let boxes: Vec<Aabb> = corners.iter().map(|c| Aabb::from_points(*c).expect("three corners")).collect();
        let planes: Vec<Plane> = (0..mesh.triangles.len() as u32).map(|t| Plane::new(mesh, t)).collect();
        (corners, boxes, planes)
    };
    let ((rule, oracle), (corners, boxes, planes)) = rayon::join(oracle, tables);
    let (distinct, copies) = if copied {
        distinct_triangles(mesh)
    } else {
        ((0..mesh.triangles.len() as u32).collect(), vec![1; mesh.triangles.len()])
    };
    let job = Job { mesh, corners, boxes, planes, copies, domain, oracle };
    let root = MeshNode { triangles: distinct.into(), reference: None };
    (rule, job, root)
}

/// One triangle of each set of corners (the first), and each triangle's number of
/// copies: the triangles handed down the tree are the distinct ones, each crossing
/// counted as many times as it has copies (after [`TriangleMesh::solid_boundary`] the
/// copies of a set of corners all face one way), so a face repeated a thousand times
/// costs a node what one does. The oracle keeps every copy.
fn distinct_triangles(mesh: &TriangleMesh) -> (Vec<u32>, Vec<i32>) {
    let sets = super::corner_sets(&mesh.triangles);
    let mut copies = vec![0i32; mesh.triangles.len()];
    let mut distinct = Vec::with_capacity(sets.len());
    for group in sets.chunk_by(|a, b| a.0 == b.0) {
        let first = group.iter().map(|&(_, t, _)| t).min().expect("a group has a member");
        distinct.push(first);
        copies[first as usize] = group.len() as i32;
    }
    distinct.sort_unstable();
    (distinct, copies)
}

/// Children on the low side of axis `a` (bit `a` of the child's index clear).
const LOW: [u8; 3] = [0x55, 0x33, 0x0f];

/// For each axis mask (bit `a` for axis `a`): the children a box can reach when it
/// lies wholly above the centre on those axes (the children on their high sides).
const REACHED_ABOVE: [u8; 8] = reached(true);

/// For each axis mask: the children a box can reach when it lies wholly below the
/// centre on those axes.
const REACHED_BELOW: [u8; 8] = reached(false);

/// [`REACHED_ABOVE`] (`above`) or [`REACHED_BELOW`].
const fn reached(above: bool) -> [u8; 8] {
    let mut table = [0xffu8; 8];
    let mut mask = 0;
    while mask < 8 {
        let mut a = 0;
        while a < 3 {
            if mask >> a & 1 == 1 {
                table[mask] &= if above { !LOW[a] } else { LOW[a] };
            }
            a += 1;
        }
        mask += 1;
    }
    table
}

/// A point, the rule's value there, and the triangles a segment from it to the points
/// being decided can cross.
#[derive(Clone, Copy)]
struct Reference<'t> {
    q: DVec3,
    value: f64,
    triangles: &'t [u32],
}

/// A node's box: lowest corner and side.
struct Cell {
    min: DVec3,
    side: f64,
}

/// Roberts' R3 sequence step `(1/g, 1/g^2, 1/g^3)`, `g` the plastic ratio's 3-D
/// analogue (`g^4 = g + 1`): well spread points of a box, none on its lattice planes.
const R3: DVec3 = DVec3::new(0.819_172_513_396_164_4, 0.671_043_606_703_789_2, 0.549_700_477_901_970_4);

/// Points of a node tried before a query from scratch gives up avoiding the planes of
/// its triangles (each plane holds at most a few of them unless the points are
/// collinear on it, which R3's steps are not).
const OFF_SURFACE_TRIES: u32 = 32;

/// What a node is handed by its parent.
struct MeshNode {
    /// The triangles that may meet the node (every one that does; see [`SAT_MIN_SIZE`]).
    triangles: SmallVec<[u32; 16]>,
    /// Below the reference size: the parent's centre (a corner of this node) and the
    /// value there. A segment from it to a point of the node stays in the node, so only
    /// the node's own triangles can cross it.
    reference: Option<(DVec3, f64)>,
}

/// One mesh voxelization's fixed inputs: the mesh, its per-triangle tables, the oracle.
struct Job<'a> {
    mesh: &'a TriangleMesh,
    /// Corners of each triangle.
    corners: Vec<[DVec3; 3]>,
    /// Bounding box of each triangle.
    boxes: Vec<Aabb>,
    /// Plane of each triangle, for fast side tests.
    planes: Vec<Plane>,
    /// Copies of each handed-down triangle ([`distinct_triangles`]).
    copies: Vec<i32>,
    domain: Domain,
    oracle: Oracle,
}

impl Voxelizer for Job<'_> {
    type Node = MeshNode;
    type Counters = MeshVoxelizeStats;

    fn decide(&self, key: NodeKey, node: MeshNode, stats: &mut MeshVoxelizeStats) -> Decision<MeshNode> {
        stats.nodes_visited += 1;
        let min = morton::decode(key.start());
        let triangles = &node.triangles[..];
        let reference = node.reference.map(|(q, value)| Reference { q, value, triangles });
        let size = 1u32 << key.k();
        let cell = Cell { min: self.domain.lattice_point(min), side: f64::from(size) * self.domain.voxel_size() };
        // Step 1: no surface in the node (or a voxel): one point decides.
        if triangles.is_empty() || key.k() == 0 {
            let p = self.domain.voxel_center(min);
            let inside = self.oracle.inside(self.value(p, reference, &cell, triangles, stats));
            return if inside { Decision::Full } else { Decision::Empty };
        }
        // Step 2: small enough: the value at this node's centre, carried from the
        // parent's centre or queried, becomes the reference of the children.
        let here = (size <= REFERENCE_SIZE).then(|| {
            let q = self.domain.lattice_point(min.map(|c| c + size / 2));
            (q, self.value(q, reference, &cell, triangles, stats))
        });
        if key.k() == 1 {
            let (q, value) = here.expect("a 2-voxel node is below the reference size");
            return Decision::Children(self.voxels(key, triangles, q, value, stats));
        }
        // Step 3: the children (of at least two voxels a side here) with their own
        // triangles; this centre, a corner of each, is their reference.
        Decision::Split(self.children(min, size / 2, triangles, here, stats))
    }
}

impl Job<'_> {
    /// The value at `p` (a point of the node `cell`, whose triangles are `triangles`),
    /// carried from the reference when there is one, else queried.
    fn value(
        &self,
        p: DVec3,
        reference: Option<Reference>,
        cell: &Cell,
        triangles: &[u32],
        stats: &mut MeshVoxelizeStats,
    ) -> f64 {
        match reference {
            Some(r) => self.carry(p, r),
            None => self.query(p, cell, triangles, stats),
        }
    }

    /// The value at `p` carried from the reference `r` by the signed crossings of the
    /// segment between them.
    fn carry(&self, p: DVec3, r: Reference) -> f64 {
        // Only triangles whose box meets the segment's box can cross it.
        let (lo, hi) = (r.q.min(p), r.q.max(p));
        let crossings: i32 = r
            .triangles
            .iter()
            .filter(|&&t| {
                let b = &self.boxes[t as usize];
                b.min.cmple(hi).all() && b.max.cmpge(lo).all()
            })
            .map(|&t| signed_crossing(self.mesh, &self.planes[t as usize], t, r.q, p) * self.copies[t as usize])
            .sum();
        self.oracle.carry(r.value, crossings)
    }

    /// The value at `p` from scratch. When `p` lies on the plane of one of the node's
    /// triangles (every triangle meeting the closed box `cell`, which holds `p`), the
    /// query is made at a point of the box off all their planes instead (a few points
    /// of an additive recurrence, Roberts' R3 sequence) and carried to `p`: the segment
    /// stays in the box, so only those triangles can cross it.
    fn query(&self, p: DVec3, cell: &Cell, triangles: &[u32], stats: &mut MeshVoxelizeStats) -> f64 {
        stats.point_queries += 1;
        let on_surface = |x: DVec3| triangles.iter().any(|&t| self.planes[t as usize].contains(self.mesh, t, x));
        if !on_surface(p) {
            return self.oracle.value(p);
        }
        let start = (1..=OFF_SURFACE_TRIES)
            .map(|k| cell.min + (DVec3::splat(0.5) + R3 * f64::from(k)).fract() * cell.side)
            .find(|&q| !on_surface(q))
            .unwrap_or(cell.min + DVec3::splat(0.5 * cell.side));
        self.carry(p, Reference { q: start, value: self.oracle.value(start), triangles })
    }

    /// The children (of `child_size` voxels a side, at least two, of the node with
    /// lowest voxel `min`), each with reference `here` and the triangles of
    /// `triangles` it overlaps: a triangle's bounding box picks the candidates, the
    /// separating-axis test (large children) or the plane test (small ones, see
    /// [`SAT_MIN_SIZE`]) decides unless the box settles it.
    fn children(
        &self,
        min: [u32; 3],
        child_size: u32,
        triangles: &[u32],
        here: Option<(DVec3, f64)>,
        stats: &mut MeshVoxelizeStats,
    ) -> [MeshNode; 8] {
        let center = self.domain.lattice_point(min.map(|c| c + child_size));
        let half = DVec3::splat(f64::from(child_size) * self.domain.voxel_size() * 0.5);
        // Most lists are short: kept inline, no allocation a node.
        let mut children: [MeshNode; 8] =
            std::array::from_fn(|_| MeshNode { triangles: SmallVec::new(), reference: here });
        // Each child's centre and box, once a node.
        let cubes: [(DVec3, DVec3, DVec3); 8] = std::array::from_fn(|i| {
            let offset = DVec3::new((i & 1) as f64, (i >> 1 & 1) as f64, (i >> 2 & 1) as f64) * 2.0 - 1.0;
            let c = center + offset * half;
            (c, c - half, c + half)
        });
        for &t in triangles {
            let b = &self.boxes[t as usize];
            // The children the triangle's box reaches: a side of an axis it misses
            // rules out the four children on that side.
            let above = b.min.cmpgt(center).bitmask() as usize;
            let below = b.max.cmplt(center).bitmask() as usize;
            let mut reached = REACHED_ABOVE[above] & REACHED_BELOW[below];
            while reached != 0 {
                let i = reached.trailing_zeros() as usize;
                reached &= reached - 1;
                let (c, lo, hi) = cubes[i];
                let inside = b.min.cmpge(lo).all() && b.max.cmple(hi).all();
                if !inside && child_size >= SAT_MIN_SIZE {
                    stats.triangle_box_tests += 1;
                    if !triangle_box_overlap(&self.corners[t as usize], c, half) {
                        continue;
                    }
                } else if !inside && !self.planes[t as usize].meets_cube(c, half.x) {
                    continue;
                }
                children[i].triangles.push(t);
            }
        }
        children
    }

    /// Which of the eight voxels of a 2-voxel node with triangles are inside (bit `i`
    /// for child `i`), each carried from the node's centre `q` (value `vq`). Triangle
    /// by triangle: `q`'s side of it is found once, and only the voxels whose segment
    /// from `q` its box meets are looked at (the centre's side of each axis picks them,
    /// as for child lists, then the far end of the segment); the crossings are summed
    /// a voxel.
    fn voxels(&self, key: NodeKey, triangles: &[u32], q: DVec3, vq: f64, stats: &mut MeshVoxelizeStats) -> u8 {
        let min = morton::decode(key.start());
        let centers: [DVec3; 8] = std::array::from_fn(|i| {
            self.domain.voxel_center([
                min[0] + (i & 1) as u32,
                min[1] + (i >> 1 & 1) as u32,
                min[2] + (i >> 2 & 1) as u32,
            ])
        });
        let mut crossings = [0i32; 8];
        for &t in triangles {
            let b = &self.boxes[t as usize];
            let above = b.min.cmpgt(q).bitmask() as usize;
            let below = b.max.cmplt(q).bitmask() as usize;
            let mut reached = REACHED_ABOVE[above] & REACHED_BELOW[below];
            if reached == 0 {
                continue;
            }
            let plane = &self.planes[t as usize];
            let front_q = plane.in_front(self.mesh, t, q);
            while reached != 0 {
                let i = reached.trailing_zeros() as usize;
                reached &= reached - 1;
                let p = centers[i];
                if !(b.min.cmple(q.max(p)).all() && b.max.cmpge(q.min(p)).all()) {
                    continue;
                }
                let front_p = plane.in_front(self.mesh, t, p);
                if front_p != front_q {
                    crossings[i] +=
                        signed_crossing_sides(self.mesh, t, q, front_q, p, front_p) * self.copies[t as usize];
                }
            }
        }
        stats.nodes_visited += 8;
        (0..8).filter(|&i| self.oracle.inside(self.oracle.carry(vq, crossings[i]))).fold(0, |m, i| m | 1 << i)
    }
}
