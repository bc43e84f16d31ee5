//! Hermite data of a triangle mesh's solid: each boundary face's crossing where the
//! segment between the two voxel centres meets the mesh's triangles, and the
//! triangle's normal there ([`HermiteData::from_mesh`]).
//!
//! The mesh solid voxelizer (`mesh/solid.rs`) decides a voxel by the value of its
//! inside rule at the voxel's centre, carried between points by the **signed
//! crossings** of the segment joining them (`mesh/crossing.rs`: `+1` entering a
//! triangle against its normal, `-1` leaving, ties broken by one simulated
//! perturbation of every point). So along a boundary face's segment, from the full
//! voxel's centre `c0` to the empty one's `c1`, the rule's value changes exactly at the
//! triangles the segment crosses under that same count, and the crossing kept is one
//! where it changes from inside to outside:
//!
//! - **parity**: the `k`-th crossing from `c0` leaves the solid when `k` is odd; of
//!   those, the one nearest the face (`t = 1/2`);
//! - **winding**: the winding number at `c0` (the voxelizer's oracle,
//!   [`WindingNumber`], asked only when the segment crosses more than one triangle)
//!   plus the signed crossings passed; the crossings where it drops below `1/2`, and of
//!   those the one nearest the face.
//!
//! The crossing's place is where the segment meets the triangle's plane (`t = n . (a -
//! c0) / n . (c1 - c0)`, in voxels), its normal the triangle's unit normal turned to
//! point from the full voxel to the empty one (a parity mesh need not be consistently
//! oriented). A face whose segment crosses no triangle that changes the rule's side
//! (the winding number varying smoothly across a hole in the mesh, where it is not a
//! count of crossings) is left out: the extractor estimates it.
//!
//! Candidates: the triangles whose bounding box meets the segment's, from a bounding
//! hierarchy over the triangles (`mesh/triangle_tree.rs`); the exact signed crossing
//! decides each. Parallel over the faces.

use glam::DVec3;
use rayon::prelude::*;
use smallvec::SmallVec;

use super::hermite::{Crossing, FaceKey, HermiteData};
use crate::aabb::Aabb;
use crate::mesh::{InsideRule, Plane, TriangleMesh, TriangleTree, WindingNumber, signed_crossing, solid_triangles};
use crate::octree::{Domain, LinearOctree};

/// One crossing of a segment: its place along it (voxels), its sign (`+1` entering
/// against the triangle's normal, `-1` leaving) and the triangle.
#[derive(Clone, Copy)]
struct Hit {
    t: f64,
    sign: i32,
    triangle: u32,
}

/// The mesh, its triangle hierarchy, the rule and (for the winding rule) its oracle.
struct MeshCrossings<'m> {
    mesh: &'m TriangleMesh,
    tree: TriangleTree,
    winding: Option<WindingNumber>,
    domain: Domain,
}

impl HermiteData {
    /// Crossings and normals of the triangles of `mesh` on the boundary faces of
    /// `tree`, its solid voxelization under `rule` ([`crate::mesh::voxelize_mesh`];
    /// `Auto` resolved as the voxelizer resolves it: parity when the mesh is
    /// watertight). Faces whose segment crosses no triangle where the rule's side
    /// changes are left out (see the module doc).
    #[must_use]
    pub fn from_mesh(mesh: &TriangleMesh, rule: InsideRule, tree: &LinearOctree) -> Self {
        let faces = mesh_crossings(mesh, rule, tree).into_iter().map(|(key, crossing, _)| (key, crossing)).collect();
        HermiteData::from_sorted(faces)
    }
}

