//! Adaptive simplification of a closed surface mesh by edge collapses under a true
//! distance bound (quadric error order: Garland and Heckbert, "Surface simplification
//! using quadric error metrics", SIGGRAPH 1997).
//!
//! Each vertex carries the quadric of its input faces' planes, area-weighted
//! (`quadric`); an edge's cost is the quadric of its two ends at the best point, the
//! quadric's minimiser (near-null directions left at the midpoint, so planes, creases
//! and corners keep their place) or else the better of the ends and the midpoint.
//! Edges collapse cheapest first, each only when:
//! - **the distance stays under the tolerance**, two-sided: every vertex carries a
//!   bound `e` (0 for input vertices), interpolated linearly over each face, such that
//!   the current surface and the input are related point to point (each point of
//!   either related to some point of the other) with related points `p`, `q` within
//!   `e(p)` (after Guéziec's tolerance volumes, "Surface simplification inside a
//!   tolerance volume", 1996). A collapse replaces a patch by a fan over the same
//!   boundary; both are height fields over one plane (else the collapse is refused),
//!   the vertical line pairs their points, and the new vertex takes the least `e` that
//!   covers the vertical gap plus the old bound at every corner of the two
//!   triangulations' common refinement, where the condition is tight (`gap`). The
//!   collapse is refused when that `e` exceeds the tolerance. So the output lies within
//!   [`SimplifyReport::max_distance_bound`] of the input everywhere, both ways. The
//!   bound adds up over the collapses a point goes through; it is conservative, not
//!   an estimate;
//! - **the normals stay within [`SimplifyOptions::normal_tolerance`]**, when one is
//!   given: every face carries the cone of the normals of the input faces under it,
//!   carried through the collapses over the same vertical pairing (`normal`), and a
//!   collapse is refused when a new face's normal would leave its cone by more than
//!   the tolerance (the angle to the cone's axis plus its half-angle). So triangles go where the surface turns: the distance
//!   bound alone lets a face of a cylinder or a sphere tilt by about
//!   `sqrt(8 tolerance / radius)` across its width, which at a tenth of a voxel and a
//!   radius of a hundred voxels is degrees;
//! - **topology is kept**: the link condition (Dey, Edelsbrunner et al. 1999: the links
//!   of the two ends share exactly the two opposite vertices), and no two new faces on
//!   the same three vertices (so no tetrahedron closes and no edge gets three faces);
//! - **no face flips or degenerates**: each new face's normal stays within
//!   [`SimplifyOptions::max_normal_change`] of the face it replaces and its area is not
//!   negligible against its longest edge squared (long thin faces, as on a cylinder,
//!   are fine);
//! - **no self-intersection**: each new face is tested against the faces near it (a
//!   grid of face boxes) with an exact triangle-triangle test (`tri_tri`) that lets
//!   faces meet only in the corners they share by position (the vertices of a sheet,
//!   where voxels touch along an edge or a corner, share a position, never an index,
//!   and are never welded).
//!
//! **Parallel and deterministic.** Space is cut into cubic blocks; a vertex belongs to
//! the block holding it, a face to a block when its three corners do. Each block
//! collapses its own faces' edges alone (`block`), against the faces of the snapshot
//! meeting its box as fixed obstacles, every new face strictly inside its open box, so
//! blocks never see each other's new faces and their results are joined in block
//! order: the output is the same for any number of threads. Faces across block borders
//! wait for the next round, whose blocks are shifted by half a block; every second
//! round the blocks double, until one block holds the whole mesh, which is repeated
//! while it still collapses more than a thousandth of the faces. The doubling stops
//! there too once the blocks have been wide enough to collapse: when a width's two
//! rounds together collapse fewer than a thousandth of the faces after an earlier
//! width collapsed more, wider blocks would find few more (each round prices and tries
//! every edge not refused before, and the closed bunny at depth 9 within 0.04 voxel
//! spent a quarter of its simplification on its last three rounds, which made 5 of
//! its 428,000 collapses). Before that the rule waits: on a small mesh the first widths' blocks
//! are too small for any collapse (a link must lie strictly inside its block), and a
//! width that collapses nothing says nothing of the next. Ties are broken by vertex
//! index, never by timing.
//! An edge refused on its own faces is not tried again until a vertex near it moves
//! (`block`: the same result, without pricing and testing it every round).

