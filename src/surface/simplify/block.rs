//! Greedy edge collapses inside one block of space (Garland and Heckbert 1997), each
//! kept only when the checks of the module above pass.
//!
//! The block's own faces (all three corners owned by the block) may change; the faces
//! of the snapshot near it (the halo: faces meeting its closed box that are not its
//! own) are fixed obstacles, and a vertex on one is locked. Every face a collapse makes
//! lies strictly inside the block's open box, so blocks never touch each other's new
//! faces and run in parallel on a shared snapshot, each deterministic on its own.
//!
//! Collapses are taken cheapest first from a heap keyed by (quadric cost, the edge's
//! length, its local vertex indices), entries made stale by a later collapse at either end skipped
//! by a per-vertex stamp. Edge `a b` becomes `a` at the candidate point that passes
//! every check, tried by rising cost among the quadric's minimiser and `a`, `b` and the
//! midpoint. A refused edge is not tried again in this block; the next round (other
//! blocks) tries it again. Self-intersection is tested on the block's result, and
//! only a block whose result clashes tests collapses, those near its clashes
//! ([`simplify_block`]).
//!
//! **Refusals remembered across rounds.** Whether a collapse passes depends on the
//! faces around its two ends (the region), their corners' positions, quadrics and
//! bounds, and the faces' cones, and on two things outside the region: the block's box
//! (the link strictly inside it, the candidate point inside it) and, when each
//! collapse is tested, the faces near it. A refusal where every candidate failed for
//! a reason of the region alone (`Local::refusal_kept`), on a region no collapse of
//! the block had touched, is handed back with the edge's cost; a later round skips the
//! edge, and takes its cost as it was, while no vertex of its region (its ends and
//! their neighbours) has moved since (`BlockInput::moved_in`). That is exact: a
//! collapse changes only the faces around its two ends, and leaves its kept vertex,
//! moved, in every face it makes, so a region with no vertex moved is the region that
//! was refused, and the same checks refuse it again. The late rounds, which try every
//! edge for a few collapses, then try only the edges near a change or at a block's
//! border.
//!
//! With a normal limit ([`Limits::max_turn`]) every face carries its normal bound
//! (module `normal`): its cone of input normals, worked out for a candidate's fan after
//! its distance bound passes.

use std::cmp::Reverse;
use std::collections::BinaryHeap;

use glam::DVec3;
use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use super::face_grid::FaceGrid;
use super::gap::{Patches, vertex_bound};
use super::normal::{Cone, fan_cones};
use super::quadric::Quadric;
use super::tri_tri::triangles_clash;

/// What one block reads: its box and its faces.
pub(crate) struct BlockInput<'a> {
    /// Lowest corner of the block's box.
    pub min: DVec3,
    /// Highest corner of the block's box.
    pub max: DVec3,
    /// The snapshot's positions, quadrics and distance bounds by vertex, and faces.
    pub positions: &'a [DVec3],
    pub quadrics: &'a [Quadric],
    pub bounds: &'a [f64],
    pub faces: &'a [[u32; 3]],
    /// Each face's cone of input normals (module `normal`), by face.
    pub cones: &'a [Cone],
    /// The block's own faces (indices into `faces`, ascending).
    pub own: &'a [u32],
    /// The halo (indices into `faces`, ascending).
    pub halo: &'a [u32],
    /// Each vertex's last round moved in (0: never).
    pub moved_in: &'a [u32],
    /// Edges refused in an earlier round on their neighbourhood alone, by global ends
    /// in the order tried, with that round and their cost's bits then (module doc).
    pub refused: &'a FxHashMap<(u32, u32), (u32, u64)>,
}

/// The limits every collapse keeps.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    /// Largest distance bound of a vertex, in world units.
    pub tolerance: f64,
    /// Least cosine between a face's normal before and after a collapse.
    pub min_normal_cosine: f64,
    /// Largest angle between a face's normal and its cone of input normals (module
    /// `normal`), in radians; `None`: the cones are not kept.
    pub max_turn: Option<f64>,
}

