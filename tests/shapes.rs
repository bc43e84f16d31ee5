//! Shapes: classification is conservative (sampled), not trivially Boundary, volumes
//! converge to the analytic ones, and a voxelized CSG tree is the CSG of its leaves.

use std::f64::consts::PI;

use glam::{DAffine3, DVec3};
use octsolid::Aabb;
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::shape::*;

mod common;

use common::Rng;

fn random_axis(rng: &mut Rng) -> Axis {
    [Axis::X, Axis::Y, Axis::Z][rng.below(3) as usize]
}

/// A random primitive inside roughly [-1, 1]^3.
fn random_primitive(rng: &mut Rng) -> Csg {
    let c = rng.vec(-0.4, 0.4);
    match (rng.unit() * 8.0) as u32 {
        0 => Sphere::new(c, rng.range(0.2, 0.8)).unwrap().into(),
        1 => Ellipsoid::new(c, rng.vec(0.1, 0.7)).unwrap().into(),
        2 => Cuboid::new(c, rng.vec(0.2, 1.2)).unwrap().into(),
        3 => Cylinder::new(c, random_axis(rng), rng.range(0.1, 0.6), rng.range(0.2, 1.2)).unwrap().into(),
        4 => Cone::new(c, random_axis(rng), rng.range(0.2, 0.6), rng.range(0.2, 0.8)).unwrap().into(),
        5 => Torus::new(c, random_axis(rng), rng.range(0.35, 0.6), rng.range(0.05, 0.3)).unwrap().into(),
        6 => HalfSpace::new(rng.vec(-1.0, 1.0), rng.range(-0.3, 0.3)).unwrap().into(),
        _ => {
            let inner = Cuboid::new(DVec3::ZERO, rng.vec(0.2, 0.9)).unwrap();
            let axis = rng.vec(-1.0, 1.0);
            inner.rotate(axis, rng.range(0.0, PI)).translate(c).into()
        }
    }
}

/// A random CSG tree of `leaves` primitives.
fn random_tree(rng: &mut Rng, leaves: u32) -> Csg {
    if leaves <= 1 {
        return random_primitive(rng);
    }
    let split = 1 + (rng.unit() * f64::from(leaves - 1)) as u32;
    let (a, b) = (random_tree(rng, split), random_tree(rng, leaves - split));
    match (rng.unit() * 5.0) as u32 {
        0 => a | b,
        1 => a & b,
        2 => a - b,
        3 => a ^ b,
        _ => !a & b,
    }
}

/// Samples points of `b` (corners, centre, random) and checks the class against them.
fn assert_sound(shape: &dyn Shape, b: &Aabb, rng: &mut Rng) -> Class {
    let class = shape.classify(b);
    if class == Class::Boundary {
        return class;
    }
    let want = class == Class::Inside;
    let points = (0..8).map(|i| b.corner(i)).chain([b.center()]).chain((0..24).map(|_| {
        let t = DVec3::new(rng.unit(), rng.unit(), rng.unit());
        b.min + (b.max - b.min) * t
    }));
    for p in points.collect::<Vec<_>>() {
        assert_eq!(shape.contains(p), want, "{class:?} box {b:?} has a point {p} on the wrong side");
    }
    class
}

#[test]
fn classification_is_conservative_and_useful() {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    for trial in 0..400 {
        let shape = if trial % 2 == 0 { random_primitive(&mut rng) } else { random_tree(&mut rng, 4) };
        let mut decided = 0;
        for _ in 0..300 {
            let size = rng.range(0.001, 0.4);
            let b = Aabb::from_center_half(rng.vec(-1.2, 1.2), rng.vec(0.0005, size));
            if assert_sound(&shape, &b, &mut rng) != Class::Boundary {
                decided += 1;
            }
        }
        // Most random boxes lie clearly on one side; a lazy classifier would decide none.
        assert!(decided > 60, "trial {trial}: only {decided} of 300 boxes decided for {shape:?}");
    }
}

#[test]
fn tiny_boxes_on_the_surface_stay_sound() {
    // Boxes straddling the surface at many scales, where rounding could matter.
    let mut rng = Rng(77);
    let sphere = Sphere::new(DVec3::new(1e3, -2e3, 5e2), 0.75).unwrap();
    for _ in 0..20_000 {
        let dir = rng.vec(-1.0, 1.0).normalize_or(DVec3::X);
        let p = DVec3::new(1e3, -2e3, 5e2) + dir * 0.75;
        let half = DVec3::splat(10f64.powf(rng.range(-12.0, -2.0)));
        assert_sound(&sphere, &Aabb::from_center_half(p, half), &mut rng);
    }
}