mod block;
mod face_grid;
mod gap;
mod normal;
mod quadric;
mod tri_tri;
pub(crate) use tri_tri::{DEGENERATE_AREA, triangles_clash};

use glam::DVec3;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use smallvec::SmallVec;

use crate::error::{Error, Result};
use crate::mesh::TriangleMesh;
use crate::progress::{NoProgress, Progress, stop_if_cancelled};
use block::{BlockInput, BlockOutput, Limits, simplify_block};
use normal::Cone;
use quadric::Quadric;

/// Blocks along the mesh's longest side in the first round.
const FIRST_BLOCKS: f64 = 8.0;
/// Most rounds with one block holding the whole mesh.
const LAST_ROUNDS: usize = 4;
/// Those rounds stop once one collapses fewer than this share of the faces, and the
/// doubling once a width's two rounds do after an earlier width's collapsed more: each
/// round tries every edge again (a second a round for 20,000 faces) for a handful of
/// collapses.
const SETTLED_SHARE: f64 = 1e-3;

/// How [`simplify`] simplifies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimplifyOptions {
    /// Largest distance between the output and the input surface, both ways, in
    /// world units (the export's `--tolerance` in voxels times the voxel size).
    pub tolerance: f64,
    /// Largest angle, in radians, a face's normal may turn in one collapse.
    pub max_normal_change: f64,
    /// Largest angle, in radians, between an output face's normal and the normal of
    /// any input face under it (a true bound, module doc); `None`: normals are bounded
    /// only by `max_normal_change` a collapse.
    pub normal_tolerance: Option<f64>,
}

impl SimplifyOptions {
    /// Simplification within `tolerance` world units, normals turning at most 30
    /// degrees a collapse.
    #[must_use]
    pub fn new(tolerance: f64) -> Self {
        SimplifyOptions { tolerance, max_normal_change: 30f64.to_radians(), normal_tolerance: None }
    }
}

/// What [`simplify`] did.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SimplifyReport {
    /// Triangles of the input.
    pub triangles_before: usize,
    /// Triangles of the output.
    pub triangles_after: usize,
    /// Vertices of the output.
    pub vertices_after: usize,
    /// A true bound on the distance between the output and the input surface, both
    /// ways (the largest of the faces' bounds; at most the tolerance).
    pub max_distance_bound: f64,
    /// With a normal tolerance, a true bound, in radians, on the angle between an
    /// output face's normal and the input's normals under it (the largest of the
    /// faces' bounds; at most the tolerance).
    pub max_normal_bound: Option<f64>,
    /// The root mean square distance of the output vertices to the planes of the input
    /// faces they replaced, weighted by those faces' areas (the quadrics' measure).
    pub rms_quadric_distance: f64,
    /// Edge collapses made.
    pub collapses: usize,
    /// Rounds of blocks run.
    pub rounds: usize,
}

/// Simplifies a closed, 2-manifold, consistently oriented mesh (every edge in two
/// faces, run opposite ways) within `options.tolerance` of it; see the module doc. The
/// output is closed, 2-manifold, oriented and free of self-intersections when the input
/// is; its vertices keep the input's order (unused ones dropped).
///
/// # Errors
/// When the mesh is not valid ([`TriangleMesh::validate`]) or not watertight, or the
/// options are not finite and non-negative.
pub fn simplify(mesh: &TriangleMesh, options: &SimplifyOptions) -> Result<(TriangleMesh, SimplifyReport)> {
    simplify_with_progress(mesh, options, &NoProgress)
}