/// What one block gives back: its faces now, the vertices it moved, its collapses.
#[derive(Debug, Default)]
pub(crate) struct BlockOutput {
    /// Its faces (global vertex indices).
    pub faces: Vec<[u32; 3]>,
    /// Their cones of input normals (as given when not kept).
    pub cones: Vec<Cone>,
    /// Kept vertices that moved: global index, position, merged quadric, bound.
    pub moved: Vec<(u32, DVec3, Quadric, f64)>,
    /// Collapses made.
    pub collapses: usize,
    /// Edges refused on the snapshot's neighbourhood for reasons the block's box has
    /// no part in (global ends in the order tried), with their cost's bits.
    pub refused: Vec<((u32, u32), u64)>,
    /// Tries made (1: the first result had no clash; [`simplify_block`]).
    pub tries: usize,
    /// Cells of the block's grid the last try watched (0 after one try).
    pub watched: usize,
}

/// The block's working mesh, in local vertex indices.
struct Local {
    global: Vec<u32>,
    position: Vec<DVec3>,
    quadric: Vec<Quadric>,
    bound: Vec<f64>,
    /// Not on a halo face, so free to move or disappear.
    free: Vec<bool>,
    /// Strictly inside the block's open box.
    interior: Vec<bool>,
    alive_vertex: Vec<bool>,
    stamp: Vec<u32>,
    /// Scratch marks by vertex: the vertices listed by the last [`Local::neighbours`]
    /// hold `tick`.
    mark: Vec<u32>,
    tick: u32,
    incident: Vec<SmallVec<[u32; 8]>>,
    faces: Vec<[u32; 3]>,
    /// Each face's cone of input normals (module `normal`).
    cone: Vec<Cone>,
    alive: Vec<bool>,
    /// Whether the face is the block's own (else halo).
    own: Vec<bool>,
    /// Last query that looked at the face (to test each once a query).
    seen: Vec<u32>,
    query: u32,
    /// When collapses are tested for self-intersection.
    test: ClashTest,
    /// Whether the last refused collapse was refused for reasons of its neighbourhood
    /// alone (not the block's box, not a clash).
    refusal_kept: bool,
    /// Edges refused so, global ends, with their cost's bits.
    refused: Vec<((u32, u32), u64)>,
    /// The block's box.
    min: DVec3,
    max: DVec3,
}

/// A heap entry: cost, the edge's squared length, its ends, and the slot of
/// [`Queue::priced`] holding what it was priced on.
/// Equal costs (a plane's edges all cost nothing) go shortest edge first: taken by
/// vertex index, one vertex would swallow its whole plane, its fan growing with every
/// collapse. Entries equal but for the slot are one edge priced at different stamps,
/// all stale but the one at its ends' stamps now, so their order does not matter.
type Entry = Reverse<(u64, u64, u32, u32, u32)>;

/// An edge's candidate points and their quadric costs, cheapest first
/// ([`Local::candidates`]).
type Candidates = [(f64, DVec3); 4];

/// What an entry was priced on: its ends' stamps (the entry is stale once either
/// moved) and its quadric minimiser, unless its cost came from an earlier round. The
/// ends and their quadrics are what they were when it was priced while their stamps
/// are, so the minimiser (an eigen-decomposition where the planes do not nearly
/// agree) is not worked out again.
#[derive(Clone, Copy)]
struct Priced {
    stamps: [u32; 2],
    minimizer: Option<DVec3>,
}

/// The edges to try, cheapest first.
struct Queue {
    heap: BinaryHeap<Entry>,
    /// What each entry was priced on, by slot.
    priced: Vec<Priced>,
    /// Slots free for reuse.
    free: Vec<u32>,
}

impl Queue {
    fn with_capacity(entries: usize) -> Self {
        Queue { heap: BinaryHeap::with_capacity(entries), priced: Vec::with_capacity(entries), free: Vec::new() }
    }

    fn push(&mut self, cost: u64, length: f64, a: u32, b: u32, priced: Priced) {
        let slot = if let Some(slot) = self.free.pop() {
            self.priced[slot as usize] = priced;
            slot
        } else {
            self.priced.push(priced);
            (self.priced.len() - 1) as u32
        };
        self.heap.push(Reverse((cost, length.to_bits(), a, b, slot)));
    }
}