/// The crossings of [`HermiteData::from_mesh`], sorted by face, each with the index in
/// `mesh` of the triangle it lies on (`None` where the voxelizer's triangles are not
/// the mesh's own: some bounded nothing, [`solid_triangles`]).
pub(crate) fn mesh_crossings(
    mesh: &TriangleMesh,
    rule: InsideRule,
    tree: &LinearOctree,
) -> Vec<(FaceKey, Crossing, Option<u32>)> {
    if tree.is_empty() || mesh.validate().is_err() {
        return Vec::new();
    }
    // The triangles the voxelizer counts: those that bound a solid.
    let (mesh, _, _) = solid_triangles(mesh);
    let own = matches!(mesh, std::borrow::Cow::Borrowed(_));
    if mesh.triangles.is_empty() {
        return Vec::new();
    }
    let rule = match rule {
        InsideRule::Auto if mesh.is_watertight() => InsideRule::Parity,
        InsideRule::Auto => InsideRule::Winding,
        r => r,
    };
    let (triangles, winding) =
        rayon::join(|| TriangleTree::new(&mesh), || (rule == InsideRule::Winding).then(|| WindingNumber::new(&mesh)));
    let job = MeshCrossings { mesh: &mesh, tree: triangles, winding, domain: *tree.domain() };
    let faces = super::faces::boundary_faces(tree);
    faces.par_iter().filter_map(|&key| job.crossing(key).map(|(c, t)| (key, c, own.then_some(t)))).collect()
}

impl MeshCrossings<'_> {
    /// The crossing of face `key` (module doc) and its triangle, or `None`.
    fn crossing(&self, key: FaceKey) -> Option<(Crossing, u32)> {
        let c0 = self.domain.voxel_center(key.voxel());
        let step = key.outward() * self.domain.voxel_size();
        let c1 = c0 + step;
        let mut hits: SmallVec<[Hit; 4]> = SmallVec::new();
        self.tree.for_each_near(&Aabb { min: c0.min(c1), max: c0.max(c1) }, |t| {
            let plane = Plane::new(self.mesh, t);
            let sign = signed_crossing(self.mesh, &plane, t, c0, c1);
            if sign != 0 {
                let [a, b, c] = self.mesh.corners(t as usize);
                let n = (b - a).cross(c - a);
                let along = n.dot(step);
                let at = if along == 0.0 { 0.5 } else { (n.dot(a - c0) / along).clamp(0.0, 1.0) };
                hits.push(Hit { t: at, sign, triangle: t });
            }
        });
        let chosen = match hits.as_slice() {
            [] => return None,
            // One crossing: the side changes there, unless it enters (a winding
            // number varying across a hole, which no crossing accounts for).
            [one] => (self.winding.is_none() || one.sign < 0).then_some(*one)?,
            _ => {
                hits.sort_unstable_by(|a, b| a.t.total_cmp(&b.t));
                self.leaving(c0, &hits)?
            }
        };
        let [a, b, c] = self.mesh.corners(chosen.triangle as usize);
        let n = (b - a).cross(c - a).normalize_or_zero();
        let normal = if n == DVec3::ZERO {
            key.outward()
        } else if n.dot(key.outward()) < 0.0 {
            -n
        } else {
            n
        };
        Some((Crossing { t: chosen.t as f32, normal: normal.as_vec3() }, chosen.triangle))
    }

    /// Of `hits` (sorted along the segment from `c0`), the one nearest the face where
    /// the rule's side changes from inside to outside.
    fn leaving(&self, c0: DVec3, hits: &[Hit]) -> Option<Hit> {
        let nearest = |a: &&Hit, b: &&Hit| (a.t - 0.5).abs().total_cmp(&(b.t - 0.5).abs());
        match &self.winding {
            None => hits.iter().step_by(2).min_by(nearest).copied(),
            Some(winding) => {
                let mut value = winding.at(c0);
                let mut leaving: SmallVec<[&Hit; 4]> = SmallVec::new();
                for hit in hits {
                    let before = value >= 0.5;
                    value += f64::from(hit.sign);
                    if before && value < 0.5 {
                        leaving.push(hit);
                    }
                }
                leaving.into_iter().min_by(nearest).copied()
            }
        }
    }
}
