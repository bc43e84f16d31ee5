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

use super::faces::{is_boundary_face, neighbour};
use super::hermite::{Crossing, FaceKey, HermiteData};
use crate::error::{Error, Result};
use crate::octree::{FaceCrossings, LinearOctree, NewCrossing, OffsetOptions, SetOp};
use crate::progress::Stages;

impl FaceCrossings for HermiteData {
    fn face_crossing(&self, voxel: u64, direction: u8) -> Option<(f32, [f32; 3])> {
        self.get(FaceKey { voxel, direction }).map(|c| (c.t, c.normal.to_array()))
    }

    /// The voxel's faces lie together in the sorted list: one search finds them all.
    fn voxel_crossings(&self, voxel: u64, directions: u8) -> [Option<(f32, [f32; 3])>; 6] {
        let faces = self.faces();
        let start = faces.partition_point(|(key, _)| key.voxel < voxel);
        let mut out = [None; 6];
        for (key, c) in faces[start..].iter().take_while(|(key, _)| key.voxel == voxel) {
            if key.direction < 6 && (directions >> key.direction) & 1 == 1 {
                out[usize::from(key.direction)] = Some((c.t, c.normal.to_array()));
            }
        }
        out
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
    let data = result_surface(&result, surface, new, distance_in_voxels != 0.0);
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
    tree.check_offset_steps(
        format!("shell of {} voxels", crate::error::in_voxels(thickness_in_voxels)),
        &[step],
        true,
        options.budget,
    )?;
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
    tree.check_offset_steps(
        format!("round by {} voxels", crate::error::in_voxels(radius_in_voxels)),
        &steps,
        true,
        options.budget,
    )?;
    // Two offsets a kind of edge, on one bar.
    let stages = Stages::new(options.progress, 2 * (u64::from(convex) + u64::from(concave)));
    let options = &OffsetOptions { progress: &stages, ..*options };
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

/// The crossings of `result`'s boundary faces: the step's new ones (sorted by face,
/// each once), else the old solid's where the face was its own, else none.
///
/// A step that `reached` a voxel (a distance other than 0) gives a new crossing on
/// every boundary face of its result between two voxels of the domain
/// ([`LinearOctree::offset_along_surface`]), so the old solid's count only on the
/// domain's own faces, where their voxel is still full: the result's faces are never
/// listed. A step of 0 gives none, and the old crossings of the result's faces stay.
fn result_surface(result: &LinearOctree, old: &HermiteData, new: Vec<NewCrossing>, reached: bool) -> HermiteData {
    // Sorted by face, each once (`offset_along_surface`).
    let new: Vec<(FaceKey, Crossing)> = new
        .into_par_iter()
        .map(|c| {
            (FaceKey { voxel: c.voxel, direction: c.direction }, Crossing { t: c.t, normal: Vec3::from(c.normal) })
        })
        .collect();
    let n = result.domain().resolution();
    let kept: Vec<(FaceKey, Crossing)> = old
        .faces()
        .par_iter()
        .filter(|(key, _)| (!reached || neighbour(*key, n).is_none()) && is_boundary_face(result, *key))
        .copied()
        .collect();
    if kept.is_empty() {
        return HermiteData::from_sorted(new);
    }
    // Both sorted by face; a face in both (none when `reached`) keeps the new crossing.
    let mut faces = Vec::with_capacity(new.len() + kept.len());
    let mut b = 0;
    for &(key, crossing) in &new {
        while b < kept.len() && kept[b].0 < key {
            faces.push(kept[b]);
            b += 1;
        }
        if b < kept.len() && kept[b].0 == key {
            b += 1;
        }
        faces.push((key, crossing));
    }
    faces.extend_from_slice(&kept[b..]);
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface::faces::boundary_faces;
    use crate::test_util::{BoxesAndNoise, Rng, boxes_and_noise};

    /// A solid at depth 5 of a few random boxes, some against the domain's faces, and
    /// scattered voxels, with a random crossing on every boundary face.
    fn random_solid(rng: &mut Rng) -> (LinearOctree, HermiteData) {
        let how = BoxesAndNoise { fewest: 2, more: 3, against_face: 3, shortest: 2, noise: 80 };
        let tree = boxes_and_noise(rng, &how);
        let faces = boundary_faces(&tree)
            .into_iter()
            .map(|key| {
                let normal = (key.outward() + rng.vec(-0.4, 0.4)).normalize().as_vec3();
                (key, Crossing { t: rng.range(0.05, 0.95) as f32, normal })
            })
            .collect();
        (tree, HermiteData::from_faces(faces))
    }

    /// The crossings by the definition: on each of the result's boundary faces (listed
    /// from the tree), the step's new one, else the old one.
    fn by_definition(result: &LinearOctree, old: &HermiteData, new: &[NewCrossing]) -> HermiteData {
        let mut new: Vec<(FaceKey, Crossing)> = new
            .iter()
            .map(|c| {
                (FaceKey { voxel: c.voxel, direction: c.direction }, Crossing { t: c.t, normal: Vec3::from(c.normal) })
            })
            .collect();
        new.sort_by_key(|(key, _)| *key);
        new.dedup_by_key(|(key, _)| *key);
        let find =
            |list: &[(FaceKey, Crossing)], key| list.binary_search_by_key(&key, |(k, _)| *k).ok().map(|i| list[i]);
        HermiteData::from_sorted(
            boundary_faces(result)
                .into_iter()
                .filter_map(|key| find(&new, key).or_else(|| find(old.faces(), key)))
                .collect(),
        )
    }

    #[test]
    fn the_result_keeps_old_crossings_only_on_the_domain_faces_and_equals_the_definition() {
        let mut rng = Rng(0x39_5f0e);
        let mut on_domain_faces = 0;
        for round in 0..4 {
            let (tree, old) = random_solid(&mut rng);
            for distance in [0.0, 0.8, -1.3, 2.6, -3.4, 5.1] {
                let (result, data) = offset_with_surface(&tree, &old, distance, &OffsetOptions::default()).unwrap();
                let (again, new) = tree.offset_along_surface(distance, &old, &OffsetOptions::default()).unwrap();
                assert_eq!(again, result);
                assert_eq!(data, by_definition(&result, &old, &new), "round {round} distance {distance}");
                let n = result.domain().resolution();
                on_domain_faces += data.faces().iter().filter(|(key, _)| neighbour(*key, n).is_none()).count();
            }
        }
        assert!(on_domain_faces > 100, "{on_domain_faces} crossings on the domain's faces");
    }
}
