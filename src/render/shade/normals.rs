//! Shading normals. [`Normals::Axis`] is the entered face's axis normal;
//! [`Normals::Smooth`] the source shape's normal where there is one (within two voxels
//! of the hit), else (and always with [`Normals::Octree`]) the octree's occupancy
//! gradient (`scene::NormalField`); a smooth normal falls back to the axis normal
//! where it would face away from the viewer. A material's bump map then tilts it.

use glam::DVec3;

use crate::ray::Ray;
use crate::render::scene::{Scene, SceneHit, SceneSolid};
use crate::render::trace::Hit;

/// Which normal shades a surface. Scene files write it in snake case (`normals =
/// "smooth"`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normals {
    /// The entered voxel face's axis normal (exact for the voxel solid).
    #[default]
    Axis,
    /// The source shape's normal where the solid was voxelized from a shape that
    /// knows its surface ([`crate::shape::Shape::surface`]) and the hit lies within
    /// two voxels of that surface; else the octree's estimate.
    Smooth,
    /// Estimated from the octree's occupancy around the hit (`scene::NormalField`).
    Octree,
}

impl std::str::FromStr for Normals {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "axis" => Ok(Normals::Axis),
            "smooth" => Ok(Normals::Smooth),
            "octree" => Ok(Normals::Octree),
            other => Err(format!("{other:?} is not axis, smooth or octree")),
        }
    }
}

/// The smooth surface at the surface point `p` of `solid` under the normals `mode`:
/// the outward normal and the point where textures are looked up. With
/// [`Normals::Smooth`] and a source shape whose surface lies within two voxels of `p`:
/// the shape's normal, and `p` moved onto that surface (`p - d n`), so pictures do not
/// follow the voxel staircase. Else the octree's estimate (`None` without a gradient,
/// and always with [`Normals::Axis`]) at `p` itself.
#[must_use]
pub fn smooth_at(solid: &SceneSolid, p: DVec3, mode: Normals) -> (Option<DVec3>, DVec3) {
    if mode == Normals::Axis {
        return (None, p);
    }
    match solid.shape_surface(p).filter(|_| mode == Normals::Smooth) {
        Some(s) => (Some(s.normal), p - s.normal * s.distance),
        None => (solid.estimated_normal(p), p),
    }
}

/// The geometric and the shading normal at a hit of the ray direction `dir`, both unit
/// and facing the ray (for a hit with no face, the origin inside: `-dir`), from the
/// raw smooth estimate `smooth` (outward; `None` with axis normals).
#[must_use]
fn normals_at(solid: &SceneSolid, hit: &Hit, dir: DVec3, p: DVec3, smooth: Option<DVec3>) -> (DVec3, DVec3) {
    let axis = hit.normal(dir);
    let geometric = if axis == DVec3::ZERO { -dir } else { axis };
    let shading = smooth.filter(|n| n.dot(dir) < 0.0).unwrap_or(geometric);
    let shading = match &solid.material.bump {
        Some(bump) => bump.perturb(p, shading),
        None => shading,
    };
    (geometric, shading)
}

/// A shaded point: where a ray of direction `dir` hit solid `solid`, with the
/// geometric and shading normals of `normals_at`.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// Index of the solid.
    pub solid: usize,
    /// The point.
    pub p: DVec3,
    /// Unit direction of the arriving ray.
    pub dir: DVec3,
    /// The face's axis normal, facing the ray.
    pub geometric: DVec3,
    /// The normal that shades.
    pub normal: DVec3,
    /// The smooth estimate of the outward normal, when smooth normals are on.
    pub smooth: Option<DVec3>,
    /// Where the material's texture is looked up ([`smooth_at`]).
    pub texture_at: DVec3,
}

impl SurfacePoint {
    /// The point where `ray` (unit direction) hits `sh`.
    #[must_use]
    pub fn new(scene: &Scene, ray: &Ray, sh: &SceneHit, mode: Normals) -> Self {
        let (p, dir) = (ray.at(sh.hit.t), ray.dir);
        let solid = &scene.solids[sh.solid];
        let (smooth, texture_at) = smooth_at(solid, p, mode);
        let (geometric, normal) = normals_at(solid, &sh.hit, dir, p, smooth);
        SurfacePoint { solid: sh.solid, p, dir, geometric, normal, smooth, texture_at }
    }
}
