//! Cells merged up the lattice before simplification: the dual mesh's vertices in a
//! block of `2^k` voxel corners replaced by one where the block's surface is one flat
//! sheet (octree simplification, Ju, Losasso, Schaefer and Warren, *Dual Contouring of
//! Hermite Data*, 2002, section 4; kept manifold as Manifold Dual Contouring's vertex
//! clustering asks, Schaefer, Ju and Warren 2007, by checking the result).
//!
//! Why a pre-pass: simplifying the dual mesh of the classic part at depth 9 within a
//! tenth of a voxel took 1.6 million edge collapses, each pricing its edge by a quadric
//! (an eigen-decomposition), bounding its distance and testing its faces (`perf`: 85%
//! of the export's time, about 16 microseconds a collapse). Most of those collapses
//! happen where the surface is flat at the scale of a few voxels, which a block merge
//! decides at once; [`super::simplify`] then starts from a mesh about ten times
//! smaller.
//!
//! Blocks are tried from the largest (`2^MAX_LEVEL` corners a side) down to two a side,
//! aligned to the lattice as an octree's cells are; a block merges when every vertex
//! with its corner inside it is free (not merged in a larger block), smooth (the QEF's
//! rank 1: no crease, no corner, not clamped to its cell, its corner not shared with
//! another sheet), the vertices are connected through the mesh's edges, every face
//! around them, before the merge and after, turns from their area-weighted mean normal
//! `n` by less than the fan's bound (module `fan_cone`: twice the limit over the fan's
//! reach, the distance limit carried to the whole fan; at most 25 degrees), and every
//! vertex lies within the limit of the plane with normal `n` through the merged vertex (the paper's QEF error, here of that one plane, taken as a maximum
//! rather than a sum). That distance overestimates the error (the new faces are chords
//! between merged vertices, which pass about half as far from the surface), but
//! allowing twice the limit made the classic part's simplified mesh worse for little
//! time (RMS 0.022 voxel against 0.015 at `--tolerance 0.1`, 11.2 s of CPU against
//! 12.4). The merged vertex is the member nearest the faces' centroid, so it stays on
//! the surface (a point of the fitted plane lies inside a convex patch: on the classic
//! part that bias doubled the simplified mesh's RMS distance, 0.028 voxel against
//! 0.015), and the plane is taken through it.
//!
//! Departure from the papers: rather than deciding manifoldness from each cell's signs
//! (Manifold DC's tables), the merged mesh is checked, and blocks whose vertices take
//! part in a defect are split back to their vertices, until none is left: every edge in
//! exactly two faces run opposite ways, no two faces on the same three vertices, each
//! merged vertex's faces one fan (a disk), the Euler characteristic unchanged (so the
//! genus too, the mesh staying closed and manifold), and no face at a merged vertex
//! meeting another face beyond their shared corners (the exact test of
//! [`super::simplify`]; two faces across an edge, facing the same side, are not
//! tested: oriented, they could meet beyond it only folded flat). Before that, and
//! after each split, blocks are split back until no face between two merged blocks
//! turns more than [`FOLD_TURN`] from its dual face (`Folds`: each block's own test
//! saw its neighbours unmerged). After
//! [`MAX_CHECK_ROUNDS`] rounds, or when only the Euler characteristic fails, nothing is
//! merged. The limit is a fitted plane's, not a true
//! bound like the one [`super::simplify`] keeps: the extraction gives the merge a
//! quarter of the tolerance and simplification the rest, and the tests measure the
//! result against the exact surface.

use glam::{DVec2, DVec3};
use rayon::prelude::*;
use rustc_hash::{FxHashMap, FxHashSet};
use smallvec::SmallVec;

use super::dual::{DualMesh, Fans, VertexKind};
use super::fan_cone::fan_within_cone;
use super::simplify::{DEGENERATE_AREA, triangles_clash};

/// Largest block merged: `2^MAX_LEVEL` voxel corners a side.
const MAX_LEVEL: u32 = 4;
/// Rounds of checking and splitting blocks back before giving up on merging.
const MAX_CHECK_ROUNDS: usize = 6;
/// Side of the grid cells the clash test sorts faces into, lattice units.
const CLASH_CELL: f64 = 4.0;
/// A face between merged blocks turned farther than this from its dual face is
/// folded (module doc), radians (60 degrees).
const FOLD_TURN: f64 = 60.0 * std::f64::consts::PI / 180.0;

