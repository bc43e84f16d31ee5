//! The smooth surface (`surface::extract`, dual contouring of Hermite data) against
//! analytic surfaces, and its mesh checked closed, oriented, manifold and uncrossed
//! (an exact triangle-triangle test) on random solids, thin walls, touching solids and
//! single voxels.

mod common;

use common::Rng;
use common::exact_surface::{ExactSolid, measure_with, par_map};
use common::mesh_checks::assert_closed_manifold;
#[path = "common/self_intersection.rs"]
mod self_intersection;
use octsolid::NoProgress;
use octsolid::glam::{DQuat, DVec3};
use octsolid::mesh::TriangleMesh;
use octsolid::octree::{Domain, LinearOctree, voxelize};
use octsolid::shape::{Axis, Cuboid, Cylinder, Shape, ShapeExt, Sphere};
use octsolid::surface::{ExtractOptions, HermiteData, Style, SurfaceMesh, extract};
use self_intersection::self_crossings;

fn smooth(tolerance: f64) -> ExtractOptions {
    ExtractOptions { style: Style::Smooth, tolerance, ..ExtractOptions::default() }
}

/// The surface of `shape` voxelized in `domain`, with its exact crossings.
fn surface_of(shape: &dyn Shape, domain: Domain, tolerance: f64) -> (LinearOctree, SurfaceMesh) {
    let tree = voxelize(shape, domain, &Default::default()).unwrap();
    let hermite = HermiteData::from_shape(shape, &tree);
    let surface = extract(&tree, &hermite, &smooth(tolerance), &NoProgress).unwrap();
    (tree, surface)
}

fn assert_uncrossed(mesh: &TriangleMesh, cell: f64, what: &str) {
    let crossings = self_crossings(mesh, cell, 5);
    assert!(crossings.is_empty(), "{what}: triangles cross: {crossings:?}");
}

#[test]
fn sphere_vertices_and_normals_follow_the_sphere() {
    let (centre, radius) = (DVec3::new(0.013, -0.021, 0.007), 0.77);
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let (_, surface) = surface_of(&Sphere::new(centre, radius).unwrap(), domain, 0.0);
    let voxel = domain.voxel_size();
    let mesh = &surface.mesh;
    assert_closed_manifold(mesh, "sphere");
    assert_eq!((surface.creases, surface.corners, surface.estimated), (0, 0, 0));
    for v in &mesh.vertices {
        let off = ((*v - centre).length() - radius).abs() / voxel;
        assert!(off < 0.03, "vertex {v} is {off} voxel off the sphere");
    }
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let n = (b - a).cross(c - a).normalize();
        let radial = ((a + b + c) / 3.0 - centre).normalize();
        let degrees = n.dot(radial).clamp(-1.0, 1.0).acos().to_degrees();
        assert!(degrees < 6.0, "a face is {degrees} degrees off the sphere's normal");
    }
    let exact = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
    let relative = mesh.volume() / exact - 1.0;
    assert!(relative.abs() < 2e-3, "volume off by {relative}");
    assert_uncrossed(mesh, voxel, "sphere");
}

#[test]
fn a_turned_box_keeps_its_corners_and_edges_sharp() {
    let size = DVec3::new(1.1, 0.7, 0.9);
    let turned = Cuboid::new(DVec3::ZERO, size).unwrap().rotate(DVec3::new(1.0, 2.0, 0.5), 0.6);
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let (_, surface) = surface_of(&turned, domain, 0.0);
    let voxel = domain.voxel_size();
    let mesh = &surface.mesh;
    assert_closed_manifold(mesh, "turned box");
    // Every vertex within the 0.25 voxel of the box (0.223 at most here, at a
    // vertex more than a voxel and a half from every corner; those nearer a corner,
    // the creases' vertices past it included, are within 0.01).
    let mut squares = 0.0;
    for v in &mesh.vertices {
        let d = turned.surface(*v).unwrap().distance.abs() / voxel;
        assert!(d < 0.25, "vertex {v} is {d} voxel off the box");
        squares += d * d;
    }
    let rms = (squares / mesh.vertices.len() as f64).sqrt();
    assert!(rms < 0.02, "vertices are {rms} voxel off the box (RMS)");
    // Each of the 8 corners has a vertex on it.
    for i in 0..8 {
        let local = DVec3::new(
            if i & 1 == 0 { -0.5 } else { 0.5 },
            if i & 2 == 0 { -0.5 } else { 0.5 },
            if i & 4 == 0 { -0.5 } else { 0.5 },
        ) * size;
        let corner: DVec3 = DQuat::from_axis_angle(DVec3::new(1.0, 2.0, 0.5).normalize(), 0.6) * local;
        let nearest = mesh.vertices.iter().map(|v| (*v - corner).length()).fold(f64::INFINITY, f64::min) / voxel;
        assert!(nearest < 0.05, "corner {i} has no vertex within {nearest} voxel");
    }
    assert!(surface.corners >= 8 && surface.creases > 0, "{surface:?}");
    let relative = mesh.volume() / size.element_product() - 1.0;
    assert!(relative.abs() < 1e-3, "volume off by {relative}");
    assert_uncrossed(mesh, voxel, "turned box");
}

