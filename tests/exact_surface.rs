//! The exact-surface oracle (tests/common/exact_surface.rs) and the reference-mesh
//! distance (tests/common/mesh_distance.rs) checked against brute force.
//!
//! The oracle's nearest point is compared with the nearest of a dense sample of each
//! solid's surface, made without the oracle's case analysis: points on a grid of each
//! primitive surface (spacing [`H`]), kept where the solid's own membership test (a
//! closed formula written here, not the oracle's tree) differs a hair to either side,
//! the outward normal the side the solid is not on. The oracle's distance must not
//! exceed the dense sample's (it is the true minimum) and must be within the sample's
//! covering radius of it; its point must lie on the dense surface (within [`COVER`]), its
//! normal agree with the nearest dense point's away from creases. Crease distances
//! are checked where they have closed forms (the cube's faces, the classic part's flat
//! faces between the bore and the sphere), and the measurement on meshes whose
//! answers are known (a cube's own faces, a cube grown by one voxel, one turned
//! inside out).

mod common;

use std::f64::consts::{PI, TAU};

use common::Rng;
use common::exact_surface::{ExactSolid, Primitive, measure_with, sample_mesh};
use common::mesh_distance::{MeshDistance, closest_on_triangle};
use glam::DVec3;
use octsolid::mesh::{TriangleMesh, generate};

/// Spacing of the dense surface samples.
const H: f64 = 0.01;
/// How far a surface point may lie from the nearest dense sample: half a diagonal of
/// a grid cell inside a face, but at a corner where two grid rows are not kept (on a
/// crease membership is the same a hair to either side of one face) a whole spacing
/// in two directions: sqrt(2) H; the Fibonacci lattice's points are closer.
const COVER: f64 = 1.42 * H;

/// Points of a primitive's surface within the box `[lo, hi]`, about `H` apart.
fn surface_grid(prim: &Primitive, lo: DVec3, hi: DVec3) -> Vec<(DVec3, DVec3)> {
    let steps = |a: f64, b: f64| ((b - a) / H).ceil().max(1.0) as usize;
    let span = |a: f64, b: f64, k: usize, n: usize| a + (b - a) * k as f64 / n as f64;
    let mut out = Vec::new();
    match *prim {
        Primitive::Plane { axis, at, outward } => {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let (nu, nv) = (steps(lo[u], hi[u]), steps(lo[v], hi[v]));
            for i in 0..=nu {
                for j in 0..=nv {
                    let mut x = DVec3::ZERO;
                    x[axis] = at;
                    x[u] = span(lo[u], hi[u], i, nu);
                    x[v] = span(lo[v], hi[v], j, nv);
                    let mut n = DVec3::ZERO;
                    n[axis] = outward;
                    out.push((x, n));
                }
            }
        }
        Primitive::Sphere { centre, radius } => {
            // A Fibonacci lattice: n points of equal area, about H apart.
            let n = (4.0 * PI * radius * radius / (H * H)).ceil() as usize;
            let golden = PI * (3.0 - 5f64.sqrt());
            for k in 0..n {
                let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
                let r = (1.0 - z * z).sqrt();
                let d = DVec3::new(r * (golden * k as f64).cos(), r * (golden * k as f64).sin(), z);
                out.push((centre + radius * d, d));
            }
        }
        Primitive::Cylinder { axis, centre, radius } => {
            let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
            let (na, nt) = ((TAU * radius / H).ceil() as usize, steps(lo[axis], hi[axis]));
            for i in 0..na {
                let a = TAU * i as f64 / na as f64;
                let mut d = DVec3::ZERO;
                d[u] = a.cos();
                d[v] = a.sin();
                for j in 0..=nt {
                    let mut x = centre + radius * d;
                    x[axis] = span(lo[axis], hi[axis], j, nt);
                    out.push((x, d));
                }
            }
        }
        Primitive::Torus { centre, major, minor } => {
            let (np, nq) = ((TAU * (major + minor) / H).ceil() as usize, (TAU * minor / H).ceil() as usize);
            for i in 0..np {
                let p = TAU * i as f64 / np as f64;
                let ring = DVec3::new(p.cos(), p.sin(), 0.0);
                for j in 0..nq {
                    let q = TAU * j as f64 / nq as f64;
                    let d = q.cos() * ring + q.sin() * DVec3::Z;
                    out.push((centre + major * ring + minor * d, d));
                }
            }
        }
    }
    out
}