/// What [`merge_cells`] did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct MergeReport {
    /// Blocks merged into one vertex each.
    pub blocks: usize,
    /// Vertices those blocks held.
    pub merged_vertices: usize,
    /// The largest distance of a merged vertex's original from its block's plane,
    /// lattice units (at most the limit).
    pub max_plane_distance: f64,
}

/// A candidate block: its vertices, its merged point and plane distance.
struct Block {
    members: Vec<u32>,
    point: DVec3,
    distance: f64,
}

/// The dual mesh (`dual.positions`, lattice units, and `triangles`) with flat blocks
/// of cells merged (module doc), each block's distance to its plane at most `limit`
/// lattice units. Returns the positions and triangles (vertices kept in their order,
/// a block's at its first vertex's place) and what was merged.
pub(crate) fn merge_cells(
    dual: &DualMesh,
    triangles: &[[u32; 3]],
    limit: f64,
) -> (Vec<DVec3>, Vec<[u32; 3]>, MergeReport) {
    let unchanged = || (dual.positions.clone(), triangles.to_vec(), MergeReport::default());
    let n = dual.positions.len();
    if n == 0 || limit <= 0.0 {
        return unchanged();
    }
    let fans = Fans::of(n, triangles);
    let (normals, areas): (Vec<DVec3>, Vec<f64>) = triangles
        .par_iter()
        .with_min_len(4096)
        .map(|t| {
            let [a, b, c] = t.map(|v| dual.positions[v as usize]);
            let cross = (b - a).cross(c - a);
            let twice = cross.length();
            if twice > 0.0 { (cross / twice, twice / 2.0) } else { (DVec3::ZERO, 0.0) }
        })
        .unzip();
    let eligible: Vec<bool> = (0..n)
        .into_par_iter()
        .with_min_len(4096)
        .map(|v| {
            let shared = (v > 0 && dual.corners[v - 1] == dual.corners[v])
                || (v + 1 < n && dual.corners[v + 1] == dual.corners[v]);
            dual.kinds[v] == VertexKind::Smooth && !dual.clamped[v] && !shared
        })
        .collect();
    // Each vertex's block (index into `blocks`), largest blocks first.
    let mut block_of: Vec<u32> = vec![u32::MAX; n];
    let mut blocks: Vec<Block> = Vec::new();
    for level in (1..=MAX_LEVEL).rev() {
        let mut keyed: Vec<([u32; 3], u32)> = (0..n as u32)
            .into_par_iter()
            .with_min_len(4096)
            .map(|v| (dual.corners[v as usize].map(|c| c >> level), v))
            .collect();
        keyed.par_sort_unstable();
        let mut runs: Vec<(usize, usize)> = Vec::new();
        let mut start = 0;
        for i in 1..=keyed.len() {
            if i == keyed.len() || keyed[i].0 != keyed[start].0 {
                runs.push((start, i));
                start = i;
            }
        }
        let context = Context { dual, fans: &fans, normals: &normals, areas: &areas, triangles, limit };
        let found: Vec<Option<Block>> = runs
            .par_iter()
            .with_min_len(64)
            .map(|&(s, e)| {
                let members: Vec<u32> = keyed[s..e].iter().map(|k| k.1).collect();
                if members.iter().any(|&v| !eligible[v as usize] || block_of[v as usize] != u32::MAX) {
                    return None;
                }
                context.block(members)
            })
            .collect();
        for block in found.into_iter().flatten() {
            for &v in &block.members {
                block_of[v as usize] = blocks.len() as u32;
            }
            blocks.push(block);
        }
    }
    let euler = n as i64 - triangles.len() as i64 / 2;
    let mut alive = vec![true; blocks.len()];
    let folds = Folds { dual, triangles, fans: &fans, normals: &normals, blocks: &blocks, block_of: &block_of };
    let folded: Vec<u32> =
        (0..triangles.len() as u32).into_par_iter().with_min_len(4096).filter(|&f| folds.folded(f, &alive)).collect();
    folds.split(&mut alive, folded);
    // The blocks alive when the faces were last tested for clashes (none yet).
    let mut tested: Option<Vec<bool>> = None;
    for _ in 0..MAX_CHECK_ROUNDS {
        let merged = apply(dual, triangles, &blocks, &block_of, &alive, tested.as_deref());
        let Some(Defects { blocks: bad, clashes_tested }) = defects(&merged) else { return unchanged() };
        if clashes_tested {
            tested = Some(alive.clone());
        }
        if bad.is_empty() {
            let euler_after = merged.positions.len() as i64 - merged.triangles.len() as i64 / 2;
            if euler_after != euler {
                return unchanged();
            }
            let live = blocks.iter().zip(&alive).filter(|(_, a)| **a);
            let report = live.fold(MergeReport::default(), |r, (b, _)| MergeReport {
                blocks: r.blocks + 1,
                merged_vertices: r.merged_vertices + b.members.len(),
                max_plane_distance: r.max_plane_distance.max(b.distance),
            });
            return (merged.positions, merged.triangles, report);
        }
        let mut around = Vec::new();
        for b in bad {
            alive[b as usize] = false;
            for &v in &blocks[b as usize].members {
                around.extend_from_slice(fans.of_vertex(v as usize));
            }
        }
        folds.split(&mut alive, around);
    }
    unchanged()
}