/// [`simplify`], reporting to `progress`: four units a face of the input, three of
/// them as the first round's blocks finish their faces (about three quarters of the
/// time), then half of what is left a round.
///
/// # Errors
/// As [`simplify`].
pub fn simplify_with_progress(
    mesh: &TriangleMesh,
    options: &SimplifyOptions,
    progress: &dyn Progress,
) -> Result<(TriangleMesh, SimplifyReport)> {
    if !(options.tolerance.is_finite() && options.tolerance >= 0.0) {
        return Err(Error::invalid("tolerance", format!("{} is not a finite non-negative length", options.tolerance)));
    }
    if !(options.max_normal_change.is_finite() && options.max_normal_change >= 0.0) {
        return Err(Error::invalid("max normal change", "it is not a finite non-negative angle"));
    }
    if let Some(angle) = options.normal_tolerance
        && !(angle.is_finite() && angle >= 0.0)
    {
        return Err(Error::invalid("normal tolerance", format!("{angle} is not a finite non-negative angle")));
    }
    mesh.validate()?;
    if !mesh.is_watertight() {
        return Err(Error::invalid("mesh", "it is not closed, manifold and consistently oriented"));
    }
    let limits = Limits {
        tolerance: options.tolerance,
        min_normal_cosine: options.max_normal_change.min(PI_HALF).cos(),
        max_turn: options.normal_tolerance,
    };
    let total = 4 * mesh.triangles.len() as u64;
    progress.start(total);
    let mut shown = 0;
    let mut state = State::new(mesh);
    let bounds = mesh.bounds();
    let extent = (bounds.max - bounds.min).max_element().max(f64::MIN_POSITIVE);
    let pad = extent * 1e-3 + 1e-300;
    let origin = bounds.min - DVec3::splat(pad);
    let whole = extent + 2.0 * pad;
    let mut width = whole / FIRST_BLOCKS;
    let (mut rounds, mut collapses, mut last_rounds, mut at_width) = (0, 0, 0, 0);
    // Whether a width's rounds have collapsed at least the settled share: only then
    // does a settled width stop the doubling.
    let mut collapsing = false;
    loop {
        // One block holds everything once the width passes twice the mesh: its box
        // starts a quarter block before the mesh.
        let single = width >= 2.0 * whole;
        let shift = if single {
            DVec3::splat(-width / 4.0)
        } else if rounds % 2 == 1 {
            DVec3::splat(-width / 2.0)
        } else {
            DVec3::ZERO
        };
        rounds += 1;
        // The first round's blocks report their faces as they finish; each later
        // round, half of what is left.
        let per_face = if rounds == 1 { 3 } else { 0 };
        let (made, reported) = state.round(origin + shift, width, &limits, rounds as u32, progress, per_face);
        stop_if_cancelled(progress)?;
        if rounds == 1 {
            shown = reported;
        } else {
            let step = (total - shown) / 2;
            progress.advance(step);
            shown += step;
        }
        collapses += made;
        let settled = |made: usize| (made as f64) < SETTLED_SHARE * state.faces.len() as f64;
        if single {
            last_rounds += 1;
            if settled(made) || last_rounds == LAST_ROUNDS {
                break;
            }
        } else {
            at_width += made;
            if rounds % 2 == 0 {
                if !settled(at_width) {
                    collapsing = true;
                } else if collapsing {
                    break;
                }
                width *= 2.0;
                at_width = 0;
            }
        }
    }
    progress.finish();
    Ok(state.finish(mesh.triangles.len(), collapses, rounds, options.normal_tolerance.is_some()))
}

const PI_HALF: f64 = std::f64::consts::FRAC_PI_2;

/// The mesh between rounds: positions, quadrics and distance bounds by input vertex,
/// faces and their normal bounds.
struct State {
    positions: Vec<DVec3>,
    quadrics: Vec<Quadric>,
    /// Each vertex's distance bound (module `gap`).
    bounds: Vec<f64>,
    faces: Vec<[u32; 3]>,
    /// Each face's cone of input normals (module `normal`).
    cones: Vec<Cone>,
    /// The input's total face area (the quadrics' weight).
    area: f64,
    /// Each vertex's last round moved in (0: never).
    moved_in: Vec<u32>,
    /// Edges refused on their neighbourhood alone, by global ends in the order tried,
    /// with the round and their cost's bits (module `block`).
    refused: FxHashMap<(u32, u32), (u32, u64)>,
}

