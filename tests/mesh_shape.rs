//! Closed meshes as shapes: CSG with other shapes against the dense-grid brute force of
//! the analytic predicate, the same octree as the mesh solid voxelizer for closed
//! models, and refusal of meshes that are not closed.

use glam::DVec3;
use octsolid::mesh::generate::{cuboid, icosphere, torus};
use octsolid::mesh::{MeshShape, MeshVoxelizeOptions, TriangleMesh, read_mesh, voxelize_mesh};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::shape::{Axis, Class, Cylinder, Shape, Sphere};
use octsolid::{Aabb, Error};

/// Every voxel of `domain` whose centre `inside` holds: the dense brute force.
fn brute_force(domain: Domain, inside: impl Fn(DVec3) -> bool) -> LinearOctree {
    let n = domain.resolution();
    let voxels = (0..n)
        .flat_map(|z| (0..n).flat_map(move |y| (0..n).map(move |x| [x, y, z])))
        .filter(|&v| inside(domain.voxel_center(v)));
    LinearOctree::from_voxels(domain, voxels).unwrap()
}

#[test]
fn cube_mesh_minus_a_sphere_is_the_predicate_voxel_by_voxel() {
    // Faces off the voxel centres (voxel 1/32, centres at odd multiples of 1/64).
    let (center, size) = (DVec3::new(0.03, -0.02, 0.01), DVec3::new(1.5, 1.3, 1.1));
    let (ball_center, radius) = (DVec3::new(0.4, 0.3, 0.2), 0.6);
    let cube = MeshShape::new(&cuboid(center, size)).unwrap();
    let part = cube - Sphere::new(ball_center, radius).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let got = voxelize(&part, domain, &VoxelizeOptions::default()).unwrap();
    got.validate().unwrap();
    // The oracle: in the box (|p - c| <= size / 2 on each axis) and not in the ball.
    let want = brute_force(domain, |p| {
        let in_box = ((p - center).abs() - size * 0.5).max_element() <= 0.0;
        in_box && (p - ball_center).length_squared() > radius * radius
    });
    assert!(want.voxel_count() > 10_000, "{}", want.voxel_count());
    assert_eq!(got, want, "{} voxels differ", (&got ^ &want).voxel_count());
}

#[test]
fn a_mesh_shape_alone_voxelizes_to_the_mesh_solid_voxelizers_octree() {
    let models = ["models/bunny-watertight.obj", "models/spot.obj"];
    let mut meshes: Vec<(String, TriangleMesh)> =
        models.iter().map(|m| (m.to_string(), read_mesh(m).unwrap())).collect();
    meshes.push(("icosphere".into(), icosphere(DVec3::new(0.1, -0.2, 0.05), 1.0, 3)));
    meshes.push(("torus".into(), torus(1.0, 0.35, 48, 24)));
    for (name, mesh) in &meshes {
        for depth in [5, 7] {
            let domain = Domain::around(&mesh.bounds(), 0.03, depth).unwrap();
            let (want, stats) = voxelize_mesh(mesh, domain, &MeshVoxelizeOptions::default()).unwrap();
            let shape = MeshShape::new(mesh).unwrap();
            let got = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
            assert!(want.voxel_count() > 0, "{name}");
            // Canonical keys: the same voxels give the same bytes.
            assert_eq!(got.keys(), want.keys(), "{name} depth {depth} ({:?}): {} voxels differ", stats.rule, {
                (&got ^ &want).voxel_count()
            });
        }
    }
}

#[test]
fn boxes_are_decided_only_where_no_triangle_meets_them() {
    let (center, size) = (DVec3::new(0.03, -0.02, 0.01), DVec3::splat(1.0));
    let cube = MeshShape::new(&cuboid(center, size)).unwrap();
    let half = 0.5;
    // (box, class) against the analytic cube [center -+ 0.5].
    let cases = [
        (Aabb::from_center_half(center, DVec3::splat(0.3)), Class::Inside),
        (Aabb::from_center_half(center + DVec3::new(2.0, 0.0, 0.0), DVec3::splat(0.3)), Class::Outside),
        (Aabb::from_center_half(center + DVec3::new(half, 0.0, 0.0), DVec3::splat(0.01)), Class::Boundary),
        // Touching a face from outside: the closed box meets the face.
        (Aabb::new(center + DVec3::new(half, -0.1, -0.1), center + DVec3::new(half + 0.2, 0.1, 0.1)), Class::Boundary),
        // A box holding the whole cube: every face meets it.
        (Aabb::from_center_half(center, DVec3::splat(2.0)), Class::Boundary),
    ];
    for (b, want) in cases {
        assert_eq!(cube.classify(&b), want, "{b:?}");
    }
    assert!(cube.contains(center) && !cube.contains(center + DVec3::splat(0.51)));
    assert_eq!(cube.bounds(), Some(Aabb::from_center_half(center, DVec3::splat(half))));
}

#[test]
fn meshes_that_are_not_closed_are_refused_with_their_edges() {
    let mut open = cuboid(DVec3::ZERO, DVec3::ONE);
    open.retain_triangles(|t| t != 0);
    let e = MeshShape::new(&open).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, Error::InvalidArgument { what: "mesh", .. }), "{e:?}");
    // Removing one triangle of a box opens its three edges.
    assert!(text.contains("closed") && text.contains("3 boundary"), "{text}");
    let mut flipped = cuboid(DVec3::ZERO, DVec3::ONE);
    flipped.triangles[0].swap(1, 2);
    let text = MeshShape::new(&flipped).unwrap_err().to_string();
    assert!(text.contains("misoriented"), "{text}");
}

#[test]
fn mesh_shapes_take_part_in_csg_with_every_operator() {
    let cube = || MeshShape::new(&cuboid(DVec3::ZERO, DVec3::splat(2.0))).unwrap();
    let rod = || Cylinder::new(DVec3::ZERO, Axis::Z, 0.5, 4.0).unwrap();
    let p_hole = DVec3::new(0.0, 0.0, 0.9); // in the cube and the rod
    let p_wall = DVec3::new(0.9, 0.0, 0.0); // in the cube only
    let p_rod = DVec3::new(0.0, 0.0, 1.5); // in the rod only
    let drilled = cube() - rod();
    assert!(!drilled.contains(p_hole) && drilled.contains(p_wall) && !drilled.contains(p_rod));
    let both = cube() | rod();
    assert!(both.contains(p_hole) && both.contains(p_wall) && both.contains(p_rod));
    let common = cube() & rod();
    assert!(common.contains(p_hole) && !common.contains(p_wall) && !common.contains(p_rod));
    let odd = cube() ^ rod();
    assert!(!odd.contains(p_hole) && odd.contains(p_wall) && odd.contains(p_rod));
    let outside = !cube();
    assert!(!outside.contains(p_wall) && outside.contains(p_rod));
    let flipped = rod() - cube();
    assert!(flipped.contains(p_rod) && !flipped.contains(p_hole));
}
