//! Hermite data of a `.vdb` level set: each boundary face's crossing from the signed
//! distances at the two voxel centres, and the normal from their gradient.
//!
//! A level set stores, in a narrow band about the surface, the signed distance at each
//! voxel centre (negative inside), and octsolid reads a voxel as full where it is
//! negative. Along a boundary face's segment, from the full voxel's centre (distance
//! `d0 < 0`) to the empty one's (`d1 >= 0`), the crossing is the zero of the linear
//! interpolation, `t = d0 / (d0 - d1)` (OpenVDB's `volumeToMesh` places its edge points
//! the same way). The normal is the distance's gradient there: the central differences
//! `(d(c + e_a) - d(c - e_a)) / 2` at both centres, interpolated by `t` (a one-sided
//! difference where a neighbour is outside the band, the other centre's gradient where
//! a centre has none on any axis), normalized; the face's axis where it vanishes.
//!
//! Only leaf voxels carry distances: a face with a centre in a tile (a band thinner
//! than a voxel there) is left out, and the extractor estimates it. Fog volumes and
//! bool grids hold no distances and give no crossings.

use std::collections::HashMap;

use glam::DVec3;
use rayon::prelude::*;

use crate::octree::LinearOctree;
use crate::surface::{Crossing, FaceKey, HermiteData};

/// Voxels a side of a leaf (OpenVDB's `LeafNode` of `8^3`).
const LEAF: i64 = 8;

/// The distances of a level set's leaves, by leaf origin in index space.
#[derive(Default)]
pub(crate) struct LevelSetValues {
    leaves: HashMap<[i64; 3], Box<[f32; 512]>>,
}

impl LevelSetValues {
    /// Keeps the 512 values of the leaf at `origin` (x slowest, z fastest).
    pub(crate) fn insert(&mut self, origin: [i64; 3], values: &[f64]) {
        let mut leaf = Box::new([0f32; 512]);
        for (to, &from) in leaf.iter_mut().zip(values) {
            *to = from as f32;
        }
        self.leaves.insert(origin, leaf);
    }

    /// The distance at index `c`, if a leaf holds it.
    fn at(&self, c: [i64; 3]) -> Option<f64> {
        let origin = c.map(|v| v.div_euclid(LEAF) * LEAF);
        let leaf = self.leaves.get(&origin)?;
        let [x, y, z] = [0, 1, 2].map(|a| (c[a] - origin[a]) as usize);
        Some(f64::from(leaf[(x << 6) | (y << 3) | z]))
    }

    /// The central-difference gradient at index `c` (one-sided where a neighbour has no
    /// value; `None` when an axis has neither).
    fn gradient(&self, c: [i64; 3]) -> Option<DVec3> {
        let here = self.at(c)?;
        let mut g = DVec3::ZERO;
        for a in 0..3 {
            let (mut lo, mut hi) = (c, c);
            lo[a] -= 1;
            hi[a] += 1;
            g[a] = match (self.at(lo), self.at(hi)) {
                (Some(l), Some(h)) => 0.5 * (h - l),
                (None, Some(h)) => h - here,
                (Some(l), None) => here - l,
                (None, None) => return None,
            };
        }
        Some(g)
    }

    /// The crossings of the boundary faces of `tree`, the level set's solid, whose
    /// lattice voxel `v` is index `v + origin` (module doc).
    pub(crate) fn crossings(&self, tree: &LinearOctree, origin: [i64; 3]) -> HermiteData {
        let faces = crate::surface::boundary_faces(tree);
        let faces: Vec<(FaceKey, Crossing)> =
            faces.par_iter().filter_map(|&key| self.crossing(key, origin).map(|c| (key, c))).collect();
        HermiteData::from_sorted(faces)
    }

    /// The crossing of face `key`, or `None` when a centre has no distance or the
    /// distances disagree with the voxels.
    fn crossing(&self, key: FaceKey, origin: [i64; 3]) -> Option<Crossing> {
        let v = key.voxel();
        let c0 = [0, 1, 2].map(|a| i64::from(v[a]) + origin[a]);
        let mut c1 = c0;
        c1[key.axis()] += if key.positive() { 1 } else { -1 };
        let (d0, d1) = (self.at(c0)?, self.at(c1)?);
        if !(d0 < 0.0 && d1 >= 0.0) {
            return None;
        }
        let t = d0 / (d0 - d1);
        let gradient = match (self.gradient(c0), self.gradient(c1)) {
            (Some(g0), Some(g1)) => g0.lerp(g1, t),
            (Some(g), None) | (None, Some(g)) => g,
            (None, None) => DVec3::ZERO,
        };
        let normal = gradient.try_normalize().unwrap_or_else(|| key.outward());
        Some(Crossing { t: t as f32, normal: normal.as_vec3() })
    }
}