/// When a block tests its collapses for self-intersection.
enum ClashTest {
    /// Once, on the block's result: its new faces against every live face near them.
    OnResult,
    /// Before it is made, each collapse whose new faces' box meets a watched cell
    /// (by cell index) of `grid`, the block's live faces by cell (stale ids of dead
    /// faces left in).
    Watched { cells: Vec<bool>, grid: FaceGrid },
}

/// The face lists of a block's working mesh are made this many times the faces it
/// starts with, and its queue this many times its own faces, rather than grown: in
/// the classic part's first round within 0.04 voxel a block's faces end at 4.3 times
/// (median; 5.3 at most) and its queue peaks at 3.1 times (4.2 at most): each
/// collapse adds its fan and re-prices its kept vertex's edges, the dead faces and
/// stale entries staying listed.
const FACES_GROWN: usize = 5;

/// Tries of a block that watch only the cells near its results' clashes before one
/// that watches every cell ([`simplify_block`]).
const NEAR_TRIES: usize = 1;

/// Simplifies one block; see the module doc.
///
/// The block first collapses without self-intersection tests and then tests its
/// result once: each new face against the live faces near it. A collapse changes
/// only its own region, so a result without clashes is a mesh free of
/// self-intersections. A block whose result clashes (thin walls, sheets) is
/// simplified again from the same snapshot, testing before it is made each collapse
/// near a clash of an earlier try (the grid cells the clashing faces' boxes meet and
/// the cells around them), and its result tested again; after [`NEAR_TRIES`] such
/// tries, one tests every collapse, and its result is free of clashes as made. Either
/// way the output depends on the snapshot alone.
pub(crate) fn simplify_block(input: &BlockInput, limits: &Limits) -> BlockOutput {
    simplify_block_trying(input, limits, NEAR_TRIES)
}

/// [`simplify_block`] with `near_tries` tries near the clashes before the one that
/// watches every cell.
pub(super) fn simplify_block_trying(input: &BlockInput, limits: &Limits, near_tries: usize) -> BlockOutput {
    let first_new = input.own.len() + input.halo.len();
    let (mut local, mut collapses) = collapse_all(input, limits, ClashTest::OnResult);
    let mut tries = 1;
    let mut watched: Option<Vec<bool>> = None;
    while collapses > 0 && !watched.as_ref().is_some_and(|cells| cells.iter().all(|&c| c)) {
        let clashes = local.result_clashes(first_new);
        if clashes.is_empty() {
            break;
        }
        let grid = collapse_grid(input);
        let cells = watched.get_or_insert_with(|| vec![false; grid.len()]);
        if tries > near_tries {
            cells.fill(true);
        } else {
            for (lo, hi) in clashes {
                for cell in grid.cells(grid.grown(grid.cells_between(lo, hi), 1)) {
                    cells[cell] = true;
                }
            }
        }
        tries += 1;
        let test = ClashTest::Watched { cells: cells.clone(), grid };
        (local, collapses) = collapse_all(input, limits, test);
    }
    let mut out = local.output(collapses);
    out.tries = tries;
    out.watched = watched.map_or(0, |cells| cells.iter().filter(|&&c| c).count());
    out
}

/// The grid a block's collapses are tested on: cells twice the mean edge of its own
/// faces.
fn collapse_grid(input: &BlockInput) -> FaceGrid {
    let edges: f64 = input
        .own
        .iter()
        .map(|&f| {
            let [a, b, c] = input.faces[f as usize].map(|v| input.positions[v as usize]);
            (b - a).length() + (c - b).length() + (a - c).length()
        })
        .sum();
    FaceGrid::new(input.min, input.max, edges / (3 * input.own.len().max(1)) as f64)
}