#[test]
fn a_concave_corner_is_kept() {
    // A ball with one octant's box cut out: a concave corner at the cube's corner.
    let cut =
        Sphere::new(DVec3::ZERO, 0.8).unwrap() - Cuboid::new(DVec3::splat(0.5 + 0.1037), DVec3::splat(1.0)).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let (_, surface) = surface_of(&cut, domain, 0.0);
    let voxel = domain.voxel_size();
    let mesh = &surface.mesh;
    assert_closed_manifold(mesh, "cut ball");
    let corner = DVec3::splat(0.1037);
    let nearest = mesh.vertices.iter().map(|v| (*v - corner).length()).fold(f64::INFINITY, f64::min) / voxel;
    assert!(nearest < 0.05, "the concave corner has no vertex within {nearest} voxel");
    assert_uncrossed(mesh, voxel, "cut ball");
}

#[test]
fn the_classic_part_stays_within_a_quarter_voxel_of_its_exact_surface() {
    // Issue 38's bound on the classic part, against its exact surface (the oracle of
    // tests/common/exact_surface.rs): area-weighted samples of the mesh and every
    // vertex. Its bores meet along creases running diagonally through the lattice,
    // where neighbouring cells' vertices meet and the untangling must part them.
    let part = octsolid::samples::classic_csg();
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 8).unwrap();
    let voxel = domain.voxel_size();
    let (_, surface) = surface_of(&part, domain, 0.0);
    let mesh = &surface.mesh;
    let exact = ExactSolid::classic();
    let quality = measure_with(mesh, &exact, voxel, 100_000, 1);
    assert!(quality.max <= 0.25 && quality.rms <= 0.02, "{quality:?}");
    assert!(quality.median_normal_deg <= 0.2, "{quality:?}");
    let off = par_map(&mesh.vertices, |v| exact.nearest(*v).distance / voxel);
    let (worst, at) =
        off.iter().zip(&mesh.vertices).fold((0.0, DVec3::ZERO), |b, (&d, &v)| if d > b.0 { (d, v) } else { b });
    assert!(worst <= 0.25, "vertex {at} is {worst} voxel off the exact surface");
}

/// A random CSG tree of balls, boxes and cylinders in the unit cube.
fn random_tree(rng: &mut Rng) -> octsolid::shape::Csg {
    let leaf = |rng: &mut Rng| -> octsolid::shape::Csg {
        let c = DVec3::new(rng.range(-0.5, 0.5), rng.range(-0.5, 0.5), rng.range(-0.5, 0.5));
        match rng.below(3) {
            0 => Sphere::new(c, rng.range(0.05, 0.5)).unwrap().into(),
            1 => Cuboid::new(c, DVec3::new(rng.range(0.02, 0.8), rng.range(0.02, 0.8), rng.range(0.02, 0.8)))
                .unwrap()
                .rotate(DVec3::new(rng.range(-1.0, 1.0), 1.0, rng.range(-1.0, 1.0)), rng.range(0.0, 3.0))
                .into(),
            _ => Cylinder::new(
                c,
                [Axis::X, Axis::Y, Axis::Z][rng.below(3) as usize],
                rng.range(0.02, 0.3),
                rng.range(0.1, 1.5),
            )
            .unwrap()
            .into(),
        }
    };
    let mut tree = leaf(rng);
    for _ in 0..1 + rng.below(4) {
        let other = leaf(rng);
        tree = match rng.below(3) {
            0 => tree | other,
            1 => tree & other,
            _ => tree - other,
        };
    }
    tree
}

#[test]
fn random_csg_trees_give_closed_uncrossed_surfaces() {
    let mut rng = Rng(38);
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 5).unwrap();
    for case in 0..40 {
        let tree = random_tree(&mut rng);
        let solid = voxelize(&tree, domain, &Default::default()).unwrap();
        if solid.is_empty() {
            continue;
        }
        let hermite = HermiteData::from_shape(&tree, &solid);
        let surface = extract(&solid, &hermite, &smooth(0.0), &NoProgress).unwrap();
        let what = format!("case {case}");
        assert_closed_manifold(&surface.mesh, &what);
        assert_uncrossed(&surface.mesh, domain.voxel_size(), &what);
    }
}

#[test]
fn random_voxel_sets_without_crossings_are_estimated_closed_and_uncrossed() {
    let mut rng = Rng(7);
    let domain = Domain::new(DVec3::ZERO, 1.0, 4).unwrap();
    for case in 0..200 {
        let tree = common::random_octree(&mut rng, domain);
        if tree.is_empty() {
            continue;
        }
        let surface = extract(&tree, &HermiteData::none(), &smooth(0.0), &NoProgress).unwrap();
        assert!(surface.is_estimate());
        let what = format!("voxel set {case}");
        assert_closed_manifold(&surface.mesh, &what);
        assert_uncrossed(&surface.mesh, domain.voxel_size(), &what);
    }
}

