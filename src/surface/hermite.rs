//! Hermite data: where the surface crosses the lattice's edges, and its normal there
//! (Ju, Losasso, Schaefer and Warren, *Dual Contouring of Hermite Data*, 2002, §2).
//!
//! A solid's voxels are decided by their centres, so the surface crosses the segment
//! between the centres of a full voxel and an empty neighbour (one voxel long, along
//! one axis) an odd number of times; it is one crossing wherever the surface is
//! resolved at the voxel size. That segment is dual to the **boundary face** between
//! the two voxels, the face the staircase mesh shows. A [`Crossing`] is kept a boundary
//! face, keyed by the full voxel and the face's direction ([`FaceKey`]): its place `t`
//! along the segment from the full voxel's centre (`0..=1`, in voxels) and the outward
//! unit normal of the surface there.
//!
//! A face without a crossing (a solid read from a file that carries none, a face of a
//! coarse node) is read as the face itself: `t = 0.5` and the axis normal
//! ([`Crossing::face`]); the extractor then estimates, as Surface Nets does.
//!
//! Sources: [`HermiteData::from_shape`] finds each crossing on the segment from the
//! shape's signed distance ([`Shape::surface`], in voxels: the Illinois variant of
//! regula falsi, to a ten-millionth of a voxel) and takes the normal there; where the
//! distance's signs at the segment's ends disagree with the voxels' decisions, or a
//! shape gives no distance, it is bisected on [`Shape::contains`] (and a shape without
//! normals keeps the axis normal).

use glam::{DVec3, Vec3};
use rayon::prelude::*;

use crate::morton;
use crate::octree::{Domain, LinearOctree, NodeKey};
use crate::progress::{NoProgress, Progress, stop_if_cancelled};
use crate::shape::{Shape, Surface};

pub use super::faces::{Direction, FaceKey};

/// Where the surface crosses a boundary face's segment, and its normal there.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    /// Place along the segment from the full voxel's centre to the empty one's, in
    /// voxels (`0..=1`).
    pub t: f32,
    /// Outward unit normal of the surface at the crossing.
    pub normal: Vec3,
}

impl Crossing {
    /// The face itself: the segment's midpoint and the face's own normal (what a face
    /// without data is read as).
    #[must_use]
    pub fn face(key: FaceKey) -> Crossing {
        Crossing { t: 0.5, normal: key.outward().as_vec3() }
    }

    /// The crossing point in lattice units (voxel corners at integers).
    #[must_use]
    pub fn point(self, key: FaceKey) -> DVec3 {
        let v = key.voxel();
        let centre = DVec3::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2])) + 0.5;
        centre + key.outward() * f64::from(self.t)
    }
}

/// The crossings of a solid's boundary faces, sorted by face.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct HermiteData {
    faces: Vec<(FaceKey, Crossing)>,
}

impl HermiteData {
    /// No crossings: every face is read as itself ([`Crossing::face`]).
    #[must_use]
    pub fn none() -> Self {
        HermiteData::default()
    }

    /// From `(face, crossing)` pairs in any order (sorted here; a face given twice
    /// keeps its first crossing).
    #[must_use]
    pub fn from_faces(mut faces: Vec<(FaceKey, Crossing)>) -> Self {
        faces.par_sort_by_key(|(key, _)| *key);
        faces.dedup_by_key(|(key, _)| *key);
        HermiteData { faces }
    }

    /// From `(face, crossing)` pairs already strictly sorted by face.
    pub(crate) fn from_sorted(faces: Vec<(FaceKey, Crossing)>) -> Self {
        debug_assert!(faces.windows(2).all(|w| w[0].0 < w[1].0), "faces not strictly sorted");
        HermiteData { faces }
    }

    /// The crossings, sorted by face.
    #[must_use]
    pub fn faces(&self) -> &[(FaceKey, Crossing)] {
        &self.faces
    }

    /// How many faces carry a crossing.
    #[must_use]
    pub fn len(&self) -> usize {
        self.faces.len()
    }

    /// The memory the crossings hold, in bytes (what a reader checks against its
    /// budget before allocating them).
    #[must_use]
    pub fn bytes(&self) -> usize {
        self.faces.len() * std::mem::size_of::<(FaceKey, Crossing)>()
    }

