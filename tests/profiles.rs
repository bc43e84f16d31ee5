//! Profiles and hulls (issue 39, item 4) against independent oracles: extrusions
//! against area times height (twisted and scaled ones against the integral of their
//! layers' areas), revolutions against Pappus's centroid theorem, the hull of two
//! balls against the capsule's volume, each within 0.5% at depth 9; scene forms and
//! their errors. (The solid hull against a brute-force hull of the voxel corners is a
//! unit test of `octree::hull`; the command's round trip is in tests/cli.rs.)

mod common;

use std::f64::consts::PI;

use glam::{DVec2, DVec3};
use octsolid::MemoryBudget;
use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
use octsolid::scene_file::read_scene;
use octsolid::shape::{Axis, Csg, Extrude, Hull, HullOptions, Profile, Revolve, Shape, Sphere};

/// The voxels' volume of `shape` at depth 9 in the cube `[min, min + edge]^3`.
fn voxel_volume(shape: &dyn Shape, min: f64, edge: f64) -> f64 {
    let domain = Domain::new(DVec3::splat(min), edge, 9).unwrap();
    let tree = voxelize(shape, domain, &VoxelizeOptions::default()).unwrap();
    tree.voxel_count() as f64 * domain.voxel_size().powi(3)
}

fn close(got: f64, want: f64, what: &str) {
    eprintln!("{what}: {:+.3}%", (got / want - 1.0) * 100.0);
    assert!((got / want - 1.0).abs() < 0.005, "{what}: {got} against {want} ({:+.3}%)", (got / want - 1.0) * 100.0);
}

/// A polygon's area and centroid by the shoelace formulas, written here apart from
/// the library's.
fn shoelace(points: &[[f64; 2]]) -> (f64, DVec2) {
    let (mut a, mut c) = (0.0, DVec2::ZERO);
    for i in 0..points.len() {
        let (p, q) = (DVec2::from_array(points[i]), DVec2::from_array(points[(i + 1) % points.len()]));
        let cross = p.x * q.y - q.x * p.y;
        a += cross;
        c += (p + q) * cross;
    }
    (a / 2.0, c / (3.0 * a))
}

fn polygon(points: &[[f64; 2]]) -> Profile {
    Profile::polygon(points.iter().map(|&p| DVec2::from_array(p)).collect()).unwrap()
}

const ELL: [[f64; 2]; 6] = [[-0.8, -0.7], [0.9, -0.7], [0.9, -0.1], [-0.2, -0.1], [-0.2, 0.8], [-0.8, 0.8]];

#[test]
fn extrusions_have_area_times_height() {
    let (area, _) = shoelace(&ELL);
    let plain = Extrude::new(polygon(&ELL), Axis::Z, 1.6, true, 0.0, DVec2::ONE).unwrap();
    close(voxel_volume(&plain, -1.0, 2.0), area * 1.6, "an L extruded");
    // A plate with a round hole, along x: area 1.5 x 1.25 - pi 0.3^2 (its sides on
    // voxel planes).
    let plate = Profile::difference(vec![
        Profile::rectangle(DVec2::ZERO, DVec2::new(1.5, 1.25)).unwrap(),
        Profile::circle(DVec2::new(0.2, 0.1), 0.3).unwrap(),
    ])
    .unwrap();
    let along_x = Extrude::new(plate, Axis::X, 1.5, true, 0.0, DVec2::ONE).unwrap();
    close(voxel_volume(&along_x, -1.0, 2.0), (1.5 * 1.25 - PI * 0.09) * 1.5, "a plate with a hole along x");
}

#[test]
fn twisted_and_scaled_extrusions_have_their_layers_volume() {
    // Twist keeps every layer's area; a top scale s gives A h (1 + s + s^2) / 3.
    let (area, _) = shoelace(&ELL);
    let (h, s) = (1.8, 0.5);
    let twisted = Extrude::new(polygon(&ELL), Axis::Z, h, true, 150.0, DVec2::ONE).unwrap();
    close(voxel_volume(&twisted, -1.25, 2.5), area * h, "an L twisted by 150 degrees");
    let both = Extrude::new(polygon(&ELL), Axis::Y, h, true, 90.0, DVec2::splat(s)).unwrap();
    close(voxel_volume(&both, -1.25, 2.5), area * h * (1.0 + s + s * s) / 3.0, "an L twisted and scaled by 0.5");
    // Scale [sx, sy]: the integral of (1 + a t)(1 + b t) over t.
    let (a, b) = (1.4 - 1.0, 0.6 - 1.0);
    let square = Profile::rectangle(DVec2::new(0.1, 0.0), DVec2::new(0.8, 1.0)).unwrap();
    let stretched = Extrude::new(square, Axis::Z, h, true, 0.0, DVec2::new(1.4, 0.6)).unwrap();
    let want = 0.8 * h * (1.0 + (a + b) / 2.0 + a * b / 3.0);
    close(voxel_volume(&stretched, -1.0, 2.0), want, "a square scaled by [1.4, 0.6]");
}