/// The dense surface of `solid` by rejection: grid points of each primitive surface
/// where `member` differs a hair to either side, with the outward normal.
fn dense_surface(solid: &ExactSolid, member: &dyn Fn(DVec3) -> bool) -> Vec<(DVec3, DVec3)> {
    let (lo, hi) = (solid.bounds.0 - DVec3::splat(2.0 * H), solid.bounds.1 + DVec3::splat(2.0 * H));
    let eps = 1e-9;
    let mut out = Vec::new();
    for prim in &solid.primitives {
        for (x, n) in surface_grid(prim, lo, hi) {
            let (ahead, behind) = (member(x + eps * n), member(x - eps * n));
            if ahead != behind {
                out.push((x, if behind { n } else { -n }));
            }
        }
    }
    out
}

fn brute_nearest(dense: &[(DVec3, DVec3)], p: DVec3) -> (f64, DVec3) {
    dense.iter().map(|&(x, n)| ((x - p).length(), n)).min_by(|a, b| a.0.total_cmp(&b.0)).unwrap()
}

/// The oracle against the dense surface at `queries` random points about the solid.
fn check_against_brute_force(solid: &ExactSolid, member: &dyn Fn(DVec3) -> bool, queries: usize, seed: u64) {
    let dense = dense_surface(solid, member);
    assert!(dense.len() > 1000, "{}: dense surface of {} points", solid.name, dense.len());
    let mut rng = Rng(seed);
    let (lo, hi) = (solid.bounds.0 - DVec3::splat(0.2), solid.bounds.1 + DVec3::splat(0.2));
    let mut normals_checked = 0;
    for q in 0..queries {
        // Half the queries near the surface (a dense point moved a little), half anywhere.
        let p = if q % 2 == 0 {
            let (x, _) = dense[rng.below(dense.len() as u64) as usize];
            x + rng.vec(-0.05, 0.05)
        } else {
            DVec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z))
        };
        let near = solid.nearest(p);
        let (brute, brute_normal) = brute_nearest(&dense, p);
        let what = format!("{} at {p}: oracle {} at {}, brute {brute}", solid.name, near.distance, near.point);
        assert!(near.distance <= brute + 1e-9, "{what}: the oracle is not the minimum");
        assert!(brute - near.distance <= COVER, "{what}: the oracle is nearer than the surface allows");
        assert!(((near.point - p).length() - near.distance).abs() < 1e-9, "{what}: distance to its own point");
        assert!(brute_nearest(&dense, near.point).0 <= COVER, "{what}: its point is not on the surface");
        assert_eq!(near.inside, member(p), "{what}: inside");
        if brute < 0.05 && solid.crease_distance(near.point) > 0.1 {
            let angle = near.normal.dot(brute_normal).clamp(-1.0, 1.0).acos().to_degrees();
            assert!(angle < 2.0, "{what}: normal {} against {brute_normal} ({angle} degrees)", near.normal);
            normals_checked += 1;
        }
    }
    assert!(normals_checked > queries / 8, "{}: only {normals_checked} normals checked", solid.name);
}

#[test]
fn sphere_and_torus_match_brute_force() {
    let sphere = ExactSolid::by_name("sphere").unwrap();
    check_against_brute_force(&sphere, &|p| p.length() <= 1.0, 200, 11);
    assert!(!sphere.has_creases());
    let torus = ExactSolid::by_name("torus").unwrap();
    check_against_brute_force(&torus, &|p| (p.x.hypot(p.y) - 1.0).hypot(p.z) <= 0.4, 200, 12);
    assert!(torus.crease_distance(DVec3::new(1.4, 0.0, 0.0)).is_infinite());
}

#[test]
fn cube_matches_brute_force_and_its_edges() {
    let cube = ExactSolid::by_name("cube").unwrap();
    check_against_brute_force(&cube, &|p| p.abs().max_element() <= 1.0, 300, 13);
    // Its corners are the eight vertices.
    let mut corners = cube.corners();
    assert_eq!(corners.len() % 8, 0, "{corners:?}");
    corners.iter_mut().for_each(|c| *c = (*c * 1e6).round() / 1e6);
    for c in &corners {
        assert!((c.abs() - DVec3::ONE).abs().max_element() < 1e-9, "{c}");
    }
    // On a face, the nearest crease is the nearest of its four edges.
    let mut rng = Rng(14);
    for _ in 0..200 {
        let axis = rng.below(3) as usize;
        let mut x = rng.vec(-1.0, 1.0);
        x[axis] = if rng.below(2) == 0 { 1.0 } else { -1.0 };
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let expected = (1.0 - x[u].abs()).min(1.0 - x[v].abs());
        let got = cube.crease_distance(x);
        assert!((got - expected).abs() < 1e-9, "{x}: {got} against {expected}");
    }
}

