//! Hermite data of a patch set's solid: the crossings of its tessellation (the mesh it
//! is voxelized as, [`HermiteData::from_mesh`]) moved onto the patches themselves
//! ([`HermiteData::from_patches`]).
//!
//! A solid of Bezier patches is the solid of their tessellation, so each boundary
//! face's crossing is first found on the tessellation's triangles under the voxelizer's
//! rule. The triangle names its patch and the `(u, v)` of its corners; the crossing's
//! barycentric coordinates on it give a starting `(u, v)`, and Newton's method solves
//! `p(u, v) = c0 + t s` (the patch point on the face's segment, `s` the segment's step)
//! for `(u, v, t)`, with the Jacobian `[p_u, p_v, -s]`. The normal is
//! `p_u x p_v / |p_u x p_v|` there, turned from the full voxel to the empty one.
//!
//! Departure: the voxels stay the tessellation's (within its chord error of the
//! patches), so a crossing Newton moves off the segment (`t` outside `0..=1`), off its
//! patch (`u` or `v` outside `0..=1`), more than half a voxel along it, or that does
//! not converge keeps the tessellation's crossing.

use glam::{DMat3, DVec2, DVec3};
use rayon::prelude::*;

use super::hermite::{Crossing, FaceKey, HermiteData};
use super::hermite_mesh::mesh_crossings;
use crate::mesh::{InsideRule, TriangleMesh};
use crate::octree::{Domain, LinearOctree};
use crate::patch::{BezierPatch, TriangleParams};

/// Newton steps at most.
const NEWTON_STEPS: usize = 12;
/// Converged when the step in `(u, v, t)` is below this.
const NEWTON_TOLERANCE: f64 = 1e-12;
/// Largest move along the segment, in voxels, from the tessellation's crossing.
const MAX_MOVE: f64 = 0.5;

impl HermiteData {
    /// Crossings and normals of `patches` on the boundary faces of `tree`, the solid
    /// voxelization under `rule` of their tessellation `mesh` whose triangles' patches
    /// and parameters are `params` ([`crate::patch::tessellate_with_params`]): the
    /// tessellation's crossings moved onto the patches (see the module doc).
    #[must_use]
    pub fn from_patches(
        patches: &[BezierPatch],
        mesh: &TriangleMesh,
        params: &[TriangleParams],
        rule: InsideRule,
        tree: &LinearOctree,
    ) -> Self {
        let domain = *tree.domain();
        let faces = mesh_crossings(mesh, rule, tree)
            .into_par_iter()
            .map(|(key, crossing, triangle)| {
                let on_patch = triangle
                    .and_then(|t| params.get(t as usize).map(|p| (t, p)))
                    .and_then(|(t, p)| onto_patch(patches, mesh, t, p, &domain, key, crossing));
                (key, on_patch.unwrap_or(crossing))
            })
            .collect();
        HermiteData::from_sorted(faces)
    }
}

/// The crossing of face `key`, found at `crossing` on triangle `t` of `mesh` (cut from
/// the patch and at the parameters `p` names), moved onto the patch; `None` when
/// Newton's method does not settle on the segment and the patch.
fn onto_patch(
    patches: &[BezierPatch],
    mesh: &TriangleMesh,
    t: u32,
    p: &TriangleParams,
    domain: &Domain,
    key: FaceKey,
    crossing: Crossing,
) -> Option<Crossing> {
    let patch = patches.get(p.patch as usize)?;
    let c0 = domain.voxel_center(key.voxel());
    let step = key.outward() * domain.voxel_size();
    let start_t = f64::from(crossing.t);
    let x = c0 + step * start_t;
    // Barycentric coordinates of the crossing on the triangle give the start.
    let [a, b, c] = mesh.corners(t as usize);
    let n = (b - a).cross(c - a);
    let area = n.length_squared();
    if area == 0.0 {
        return None;
    }
    let wb = (x - a).cross(c - a).dot(n) / area;
    let wc = (b - a).cross(x - a).dot(n) / area;
    let uv: DVec2 = p.uv[0] * (1.0 - wb - wc) + p.uv[1] * wb + p.uv[2] * wc;
    let mut unknown = DVec3::new(uv.x, uv.y, start_t);
    let mut converged = false;
    for _ in 0..NEWTON_STEPS {
        let (u, v, along) = (unknown.x, unknown.y, unknown.z);
        let residual = patch.eval(u, v) - (c0 + step * along);
        let (pu, pv) = patch.tangents(u, v);
        let jacobian = DMat3::from_cols(pu, pv, -step);
        if jacobian.determinant().abs() < 1e-300 {
            return None;
        }
        let delta = jacobian.inverse() * -residual;
        unknown += delta;
        if !unknown.is_finite() {
            return None;
        }
        if delta.abs().max_element() < NEWTON_TOLERANCE {
            converged = true;
            break;
        }
    }
    let (u, v, along) = (unknown.x, unknown.y, unknown.z);
    let inside = |x: f64| (-1e-9..=1.0 + 1e-9).contains(&x);
    if !converged || !inside(u) || !inside(v) || !inside(along) || (along - start_t).abs() > MAX_MOVE {
        return None;
    }
    let normal = patch.normal(u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
    if normal == DVec3::ZERO {
        return None;
    }
    let normal = if normal.dot(key.outward()) < 0.0 { -normal } else { normal };
    Some(Crossing { t: along.clamp(0.0, 1.0) as f32, normal: normal.as_vec3() })
}