#[test]
fn single_voxels_thin_walls_and_touching_solids() {
    let domain = Domain::new(DVec3::ZERO, 1.0, 4).unwrap();
    let v = domain.voxel_size();
    // One voxel; two voxels touching along an edge; two at a corner.
    let sets: [&[[u32; 3]]; 3] = [&[[5, 5, 5]], &[[5, 5, 5], [6, 6, 5]], &[[5, 5, 5], [6, 6, 6]]];
    for (i, voxels) in sets.iter().enumerate() {
        let tree = LinearOctree::from_voxels(domain, voxels.iter().copied()).unwrap();
        let surface = extract(&tree, &HermiteData::none(), &smooth(0.0), &NoProgress).unwrap();
        assert_closed_manifold(&surface.mesh, &format!("voxel set {i}"));
        assert_uncrossed(&surface.mesh, v, &format!("voxel set {i}"));
    }
    // A wall a third of a voxel thick, turned; two boxes touching along an edge.
    let wall = Cuboid::new(DVec3::splat(0.5), DVec3::new(0.8, 0.8, v / 3.0)).unwrap().rotate(DVec3::X, 0.3);
    let touching = Cuboid::new(DVec3::new(0.3, 0.3, 0.5), DVec3::new(0.2, 0.2, 0.6)).unwrap()
        | Cuboid::new(DVec3::new(0.5, 0.5, 0.5), DVec3::new(0.2, 0.2, 0.6)).unwrap();
    for (what, shape) in [("thin wall", &wall as &dyn Shape), ("touching boxes", &touching)] {
        let domain = Domain::new(DVec3::new(0.013, 0.007, 0.011), 1.0, 6).unwrap();
        let (_, surface) = surface_of(shape, domain, 0.0);
        assert_closed_manifold(&surface.mesh, what);
        assert_uncrossed(&surface.mesh, domain.voxel_size(), what);
    }
}

#[test]
fn one_and_two_threads_give_the_same_mesh() {
    let part = octsolid::samples::classic_csg();
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 6).unwrap();
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| surface_of(&part, domain, octsolid::surface::DEFAULT_TOLERANCE).1.mesh)
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.triangles, two.triangles);
    assert!(one.vertices.iter().zip(&two.vertices).all(|(a, b)| a.to_array() == b.to_array()));
    assert_eq!(one.vertices.len(), two.vertices.len());
}

#[test]
fn the_voxels_style_is_the_staircase_bit_for_bit() {
    let part = octsolid::samples::classic_csg();
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 5).unwrap();
    let tree = voxelize(&part, domain, &Default::default()).unwrap();
    for unit_faces in [false, true] {
        let options = ExtractOptions { style: Style::Voxels, unit_faces, ..ExtractOptions::default() };
        let surface = extract(&tree, &HermiteData::from_shape(&part, &tree), &options, &NoProgress).unwrap();
        let staircase = octsolid::mesh::boundary_mesh(&tree, &octsolid::mesh::BoundaryOptions { unit_faces });
        assert_eq!(surface.mesh.triangles, staircase.triangles);
        assert_eq!(surface.mesh.vertices, staircase.vertices);
    }
}

#[test]
fn the_crossing_check_passes_the_separated_staircase() {
    let mut rng = Rng(7);
    let domain = Domain::new(DVec3::ZERO, 1.0, 4).unwrap();
    for case in 0..30 {
        let tree = common::random_octree(&mut rng, domain);
        if tree.is_empty() {
            continue;
        }
        let stairs = octsolid::mesh::boundary_mesh(&tree, &octsolid::mesh::BoundaryOptions { unit_faces: true });
        let separated = octsolid::mesh::separate_sheets(&stairs).unwrap();
        assert_uncrossed(&separated, domain.voxel_size(), &format!("staircase {case}"));
    }
}

#[test]
fn a_tolerance_that_is_not_a_distance_is_refused() {
    // A NaN or negative tolerance was taken as none (the Python package passed them on).
    let d = Domain::new(DVec3::splat(-1.1), 2.2, 4).unwrap();
    let ball = Sphere::new(DVec3::ZERO, 1.0).unwrap();
    let tree = voxelize(&ball, d, &Default::default()).unwrap();
    let hermite = HermiteData::from_shape(&ball, &tree);
    for style in [Style::Smooth, Style::Voxels] {
        for tolerance in [f64::NAN, -1.0, f64::INFINITY] {
            let options = ExtractOptions { style, tolerance, ..ExtractOptions::default() };
            let e = extract(&tree, &hermite, &options, &NoProgress).unwrap_err().to_string();
            assert!(e.contains("invalid tolerance"), "{style:?} {tolerance}: {e}");
        }
        let options =
            ExtractOptions { style, tolerance: 0.1, normal_tolerance: Some(-1.0), ..ExtractOptions::default() };
        let e = extract(&tree, &hermite, &options, &NoProgress).unwrap_err().to_string();
        assert!(e.contains("invalid normal tolerance: -1 is not an angle"), "{style:?}: {e}");
    }
}
