//! Offsets, shells and rounds of a solid with surface data: measured to its true
//! surface, and the results carrying the crossings of their own surface.
//!
//! [`LinearOctree::offset`] measures to the voxel cubes of the other phase, whose
//! staircase stands up to half a voxel off a curved surface: a sphere's shell comes
//! out about half a voxel thicker. [`offset_with_surface`] measures to the surface the
//! solid's crossings describe ([`LinearOctree::offset_along_surface`]: each voxel's
//! nearest site, by the exact band transform, and the tangent planes of its crossings),
//! so Steiner's formulas hold to the lattice's sampling of the true offset, and takes
//! the result's crossings from that distance field: on a face whose ends lie at
//! distances `g_0 < D <= g_1`, at `t = (D - g_0) / (g_1 - g_0)`, with the normal
//! from the foot point on the old surface to the voxel (Frisken et al., *Adaptively
//! Sampled Distance Fields*, 2000, for the interpolation of a sampled distance's
//! level set; the direction to the nearest point is the distance's gradient). A shell
//! `T` thick inward is then `T` thick on the exported mesh, not `T + 1/2` voxel.
//!
//! Shells and rounds combine these steps with set operations, their crossings through
//! [`HermiteData::combine`]. A round's opening is intersected with the solid and its
//! closing united with it: true of the continuous operations (the opening lies in the
//! solid, the closing holds it), and kept so on the lattice, where the sub-voxel rule
//! could otherwise move a voxel across.

use glam::Vec3;
use rayon::prelude::*;

use super::faces::boundary_faces;
use super::hermite::{Crossing, FaceKey, HermiteData};
use crate::error::{Error, Result};
use crate::octree::{FaceCrossings, LinearOctree, NewCrossing, OffsetOptions, SetOp};

impl FaceCrossings for HermiteData {
    fn face_crossing(&self, voxel: u64, direction: u8) -> Option<(f32, [f32; 3])> {
        self.get(FaceKey { voxel, direction }).map(|c| (c.t, c.normal.to_array()))
    }
}

/// `tree` (with `surface`, its crossings) grown (`distance > 0`) or shrunk by
/// `distance` voxels measured to its true surface, and the result's crossings (see
/// the module doc).
///
/// # Errors
/// When `distance` is not finite or the estimate exceeds `options.budget`.
pub fn offset_with_surface(
    tree: &LinearOctree,
    surface: &HermiteData,
    distance_in_voxels: f64,
    options: &OffsetOptions,
) -> Result<(LinearOctree, HermiteData)> {
    let (result, new) = tree.offset_along_surface(distance_in_voxels, surface, options)?;
    let data = result_surface(&result, surface, new);
    Ok((result, data))
}

/// The wall `thickness` voxels thick inside `tree`'s true surface (outside it when
/// `outward`), and its crossings.
///
/// # Errors
/// When `thickness` is not finite and positive or the budget is exceeded.
pub fn shell_with_surface(
    tree: &LinearOctree,
    surface: &HermiteData,
    thickness_in_voxels: f64,
    outward: bool,
    options: &OffsetOptions,
) -> Result<(LinearOctree, HermiteData)> {
    positive("shell thickness", thickness_in_voxels)?;
    let step = if outward { thickness_in_voxels } else { -thickness_in_voxels };
    tree.check_offset_steps(format!("shell of {thickness_in_voxels} voxels"), &[step], true, options.budget)?;
    let (a, b) = if outward {
        (offset_with_surface(tree, surface, thickness_in_voxels, options)?, (tree.clone(), surface.clone()))
    } else {
        ((tree.clone(), surface.clone()), offset_with_surface(tree, surface, -thickness_in_voxels, options)?)
    };
    combined(SetOp::Difference, &a, &b)
}

/// `tree` with its convex edges (`convex`: the opening by a ball of `radius` voxels)
/// and its concave edges (`concave`: the closing) rounded along its true surface, and
/// the result's crossings; both: the opening, then the closing.
///
/// # Errors
/// When `radius` is not finite and positive or the budget is exceeded.
pub fn round_with_surface(
    tree: &LinearOctree,
    surface: &HermiteData,
    radius_in_voxels: f64,
    convex: bool,
    concave: bool,
    options: &OffsetOptions,
) -> Result<(LinearOctree, HermiteData)> {
    positive("round radius", radius_in_voxels)?;
    let steps = if convex || concave { vec![-radius_in_voxels, radius_in_voxels] } else { Vec::new() };
    tree.check_offset_steps(format!("round by {radius_in_voxels} voxels"), &steps, true, options.budget)?;
    let mut solid = (tree.clone(), surface.clone());
    if convex {
        let (eroded, data) = offset_with_surface(&solid.0, &solid.1, -radius_in_voxels, options)?;
        let opened = offset_with_surface(&eroded, &data, radius_in_voxels, options)?;
        solid = combined(SetOp::Intersection, &opened, &solid)?;
    }
    if concave {
        let (grown, data) = offset_with_surface(&solid.0, &solid.1, radius_in_voxels, options)?;
        let closed = offset_with_surface(&grown, &data, -radius_in_voxels, options)?;
        solid = combined(SetOp::Union, &closed, &solid)?;
    }
    Ok(solid)
}

/// `a op b` with its crossings from theirs.
fn combined(
    op: SetOp,
    a: &(LinearOctree, HermiteData),
    b: &(LinearOctree, HermiteData),
) -> Result<(LinearOctree, HermiteData)> {
    let result = a.0.combine(&b.0, op)?;
    let data = HermiteData::combine(op, &[(&a.0, &a.1), (&b.0, &b.1)], &result)?;
    Ok((result, data))
}

/// The crossings of `result`'s boundary faces: the step's new ones (the first of a
/// face given twice), else the old solid's where the face was its own, else none.
fn result_surface(result: &LinearOctree, old: &HermiteData, new: Vec<NewCrossing>) -> HermiteData {
    let new = HermiteData::from_faces(
        new.into_iter()
            .map(|c| {
                (FaceKey { voxel: c.voxel, direction: c.direction }, Crossing { t: c.t, normal: Vec3::from(c.normal) })
            })
            .collect(),
    );
    // All three lists are sorted by face: each chunk of the faces walks the two
    // crossing lists from where its first face would lie.
    let (new, old) = (new.faces(), old.faces());
    let faces: Vec<(FaceKey, Crossing)> = boundary_faces(result)
        .par_chunks(1 << 12)
        .flat_map_iter(|chunk| {
            let mut a = new.partition_point(|(k, _)| *k < chunk[0]);
            let mut b = old.partition_point(|(k, _)| *k < chunk[0]);
            chunk.iter().filter_map(move |&key| {
                while a < new.len() && new[a].0 < key {
                    a += 1;
                }
                if a < new.len() && new[a].0 == key {
                    return Some((key, new[a].1));
                }
                while b < old.len() && old[b].0 < key {
                    b += 1;
                }
                (b < old.len() && old[b].0 == key).then(|| (key, old[b].1))
            })
        })
        .collect();
    HermiteData::from_sorted(faces)
}

/// Fails unless `value` is finite and positive.
fn positive(what: &'static str, value: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(what, format!("{value} is not a finite positive number of voxels")))
    }
}