/// Greedy collapses, cheapest first, until none passes the checks.
fn collapse_all(input: &BlockInput, limits: &Limits, test: ClashTest) -> (Local, usize) {
    let mut local = Local::new(input, test);
    let mut queue = Queue::with_capacity(FACES_GROWN * input.own.len());
    for a in 0..local.global.len() as u32 {
        if local.free[a as usize] {
            for b in local.neighbours(a) {
                if a < b && local.free[b as usize] {
                    match local.cost_before(input, a, b) {
                        Some(cost) => local.push_priced(&mut queue, a, b, cost, None),
                        None => local.push(&mut queue, a, b),
                    }
                }
            }
        }
    }
    let mut collapses = 0;
    while let Some(Reverse((cost, _, a, b, slot))) = queue.heap.pop() {
        queue.free.push(slot);
        let (ua, ub) = (a as usize, b as usize);
        let priced = &queue.priced[slot as usize];
        if !local.alive_vertex[ua] || !local.alive_vertex[ub] || [local.stamp[ua], local.stamp[ub]] != priced.stamps {
            continue;
        }
        if local.refused_before(input, a, b) && local.untouched(a, b) {
            continue;
        }
        let minimizer = priced.minimizer.unwrap_or_else(|| local.minimizer(a, b));
        if local.try_collapse(a, b, &local.candidates(a, b, minimizer), limits) {
            collapses += 1;
            for c in local.neighbours(a) {
                if local.free[c as usize] {
                    local.push(&mut queue, a.min(c), a.max(c));
                }
            }
        } else if local.refusal_kept && local.untouched(a, b) {
            local.refused.push(((local.global[ua], local.global[ub]), cost));
        }
    }
    (local, collapses)
}

impl Local {
    fn new(input: &BlockInput, test: ClashTest) -> Self {
        let given = input.own.len() + input.halo.len();
        // A closed mesh has about half as many vertices as faces.
        let (vertices, faces) = (given / 2 + 16, FACES_GROWN * given);
        let mut map: FxHashMap<u32, u32> = FxHashMap::with_capacity_and_hasher(vertices, Default::default());
        let mut local = Local {
            global: Vec::with_capacity(vertices),
            position: Vec::with_capacity(vertices),
            quadric: Vec::with_capacity(vertices),
            bound: Vec::with_capacity(vertices),
            free: Vec::with_capacity(vertices),
            interior: Vec::with_capacity(vertices),
            alive_vertex: Vec::with_capacity(vertices),
            stamp: Vec::with_capacity(vertices),
            mark: Vec::with_capacity(vertices),
            tick: 0,
            incident: Vec::with_capacity(vertices),
            faces: Vec::with_capacity(faces),
            cone: Vec::with_capacity(faces),
            alive: Vec::with_capacity(faces),
            own: Vec::with_capacity(faces),
            seen: Vec::with_capacity(faces),
            query: 0,
            test,
            refusal_kept: false,
            refused: Vec::new(),
            min: input.min,
            max: input.max,
        };
        for (&f, own) in input.own.iter().map(|f| (f, true)).chain(input.halo.iter().map(|f| (f, false))) {
            let face = input.faces[f as usize].map(|g| {
                *map.entry(g).or_insert_with(|| {
                    let p = input.positions[g as usize];
                    local.global.push(g);
                    local.position.push(p);
                    local.quadric.push(input.quadrics[g as usize]);
                    local.bound.push(input.bounds[g as usize]);
                    local.free.push(true);
                    local.interior.push(p.cmpgt(input.min).all() && p.cmplt(input.max).all());
                    local.alive_vertex.push(true);
                    local.stamp.push(0);
                    local.mark.push(0);
                    local.incident.push(SmallVec::new());
                    (local.global.len() - 1) as u32
                })
            });
            if !own {
                for v in face {
                    local.free[v as usize] = false;
                }
            }
            local.add_face(face, own, input.cones[f as usize]);
        }
        local
    }

    fn add_face(&mut self, face: [u32; 3], own: bool, cone: Cone) -> u32 {
        let id = self.faces.len() as u32;
        self.faces.push(face);
        self.cone.push(cone);
        self.alive.push(true);
        self.own.push(own);
        self.seen.push(0);
        for v in face {
            self.incident[v as usize].push(id);
        }
        if let ClashTest::Watched { grid, .. } = &mut self.test {
            grid.insert(id, grid.cells_of(face.map(|v| self.position[v as usize])));
        }
        id
    }