#[test]
fn volumes_match_the_analytic_ones() {
    let o = DVec3::new(0.03, -0.02, 0.01);
    let cases: Vec<(&str, Csg, f64)> = vec![
        ("sphere", Sphere::new(o, 0.8).unwrap().into(), 4.0 / 3.0 * PI * 0.512),
        ("ellipsoid", Ellipsoid::new(o, DVec3::new(0.9, 0.5, 0.3)).unwrap().into(), 4.0 / 3.0 * PI * 0.135),
        ("box", Cuboid::new(o, DVec3::new(1.5, 0.7, 1.1)).unwrap().into(), 1.5 * 0.7 * 1.1),
        ("cylinder", Cylinder::new(o, Axis::Y, 0.6, 1.4).unwrap().into(), PI * 0.36 * 1.4),
        ("cone", Cone::new(o - DVec3::Z * 0.7, Axis::Z, 0.8, 1.5).unwrap().into(), PI * 0.64 * 1.5 / 3.0),
        ("torus", Torus::new(o, Axis::X, 0.6, 0.25).unwrap().into(), 2.0 * PI * PI * 0.6 * 0.0625),
        (
            "rotated box",
            Cuboid::new(DVec3::ZERO, DVec3::new(1.0, 0.6, 0.8)).unwrap().rotate(DVec3::new(1.0, 2.0, 0.5), 0.7).into(),
            0.48,
        ),
        (
            "half-space & ball",
            HalfSpace::new(DVec3::new(0.0, 0.0, 1.0), 0.0).unwrap() & Sphere::new(DVec3::ZERO, 0.9).unwrap(),
            2.0 / 3.0 * PI * 0.729,
        ),
    ];
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 8).unwrap();
    for (name, shape, exact) in cases {
        let tree = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
        tree.validate().unwrap();
        let error = (tree.volume() / exact - 1.0).abs();
        assert!(error < 0.02, "{name}: {} vs {exact} ({:.3}%)", tree.volume(), error * 100.0);
    }
}

#[test]
fn menger_sponge_is_sound_and_has_its_volume() {
    let mut rng = Rng(2718);
    let sponge = Menger::new(DVec3::new(0.1, -0.05, 0.02), 1.8, 3).unwrap();
    let mut decided = 0;
    for _ in 0..20_000 {
        let b = Aabb::from_center_half(rng.vec(-1.0, 1.0), rng.vec(0.0001, 0.01));
        decided += u32::from(assert_sound(&sponge, &b, &mut rng) != Class::Boundary);
    }
    assert!(decided > 10_000, "only {decided} of 20000 boxes decided");
    // The voxel set is the voxel-centre point test, voxel for voxel (dense oracle).
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let tree = voxelize(&sponge, domain, &VoxelizeOptions::default()).unwrap();
    let n = domain.resolution();
    let mut want = 0;
    for v in (0..n * n * n).map(|i| [i % n, i / n % n, i / (n * n)]) {
        let inside = sponge.contains(domain.voxel_center(v));
        want += u64::from(inside);
        assert_eq!(tree.contains_voxel(v), inside, "voxel {v:?}");
    }
    assert_eq!(tree.voxel_count(), want);
    // Level 3 keeps (20/27)^3 of the cube; the volume converges at depth 8.
    let fine = voxelize(&sponge, Domain::new(DVec3::splat(-1.0), 2.0, 8).unwrap(), &VoxelizeOptions::default());
    let error = (fine.unwrap().volume() / sponge.volume() - 1.0).abs();
    assert!(error < 0.02, "volume error {:.3}%", error * 100.0);
    assert!((sponge.volume() - 1.8f64.powi(3) * 8000.0 / 19683.0).abs() < 1e-12);
}

