//! Untangling: the dual mesh made free of self-intersections by moving the vertices
//! of crossing triangles back towards the staircase.
//!
//! Dual contouring keeps every vertex in its cell but not every triangle clear of the
//! others: where a cell holds a crease, a thin wall or two sheets, a quad can pass
//! through its neighbours (Ju et al. 2002 leave this open; Manifold Dual Contouring
//! avoids it by its vertex clustering's tests). Here each vertex has a **safe**
//! position, the staircase's corner with the sheets moved apart
//! ([`crate::mesh::separate_sheets`], a thousandth of a voxel), where the mesh is the
//! voxels' boundary and crosses nothing (tests/stl_export.rs checks it). A vertex sits at
//! `safe + w (qef - safe)`, `w` from 1 down to 0. Each round finds the pairs of
//! triangles that cross (exact predicates) and steps `w` at their vertices down
//! [`WEIGHTS`] (7/8, 3/4, then halving to 1/16, then 0), and their faces fall back to
//! the staircase's diagonal when all four corners are safe, until no pair crosses. At
//! `w = 0` everywhere it is the staircase, so the loop ends; in practice one round
//! moves a few thousand vertices an eighth of the way.
//!
//! The first step is small because most crossings are touches, not folds: where a
//! crease runs diagonally through the lattice (the classic part's bores meet along
//! `x + z` constant, through the cells' corners), two neighbouring cells' vertices land
//! on the crease at their common corner, a hundredth of a voxel apart or at one point,
//! and their triangles touch. Any move parts them; halving `w` parted them too but put
//! the vertices up to 0.4 voxel off the surface (the distance's maximum over the part),
//! an eighth of the way puts them 0.07 off.
//!
//! Which triangles are tested: a crossing needs a triangle near a **risky** vertex: one
//! on a crease or corner, clamped to its cell, sharing its voxel corner with another
//! sheet, with faces looking opposite ways (a wall or a gap one voxel thin), whose
//! crossings' normals differ by more than 60 degrees, or estimated (no crossings) at a
//! corner of the staircase or relaxed near its cell's side. Triangles at risky vertices
//! are tested against every triangle whose box meets theirs (those of faces with a
//! corner within two voxels), and the vertices a round moves become risky. A smooth,
//! well-resolved surface is not tested (its vertices lie on the surface, a voxel's
//! hundredth from their tangent planes, and its triangles stay in their cells); the
//! tests check the whole mesh by brute force on random solids.

use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashSet;

use super::dual::{DualMesh, VertexKind, split_quad};
use super::hermite::Crossing;
use super::simplify::triangles_clash;
use crate::mesh::{TriangleMesh, separated_vertices};

/// Rounds at most before every vertex still crossing goes to its safe position.
const MAX_ROUNDS: usize = 12;
/// The weights a vertex steps down, one step each round its triangles cross another's
/// (module doc); after the last, the safe position.
const WEIGHTS: [f64; 7] = [1.0, 0.875, 0.75, 0.5, 0.25, 0.125, 0.0625];
/// Side of the grid cells that pair triangles for the crossing test, lattice units
/// (the pairs do not depend on it; the time does).
const PAIR_CELL: f64 = 2.0;
/// Crossings' normals further apart than this (cosine of 60 degrees) make a vertex risky.
const RISKY_NORMAL_COSINE: f64 = 0.5;