    /// The vertices sharing a face with `a`, once each, marked with a new
    /// [`Local::mark`] (in no set order: the heap orders the edges pushed from them by
    /// their keys alone, which no two entries share).
    fn neighbours(&mut self, a: u32) -> SmallVec<[u32; 16]> {
        self.tick += 1;
        let mut out = SmallVec::new();
        for &f in &self.incident[a as usize] {
            for v in self.faces[f as usize] {
                if v != a && self.mark[v as usize] != self.tick {
                    self.mark[v as usize] = self.tick;
                    out.push(v);
                }
            }
        }
        out
    }

    /// How many vertices share a face with both `a` and `b`.
    fn common_neighbours(&mut self, a: u32, b: u32) -> usize {
        self.neighbours(a);
        let (was, tick) = (self.tick, self.tick + 1);
        self.tick = tick;
        let mut common = 0;
        for &f in &self.incident[b as usize] {
            for v in self.faces[f as usize] {
                if v != b && self.mark[v as usize] == was {
                    self.mark[v as usize] = tick;
                    common += 1;
                }
            }
        }
        common
    }

    /// Whether edge `a b` (local, as tried) was refused in an earlier round on its
    /// neighbourhood alone and no vertex of its neighbourhood now (its ends and their
    /// neighbours) has moved in a round since: with [`Local::untouched`], every face
    /// around either end is as it was then (a collapse that changed one left its kept
    /// vertex, moved, among them), so it would be refused again.
    fn refused_before(&self, input: &BlockInput, a: u32, b: u32) -> bool {
        let Some(&(round, _)) = input.refused.get(&(self.global[a as usize], self.global[b as usize])) else {
            return false;
        };
        let unmoved = |v: u32| input.moved_in[self.global[v as usize] as usize] < round;
        self.around(a, b, unmoved)
    }

    /// Whether `keep` holds for `a`, `b` and every vertex sharing a face with either
    /// (their neighbourhood), read off their faces without listing it.
    fn around(&self, a: u32, b: u32, keep: impl Fn(u32) -> bool) -> bool {
        [a, b].iter().all(|&v| self.incident[v as usize].iter().all(|&f| self.faces[f as usize].into_iter().all(&keep)))
            && keep(a)
            && keep(b)
    }

    /// The cost of edge `a b` (local, as tried, both unmoved in this block) when it
    /// was refused in an earlier round and neither end has moved since.
    fn cost_before(&self, input: &BlockInput, a: u32, b: u32) -> Option<u64> {
        let (ga, gb) = (self.global[a as usize], self.global[b as usize]);
        let &(round, cost) = input.refused.get(&(ga, gb))?;
        (input.moved_in[ga as usize] < round && input.moved_in[gb as usize] < round).then_some(cost)
    }

    /// Whether no collapse of this block has touched the neighbourhood of `a b` (its
    /// ends and their neighbours): it is then the snapshot's.
    fn untouched(&self, a: u32, b: u32) -> bool {
        self.around(a, b, |v| self.stamp[v as usize] == 0)
    }

    /// The quadric minimiser of edge `a b` (the first candidate point), nearest the
    /// midpoint.
    fn minimizer(&self, a: u32, b: u32) -> DVec3 {
        let (pa, pb) = (self.position[a as usize], self.position[b as usize]);
        (self.quadric[a as usize] + self.quadric[b as usize]).minimizer((pa + pb) * 0.5)
    }

    /// The candidate points of edge `a b` and their quadric costs in the order
    /// minimiser, `a`, `b`, midpoint, given its minimiser.
    fn costs(&self, a: u32, b: u32, minimizer: DVec3) -> Candidates {
        let (pa, pb) = (self.position[a as usize], self.position[b as usize]);
        let q = self.quadric[a as usize] + self.quadric[b as usize];
        let mid = (pa + pb) * 0.5;
        [minimizer, pa, pb, mid].map(|p| (q.eval(p), p))
    }

    /// The candidate points of edge `a b` and their quadric costs, cheapest first
    /// (ties in the order minimiser, `a`, `b`, midpoint), given its minimiser.
    fn candidates(&self, a: u32, b: u32, minimizer: DVec3) -> Candidates {
        let mut c = self.costs(a, b, minimizer);
        c.sort_by(|x, y| x.0.total_cmp(&y.0));
        c
    }