/// What deciding a block reads.
struct Context<'a> {
    dual: &'a DualMesh,
    fans: &'a Fans,
    normals: &'a [DVec3],
    areas: &'a [f64],
    triangles: &'a [[u32; 3]],
    limit: f64,
}

impl Context<'_> {
    /// The block of `members` (ascending), if it merges.
    fn block(&self, members: Vec<u32>) -> Option<Block> {
        if members.len() < 2 {
            return None;
        }
        let mut faces: Vec<u32> =
            members.iter().flat_map(|&v| self.fans.of_vertex(v as usize).iter().copied()).collect();
        faces.sort_unstable();
        faces.dedup();
        let (mut normal, mut area, mut centre) = (DVec3::ZERO, 0.0, DVec3::ZERO);
        for &f in &faces {
            let w = self.areas[f as usize];
            let t = self.triangles[f as usize].map(|v| self.dual.positions[v as usize]);
            normal += self.normals[f as usize] * w;
            centre += (t[0] + t[1] + t[2]) * (w / 3.0);
            area += w;
        }
        let normal = normal.try_normalize()?;
        if area <= 0.0 {
            return None;
        }
        let centre = centre / area;
        let position = |v: u32| self.dual.positions[v as usize];
        // The member nearest the faces' centroid: on the surface, where a point of the
        // fitted plane would sit inside a convex patch and outside a concave one.
        let nearest = members.iter().copied().min_by(|&u, &v| {
            (position(u) - centre).length_squared().total_cmp(&(position(v) - centre).length_squared())
        })?;
        let point = position(nearest);
        let face = |f: &u32| {
            let t = self.triangles[*f as usize];
            (self.normals[*f as usize], t.map(position), t.map(|v| members.binary_search(&v).is_ok()))
        };
        if !fan_within_cone(normal, point, faces.iter().map(face), self.limit) {
            return None;
        }
        let distance = members.iter().map(|&v| normal.dot(position(v) - point).abs()).fold(0.0, f64::max);
        if distance > self.limit {
            return None;
        }
        self.connected(&members).then_some(Block { members, point, distance })
    }

    /// Whether `members` (ascending) are connected through the mesh's edges.
    fn connected(&self, members: &[u32]) -> bool {
        let mut reached = vec![false; members.len()];
        let mut stack = vec![0usize];
        reached[0] = true;
        let mut count = 1;
        while let Some(i) = stack.pop() {
            for &f in self.fans.of_vertex(members[i] as usize) {
                for w in self.triangles[f as usize] {
                    if let Ok(j) = members.binary_search(&w)
                        && !reached[j]
                    {
                        reached[j] = true;
                        count += 1;
                        stack.push(j);
                    }
                }
            }
        }
        count == members.len()
    }
}

/// Faces between merged blocks that fold. Each block checked its fan with its
/// neighbours' corners where they were (module `fan_cone`); once two neighbours have
/// merged, a face between them has moved at two corners, and a thin one can turn over
/// (a sphere of 49 voxels at `--tolerance 1`: 19 faces of the simplified mesh 90 to
/// 169 degrees off the sphere's normal, before this test). Splitting a block back
/// brings back faces its merge had collapsed, which can fold between other blocks, so
/// the blocks are split back from a work list of faces until none folds (checking
/// the merged mesh instead, one split a round, carried a fold across the classic
/// part for more rounds than the merge allows).
struct Folds<'a> {
    dual: &'a DualMesh,
    triangles: &'a [[u32; 3]],
    fans: &'a Fans,
    /// The dual faces' unit normals (zero for a face without area).
    normals: &'a [DVec3],
    blocks: &'a [Block],
    block_of: &'a [u32],
}

