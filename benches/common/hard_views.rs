//! Views where primary visibility is hard for an object-order method: the eye inside
//! a solid's domain, large planes seen at grazing angles, nodes reaching behind the
//! eye or far wider than the view. Shared by `benches/raster.rs` (`hard_views`: the
//! default method against the ray walk) and `tests/render.rs` (the same hits, and a
//! bound on the faces the display draws).
//!
//! The first is a scene written elsewhere: POV-Ray's side of the Whitted classic
//! (`benches/peers/whitted_classic.pov`) turned into a new user's scene, the part turned
//! 20 degrees about z over a floor that is a solid of its own 40-unit domain, seen from
//! `(3.2, -4.2, 2.6)`: before the display culled what lies behind the eye, one sample a
//! pixel at 200x150 drew 2.86 M faces (100 s) where the walk took 0.04 s.

use glam::{DAffine3, DVec3};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::{Camera, Material, Scene};
use octsolid::samples::classic_csg;
use octsolid::shape::{Cuboid, Transformed};

/// A scene and a camera of one hard view.
pub struct HardView {
    /// Short name (a benchmark id).
    pub name: &'static str,
    pub scene: Scene,
    pub camera: Camera,
}

/// The classic part turned 20 degrees about z, voxelized at `depth` in `[-1.4, 1.4]^3`.
fn turned_part(depth: u8) -> LinearOctree {
    let turned = Transformed::new(classic_csg(), DAffine3::from_rotation_z(20f64.to_radians())).unwrap();
    voxelize(&turned, Domain::new(DVec3::splat(-1.4), 2.8, depth).unwrap(), &VoxelizeOptions::default()).unwrap()
}

/// A 40 x 40 x 0.2 floor under z = -1, voxelized at `depth` in its own cube
/// `[-20, 20]^2 x [-21, 19]` (`octsolid shape box --size 40,40,0.2 --center 0,0,-1.1
/// --domain -20,-20,-21,40`).
fn big_floor(depth: u8) -> LinearOctree {
    let slab = Cuboid::new(DVec3::new(0.0, 0.0, -1.1), DVec3::new(40.0, 40.0, 0.2)).unwrap();
    voxelize(&slab, Domain::new(DVec3::new(-20.0, -20.0, -21.0), 40.0, depth).unwrap(), &VoxelizeOptions::default())
        .unwrap()
}

fn scene(solids: Vec<LinearOctree>) -> Scene {
    let mut scene = Scene::new();
    for (i, tree) in solids.into_iter().enumerate() {
        scene.add(format!("solid {i}"), tree, Material::default());
    }
    scene
}

/// The hard views, the floor at depth `floor_depth` (10 in the bench) and the part at
/// `floor_depth - 1`.
pub fn hard_views(floor_depth: u8) -> Vec<HardView> {
    let (part, floor) = (turned_part(floor_depth - 1), big_floor(floor_depth));
    let z = DVec3::Z;
    vec![
        HardView {
            name: "floor_behind_eye",
            scene: scene(vec![part.clone(), floor.clone()]),
            camera: Camera::look_at(DVec3::new(3.2, -4.2, 2.6), DVec3::ZERO, z, 30.5),
        },
        HardView {
            // 0.1 above the floor's top, looking 39 units across it: half a degree.
            name: "grazing_floor",
            scene: scene(vec![floor]),
            camera: Camera::look_at(DVec3::new(0.0, -19.0, -0.9), DVec3::new(0.0, 20.0, -1.0), z, 40.0),
        },
        HardView {
            // Inside the x bore, looking at the part's centre: every node about the eye.
            name: "eye_in_bore",
            scene: scene(vec![part.clone()]),
            camera: Camera::look_at(DVec3::new(0.95, 0.1, 0.2), DVec3::ZERO, z, 60.0),
        },
        HardView {
            // Close to the part, a narrow view: nodes far wider than the picture.
            name: "close_up",
            scene: scene(vec![part]),
            camera: Camera::look_at(DVec3::new(1.4, -1.2, 0.9), DVec3::new(0.5, -0.3, 0.2), z, 10.0),
        },
    ]
}
