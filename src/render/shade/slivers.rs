//! Rays that leave a voxel staircase shaded as a smooth surface.
//!
//! With smooth normals a point is shaded on the smooth surface (the source shape's,
//! or the octree's estimate), but the solid a ray meets is the voxel staircase, whose
//! full voxels stand out of the smooth surface by up to half a voxel diagonal (a voxel
//! is full when its centre is inside, so every point of it lies within `sqrt(3) h / 2`
//! of an inside point) and whose empty voxels dig into it as much. A secondary ray
//! leaving the smooth surface therefore meets voxels of its own solid that the smooth
//! surface says it has already left: at grazing light a whole band of a curved part
//! shadows itself, and reflections fill with speckles of the part's own colour.
//!
//! Reflected and refracted rays (`whitted`): a hit on a voxel face is a *sliver* when
//! the smooth surface's outward normal there points along the ray (`n . d > 0`): the
//! ray is leaving the smooth surface, not entering it, so no surface is there; the ray
//! goes on from where it leaves that solid's voxels ([`past`]: its exit, walked
//! through the complement's traversal octree, or the domain's boundary), and may meet
//! the solid again further on. A real surface ahead, of the same solid (across a bore,
//! a concave corner) or of another, is entered, so its smooth normal faces the ray and
//! it is hit, however near. A ray that starts inside a full voxel (at a voxel's edge
//! or corner, or under a sliver) is the same case at `t = 0`. Where the smooth normal
//! is not known (axis normals, no gradient) a hit is a hit. Departures: a ray meeting
//! a surface at grazing incidence may be decided either way within a voxel of where
//! it touches, and at most [`MAX_SLIVERS`] slivers are passed a sample, after which a
//! hit is a hit.
//!
//! Shadow rays ([`transmittance`]) ask only whether anything lies between, millions
//! of times a picture, so they skip their own solid's staircase by a bound instead of
//! looking at each sliver: no voxel of a solid reaches more than `sqrt(3) h / 2` out of
//! its smooth surface, so a shadow ray walks its own solid from that far along the
//! normal ([`clear_of_staircase`]), and every other solid from the surface itself.

use glam::DVec3;

use super::Normals;
use super::normals::smooth_at;
use crate::ray::{Ray, RayCast};
use crate::render::scene::{Cast, Scene, SceneSolid};

/// Most staircase slivers one sample's rays pass through (a ray grazing a voxelized
/// surface meets one a step); they do not count against the recursion depth.
pub(crate) const MAX_SLIVERS: u32 = 256;

/// Rays start this far off a face of `solid`: a thousandth of its voxel.
pub(crate) fn eps(solid: &SceneSolid) -> f64 {
    1e-3 * solid.tree.domain().voxel_size()
}

/// Whether the point `q` of `solid`, met by a ray along `dir`, is a sliver: the smooth
/// outward normal there (under `normals`) points along the ray.
pub(crate) fn is_sliver(solid: &SceneSolid, q: DVec3, dir: DVec3, normals: Normals) -> bool {
    smooth_at(solid, q, normals).0.is_some_and(|n| n.dot(dir) > 0.0)
}

/// Where a ray along `dir` that is inside `solid` at `inside` (a point a little
/// within its voxels) leaves them: a point just past the exit face (past the domain's
/// boundary when it leaves through that).
pub(crate) fn past(solid: &SceneSolid, inside: DVec3, dir: DVec3) -> DVec3 {
    let eps = eps(solid);
    match solid.exit(&Ray::new(inside, dir)) {
        Some(exit) if exit.axis.is_some() => inside + dir * exit.t - exit.normal(dir) * eps,
        // Already outside (nudged across an edge or corner into an empty voxel).
        Some(_) => inside + dir * eps,
        None => {
            let (lo, hi) = (solid.tree.domain().aabb().min, solid.tree.domain().aabb().max);
            let t = (0..3)
                .filter(|&a| dir[a] != 0.0)
                .map(|a| ((if dir[a] > 0.0 { hi[a] } else { lo[a] }) - inside[a]) / dir[a])
                .fold(f64::INFINITY, f64::min);
            inside + dir * (t.max(0.0) + eps)
        }
    }
}

/// How far along the normal a shadow ray of a solid of voxel `h` starts its walk
/// through its own octree, clear of its own staircase where the surface is flat or
/// convex: every point of a full voxel lies within half a diagonal, `sqrt(3) h / 2`, of
/// its centre, which is inside, so no voxel reaches further out of the smooth surface;
/// from a point on the smooth surface (`on_shape`) that far, from a point on a voxel
/// face (the octree's estimated normals), which lies up to as far inside, twice that.
pub(crate) fn clear_of_staircase(h: f64, on_shape: bool) -> f64 {
    let half_diagonal = 0.5 * 3f64.sqrt() * h;
    if on_shape { half_diagonal } else { 2.0 * half_diagonal }
}

/// The fraction of light that passes along the shadow ray `ray` from a surface point
/// of solid `own`: the product of the transmittances of the solids that block it
/// (each counted once; no refraction of shadow rays), 0 when an opaque solid blocks
/// it. Every other solid's octree is walked from the ray's origin, so nothing of
/// theirs is skipped however near (a shadow ray that started a few voxels along the
/// normal moved every contact shadow by that much); `own`'s from the origin moved by
/// `lift` (with smooth normals [`clear_of_staircase`] along the normal: where `own`
/// is flat or convex no voxel of its own lies between, so its staircase never
/// shadows it; where it is concave, what is skipped lies within a voxel or two of the
/// point; with axis normals zero: the face is the surface). The ray keeps its
/// direction and end, so the light moves by as much as the origin.
pub(crate) fn transmittance(scene: &Scene, own: usize, ray: &Ray, lift: DVec3) -> f64 {
    let mut passed = 1.0;
    for (i, solid) in scene.solids.iter().enumerate() {
        let walked = if i == own { Ray { origin: ray.origin + lift, ..*ray } } else { *ray };
        if solid.walker(Cast::Shadow).occluded(&walked) {
            passed *= solid.material.transmittance;
            if passed == 0.0 {
                break;
            }
        }
    }
    passed
}