impl Folds<'_> {
    /// Whether dual face `f`, with corners in two or three `alive` blocks taken to
    /// their merged points, turns more than [`FOLD_TURN`] from its own normal.
    fn folded(&self, f: u32, alive: &[bool]) -> bool {
        let t = self.triangles[f as usize];
        let owner = |v: u32| {
            let b = self.block_of[v as usize];
            (b != u32::MAX && alive[b as usize]).then_some(b)
        };
        let owners = t.map(owner);
        let merged = owners.iter().flatten().count();
        let collapsed = (0..3).any(|k| owners[k].is_some() && owners[k] == owners[(k + 1) % 3]);
        if merged < 2 || collapsed || self.normals[f as usize] == DVec3::ZERO {
            return false;
        }
        let corner = |k: usize| owners[k].map_or(self.dual.positions[t[k] as usize], |b| self.blocks[b as usize].point);
        let cross = (corner(1) - corner(0)).cross(corner(2) - corner(0));
        cross.dot(self.normals[f as usize]) < FOLD_TURN.cos() * cross.length()
    }

    /// Splits back the blocks at the corners of the folded faces among `faces`, then
    /// of the faces that moves, until none folds. Sequential, in list order: the same
    /// blocks for any number of threads.
    fn split(&self, alive: &mut [bool], mut faces: Vec<u32>) {
        while let Some(f) = faces.pop() {
            if !self.folded(f, alive) {
                continue;
            }
            for v in self.triangles[f as usize] {
                let b = self.block_of[v as usize];
                if b != u32::MAX && alive[b as usize] {
                    alive[b as usize] = false;
                    for &m in &self.blocks[b as usize].members {
                        faces.extend_from_slice(self.fans.of_vertex(m as usize));
                    }
                }
            }
        }
    }
}

/// The dual mesh with some blocks merged.
struct Merged {
    positions: Vec<DVec3>,
    triangles: Vec<[u32; 3]>,
    /// Each vertex's block, `u32::MAX` for a vertex not merged.
    origin: Vec<u32>,
    /// Each vertex's freshness: split back from a block that was merged when the faces
    /// were last tested for clashes (`None`: never tested, every vertex fresh).
    fresh: Option<Vec<bool>>,
}

/// What [`defects`] found.
struct Defects {
    /// The blocks to split back, ascending.
    blocks: Vec<u32>,
    /// Whether the faces were tested for clashes (the topology being sound).
    clashes_tested: bool,
}

/// The merged mesh, with the `alive` blocks merged; `tested`, the blocks alive when
/// the faces were last tested for clashes, says which vertices are fresh.
fn apply(
    dual: &DualMesh,
    triangles: &[[u32; 3]],
    blocks: &[Block],
    block_of: &[u32],
    alive: &[bool],
    tested: Option<&[bool]>,
) -> Merged {
    let n = dual.positions.len();
    let live_block = |v: usize| {
        let b = block_of[v];
        (b != u32::MAX && alive[b as usize]).then_some(b as usize)
    };
    // New index of each old vertex; a block's vertices all take its first one's.
    let mut index = vec![u32::MAX; n];
    let mut positions = Vec::with_capacity(n);
    let mut origin = Vec::with_capacity(n);
    for v in 0..n {
        match live_block(v) {
            Some(b) if blocks[b].members[0] as usize != v => {}
            Some(b) => {
                index[v] = positions.len() as u32;
                positions.push(blocks[b].point);
                origin.push(block_of[v]);
            }
            None => {
                index[v] = positions.len() as u32;
                positions.push(dual.positions[v]);
                origin.push(u32::MAX);
            }
        }
    }
    for v in 0..n {
        if let Some(b) = live_block(v) {
            index[v] = index[blocks[b].members[0] as usize];
        }
    }
    let merged: Vec<[u32; 3]> = triangles
        .par_iter()
        .with_min_len(4096)
        .map(|t| t.map(|v| index[v as usize]))
        .filter(|t| t[0] != t[1] && t[1] != t[2] && t[2] != t[0])
        .collect();
    let fresh = tested.map(|tested| {
        let mut fresh = vec![false; positions.len()];
        for v in 0..n {
            let b = block_of[v];
            if b != u32::MAX && !alive[b as usize] && tested[b as usize] {
                fresh[index[v] as usize] = true;
            }
        }
        fresh
    });
    Merged { positions, triangles: merged, origin, fresh }
}

