//! Rooms of boxes for the radiosity suites: the cube [-1, 1]^3 at depth 6 (voxels of
//! 1/32, so every box given on that lattice is voxelized exactly) and grey diffuse
//! materials.

use glam::DVec3;
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::Material;
use octsolid::shape::{Cuboid, Shape};

/// The domain of every room: the cube [-1, 1]^3 at depth 6.
pub fn domain() -> Domain {
    Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap()
}

/// The box from `min` to `max`.
pub fn cuboid(min: [f64; 3], max: [f64; 3]) -> Cuboid {
    let (min, max) = (DVec3::from(min), DVec3::from(max));
    Cuboid::new((min + max) * 0.5, max - min).unwrap()
}

/// `shape` voxelized in [`domain`].
pub fn tree(shape: &dyn Shape) -> LinearOctree {
    voxelize(shape, domain(), &VoxelizeOptions::default()).unwrap()
}

/// A diffuse material of reflectance `rho` (grey) emitting `emission` (grey).
pub fn diffuse(rho: f64, emission: f64) -> Material {
    Material { color: DVec3::splat(rho), kd: 1.0, emission: DVec3::splat(emission), ..Material::default() }
}
