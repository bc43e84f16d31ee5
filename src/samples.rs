//! Bundled sample solids shared by the CLI's `demo`, tests and benches, so no one
//! writes a second showcase.

use std::sync::Arc;

use glam::DVec3;

use crate::error::Result;
use crate::octree::{Domain, VoxelizeOptions, voxelize};
use crate::render::{Light, Material, Scene};
use crate::shape::{Axis, Csg, Cuboid, Cylinder, Shape, ShapeExt, Sphere, Torus};

/// One line saying what [`showcase_scene`] shows.
pub const SCENE_DESCRIPTION: &str = "the classic CSG part inside a torus ring, a ball and a tilted cylinder on a floor, \
     two lights with shadows";

/// The showcase scene of `octsolid demo`: several solids with their own materials on a
/// floor, voxelized at `depth` in one domain, lit by a key and a fill light; each solid
/// keeps its shape, whose surface gives its smooth normals.
pub fn showcase_scene(depth: u8, options: &VoxelizeOptions) -> Result<Scene> {
    let domain = Domain::new(DVec3::new(-3.2, -3.2, -1.4), 6.4, depth)?;
    let part = classic_csg();
    let ring = Torus::new(DVec3::ZERO, Axis::Z, 1.55, 0.2)?;
    let ball = Sphere::new(DVec3::new(-2.1, -1.3, -0.4), 0.6)?;
    let post =
        Cylinder::new(DVec3::ZERO, Axis::Z, 0.35, 1.6)?.rotate(DVec3::X, 0.5).translate(DVec3::new(2.1, 1.3, -0.12));
    let floor = Cuboid::new(DVec3::new(0.0, 0.0, -1.1), DVec3::new(6.2, 6.2, 0.2))?;
    let material = |r, g, b, ks, shininess| Material::phong(DVec3::new(r, g, b), 0.2, 0.8, ks, shininess);
    let solids: [(&str, Arc<dyn Shape>, Material); 5] = [
        ("classic part", Arc::new(part), material(0.85, 0.42, 0.16, 0.35, 32.0)),
        ("ring", Arc::new(ring), material(0.12, 0.55, 0.55, 0.4, 48.0)),
        ("ball", Arc::new(ball), material(0.25, 0.32, 0.7, 0.5, 64.0)),
        ("post", Arc::new(post), material(0.75, 0.7, 0.25, 0.3, 24.0)),
        ("floor", Arc::new(floor), material(0.78, 0.78, 0.74, 0.05, 8.0)),
    ];
    let mut scene = Scene::new();
    for (name, shape, material) in solids {
        let tree = voxelize(shape.as_ref(), domain, options)?;
        scene.add_shaped(name, tree, material, shape);
    }
    scene.ambient = DVec3::splat(0.9);
    scene.lights = vec![
        Light::Point { position: DVec3::new(5.0, -4.0, 7.0), color: DVec3::splat(0.8) },
        Light::Directional { direction: DVec3::new(0.7, 0.9, -0.6), color: DVec3::splat(0.25) },
    ];
    Ok(scene)
}

/// The classic CSG part: a cube of side 2 intersected with a sphere of radius 1.3,
/// minus three cylinders of radius 0.6 along x, y and z (all centred at the origin).
#[must_use]
pub fn classic_csg() -> Csg {
    let cube = Cuboid::new(DVec3::ZERO, DVec3::splat(2.0)).expect("valid cube");
    let ball = Sphere::new(DVec3::ZERO, 1.3).expect("valid sphere");
    let bore = |axis| Cylinder::new(DVec3::ZERO, axis, 0.6, 3.0).expect("valid cylinder");
    (cube & ball) - bore(Axis::X) - bore(Axis::Y) - bore(Axis::Z)
}

/// The showcase solid of `octsolid demo`: the classic part inside a torus ring.
#[must_use]
pub fn showcase() -> Csg {
    classic_csg() | Torus::new(DVec3::ZERO, Axis::Z, 1.55, 0.2).expect("valid torus")
}

/// The showcase's domain at `depth`: the cube `[-1.8, 1.8]^3`.
pub fn showcase_domain(depth: u8) -> Result<Domain> {
    Domain::new(DVec3::splat(-1.8), 3.6, depth)
}