/// The blocks whose merged vertices take part in a defect of the merged mesh (module
/// doc): none when it has none, `None` when a defect touches no merged vertex.
///
/// After a full test (`fresh` given) only the faces at a fresh vertex are looked at:
/// blocks have only been split back since, and every defect the last test found had a
/// merged vertex, so its faces are at fresh vertices now; a face with no fresh vertex is
/// a face of that test, and an edge none of whose faces changed has the faces it had.
fn defects(merged: &Merged) -> Option<Defects> {
    let Merged { positions, triangles, origin, fresh } = merged;
    let mut bad: Vec<u32> = Vec::new();
    let blame = |vs: &[u32], bad: &mut Vec<u32>| {
        for &v in vs {
            if origin[v as usize] != u32::MAX {
                bad.push(origin[v as usize]);
            }
        }
    };
    let fans = Fans::of(positions.len(), triangles);
    // The faces looked at: those at a fresh vertex, or all.
    let changed: Option<Vec<u32>> = fresh.as_ref().map(|fresh| {
        (0..triangles.len() as u32)
            .into_par_iter()
            .with_min_len(4096)
            .filter(|&f| triangles[f as usize].iter().any(|&v| fresh[v as usize]))
            .collect()
    });
    let all: Vec<u32>;
    let looked_at = match &changed {
        Some(changed) => changed,
        None => {
            all = (0..triangles.len() as u32).collect();
            &all
        }
    };
    let defect = topology_defects(triangles, &fans, looked_at, &mut |vs| blame(vs, &mut bad));
    if defect {
        bad.sort_unstable();
        bad.dedup();
        return (!bad.is_empty()).then_some(Defects { blocks: bad, clashes_tested: false });
    }
    // Each merged vertex's faces one fan: following each face's next corner around it
    // comes back after visiting them all (after a full test, those at a face looked at).
    let at_changed: Option<Vec<bool>> = changed.as_ref().map(|changed| {
        let mut at = vec![false; positions.len()];
        for &f in changed {
            for v in triangles[f as usize] {
                at[v as usize] = true;
            }
        }
        at
    });
    let pinched: Vec<u32> = (0..positions.len() as u32)
        .into_par_iter()
        .with_min_len(4096)
        .filter(|&v| origin[v as usize] != u32::MAX && at_changed.as_ref().is_none_or(|at| at[v as usize]))
        .filter(|&v| {
            let fan = fans.of_vertex(v as usize);
            let next: FxHashMap<u32, u32> = fan
                .iter()
                .map(|&f| {
                    let t = triangles[f as usize];
                    let k = t.iter().position(|&w| w == v).unwrap_or(0);
                    (t[(k + 1) % 3], t[(k + 2) % 3])
                })
                .collect();
            let Some((&first, _)) = next.iter().min() else { return true };
            let (mut at, mut steps) = (first, 0);
            loop {
                at = next.get(&at).copied().unwrap_or(first);
                steps += 1;
                if at == first || steps > fan.len() {
                    break;
                }
            }
            steps != fan.len() || next.len() != fan.len()
        })
        .collect();
    bad.extend(pinched.iter().map(|&v| origin[v as usize]));
    // Faces at merged vertices against faces near them.
    for (f, g) in clashing_pairs(positions, triangles, &fans, origin, fresh.as_deref()) {
        blame(&triangles[f as usize], &mut bad);
        blame(&triangles[g as usize], &mut bad);
    }
    bad.sort_unstable();
    bad.dedup();
    Some(Defects { blocks: bad, clashes_tested: true })
}

/// Whether a face of `changed` has the same three vertices as another face, or an
/// edge not in exactly two faces run opposite ways, read off the fans of its corners;
/// `blame` is given the corners of every face of each defect.
fn topology_defects(triangles: &[[u32; 3]], fans: &Fans, changed: &[u32], blame: &mut impl FnMut(&[u32])) -> bool {
    let sorted = |t: [u32; 3]| {
        let mut k = t;
        k.sort_unstable();
        k
    };
    let found: Vec<[u32; 3]> = changed
        .par_iter()
        .with_min_len(1024)
        .flat_map_iter(|&f| {
            let t = triangles[f as usize];
            let mut found: Vec<[u32; 3]> = Vec::new();
            let key = sorted(t);
            if fans.of_vertex(t[0] as usize).iter().any(|&g| g != f && sorted(triangles[g as usize]) == key) {
                found.push(key);
            }
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let on_edge: SmallVec<[u32; 4]> = fans
                    .of_vertex(a as usize)
                    .iter()
                    .copied()
                    .filter(|&g| triangles[g as usize].contains(&b))
                    .collect();
                let forward = |g: u32| {
                    let u = triangles[g as usize];
                    (0..3).any(|i| u[i] == a && u[(i + 1) % 3] == b)
                };
                if on_edge.len() != 2 || forward(on_edge[0]) == forward(on_edge[1]) {
                    found.extend(on_edge.iter().map(|&g| triangles[g as usize]));
                }
            }
            found
        })
        .collect();
    for corners in &found {
        blame(corners);
    }
    !found.is_empty()
}