    /// Queues edge `a b` at its cost, its cheapest candidate's (the least in the
    /// order the candidates are sorted by, so the same bits), with its minimiser.
    fn push(&self, queue: &mut Queue, a: u32, b: u32) {
        let minimizer = self.minimizer(a, b);
        let costs = self.costs(a, b, minimizer).map(|(cost, _)| cost);
        let cost = costs.into_iter().min_by(f64::total_cmp).unwrap_or(f64::INFINITY);
        self.push_priced(queue, a, b, cost.to_bits(), Some(minimizer));
    }

    /// Queues edge `a b` at the cost `cost` (bits), with its minimiser if known.
    fn push_priced(&self, queue: &mut Queue, a: u32, b: u32, cost: u64, minimizer: Option<DVec3>) {
        let length = (self.position[a as usize] - self.position[b as usize]).length_squared();
        let stamps = [self.stamp[a as usize], self.stamp[b as usize]];
        queue.push(cost, length, a, b, Priced { stamps, minimizer });
    }

    /// Collapses `a b` into `a` at the cheapest candidate that passes every check.
    /// A refusal says in [`Local::refusal_kept`] whether it is the neighbourhood's alone.
    fn try_collapse(&mut self, a: u32, b: u32, candidates: &Candidates, limits: &Limits) -> bool {
        let (ua, ub) = (a as usize, b as usize);
        self.refusal_kept = false;
        if !self.free[ua] || !self.free[ub] {
            return false;
        }
        self.refusal_kept = true;
        // The region: faces around a or b; exactly two hold both.
        let mut region: SmallVec<[u32; 24]> = self.incident[ua].iter().chain(&self.incident[ub]).copied().collect();
        region.sort_unstable();
        region.dedup();
        let both: SmallVec<[u32; 2]> = region
            .iter()
            .copied()
            .filter(|&f| {
                let t = self.faces[f as usize];
                t.contains(&a) && t.contains(&b)
            })
            .collect();
        if both.len() != 2 {
            return false;
        }
        let apex = |f: u32| self.faces[f as usize].into_iter().find(|&v| v != a && v != b).unwrap_or(a);
        let mut apexes = [apex(both[0]), apex(both[1])];
        apexes.sort_unstable();
        if apexes[0] == apexes[1] {
            return false;
        }
        // Link condition: the links of a and b share exactly the two apexes.
        if self.common_neighbours(a, b) != 2 {
            return false;
        }
        // The fan: every other face of the region with b renamed a.
        let mut fan: SmallVec<[([u32; 3], u32); 24]> = SmallVec::new();
        for &f in &region {
            if both.contains(&f) {
                continue;
            }
            fan.push((self.faces[f as usize].map(|v| if v == b { a } else { v }), f));
        }
        let mut keys: SmallVec<[[u32; 3]; 24]> = fan
            .iter()
            .map(|(t, _)| {
                let mut k = *t;
                k.sort_unstable();
                k
            })
            .collect();
        keys.sort_unstable();
        if keys.windows(2).any(|w| w[0] == w[1]) {
            return false;
        }
        let link_inside = fan.iter().all(|(t, _)| t.iter().all(|&v| v == a || self.interior[v as usize]));
        if !link_inside {
            self.refusal_kept = false;
            return false;
        }
        let old: SmallVec<[[DVec3; 3]; 24]> = region.iter().map(|&f| self.corners(self.faces[f as usize])).collect();
        let old_bounds: SmallVec<[[f64; 3]; 24]> =
            region.iter().map(|&f| self.faces[f as usize].map(|v| self.bound[v as usize])).collect();
        let new_bounds: SmallVec<[[f64; 3]; 24]> =
            fan.iter().map(|(t, _)| t.map(|v| if v == a { 0.0 } else { self.bound[v as usize] })).collect();
        // The normal bounds' projection, as `vertex_bound` takes it.
        let (old_cones, direction): (SmallVec<[Cone; 24]>, _) = match limits.max_turn {
            Some(_) => (
                region.iter().map(|&f| self.cone[f as usize]).collect(),
                old.iter().map(|t| (t[1] - t[0]).cross(t[2] - t[0])).sum::<DVec3>().try_normalize(),
            ),
            None => (SmallVec::new(), None),
        };
        // The replaced faces' normals (times twice their areas) and their lengths, for
        // the fan's faces in order.
        let was: SmallVec<[(DVec3, f64); 24]> = fan
            .iter()
            .map(|(_, f)| {
                let before = self.corners(self.faces[*f as usize]);
                let was = (before[1] - before[0]).cross(before[2] - before[0]);
                (was, was.length())
            })
            .collect();
        for (i, &(_, x)) in candidates.iter().enumerate() {
            if candidates[..i].iter().any(|&(_, y)| y == x) {
                continue;
            }
            if !(x.cmpgt(self.min).all() && x.cmplt(self.max).all()) {
                self.refusal_kept = false;
                continue;
            }
            let at = |v: u32| if v == a { x } else { self.position[v as usize] };
            let new: SmallVec<[[DVec3; 3]; 24]> = fan.iter().map(|(t, _)| t.map(at)).collect();
            let shapes_ok = was.iter().zip(&new).all(|(&(was, was_length), n)| {
                let normal = (n[1] - n[0]).cross(n[2] - n[0]);
                let longest = (n[1] - n[0])
                    .length_squared()
                    .max((n[2] - n[1]).length_squared())
                    .max((n[0] - n[2]).length_squared());
                normal.length() > 1e-9 * longest
                    && normal.dot(was) >= limits.min_normal_cosine * normal.length() * was_length
            });
            if !shapes_ok {
                continue;
            }
            let patches = Patches {
                old: &old,
                old_bounds: &old_bounds,
                new: &new,
                new_bounds: &new_bounds,
                old_inside: [self.position[ua], self.position[ub]],
                new_inside: x,
            };
            let Some(bound) = vertex_bound(&patches, limits.tolerance) else {
                continue;
            };
            if bound > limits.tolerance {
                continue;
            }
            // The projection `vertex_bound` used (it refused the collapse without one).
            let cones = match (limits.max_turn, direction) {
                (Some(limit), Some(direction)) => {
                    let Some(cones) = fan_cones(&old, &old_cones, &new, direction, limit) else {
                        continue;
                    };
                    cones
                }
                _ => SmallVec::from_elem(Cone::default(), fan.len()),
            };
            if self.clashes(&new, &region) {
                self.refusal_kept = false;
                continue;
            }
            self.apply(a, b, x, &fan, &cones, &region, bound);
            return true;
        }
        false
    }