/// The dual mesh's triangles, with the vertices of crossing triangles moved towards
/// their safe positions until none cross (module doc). `positions` are lattice units.
pub(crate) fn untangle(dual: &mut DualMesh) -> Vec<[u32; 3]> {
    let n = dual.positions.len();
    let qef = dual.positions.clone();
    let safe = {
        let staircase = TriangleMesh {
            vertices: dual.corners.par_iter().map(|c| DVec3::new(c[0].into(), c[1].into(), c[2].into())).collect(),
            triangles: dual.quads.par_iter().flat_map_iter(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect(),
            groups: Vec::new(),
        };
        match separated_vertices(&staircase) {
            Ok(moved) => moved,
            Err(_) => staircase.vertices,
        }
    };
    // Each vertex's step down WEIGHTS (its length: weight 0).
    let mut step = vec![0_usize; n];
    let weight = |step: usize| WEIGHTS.get(step).copied().unwrap_or(0.0);
    let mut risky = risky_vertices(dual);
    let mut triangles = split_all(dual);
    for round in 0..=MAX_ROUNDS {
        if !risky.iter().any(|&r| r) {
            break;
        }
        let crossing = crossing_vertices(dual, &triangles, &risky);
        if crossing.is_empty() {
            break;
        }
        risky = vec![false; n];
        for v in crossing {
            let v = v as usize;
            step[v] = if round == MAX_ROUNDS { WEIGHTS.len() } else { (step[v] + 1).min(WEIGHTS.len()) };
            dual.positions[v] = safe[v] + (qef[v] - safe[v]) * weight(step[v]);
            risky[v] = true;
        }
        // Faces at moved vertices (the risky ones now) are cut again; all-safe faces as
        // the staircase is.
        let placed = &*dual;
        triangles.par_chunks_mut(2).with_min_len(4096).enumerate().for_each(|(f, pair)| {
            let q = placed.quads[f];
            if q.iter().any(|&v| risky[v as usize]) {
                let cut = if q.iter().all(|&v| step[v as usize] >= WEIGHTS.len()) {
                    [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
                } else {
                    split_face(placed, f)
                };
                pair.copy_from_slice(&cut);
            }
        });
    }
    let moved_distance = moved_plane_distance(dual, &step);
    dual.vertex_distance = dual.vertex_distance.max(moved_distance);
    triangles
}

/// The largest distance, lattice units, from a vertex the untangling moved (`step`
/// past 0) to the tangent plane of a crossing on one of its faces: the placement's
/// bound ([`DualMesh::vertex_distance`]) holds the QEF's points, not the moved ones.
fn moved_plane_distance(dual: &DualMesh, step: &[usize]) -> f64 {
    dual.quads
        .par_iter()
        .zip(&dual.crossings)
        .zip(&dual.faces)
        .with_min_len(4096)
        .filter_map(|((q, c), key)| c.map(|c| (q, c, *key)))
        .map(|(q, c, key)| {
            let (point, normal) = (c.point(key), c.normal.as_dvec3());
            q.iter()
                .filter(|&&v| step[v as usize] > 0)
                .map(|&v| normal.dot(dual.positions[v as usize] - point).abs())
                .fold(0.0, f64::max)
        })
        .reduce(|| 0.0, f64::max)
}

/// Face `f`'s two triangles, cut by [`split_quad`] at the current positions.
fn split_face(dual: &DualMesh, f: usize) -> [[u32; 3]; 2] {
    let key = dual.faces[f];
    let crossing = dual.crossings[f].unwrap_or_else(|| Crossing::face(key));
    split_quad(dual.quads[f], &dual.positions, crossing.point(key))
}

/// Every face's two triangles, face `f`'s at `2 f` and `2 f + 1`.
fn split_all(dual: &DualMesh) -> Vec<[u32; 3]> {
    (0..dual.quads.len()).into_par_iter().with_min_len(4096).flat_map_iter(|f| split_face(dual, f)).collect()
}

/// The vertices where crossings may start (module doc).
fn risky_vertices(dual: &DualMesh) -> Vec<bool> {
    let n = dual.positions.len();
    (0..n)
        .into_par_iter()
        .with_min_len(4096)
        .map(|v| {
            if matches!(dual.kinds[v], VertexKind::Crease | VertexKind::Corner) || dual.clamped[v] {
                return true;
            }
            let shared = (v > 0 && dual.corners[v - 1] == dual.corners[v])
                || (v + 1 < n && dual.corners[v + 1] == dual.corners[v]);
            if shared {
                return true;
            }
            let fan = dual.fans.of_vertex(v);
            let mut directions = 0u8;
            for &f in fan {
                directions |= 1 << dual.faces[f as usize].direction;
            }
            if (0..3).any(|a| directions >> (2 * a) & 3 == 3) {
                return true;
            }
            // An estimated vertex at a corner of the staircase (faces along all three
            // axes: a bump or a notch of single voxels) or relaxed to its cell's side.
            if dual.kinds[v] == VertexKind::Estimated {
                let axes = (0..3).filter(|a| directions >> (2 * a) & 3 != 0).count();
                let c = dual.corners[v];
                let offset = dual.positions[v] - DVec3::new(c[0].into(), c[1].into(), c[2].into());
                if axes == 3 || offset.abs().max_element() > 0.4 {
                    return true;
                }
            }
            let normals: Vec<DVec3> =
                fan.iter().filter_map(|&f| dual.crossings[f as usize]).map(|c| c.normal.as_dvec3()).collect();
            normals.iter().enumerate().any(|(i, a)| normals[i + 1..].iter().any(|b| a.dot(*b) < RISKY_NORMAL_COSINE))
        })
        .collect()
}

/// The vertices of triangles that cross another, testing the triangles at `risky`
/// vertices against those near them.
fn crossing_vertices(dual: &DualMesh, triangles: &[[u32; 3]], risky: &[bool]) -> Vec<u32> {
    // Blocks of 4 voxels a side within one of a risky vertex's block: they hold every
    // voxel corner within two of it.
    // The risky vertices' blocks first (on a solid of creases and corners nearly every
    // vertex is risky, and 27 entries a vertex held 27 times the vertices), then the
    // blocks around them.
    let block = |c: [u32; 3]| c.map(|x| i64::from(x >> 2));
    let mut centres: Vec<[i64; 3]> = (0..risky.len())
        .into_par_iter()
        .with_min_len(4096)
        .filter(|&v| risky[v])
        .map(|v| block(dual.corners[v]))
        .collect();
    centres.par_sort_unstable();
    centres.dedup();
    let mut around: Vec<[i64; 3]> = centres
        .par_iter()
        .with_min_len(4096)
        .flat_map_iter(|&b| {
            (-1..=1).flat_map(move |dx| {
                (-1..=1).flat_map(move |dy| (-1..=1).map(move |dz| [b[0] + dx, b[1] + dy, b[2] + dz]))
            })
        })
        .collect();
    drop(centres);
    around.par_sort_unstable();
    around.dedup();
    let near: FxHashSet<[i64; 3]> = around.into_iter().collect();
    // The triangles of faces with a corner there, listed in every cell their boxes meet,
    // sorted by cell (so each cell's list is a slice, its triangles ascending). Which
    // pairs are tested does not depend on the cells' size; cells of two voxels list the
    // classic part's triangles 1.4 million times instead of 2.6 (at one) and take a
    // third less time.
    let position = |v: u32| dual.positions[v as usize];
    let cell_of = |x: DVec3| (x / PAIR_CELL).floor();
    let mut listed: Vec<([i64; 3], u32)> = (0..dual.quads.len())
        .into_par_iter()
        .with_min_len(4096)
        .filter(|&f| dual.quads[f].iter().any(|&v| near.contains(&block(dual.corners[v as usize]))))
        .flat_map_iter(|f| {
            [2 * f, 2 * f + 1].into_iter().flat_map(move |t| {
                let p = triangles[t].map(position);
                let (lo, hi) = (cell_of(p[0].min(p[1]).min(p[2])), cell_of(p[0].max(p[1]).max(p[2])));
                (lo.x as i64..=hi.x as i64).flat_map(move |x| {
                    (lo.y as i64..=hi.y as i64)
                        .flat_map(move |y| (lo.z as i64..=hi.z as i64).map(move |z| ([x, y, z], t as u32)))
                })
            })
        })
        .collect();
    listed.par_sort_unstable();
    let starts: Vec<usize> = (0..listed.len())
        .into_par_iter()
        .with_min_len(4096)
        .filter(|&i| i == 0 || listed[i].0 != listed[i - 1].0)
        .chain(rayon::iter::once(listed.len()))
        .collect();
    let is_risky = |t: u32| triangles[t as usize].iter().any(|&v| risky[v as usize]);
    // A pair whose boxes meet is tested only in the cell holding the low corner of
    // their intersection (it is in both lists), not again in every cell they share.
    let pairs: Vec<(u32, u32)> = starts
        .par_windows(2)
        .flat_map_iter(|w| {
            let cell = listed[w[0]].0;
            // The cell's triangles with their corners, boxes and riskiness, made once
            // for the cell's pairs.
            let list: Vec<Listed> = listed[w[0]..w[1]]
                .iter()
                .map(|&(_, t)| {
                    let p = triangles[t as usize].map(position);
                    let (lo, hi) = (p[0].min(p[1]).min(p[2]), p[0].max(p[1]).max(p[2]));
                    Listed { t, p, lo, hi, risky: is_risky(t) }
                })
                .collect();
            let mut found = Vec::new();
            for (i, a) in list.iter().enumerate() {
                for b in &list[i + 1..] {
                    if !(a.risky || b.risky) || a.lo.cmpgt(b.hi).any() || b.lo.cmpgt(a.hi).any() {
                        continue;
                    }
                    let low = cell_of(a.lo).max(cell_of(b.lo));
                    if [low.x as i64, low.y as i64, low.z as i64] != cell {
                        continue;
                    }
                    if triangles_cross(triangles[a.t as usize], a.p, triangles[b.t as usize], b.p) {
                        found.push((a.t, b.t));
                    }
                }
            }
            found
        })
        .collect();
    let mut vertices: Vec<u32> =
        pairs.iter().flat_map(|&(s, t)| triangles[s as usize].into_iter().chain(triangles[t as usize])).collect();
    vertices.par_sort_unstable();
    vertices.dedup();
    vertices
}

/// A triangle listed in a cell of the pairing grid, as its pairs read it.
struct Listed {
    t: u32,
    p: [DVec3; 3],
    lo: DVec3,
    hi: DVec3,
    risky: bool,
}

/// Whether two triangles of the mesh cross: they meet beyond what they share, by index
/// (two sheets' vertices at one point are not shared: their triangles must not touch).
fn triangles_cross(si: [u32; 3], s: [DVec3; 3], ti: [u32; 3], t: [DVec3; 3]) -> bool {
    let shares_position_not_index = (0..3).any(|i| (0..3).any(|j| s[i] == t[j] && si[i] != ti[j]));
    shares_position_not_index || triangles_clash(s, t)
}