/// The pairs of faces that meet beyond what they share (the exact test of
/// [`faces_cross`], faces across an edge facing the same side left out), among the
/// pairs **due**: one face at a merged vertex (`origin` not `u32::MAX`) and one fresh
/// (at a `fresh` vertex; every face when `fresh` is `None`). Each pair is tested once.
///
/// Why only fresh pairs: between two tests, blocks are only split back, so a face
/// with no fresh vertex is a face of the last test, at the same points and on the
/// same vertices; two such faces, one at a merged vertex, were tested then (or, not
/// due then, at an earlier test) and did not clash, else the blocks at both would
/// have been split back and neither would be at a merged vertex now.
///
/// Broad phase: a grid of cells [`CLASH_CELL`] a side, each face listed in every cell
/// its box meets (sorted by cell, so the lists are slices of one array). A pair whose
/// boxes meet is tested only in the cell holding the low corner of their boxes'
/// intersection, so faces sharing several cells are tested once; each cell's faces
/// are one run of the sorted list, its pairs taken within the run. Faces at a merged
/// vertex and fresh look for every other face (of two such, the lower looks for the
/// higher); fresh faces not at a merged vertex look for faces at one that are not
/// fresh.
///
/// Narrow phase: two faces of one fan (sharing one vertex, no other corner by
/// position) are not tested when the fan is a height field (`flat_fans`); the other
/// pairs go to the exact test. On the classic part at depth 9 that leaves 0.9 of the
/// first test's 5.2 million pairs.
fn clashing_pairs(
    positions: &[DVec3],
    triangles: &[[u32; 3]],
    fans: &Fans,
    origin: &[u32],
    fresh: Option<&[bool]>,
) -> Vec<(u32, u32)> {
    let corners = |f: u32| triangles[f as usize].map(|v| positions[v as usize]);
    let flat = flat_fans(positions, triangles, fans);
    // Whether faces `f` and `g` share one vertex, by index, whose fan is flat, and no
    // other corner, not even by position: they then meet there alone.
    let apart_in_a_flat_fan = |f: [u32; 3], p: [DVec3; 3], g: [u32; 3], q: [DVec3; 3]| {
        let mut shared = None;
        for i in 0..3 {
            for j in 0..3 {
                if p[i] == q[j] || f[i] == g[j] {
                    if shared.is_some() || f[i] != g[j] {
                        return false;
                    }
                    shared = Some(f[i]);
                }
            }
        }
        shared.is_some_and(|v| flat[v as usize])
    };
    // Per face: at a merged vertex, and fresh.
    let (merged, new): (Vec<bool>, Vec<bool>) = triangles
        .par_iter()
        .with_min_len(4096)
        .map(|t| {
            let merged = t.iter().any(|&v| origin[v as usize] != u32::MAX);
            (merged, fresh.is_none_or(|fresh| t.iter().any(|&v| fresh[v as usize])))
        })
        .unzip();
    let boxes: Vec<(DVec3, DVec3)> = (0..triangles.len() as u32)
        .into_par_iter()
        .with_min_len(4096)
        .map(|f| {
            let p = corners(f);
            (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]))
        })
        .collect();
    let cell_range = |(lo, hi): (DVec3, DVec3)| {
        let lo = (lo / CLASH_CELL).floor();
        let hi = (hi / CLASH_CELL).floor();
        ([lo.x as i64, lo.y as i64, lo.z as i64], [hi.x as i64, hi.y as i64, hi.z as i64])
    };
    let cells_of = |f: u32| {
        let (lo, hi) = cell_range(boxes[f as usize]);
        (lo[0]..=hi[0]).flat_map(move |x| (lo[1]..=hi[1]).flat_map(move |y| (lo[2]..=hi[2]).map(move |z| [x, y, z])))
    };
    // Every pair tested has a fresh face: after a full test only the cells those meet
    // are listed.
    let due_cells: Option<FxHashSet<[i64; 3]>> =
        fresh.map(|_| (0..triangles.len() as u32).filter(|&f| new[f as usize]).flat_map(cells_of).collect());
    let mut listed: Vec<([i64; 3], u32)> = (0..triangles.len() as u32)
        .into_par_iter()
        .with_min_len(4096)
        .flat_map_iter(|f| {
            cells_of(f).filter(|c| due_cells.as_ref().is_none_or(|due| due.contains(c))).map(move |c| (c, f))
        })
        .collect();
    listed.par_sort_unstable();
    let looks_for = |f: u32, g: u32| {
        let (f, g) = (f as usize, g as usize);
        if merged[f] { !(merged[g] && new[g] && g <= f) } else { merged[g] && !new[g] }
    };
    let low_cell: Vec<[i64; 3]> = boxes.par_iter().with_min_len(4096).map(|&b| cell_range(b).0).collect();
    // Each cell's run of `listed`, its pairs tested there.
    let mut runs: Vec<usize> = (0..listed.len()).filter(|&i| i == 0 || listed[i].0 != listed[i - 1].0).collect();
    runs.push(listed.len());
    runs.par_windows(2)
        .with_min_len(64)
        .flat_map_iter(|w| {
            let run = &listed[w[0]..w[1]];
            let cell = run[0].0;
            let mut found = Vec::new();
            for &(_, f) in run {
                if !(new[f as usize] && (merged[f as usize] || fresh.is_some())) {
                    continue;
                }
                let (plo, phi) = boxes[f as usize];
                let lo = low_cell[f as usize];
                let mut p = None;
                for &(_, g) in run {
                    if !looks_for(f, g) {
                        continue;
                    }
                    let (qlo, qhi) = boxes[g as usize];
                    if plo.cmpgt(qhi).any() || qlo.cmpgt(phi).any() {
                        continue;
                    }
                    let glo = low_cell[g as usize];
                    if cell != [lo[0].max(glo[0]), lo[1].max(glo[1]), lo[2].max(glo[2])] {
                        continue;
                    }
                    let p = *p.get_or_insert_with(|| corners(f));
                    let q = corners(g);
                    let (ft, gt) = (triangles[f as usize], triangles[g as usize]);
                    if across_an_edge(ft, p, gt, q) || apart_in_a_flat_fan(ft, p, gt, q) {
                        continue;
                    }
                    if faces_cross(ft, p, gt, q) {
                        found.push((f, g));
                    }
                }
            }
            found
        })
        .collect()
}

