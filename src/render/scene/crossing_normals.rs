//! Smooth shading normals from a solid's surface data (`surface::HermiteData`): the
//! exact normals where the surface crosses the segments between voxel centres, carried
//! by `.oct` files and through `csg` of files, so a solid read back from a file shades
//! as smoothly as the shape it was made from, without rings.
//!
//! At a surface point `p` (lattice units), the normal is the weighted mean of the
//! crossing normals `n_i` of the eight voxels whose centres surround `p` (the full
//! ones: crossings are keyed by their full voxel),
//!
//! ```text
//! n(p) = normalize( sum_i  w_i (1 - |x_i - p|^2 / R^2)^2  n_i ),   R = 1 voxel,
//! ```
//!
//! `x_i` the crossing point and `w_i` its voxel's trilinear weight at `p` (a moving
//! least-squares mean with a compactly supported kernel, as point-set surfaces weight
//! their samples; Alexa et al. 2001). The kernel goes to zero at one voxel, so the mean
//! is continuous in `p` and the normals of the far side of a one-voxel wall (a voxel
//! away) never cancel the near side's. Every point of a boundary face has its full
//! voxel's crossing on that face within `sqrt(3)/2` voxel, so a face with a crossing
//! always has a normal.
//!
//! Departure: crossings of faces without data (`Crossing::face`) are not stored, so a
//! solid whose data covers part of its boundary shades the rest with the octree's
//! estimate (`None` here).

use glam::DVec3;

use crate::morton;
use crate::octree::Domain;
use crate::surface::{Crossing, FaceKey, HermiteData};

/// Kernel radius, in voxels.
const RADIUS: f64 = 1.0;

/// A solid's crossings, looked up for shading.
#[derive(Clone, Debug)]
pub(crate) struct CrossingNormals {
    data: std::sync::Arc<HermiteData>,
}

impl CrossingNormals {
    /// The normals of `data` (crossings of a solid's boundary faces).
    pub(crate) fn new(data: HermiteData) -> Self {
        CrossingNormals { data: std::sync::Arc::new(data) }
    }

    /// The crossings of voxel `v`'s faces.
    fn of_voxel(&self, v: [u32; 3]) -> &[(FaceKey, Crossing)] {
        let code = morton::encode(v[0], v[1], v[2]);
        let faces = self.data.faces();
        let first = faces.partition_point(|(k, _)| k.voxel < code);
        let last = first + faces[first..].partition_point(|(k, _)| k.voxel == code);
        &faces[first..last]
    }

    /// The outward unit normal at the surface point `p` (world units) of a solid over
    /// `domain`; `None` where no crossing lies within the kernel's reach.
    pub(crate) fn normal(&self, domain: &Domain, p: DVec3) -> Option<DVec3> {
        let q = (p - domain.min()) * domain.voxels_per_unit();
        let low = (q - 0.5).floor();
        let frac = q - 0.5 - low;
        let n = f64::from(domain.resolution());
        let mut sum = DVec3::ZERO;
        for corner in 0..8u32 {
            let offset = DVec3::new(f64::from(corner & 1), f64::from((corner >> 1) & 1), f64::from(corner >> 2));
            let c = low + offset;
            if c.min_element() < 0.0 || c.max_element() >= n {
                continue;
            }
            let weight = (0..3).map(|k| if offset[k] == 1.0 { frac[k] } else { 1.0 - frac[k] }).product::<f64>();
            if weight == 0.0 {
                continue;
            }
            for &(key, crossing) in self.of_voxel([c.x as u32, c.y as u32, c.z as u32]) {
                let d2 = (crossing.point(key) - q).length_squared() / (RADIUS * RADIUS);
                if d2 < 1.0 {
                    sum += weight * (1.0 - d2) * (1.0 - d2) * crossing.normal.as_dvec3();
                }
            }
        }
        sum.try_normalize()
    }
}