#[test]
fn revolutions_have_pappus_volumes() {
    // Pappus: V = A theta r_c, r_c the profile's centroid's distance from the axis.
    let trapezoid = [[0.3, -0.6], [0.9, -0.4], [0.7, 0.6], [0.3, 0.5]];
    let (area, centroid) = shoelace(&trapezoid);
    let full = Revolve::new(polygon(&trapezoid), Axis::Z, 360.0).unwrap();
    close(voxel_volume(&full, -1.0, 2.0), area * 2.0 * PI * centroid.x, "a trapezoid turned about z");
    let part = Revolve::new(polygon(&trapezoid), Axis::X, 135.0).unwrap();
    close(voxel_volume(&part, -1.0, 2.0), area * 0.75 * PI * centroid.x, "a trapezoid turned 135 degrees about x");
    let tube = Revolve::new(Profile::circle(DVec2::new(0.6, 0.1), 0.25).unwrap(), Axis::Y, 250.0).unwrap();
    let want = PI * 0.25 * 0.25 * (250.0f64.to_radians()) * 0.6;
    close(voxel_volume(&tube, -1.0, 2.0), want, "a circle turned 250 degrees about y");
}

#[test]
fn the_hull_of_two_balls_is_a_capsule() {
    let (r, half) = (0.35, 0.5);
    let balls =
        [Sphere::new(DVec3::new(-half, 0.1, 0.0), r).unwrap(), Sphere::new(DVec3::new(half, 0.1, 0.0), r).unwrap()];
    let hull = Hull::new(&balls.map(Csg::from), HullOptions::default()).unwrap();
    let capsule = PI * r * r * 2.0 * half + 4.0 / 3.0 * PI * r * r * r;
    close(voxel_volume(hull.tree(), -1.0, 2.0), capsule, "the hull of two balls");
}

/// The scene of docs/SCENES.md's profile example: the block after its marker.
fn documented_example() -> String {
    let doc = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/docs/SCENES.md")).unwrap();
    let after = doc.split("parsed and built by tests/profiles.rs").nth(1).expect("the marker");
    let block = after.split("```toml\n").nth(1).expect("a toml block");
    block.split("```").next().unwrap().to_string()
}

#[test]
fn the_documented_example_and_the_profiles_scene_build() {
    let dir = common::scratch_dir("profiles", "example");
    let path = dir.join("example.toml");
    std::fs::write(&path, documented_example()).unwrap();
    let file = read_scene(&path, MemoryBudget::default()).unwrap();
    assert_eq!(file.scene.solids.len(), 3);
    let shown = read_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/profiles.toml"), MemoryBudget::default());
    assert_eq!(shown.unwrap().scene.solids.len(), 5);
}

#[test]
fn bad_profiles_are_refused_naming_the_file_and_place() {
    let dir = common::scratch_dir("profiles", "bad");
    let cases = [
        (
            "crossing",
            "{ extrude = { profile = { polygon = [[0, 0], [1, 1], [1, 0], [0, 0.5]] }, height = 1 } }",
            "cross",
        ),
        ("two", "{ extrude = { profile = { polygon = [[0, 0], [1, 1]] }, height = 1 } }", "2 points"),
        ("nan", "{ extrude = { profile = { polygon = [[0, 0], [1, nan], [1, 0]] }, height = 1 } }", "not finite"),
        ("flat", "{ extrude = { profile = { circle = { radius = 1 } }, height = 0 } }", "height"),
        ("left", "{ revolve = { profile = { rectangle = { size = [1, 1] } }, axis = \"z\" } }", "r >= 0"),
        ("empty", "{ hull = [] }", "operand"),
    ];
    for (name, shape, says) in cases {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, format!("[[solid]]\nname = \"bad\"\nshape = {shape}\n")).unwrap();
        let e = read_scene(&path, MemoryBudget::default()).err().unwrap().to_string();
        assert!(e.contains(&format!("{name}.toml")) && e.contains(":3:") && e.contains(says), "{name}: {e}");
    }
}

/// What voxelizing takes Hermite data from: the distance's sign agrees with the
/// point test wherever the distance is not within rounding of zero, and the normal
/// is a unit vector.
#[test]
fn distances_agree_with_the_point_test() {
    let ring = Profile::difference(vec![
        Profile::circle(DVec2::new(0.6, 0.0), 0.3).unwrap(),
        Profile::rectangle(DVec2::new(0.6, 0.2), DVec2::new(0.2, 0.2)).unwrap(),
    ])
    .unwrap();
    let shapes: Vec<Box<dyn Shape>> = vec![
        Box::new(Extrude::new(polygon(&ELL), Axis::Z, 1.6, true, 0.0, DVec2::ONE).unwrap()),
        Box::new(Extrude::new(polygon(&ELL), Axis::X, 1.6, true, 120.0, DVec2::new(0.5, 1.2)).unwrap()),
        Box::new(Revolve::new(polygon(&[[0.3, -0.6], [0.9, -0.4], [0.7, 0.6], [0.3, 0.5]]), Axis::Y, 360.0).unwrap()),
        Box::new(Revolve::new(ring, Axis::Z, 200.0).unwrap()),
    ];
    let mut seed = 99u64;
    let mut r = || {
        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.4 - 1.2
    };
    for (i, shape) in shapes.iter().enumerate() {
        let mut checked = 0;
        for _ in 0..20_000 {
            let p = DVec3::new(r(), r(), r());
            let Some(s) = shape.surface(p) else { continue };
            assert!((s.normal.length() - 1.0).abs() < 1e-9, "shape {i} at {p}: {s:?}");
            if s.distance.abs() > 1e-9 {
                assert_eq!(s.distance < 0.0, shape.contains(p), "shape {i} at {p}: {s:?}");
                checked += 1;
            }
        }
        assert!(checked > 19_000, "shape {i}: {checked}");
    }
}