    fn corners(&self, t: [u32; 3]) -> [DVec3; 3] {
        t.map(|v| self.position[v as usize])
    }

    /// Whether a triangle of `fan` clashes with a live face near it outside
    /// `region`, tested when the fan's box meets a watched cell (else false). The
    /// cells under the fan's box are read once, their dead faces dropped as they are
    /// read.
    fn clashes(&mut self, fan: &[[DVec3; 3]], region: &[u32]) -> bool {
        let ClashTest::Watched { cells: watched, grid } = &mut self.test else {
            return false;
        };
        let boxes: SmallVec<[(DVec3, DVec3); 24]> =
            fan.iter().map(|t| (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))).collect();
        let (lo, hi) = boxes.iter().fold((DVec3::INFINITY, DVec3::NEG_INFINITY), |(l, h), b| (l.min(b.0), h.max(b.1)));
        let cells: SmallVec<[usize; 16]> = grid.cells(grid.cells_between(lo, hi)).collect();
        if !cells.iter().any(|&cell| watched[cell]) {
            return false;
        }
        self.query += 1;
        for cell in cells {
            let mut ids = std::mem::take(&mut grid.lists[cell]);
            ids.retain(|&f| self.alive[f as usize]);
            let mut clash = false;
            for &f in &ids {
                let fi = f as usize;
                if clash || self.seen[fi] == self.query {
                    continue;
                }
                self.seen[fi] = self.query;
                let other = self.faces[fi].map(|v| self.position[v as usize]);
                let (olo, ohi) = (other[0].min(other[1]).min(other[2]), other[0].max(other[1]).max(other[2]));
                if !(lo.cmple(ohi).all() && olo.cmple(hi).all()) || region.contains(&f) {
                    continue;
                }
                clash = fan
                    .iter()
                    .zip(&boxes)
                    .any(|(t, b)| b.0.cmple(ohi).all() && olo.cmple(b.1).all() && triangles_clash(*t, other));
            }
            grid.lists[cell] = ids;
            if clash {
                return true;
            }
        }
        false
    }

    #[allow(clippy::too_many_arguments)]
    fn apply(&mut self, a: u32, b: u32, x: DVec3, fan: &[([u32; 3], u32)], cones: &[Cone], region: &[u32], bound: f64) {
        // Every face around a or b goes: their lists empty, the link's lose them.
        let (ua, ub) = (a as usize, b as usize);
        for &f in region {
            self.alive[f as usize] = false;
            for v in self.faces[f as usize] {
                if v != a && v != b {
                    self.incident[v as usize].retain(|g| *g != f);
                }
            }
        }
        self.incident[ua].clear();
        self.incident[ub].clear();
        self.alive_vertex[ub] = false;
        self.position[ua] = x;
        let qb = self.quadric[ub];
        self.quadric[ua] += qb;
        self.bound[ua] = bound;
        self.stamp[ua] += 1;
        for ((t, _), &cone) in fan.iter().zip(cones) {
            self.add_face(*t, true, cone);
        }
    }

    /// The boxes of the pairs of live faces that clash, one of them made by a
    /// collapse (ids from `first_new` on); faces of the snapshot never clash with each
    /// other. The test runs on a fresh grid over the result's faces.
    fn result_clashes(&self, first_new: usize) -> Vec<(DVec3, DVec3)> {
        let live: Vec<u32> = (0..self.faces.len() as u32).filter(|&f| self.alive[f as usize]).collect();
        let corners: Vec<[DVec3; 3]> = live.iter().map(|&f| self.corners(self.faces[f as usize])).collect();
        let edges: f64 =
            corners.iter().map(|c| (c[1] - c[0]).length() + (c[2] - c[1]).length() + (c[0] - c[2]).length()).sum();
        let mut grid = FaceGrid::new(self.min, self.max, edges / (3 * live.len().max(1)) as f64);
        for (i, c) in corners.iter().enumerate() {
            grid.insert(i as u32, grid.cells_of(*c));
        }
        let boxes: Vec<(DVec3, DVec3)> =
            corners.iter().map(|t| (t[0].min(t[1]).min(t[2]), t[0].max(t[1]).max(t[2]))).collect();
        let mut seen = vec![u32::MAX; live.len()];
        let mut clashes = Vec::new();
        for (i, &f) in live.iter().enumerate() {
            if (f as usize) < first_new {
                continue;
            }
            for cell in grid.cells(grid.cells_between(boxes[i].0, boxes[i].1)) {
                for &j in &grid.lists[cell] {
                    let j = j as usize;
                    // A pair of new faces is tested once, from its later face.
                    if j == i || seen[j] == i as u32 || ((live[j] as usize) >= first_new && j > i) {
                        continue;
                    }
                    seen[j] = i as u32;
                    let (olo, ohi) = boxes[j];
                    if boxes[i].0.cmple(ohi).all()
                        && olo.cmple(boxes[i].1).all()
                        && triangles_clash(corners[i], corners[j])
                    {
                        clashes.push((boxes[i].0.min(olo), boxes[i].1.max(ohi)));
                    }
                }
            }
        }
        clashes
    }

    fn output(self, collapses: usize) -> BlockOutput {
        let mut out = BlockOutput { collapses, refused: self.refused, ..BlockOutput::default() };
        for f in 0..self.faces.len() {
            if self.alive[f] && self.own[f] {
                out.faces.push(self.faces[f].map(|v| self.global[v as usize]));
                out.cones.push(self.cone[f]);
            }
        }
        for v in 0..self.global.len() {
            if self.alive_vertex[v] && self.stamp[v] > 0 {
                out.moved.push((self.global[v], self.position[v], self.quadric[v], self.bound[v]));
            }
        }
        out
    }
}