fn classic_member(p: DVec3) -> bool {
    let bore = |a: f64, b: f64| a.hypot(b) < 0.6;
    p.abs().max_element() <= 1.0 && p.length() <= 1.3 && !bore(p.y, p.z) && !bore(p.z, p.x) && !bore(p.x, p.y)
}

#[test]
fn classic_part_matches_brute_force() {
    let part = ExactSolid::classic();
    check_against_brute_force(&part, &classic_member, 400, 15);
    // The bores meet each other at the eight points |x| = |y| = |z|, x^2 + y^2 = 0.36.
    let corners = part.corners();
    let s = 0.18f64.sqrt();
    assert!(!corners.is_empty());
    for c in &corners {
        assert!((c.abs() - DVec3::splat(s)).abs().max_element() < 1e-9, "{c}");
    }
    for signs in 0..8 {
        let want = DVec3::new(
            if signs & 1 == 0 { s } else { -s },
            if signs & 2 == 0 { s } else { -s },
            if signs & 4 == 0 { s } else { -s },
        );
        assert!(corners.iter().any(|c| (*c - want).length() < 1e-9), "corner {want} missing");
    }
}

#[test]
fn classic_part_crease_distance_on_its_flat_faces() {
    // A flat face is the annulus between the bore (radius 0.6) and the sphere's circle
    // (radius sqrt(1.3^2 - 1)); its nearest crease is the nearer circle.
    let part = ExactSolid::classic();
    let outer = (1.69f64 - 1.0).sqrt();
    let mut rng = Rng(16);
    for _ in 0..300 {
        let axis = rng.below(3) as usize;
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        let (rho, angle) = (rng.range(0.6, outer), rng.range(0.0, TAU));
        let mut x = DVec3::ZERO;
        x[axis] = if rng.below(2) == 0 { 1.0 } else { -1.0 };
        x[u] = rho * angle.cos();
        x[v] = rho * angle.sin();
        let expected = (outer - rho).min(rho - 0.6);
        let got = part.crease_distance(x);
        assert!((got - expected).abs() < 1e-7, "{x}: {got} against {expected}");
        assert!(part.nearest(x).distance < 1e-12, "{x} is on the surface");
    }
}

#[test]
fn sphere_minus_cube_matches_brute_force() {
    let solid = ExactSolid::by_name("sphere-minus-cube").unwrap();
    let member = |p: DVec3| p.length() <= 1.0 && !(p.min_element() > 0.0 && p.max_element() < 2.0);
    check_against_brute_force(&solid, &member, 400, 17);
    // The concave corner at the origin is a corner of three creases.
    assert!(solid.corners().iter().any(|c| c.length() < 1e-9), "{:?}", solid.corners());
    // Just inside the removed octant, near the corner: the corner is the nearest point.
    let near = solid.nearest(DVec3::splat(0.01));
    assert!((near.distance - 0.01).abs() < 1e-9, "{near:?}");
}

#[test]
fn samples_are_area_weighted_and_on_their_triangles() {
    // Two triangles of areas 1 and 3.
    let mesh = TriangleMesh::new(
        vec![
            DVec3::ZERO,
            DVec3::new(2.0, 0.0, 0.0),
            DVec3::new(0.0, 1.0, 0.0),
            DVec3::new(0.0, 0.0, 2.0),
            DVec3::new(0.0, 3.0, 0.0),
        ],
        vec![[0, 1, 2], [0, 3, 4]],
    )
    .unwrap();
    let n = 40_000;
    let samples = sample_mesh(&mesh, n, 7);
    let first = samples.iter().filter(|s| s.triangle == 0).count() as f64 / n as f64;
    // Binomial standard deviation sqrt(0.25 * 0.75 / n) = 0.0022: within five.
    assert!((first - 0.25).abs() < 0.011, "share of the first triangle {first}");
    for s in &samples {
        let [a, b, c] = mesh.corners(s.triangle);
        assert!((closest_on_triangle(s.point, a, b, c) - s.point).length() < 1e-12, "{s:?}");
        assert!((s.normal - (b - a).cross(c - a).normalize()).length() < 1e-12);
    }
    // Seeded: the same seed, the same points.
    assert_eq!(
        sample_mesh(&mesh, 10, 7).iter().map(|s| s.point).collect::<Vec<_>>(),
        samples[..10].iter().map(|s| s.point).collect::<Vec<_>>()
    );
}