#[test]
fn displaced_sphere_is_sound_and_has_its_volume() {
    let mut rng = Rng(1618);
    let center = DVec3::new(0.02, -0.01, 0.03);
    let bumpy = DisplacedSphere::new(center, 0.7, 0.08, 9.0).unwrap();
    let mut decided = 0;
    for _ in 0..20_000 {
        let p = center + rng.vec(-1.0, 1.0).normalize_or(DVec3::X) * rng.range(0.55, 0.85);
        let b = Aabb::from_center_half(p, rng.vec(0.0001, 0.02));
        decided += u32::from(assert_sound(&bumpy, &b, &mut rng) != Class::Boundary);
    }
    assert!(decided > 10_000, "only {decided} of 20000 boxes decided");
    // Voxel for voxel the point test at voxel centres (dense oracle).
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let tree = voxelize(&bumpy, domain, &VoxelizeOptions::default()).unwrap();
    let n = domain.resolution();
    for v in (0..n * n * n).map(|i| [i % n, i / n % n, i / (n * n)]) {
        assert_eq!(tree.contains_voxel(v), bumpy.contains(domain.voxel_center(v)), "voxel {v:?}");
    }
    // Volume: the integral of r(u)^3 / 3 over the directions (midpoint rule in theta, phi).
    let (rows, columns) = (600, 1200);
    let mut exact = 0.0;
    for i in 0..rows {
        let theta = PI * (i as f64 + 0.5) / rows as f64;
        for j in 0..columns {
            let phi = 2.0 * PI * (j as f64 + 0.5) / columns as f64;
            let u = DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            exact += bumpy.radius_towards(u).powi(3) / 3.0 * theta.sin();
        }
    }
    exact *= PI / rows as f64 * 2.0 * PI / columns as f64;
    let fine = voxelize(&bumpy, Domain::new(DVec3::splat(-1.0), 2.0, 8).unwrap(), &VoxelizeOptions::default());
    let fine = fine.unwrap();
    let error = (fine.volume() / exact - 1.0).abs();
    assert!(error < 0.01, "volume {} vs {exact} ({:.3}%)", fine.volume(), error * 100.0);
    // The work follows the surface: not many more nodes than the plain ball's.
    let ball = voxelize(&Sphere::new(center, 0.7).unwrap(), *fine.domain(), &VoxelizeOptions::default()).unwrap();
    assert!(fine.node_count() < 4 * ball.node_count(), "{} vs {} nodes", fine.node_count(), ball.node_count());
}

#[test]
fn csg_tree_voxelizes_to_the_csg_of_its_leaves() {
    let mut rng = Rng(4242);
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 6).unwrap();
    let vox = |s: &Csg| voxelize(s, domain, &VoxelizeOptions::default()).unwrap();
    for _ in 0..40 {
        let (a, b) = (random_tree(&mut rng, 2), random_primitive(&mut rng));
        let (ta, tb) = (vox(&a), vox(&b));
        let cases: [(Csg, LinearOctree); 5] = [
            (&a | &b, ta.union(&tb).unwrap()),
            (&a & &b, ta.intersection(&tb).unwrap()),
            (&a - &b, ta.difference(&tb).unwrap()),
            (&a ^ &b, ta.symmetric_difference(&tb).unwrap()),
            (!&a, ta.complement()),
        ];
        for (tree, combined) in cases {
            assert_eq!(vox(&tree), combined, "{tree:?}");
        }
    }
}

#[test]
fn transforms_move_the_solid() {
    let domain = Domain::new(DVec3::splat(-2.0), 4.0, 7).unwrap();
    let vox = |s: &dyn Shape| voxelize(s, domain, &VoxelizeOptions::default()).unwrap();
    // A cylinder along x is a cylinder along z rotated a quarter turn about y.
    let along_x = vox(&Cylinder::new(DVec3::ZERO, Axis::X, 0.5, 2.0).unwrap());
    let turned = vox(&Cylinder::new(DVec3::ZERO, Axis::Z, 0.5, 2.0).unwrap().rotate(DVec3::Y, PI / 2.0));
    assert!((&along_x ^ &turned).voxel_count() * 200 < along_x.voxel_count());
    // Translation and scaling move and grow the bounds.
    let ball = Sphere::new(DVec3::ZERO, 0.5).unwrap().scale(DVec3::new(2.0, 1.0, 1.0)).unwrap();
    let moved = vox(&ball.translate(DVec3::new(0.5, 0.25, 0.0)));
    let b = moved.bounds().unwrap();
    assert!((b.min.x + 0.5).abs() < 0.04 && (b.max.x - 1.5).abs() < 0.04, "{b:?}");
    assert!((moved.volume() / (4.0 / 3.0 * PI * 0.25) - 1.0).abs() < 0.02);
    // A singular matrix is refused.
    assert!(Sphere::new(DVec3::ZERO, 1.0).unwrap().transform(DAffine3::from_scale(DVec3::new(1.0, 0.0, 1.0))).is_err());
}

