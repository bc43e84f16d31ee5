//! Hermite data through the exact moves of a solid: a cube symmetry times a scale plus
//! a translation ([`LinearOctree::transformed`]'s exact path), then a whole-voxel
//! offset into the target domain ([`Fit::Exact`] without refinement).
//!
//! Such a map `p -> s P p + t` (`P` a signed permutation: output axis `i` is
//! `sign_i` times input axis `perm[i]`) sends voxel `c` to the voxel `c'` with
//! `c'_i = c_perm[i]`, or `N - 1 - c_perm[i]` where axis `i` is mirrored, then moved by
//! the offset; a face towards `+a` or `-a` goes to the face of `c'` along the output
//! axis `i` with `perm[i] = a`, its side flipped where `i` is mirrored. The segment
//! between two voxel centres goes to the segment between their images, scaled by `s`
//! like the voxels, so `t` (in voxels, from the full voxel) is kept; the normal goes by
//! `P^-T = P` (orthogonal), `n'_i = sign_i n_perm[i]`, and stays a unit vector.
//!
//! Nothing else keeps the data: a refinement splits each face into finer faces whose
//! segments the old crossings do not lie on, and a resampling makes other voxels. Then
//! [`HermiteData::transformed`] gives `None` and the caller drops the data or
//! recomputes it from a shape it has. Faces moved out of the target domain are
//! dropped with their voxels.

use glam::{DAffine3, Vec3};
use rayon::prelude::*;

use super::faces::is_boundary_face;
use super::hermite::{Crossing, FaceKey, HermiteData};
use crate::octree::{CubeSymmetry, Domain, Fit, LinearOctree};

impl HermiteData {
    /// This data of a solid over `source` moved as [`LinearOctree::transformed`] moved
    /// the solid by `map` into `moved`, with `fit` the way it says it moved it: the
    /// faces carried along (see the module doc) when the move was exact and kept the
    /// depth (a cube symmetry times a scale, then [`Fit::Same`] or [`Fit::Exact`]
    /// without refinement); `None` otherwise, when the voxels are not the moved ones.
    #[must_use]
    pub fn transformed(&self, source: &Domain, map: DAffine3, moved: &LinearOctree, fit: Fit) -> Option<HermiteData> {
        let symmetry = CubeSymmetry::of(map.matrix3)?;
        let offset = match fit {
            Fit::Same => [0; 3],
            Fit::Exact { refined: 0, offset } => offset,
            Fit::Exact { .. } | Fit::Resampled => return None,
        };
        let n = i64::from(source.resolution());
        let target = i64::from(moved.domain().resolution());
        let CubeSymmetry { perm, mirrored, .. } = symmetry;
        let faces = self
            .faces()
            .par_iter()
            .filter_map(|&(key, crossing)| {
                let v = key.voxel();
                let mut w = [0u32; 3];
                let mut normal = Vec3::ZERO;
                let mut direction = 0;
                for i in 0..3 {
                    let a = perm[i];
                    let c = i64::from(v[a]);
                    let c = if mirrored[i] { n - 1 - c } else { c } + offset[i];
                    if !(0..target).contains(&c) {
                        return None;
                    }
                    w[i] = c as u32;
                    normal[i] = if mirrored[i] { -crossing.normal[a] } else { crossing.normal[a] };
                    if a == key.axis() {
                        direction = 2 * i as u8 + u8::from(key.positive() != mirrored[i]);
                    }
                }
                let key = FaceKey::new(w, direction);
                // Kept only where it is still a boundary face (a move never makes one
                // inner; this keeps the data a file may hold whatever the caller did).
                is_boundary_face(moved, key).then_some((key, Crossing { t: crossing.t, normal }))
            })
            .collect();
        Some(HermiteData::from_faces(faces))
    }
}