#[test]
fn measure_knows_a_cube_grown_and_turned_inside_out() {
    let cube = ExactSolid::by_name("cube").unwrap();
    let voxel = 0.01;
    let n = 20_000;
    // The cube's own faces: on the surface, normals exact; the share of area at least
    // two voxels from every edge is (1 - 0.02)^2 of each face.
    let own = generate::cuboid(DVec3::ZERO, DVec3::splat(2.0));
    let q = measure_with(&own, &cube, voxel, n, 3);
    assert_eq!(q.triangles, own.triangles.len());
    assert!(q.rms < 1e-9 && q.max < 1e-9, "{q:?}");
    assert!(q.median_normal_deg < 1e-6 && q.share_within_5deg_away_from_edges == 1.0, "{q:?}");
    assert!((q.share_away_from_edges - 0.98f64.powi(2)).abs() < 0.01, "{q:?}");
    // Grown by one voxel on every side: at least one voxel away everywhere (exactly
    // one over the faces' middles), at most sqrt(3) (a corner).
    let grown = generate::cuboid(DVec3::ZERO, DVec3::splat(2.0 + 2.0 * voxel));
    let q = measure_with(&grown, &cube, voxel, n, 3);
    assert!(q.rms >= 1.0 - 1e-9 && q.rms < 1.01 && q.max <= 3f64.sqrt() + 1e-9, "{q:?}");
    assert!(q.median_normal_deg < 1e-6, "{q:?}");
    // Turned inside out: every normal reversed.
    let mut inverted = own.clone();
    inverted.triangles.iter_mut().for_each(|t| t.swap(1, 2));
    let q = measure_with(&inverted, &cube, voxel, n, 3);
    assert!(q.median_normal_deg > 179.999 && q.share_within_5deg_away_from_edges == 0.0, "{q:?}");
}

#[test]
fn mesh_distance_matches_brute_force() {
    let mesh = generate::torus(1.0, 0.3, 40, 16);
    let tree = MeshDistance::new(&mesh);
    let mut rng = Rng(19);
    for _ in 0..300 {
        let p = rng.vec(-1.6, 1.6);
        let brute = (0..mesh.triangles.len())
            .map(|t| {
                let [a, b, c] = mesh.corners(t);
                (closest_on_triangle(p, a, b, c) - p).length()
            })
            .fold(f64::INFINITY, f64::min);
        assert_eq!(tree.distance(p), brute, "{p}");
    }
    // The nearest point of one triangle against a dense barycentric sample of it.
    let (a, b, c) = (DVec3::new(0.1, -0.2, 0.3), DVec3::new(1.2, 0.1, -0.4), DVec3::new(-0.3, 0.9, 0.2));
    for _ in 0..200 {
        let p = rng.vec(-1.5, 1.5);
        let exact = (closest_on_triangle(p, a, b, c) - p).length();
        let mut dense = f64::INFINITY;
        let n = 200;
        for i in 0..=n {
            for j in 0..=n - i {
                let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                dense = dense.min((a + u * (b - a) + v * (c - a) - p).length());
            }
        }
        assert!(exact <= dense + 1e-12 && dense - exact < 0.01, "{p}: {exact} against {dense}");
    }
}

#[test]
fn points_over_an_open_meshs_hole_are_told_apart() {
    // A cube of side 2 without its top face (z = 1): the point above the hole's middle
    // is nearest to its rim; points beside the walls and under the floor are not.
    let mut open = generate::cuboid(DVec3::ZERO, DVec3::splat(2.0));
    let top = |t: &[u32; 3]| t.iter().all(|&v| open.vertices[v as usize].z == 1.0);
    let kept: Vec<[u32; 3]> = open.triangles.iter().copied().filter(|t| !top(t)).collect();
    assert_eq!(kept.len(), open.triangles.len() - 2);
    open.triangles = kept;
    let tree = MeshDistance::new(&open);
    let mut rng = Rng(23);
    for _ in 0..200 {
        let (x, y) = (rng.vec(-0.9, 0.9).x, rng.vec(-0.9, 0.9).y);
        let above = tree.nearest(DVec3::new(x, y, 1.0 + rng.vec(0.0, 0.5).z));
        let expected = 1.0 - x.abs().max(y.abs());
        assert!(above.over_open_boundary, "({x}, {y}) above the hole");
        assert!(above.distance >= expected - 1e-12, "({x}, {y}): {above:?}");
        for (p, distance) in [(DVec3::new(1.3, x, y.min(0.8)), 0.3), (DVec3::new(x, y, -1.2), 0.2)] {
            let n = tree.nearest(p);
            assert!(!n.over_open_boundary && (n.distance - distance).abs() < 1e-12, "{p}: {n:?}");
        }
    }
    // A closed mesh has no open boundary.
    let closed = MeshDistance::new(&generate::torus(1.0, 0.3, 40, 16));
    assert!((0..300).all(|_| !closed.nearest(rng.vec(-1.6, 1.6)).over_open_boundary));
}