#[test]
fn invalid_parameters_are_refused() {
    assert!(Sphere::new(DVec3::ZERO, -1.0).is_err());
    assert!(Sphere::new(DVec3::NAN, 1.0).is_err());
    assert!(Cuboid::new(DVec3::ZERO, DVec3::new(1.0, 0.0, 1.0)).is_err());
    assert!(Cylinder::new(DVec3::ZERO, Axis::Z, 1.0, f64::INFINITY).is_err());
    assert!(Torus::new(DVec3::ZERO, Axis::Z, 0.5, 0.6).is_err());
    assert!(HalfSpace::new(DVec3::ZERO, 1.0).is_err());
    assert!("w".parse::<Axis>().unwrap_err().contains("x, y or z"));
}

/// The point where `shape`'s boundary crosses the segment from `inside` to `outside`
/// (by bisection on `contains`).
fn crossing(shape: &dyn Shape, mut inside: DVec3, mut outside: DVec3) -> DVec3 {
    for _ in 0..80 {
        let mid = (inside + outside) * 0.5;
        if shape.contains(mid) {
            inside = mid;
        } else {
            outside = mid;
        }
    }
    (inside + outside) * 0.5
}

/// Shapes whose surfaces the smooth normals use: the random primitives and trees, a
/// displaced sphere, and primitives under shear and uneven scaling.
fn surface_case(rng: &mut Rng, case: u32) -> Csg {
    match case % 4 {
        0 => random_primitive(rng),
        1 => random_tree(rng, 3),
        2 => DisplacedSphere::new(rng.vec(-0.2, 0.2), rng.range(0.5, 0.8), rng.range(0.0, 0.1), rng.range(2.0, 9.0))
            .unwrap()
            .into(),
        _ => {
            let mut m = DAffine3::from_scale(rng.vec(0.5, 1.5));
            m.matrix3.x_axis.y = rng.range(-0.4, 0.4);
            m.translation = rng.vec(-0.2, 0.2);
            let inner = if rng.below(2) == 0 {
                Csg::from(Torus::new(DVec3::ZERO, random_axis(rng), 0.45, 0.2).unwrap())
            } else {
                Csg::from(Cylinder::new(DVec3::ZERO, random_axis(rng), 0.4, 0.9).unwrap())
            };
            inner.transform(m).unwrap().into()
        }
    }
}

#[test]
fn surfaces_have_the_sign_of_contains_and_the_tangent_plane_of_the_boundary() {
    let mut rng = Rng(404);
    let (mut points, mut tangent) = (0, 0);
    for case in 0..800 {
        let shape = surface_case(&mut rng, case);
        // The distance's sign is the point's side.
        let mut inside = None;
        let mut outside = None;
        for _ in 0..200 {
            let p = rng.vec(-1.2, 1.2);
            let s = shape.surface(p).expect("these shapes know their surface");
            assert!((s.normal.length() - 1.0).abs() < 1e-12, "case {case}: normal {}", s.normal);
            if s.distance.abs() > 1e-9 {
                assert_eq!(s.distance < 0.0, shape.contains(p), "case {case} at {p}: distance {}", s.distance);
            }
            *(if shape.contains(p) { &mut inside } else { &mut outside }) = Some(p);
        }
        let (Some(a), Some(b)) = (inside, outside) else { continue };
        // At a boundary point the distance vanishes and the normal is the boundary's:
        // stepping h along a tangent, the boundary stays within a small fraction of h
        // of the tangent plane (off it by h times the normal's angle error, plus h^2
        // times the curvature), and it lies towards -n.
        let q = crossing(&shape, a, b);
        let s = shape.surface(q).unwrap();
        assert!(s.distance.abs() < 1e-6, "case {case} at {q}: distance {}", s.distance);
        let n = s.normal;
        points += 1;
        let h = 1e-3;
        let t1 = n.any_orthonormal_vector();
        let t2 = n.cross(t1);
        let flat = [t1, -t1, t2, -t2].iter().all(|t| {
            let r = q + *t * h;
            let (lo, hi) = (r - n * (4.0 * h), r + n * (4.0 * h));
            shape.contains(lo) && !shape.contains(hi) && (crossing(&shape, lo, hi) - r).dot(n).abs() < 0.05 * h
        });
        tangent += usize::from(flat);
    }
    assert!(points > 600, "{points} boundary points");
    // Edges and corners (box, cylinder and cone rims, CSG seams) are allowed to fail.
    assert!(tangent as f64 >= 0.99 * points as f64, "{tangent} of {points} boundary points have the tangent plane");
}