/// Whether each vertex's faces, seen along their summed normal, cover the plane
/// around it exactly once: every face facing that normal by [`FLAT_FAN_FACING`] (and
/// far from degenerate), their angles at the vertex summing to one turn. The faces
/// share their edges in one cycle (the mesh is checked manifold and oriented first),
/// so their projections are sectors of one turn that overlap only along shared edges:
/// two faces of the fan without a common edge meet at the vertex alone, in projection
/// and so in space (module `gap` takes a fan's projection so too).
fn flat_fans(positions: &[DVec3], triangles: &[[u32; 3]], fans: &Fans) -> Vec<bool> {
    (0..positions.len())
        .into_par_iter()
        .with_min_len(4096)
        .map(|v| {
            let fan = fans.of_vertex(v);
            let at = positions[v];
            // Each face's corners after `v`, in order, and their cross product.
            let spokes: SmallVec<[(DVec3, DVec3, DVec3); 8]> = fan
                .iter()
                .map(|&f| {
                    let t = triangles[f as usize];
                    let k = t.iter().position(|&w| w as usize == v).unwrap_or(0);
                    let (a, b) = (positions[t[(k + 1) % 3] as usize] - at, positions[t[(k + 2) % 3] as usize] - at);
                    (a, b, a.cross(b))
                })
                .collect();
            let Some(normal) = spokes.iter().map(|s| s.2).sum::<DVec3>().try_normalize() else {
                return false;
            };
            let u = normal.any_orthonormal_vector();
            let w = normal.cross(u);
            let mut turn = 0.0;
            for &(a, b, cross) in &spokes {
                if cross.dot(normal) <= FLAT_FAN_FACING * cross.length()
                    || cross.length_squared() <= DEGENERATE_AREA * a.length_squared() * b.length_squared()
                {
                    return false;
                }
                let (a2, b2) = (DVec2::new(a.dot(u), a.dot(w)), DVec2::new(b.dot(u), b.dot(w)));
                turn += a2.perp_dot(b2).atan2(a2.dot(b2));
            }
            (turn - std::f64::consts::TAU).abs() <= 1e-6
        })
        .collect()
}

/// Least cosine between a face of a flat fan and the fan's summed normal.
const FLAT_FAN_FACING: f64 = 0.2;

/// Whether two faces share an edge (by index) and face the same side: run opposite
/// ways along it (the mesh is checked oriented first), they could meet beyond it only
/// folded flat onto each other, normals opposite.
fn across_an_edge(si: [u32; 3], s: [DVec3; 3], ti: [u32; 3], t: [DVec3; 3]) -> bool {
    let shared = si.iter().filter(|v| ti.contains(v)).count();
    let normal = |p: [DVec3; 3]| (p[1] - p[0]).cross(p[2] - p[0]);
    shared == 2 && normal(s).dot(normal(t)) > 0.0
}