    /// Whether no face carries a crossing.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.faces.is_empty()
    }

    /// The crossing of face `key`, if it carries one.
    #[must_use]
    pub fn get(&self, key: FaceKey) -> Option<Crossing> {
        self.faces.binary_search_by_key(&key, |(k, _)| *k).ok().map(|i| self.faces[i].1)
    }

    /// The crossing of face `key`, or the face itself.
    #[must_use]
    pub fn crossing(&self, key: FaceKey) -> Crossing {
        self.get(key).unwrap_or_else(|| Crossing::face(key))
    }

    /// Exact crossings and normals of `shape` on the boundary faces of `tree`, its
    /// voxelization (parallel over the faces).
    #[must_use]
    pub fn from_shape(shape: &(impl Shape + ?Sized), tree: &LinearOctree) -> Self {
        Self::from_shape_with(shape, tree, &NoProgress).expect("nothing stops it")
    }

    /// [`HermiteData::from_shape`], its progress in faces reported to `progress`, which
    /// may stop it ([`Progress::cancelled`]: [`crate::Error::Cancelled`]) between
    /// blocks of 65,536 faces (a depth-11 sphere's 25 M faces take seconds).
    pub fn from_shape_with(
        shape: &(impl Shape + ?Sized),
        tree: &LinearOctree,
        progress: &dyn Progress,
    ) -> crate::Result<Self> {
        let domain = *tree.domain();
        let keys = super::faces::boundary_faces(tree);
        progress.start(keys.len() as u64);
        let mut faces = Vec::with_capacity(keys.len());
        for block in keys.chunks(FACES_A_BLOCK) {
            stop_if_cancelled(progress)?;
            faces.par_extend(block.par_iter().map(|&key| (key, crossing_of_shape(shape, &domain, key))));
            progress.advance(block.len() as u64);
        }
        progress.finish();
        Ok(HermiteData { faces })
    }

    /// Exact crossings and normals of `shape` on the boundary faces of `tree`, the
    /// nodes of `shape`'s voxelization inside the aligned node `cell` (one shard of a
    /// sharded solid): the whole solid's boundary faces whose full voxel lies in
    /// `cell`, keyed in the domain's frame as every face is. A face towards a voxel
    /// outside `cell` (on the cell's seam) is kept only where that voxel is empty, its
    /// centre outside `shape`, as the voxelizer decides a voxel; within `cell`,
    /// `tree` says.
    #[must_use]
    pub fn from_shape_in_cell(shape: &(impl Shape + ?Sized), tree: &LinearOctree, cell: NodeKey) -> Self {
        let domain = *tree.domain();
        let (lo, size) = (morton::decode(cell.start()), 1u32 << cell.k());
        let inside = |v: [u32; 3]| (0..3).all(|a| v[a] >= lo[a] && v[a] - lo[a] < size);
        let faces = super::faces::boundary_faces(tree);
        let faces: Vec<(FaceKey, Crossing)> = faces
            .par_iter()
            .filter(|&&key| match super::faces::neighbour(key, domain.resolution()) {
                Some(n) if !inside(n) => !shape.contains(domain.voxel_center(n)),
                _ => true,
            })
            .map(|&key| (key, crossing_of_shape(shape, &domain, key)))
            .collect();
        HermiteData { faces }
    }
}

/// Faces [`HermiteData::from_shape_with`] solves between two looks at its progress.
const FACES_A_BLOCK: usize = 1 << 16;

/// Steps of regula falsi, or of bisection, at most.
const SOLVE_STEPS: usize = 48;
/// The crossing is taken as found when the distance there is under this fraction of a
/// voxel, or the bracket is narrower.
const SOLVE_TOLERANCE: f64 = 1e-7;

/// The crossing of `shape` on face `key`'s segment.
fn crossing_of_shape(shape: &(impl Shape + ?Sized), domain: &Domain, key: FaceKey) -> Crossing {
    let v = key.voxel();
    let from = domain.voxel_center(v);
    let voxel = domain.voxel_size();
    let step = key.outward() * voxel;
    let at = |t: f64| from + step * t;
    let surface = |t: f64| shape.surface(at(t)).map(|s| Surface { distance: s.distance / voxel, ..s });
    let found = match (surface(0.0), surface(1.0)) {
        // The distance agrees with the voxels' decisions (inside at 0, outside at 1).
        (Some(lo), Some(hi)) if lo.distance <= 0.0 && hi.distance >= 0.0 && hi.distance > lo.distance => {
            regula_falsi(&surface, lo, hi)
        }
        _ => None,
    };
    let (t, normal) = match found {
        Some((t, s)) => (t, Some(s.normal)),
        None => {
            let t = bisect(shape, &at, 0.0, 1.0);
            (t, shape.surface(at(t)).map(|s| s.normal))
        }
    };
    let normal = normal.filter(|n| n.is_finite() && n.length_squared() > 0.5).unwrap_or_else(|| key.outward());
    Crossing { t: t.clamp(0.0, 1.0) as f32, normal: normal.normalize().as_vec3() }
}

/// The zero of the distance on `[0, 1]` from the surfaces at its ends (`lo` inside,
/// `hi` outside) by the Illinois variant of regula falsi (the end kept twice in a row
/// has its value halved), with the surface found there; `None` when the shape fails
/// on the way. An exact distance with one surface nearest both ends is linear along
/// the segment, so the first step lands on the crossing.
fn regula_falsi(surface: &impl Fn(f64) -> Option<Surface>, lo: Surface, hi: Surface) -> Option<(f64, Surface)> {
    let (mut t_lo, mut t_hi) = (0.0_f64, 1.0_f64);
    let (mut f_lo, mut f_hi) = (lo.distance, hi.distance);
    let mut side = 0i8;
    let mut last = if -f_lo < f_hi { lo } else { hi };
    for _ in 0..SOLVE_STEPS {
        let mut t = (t_lo * f_hi - t_hi * f_lo) / (f_hi - f_lo);
        if !(t > t_lo && t < t_hi) {
            t = 0.5 * (t_lo + t_hi);
        }
        let here = surface(t)?;
        last = here;
        let value = here.distance;
        if value.abs() < SOLVE_TOLERANCE || t_hi - t_lo < SOLVE_TOLERANCE {
            return Some((t, here));
        }
        if value < 0.0 {
            (t_lo, f_lo) = (t, value);
            if side == -1 {
                f_hi *= 0.5;
            }
            side = -1;
        } else {
            (t_hi, f_hi) = (t, value);
            if side == 1 {
                f_lo *= 0.5;
            }
            side = 1;
        }
    }
    Some((0.5 * (t_lo + t_hi), last))
}

/// Bisection on `contains` of the bracket `[lo, hi]` (lo inside, hi outside): its middle.
fn bisect(shape: &(impl Shape + ?Sized), at: &impl Fn(f64) -> DVec3, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..SOLVE_STEPS {
        if hi - lo < SOLVE_TOLERANCE {
            break;
        }
        let mid = 0.5 * (lo + hi);
        if shape.contains(at(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}