impl State {
    fn new(mesh: &TriangleMesh) -> Self {
        let mut quadrics = vec![Quadric::default(); mesh.vertices.len()];
        let mut area = 0.0;
        for (t, face) in mesh.triangles.iter().enumerate() {
            let c = mesh.corners(t);
            let normal = (c[1] - c[0]).cross(c[2] - c[0]);
            let twice = normal.length();
            if twice == 0.0 {
                continue;
            }
            let q = Quadric::plane(c[0], normal / twice, twice / 2.0);
            area += twice / 2.0;
            for &v in face {
                quadrics[v as usize] += q;
            }
        }
        State {
            positions: mesh.vertices.clone(),
            quadrics,
            bounds: vec![0.0; mesh.vertices.len()],
            faces: mesh.triangles.clone(),
            cones: (0..mesh.triangles.len()).map(|t| Cone::of_face(&mesh.corners(t))).collect(),
            area,
            moved_in: vec![0; mesh.vertices.len()],
            refused: FxHashMap::default(),
        }
    }

    /// Round `round` (from 1), of blocks of side `width` from `origin`, each block
    /// advancing `progress` by `per_face` units a face it owns as it finishes; returns
    /// the collapses made and the units reported.
    fn round(
        &mut self,
        origin: DVec3,
        width: f64,
        limits: &Limits,
        round: u32,
        progress: &dyn Progress,
        per_face: u64,
    ) -> (usize, u64) {
        let block_of = |p: DVec3| {
            let c = ((p - origin) / width).floor();
            [c.x as i64, c.y as i64, c.z as i64]
        };
        // Each face: its owner block, if its corners agree, and the blocks its box
        // meets (closed) that are not its owner take it as halo.
        let vertex_block: Vec<[i64; 3]> = self.positions.par_iter().map(|&p| block_of(p)).collect();
        let mut ids: FxHashMap<[i64; 3], usize> = FxHashMap::default();
        let mut keys: Vec<[i64; 3]> = Vec::new();
        let owner: Vec<Option<[i64; 3]>> = self
            .faces
            .par_iter()
            .with_min_len(4096)
            .map(|t| {
                let b = vertex_block[t[0] as usize];
                (vertex_block[t[1] as usize] == b && vertex_block[t[2] as usize] == b).then_some(b)
            })
            .collect();
        for b in owner.iter().flatten() {
            ids.entry(*b).or_insert_with(|| {
                keys.push(*b);
                keys.len() - 1
            });
        }
        // Each face's blocks (own: true), in face order, then dealt to the blocks.
        let listed: Vec<(u32, u32, bool)> = (0..self.faces.len())
            .into_par_iter()
            .with_min_len(1024)
            .flat_map_iter(|f| {
                let mut at: SmallVec<[(u32, u32, bool); 8]> = SmallVec::new();
                if let Some(b) = owner[f] {
                    at.push((ids[&b] as u32, f as u32, true));
                }
                let c = self.faces[f].map(|v| self.positions[v as usize]);
                let (lo, hi) = (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]));
                // Closed boxes: a face on a block's face plane meets that block too.
                let first = ((lo - origin) / width).floor() - 1.0;
                let last = ((hi - origin) / width).floor() + 1.0;
                for z in first.z as i64..=last.z as i64 {
                    for y in first.y as i64..=last.y as i64 {
                        for x in first.x as i64..=last.x as i64 {
                            let key = [x, y, z];
                            if Some(key) == owner[f] {
                                continue;
                            }
                            let Some(&id) = ids.get(&key) else { continue };
                            let bmin = origin + DVec3::new(x as f64, y as f64, z as f64) * width;
                            let bmax = bmin + DVec3::splat(width);
                            if lo.cmple(bmax).all() && bmin.cmple(hi).all() {
                                at.push((id as u32, f as u32, false));
                            }
                        }
                    }
                }
                at
            })
            .collect();
        let mut own: Vec<Vec<u32>> = vec![Vec::new(); keys.len()];
        let mut halo: Vec<Vec<u32>> = vec![Vec::new(); keys.len()];
        for (id, f, is_own) in listed {
            if is_own { own[id as usize].push(f) } else { halo[id as usize].push(f) }
        }
        let outputs: Vec<BlockOutput> = (0..keys.len())
            .into_par_iter()
            .map(|id| {
                let k = keys[id];
                let min = origin + DVec3::new(k[0] as f64, k[1] as f64, k[2] as f64) * width;
                let input = BlockInput {
                    min,
                    max: min + DVec3::splat(width),
                    positions: &self.positions,
                    quadrics: &self.quadrics,
                    bounds: &self.bounds,
                    faces: &self.faces,
                    cones: &self.cones,
                    own: &own[id],
                    halo: &halo[id],
                    moved_in: &self.moved_in,
                    refused: &self.refused,
                };
                if progress.cancelled() {
                    // The round's result is dropped: `simplify_with_progress` returns
                    // `Cancelled` after it.
                    return BlockOutput::default();
                }
                let output = simplify_block(&input, limits);
                if per_face > 0 {
                    progress.advance(per_face * own[id].len() as u64);
                }
                output
            })
            .collect();
        let reported = per_face * own.iter().map(|o| o.len() as u64).sum::<u64>();
        // Join: the faces no block owned, in order, then each block's in block order.
        let mut faces = Vec::with_capacity(self.faces.len());
        let mut cones = Vec::with_capacity(self.faces.len());
        for (f, t) in self.faces.iter().enumerate() {
            if owner[f].is_none() {
                faces.push(*t);
                cones.push(self.cones[f]);
            }
        }
        let mut made = 0;
        for out in outputs {
            made += out.collapses;
            faces.extend(out.faces);
            cones.extend(out.cones);
            for (v, p, q, e) in out.moved {
                self.positions[v as usize] = p;
                self.quadrics[v as usize] = q;
                self.bounds[v as usize] = e;
                self.moved_in[v as usize] = round;
            }
            self.refused.extend(out.refused.into_iter().map(|(edge, cost)| (edge, (round, cost))));
        }
        self.faces = faces;
        self.cones = cones;
        (made, reported)
    }

    fn finish(
        self,
        triangles_before: usize,
        collapses: usize,
        rounds: usize,
        normals_bounded: bool,
    ) -> (TriangleMesh, SimplifyReport) {
        let mut remap = vec![u32::MAX; self.positions.len()];
        for &v in self.faces.iter().flatten() {
            remap[v as usize] = 0;
        }
        let mut vertices = Vec::new();
        let (mut squared, mut bound) = (0.0, 0.0f64);
        for (v, r) in remap.iter_mut().enumerate() {
            if *r == 0 {
                *r = vertices.len() as u32;
                vertices.push(self.positions[v]);
                squared += self.quadrics[v].eval(self.positions[v]);
                bound = bound.max(self.bounds[v]);
            }
        }
        let triangles: Vec<[u32; 3]> = self.faces.iter().map(|t| t.map(|v| remap[v as usize])).collect();
        let report = SimplifyReport {
            triangles_before,
            triangles_after: triangles.len(),
            vertices_after: vertices.len(),
            max_distance_bound: bound,
            max_normal_bound: normals_bounded.then(|| {
                self.faces
                    .iter()
                    .zip(&self.cones)
                    .map(|(t, c)| {
                        let [a, b, c0] = t.map(|v| self.positions[v as usize]);
                        c.deviation((b - a).cross(c0 - a))
                    })
                    .fold(0.0, f64::max)
            }),
            // Each input face's plane is counted at its three corners.
            rms_quadric_distance: if self.area > 0.0 { (squared / (3.0 * self.area)).sqrt() } else { 0.0 },
            collapses,
            rounds,
        };
        (TriangleMesh { vertices, triangles, groups: Vec::new() }, report)
    }
}

#[cfg(test)]
mod tests;