/// Whether two faces meet beyond what they share by index (two sheets' vertices at one
/// point are not shared: their faces must not touch).
fn faces_cross(si: [u32; 3], s: [DVec3; 3], ti: [u32; 3], t: [DVec3; 3]) -> bool {
    let shares_position_not_index = (0..3).any(|i| (0..3).any(|j| s[i] == t[j] && si[i] != ti[j]));
    shares_position_not_index || triangles_clash(s, t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan of `n` faces around a centre vertex (index 0) whose rim vertices lie at
    /// the angles `angles` (radians) on a unit circle, lifted by `lift`.
    fn fan(angles: &[f64], lift: impl Fn(DVec2) -> f64) -> (Vec<DVec3>, Vec<[u32; 3]>) {
        let mut positions = vec![DVec3::ZERO];
        for &a in angles {
            let p = DVec2::new(a.cos(), a.sin());
            positions.push(DVec3::new(p.x, p.y, lift(p)));
        }
        let n = angles.len() as u32;
        let triangles = (0..n).map(|i| [0, 1 + i, 1 + (i + 1) % n]).collect();
        (positions, triangles)
    }

    fn centre_is_flat(positions: &[DVec3], triangles: &[[u32; 3]]) -> bool {
        flat_fans(positions, triangles, &Fans::of(positions.len(), triangles))[0]
    }

    /// The corners of the faces `topology_defects` blames, sorted, looking at all faces.
    fn blamed(triangles: &[[u32; 3]]) -> Vec<u32> {
        let fans = Fans::of(5, triangles);
        let all: Vec<u32> = (0..triangles.len() as u32).collect();
        let mut corners = Vec::new();
        let defect = topology_defects(triangles, &fans, &all, &mut |vs| corners.extend_from_slice(vs));
        corners.sort_unstable();
        corners.dedup();
        assert_eq!(defect, !corners.is_empty());
        corners
    }

    #[test]
    fn topology_defects_are_duplicates_open_and_misoriented_edges() {
        let tetrahedron = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        assert!(blamed(&tetrahedron).is_empty());
        // A face twice: its edges in three faces, and the duplicate itself.
        let twice = [tetrahedron.as_slice(), &[[1, 2, 3]]].concat();
        assert_eq!(blamed(&twice), vec![0, 1, 2, 3]);
        // A face missing: its edges in one face each.
        assert_eq!(blamed(&tetrahedron[..3]), vec![0, 1, 2, 3]);
        // A face turned over: its edges run the same way as their neighbours'.
        let flipped = [[0, 2, 1], [0, 1, 3], [1, 3, 2], [0, 3, 2]];
        assert_eq!(blamed(&flipped), vec![0, 1, 2, 3]);
        // Only the faces looked at are checked.
        let fans = Fans::of(5, &tetrahedron[..3]);
        assert!(!topology_defects(&tetrahedron[..3], &fans, &[], &mut |_| {}));
    }

    #[test]
    fn a_fan_is_flat_when_it_covers_its_plane_once() {
        let six: Vec<f64> = (0..6).map(|i| f64::from(i) * std::f64::consts::TAU / 6.0).collect();
        // Gently curved, and uneven: flat.
        let (p, t) = fan(&six, |q| 0.05 * q.x * q.x - 0.03 * q.y);
        assert!(centre_is_flat(&p, &t));
        let uneven = [0.0, 0.4, 1.9, 3.0, 3.5, 5.0];
        let (p, t) = fan(&uneven, |q| 0.1 * q.x);
        assert!(centre_is_flat(&p, &t));
        // A rim vertex pulled across its neighbour: two faces overlap in projection.
        let crossed = [0.0, 1.2, 1.0, 3.0, 4.0, 5.0];
        let (p, t) = fan(&crossed, |_| 0.0);
        assert!(!centre_is_flat(&p, &t));
        // Around twice (a pinched double cover): not flat.
        let twice: Vec<f64> = (0..8).map(|i| f64::from(i) * std::f64::consts::TAU / 4.0 + 0.1).collect();
        let (p, t) = fan(&twice, |q| 0.01 * q.x);
        assert!(!centre_is_flat(&p, &t));
        // A steep saddle whose faces turn past the facing limit: not flat.
        let (p, t) = fan(&six, |q| 8.0 * (q.x * q.x - q.y * q.y));
        assert!(!centre_is_flat(&p, &t));
    }
}
