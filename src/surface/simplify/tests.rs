//! Tests of the simplifier against independent oracles: analytic surfaces, brute-force
//! distances to the input mesh, every pair of output faces through the exact test.

use glam::DVec3;

use super::tri_tri::triangles_clash;
use super::{SimplifyOptions, SimplifyReport, simplify};
use crate::mesh::{BoundaryOptions, TriangleMesh, boundary_mesh, generate};
use crate::octree::{Domain, LinearOctree};
use crate::test_util::Rng;

/// A closed cylinder around z of `radius` from `z = -half` to `half`: `sides` around,
/// `rings` along, each cap a fan of `caps` rings; outward, welded.
fn cylinder(radius: f64, half: f64, sides: u32, rings: u32, caps: u32) -> TriangleMesh {
    let mut vertices = Vec::new();
    let angle = |i: u32| std::f64::consts::TAU * f64::from(i % sides) / f64::from(sides);
    let ring = |vertices: &mut Vec<DVec3>, r: f64, z: f64| {
        let first = vertices.len() as u32;
        for i in 0..sides {
            vertices.push(DVec3::new(r * angle(i).cos(), r * angle(i).sin(), z));
        }
        first
    };
    let mut triangles = Vec::new();
    // The wall and the caps' rings as one sequence of rings: bottom centre outward,
    // up the wall, top rim inward.
    let mut starts = Vec::new();
    for k in 1..=caps {
        starts.push(ring(&mut vertices, radius * f64::from(k) / f64::from(caps), -half));
    }
    for k in 1..rings {
        starts.push(ring(&mut vertices, radius, -half + 2.0 * half * f64::from(k) / f64::from(rings)));
    }
    for k in (1..=caps).rev() {
        starts.push(ring(&mut vertices, radius * f64::from(k) / f64::from(caps), half));
    }
    for w in starts.windows(2) {
        let (s, t) = (w[0], w[1]);
        for i in 0..sides {
            let j = (i + 1) % sides;
            triangles.extend([[s + i, s + j, t + j], [s + i, t + j, t + i]]);
        }
    }
    let (bottom, top) = (vertices.len() as u32, vertices.len() as u32 + 1);
    vertices.extend([DVec3::new(0.0, 0.0, -half), DVec3::new(0.0, 0.0, half)]);
    let (first, last) = (starts[0], *starts.last().unwrap());
    for i in 0..sides {
        let j = (i + 1) % sides;
        triangles.push([bottom, first + j, first + i]);
        triangles.push([top, last + i, last + j]);
    }
    let mesh = TriangleMesh { vertices, triangles, groups: Vec::new() };
    assert!(mesh.is_watertight() && mesh.volume() > 0.0);
    mesh
}

/// The cube `[-1, 1]^3` with each face an `n x n` grid of squares.
fn fine_cube(n: u32) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for axis in 0..3 {
        for side in [-1.0, 1.0] {
            let first = mesh.vertices.len() as u32;
            for i in 0..=n {
                for j in 0..=n {
                    let mut p = [0.0; 3];
                    p[axis] = side;
                    p[(axis + 1) % 3] = -1.0 + 2.0 * f64::from(i) / f64::from(n);
                    p[(axis + 2) % 3] = -1.0 + 2.0 * f64::from(j) / f64::from(n);
                    mesh.vertices.push(DVec3::from_array(p));
                }
            }
            let at = |i: u32, j: u32| first + i * (n + 1) + j;
            for i in 0..n {
                for j in 0..n {
                    let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                    // (axis+1) x (axis+2) = +axis: counter-clockwise seen from +axis.
                    if side > 0.0 {
                        mesh.triangles.extend([[a, b, c], [a, c, d]]);
                    } else {
                        mesh.triangles.extend([[a, c, b], [a, d, c]]);
                    }
                }
            }
        }
    }
    mesh.weld();
    assert!(mesh.is_watertight());
    mesh
}

/// Closest point of triangle `t` to `p` (Ericson, Real-Time Collision Detection 5.1.5).
fn closest_on_triangle(p: DVec3, [a, b, c]: [DVec3; 3]) -> DVec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

/// Points spread over every face of `mesh`: corners, edge midpoints, centroid and
/// `extra` random points a face.
fn samples(mesh: &TriangleMesh, extra: usize, rng: &mut Rng) -> Vec<DVec3> {
    let mut out = Vec::new();
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        out.extend([a, (a + b) / 2.0, (b + c) / 2.0, (c + a) / 2.0, (a + b + c) / 3.0]);
        for _ in 0..extra {
            let (mut u, mut v) = (rng.unit(), rng.unit());
            if u + v > 1.0 {
                (u, v) = (1.0 - u, 1.0 - v);
            }
            out.push(a + (b - a) * u + (c - a) * v);
        }
    }
    out
}

/// The largest distance from the sample points of `from` to the surface of `to`, by
/// brute force over `to`'s faces.
fn one_sided_distance(from: &TriangleMesh, to: &TriangleMesh, rng: &mut Rng) -> f64 {
    use rayon::prelude::*;
    let corners: Vec<[DVec3; 3]> = (0..to.triangles.len()).map(|t| to.corners(t)).collect();
    samples(from, 4, rng)
        .par_iter()
        .map(|&p| corners.iter().map(|&t| (closest_on_triangle(p, t) - p).length()).fold(f64::INFINITY, f64::min))
        .reduce(|| 0.0, f64::max)
}

/// Every pair of faces through the exact test (boxes first).
fn self_intersections(mesh: &TriangleMesh) -> usize {
    use rayon::prelude::*;
    let corners: Vec<[DVec3; 3]> = (0..mesh.triangles.len()).map(|t| mesh.corners(t)).collect();
    let boxes: Vec<(DVec3, DVec3)> =
        corners.iter().map(|c| (c[0].min(c[1]).min(c[2]), c[0].max(c[1]).max(c[2]))).collect();
    (0..corners.len())
        .into_par_iter()
        .map(|i| {
            (i + 1..corners.len())
                .filter(|&j| {
                    boxes[i].0.cmple(boxes[j].1).all()
                        && boxes[j].0.cmple(boxes[i].1).all()
                        && triangles_clash(corners[i], corners[j])
                })
                .count()
        })
        .sum()
}

/// The checks every output must pass: closed, manifold, oriented; no clash; volume
/// within the area times the bound; the bound within the tolerance.
fn check_output(input: &TriangleMesh, output: &TriangleMesh, report: &SimplifyReport, tolerance: f64) {
    assert!(output.is_watertight(), "not watertight");
    assert_eq!(self_intersections(output), 0, "self-intersections");
    assert_eq!(report.triangles_after, output.triangles.len());
    assert!(report.max_distance_bound <= tolerance, "{} > {tolerance}", report.max_distance_bound);
    let area: f64 = (0..input.triangles.len())
        .map(|t| {
            let [a, b, c] = input.corners(t);
            (b - a).cross(c - a).length() / 2.0
        })
        .sum();
    let dv = (output.volume() - input.volume()).abs();
    assert!(dv <= area * report.max_distance_bound + 1e-12, "volume moved {dv}, area {area}");
}

#[test]
fn a_sphere_keeps_within_the_tolerance_of_the_sphere_and_of_its_input() {
    let radius = 1.0;
    let input = generate::icosphere(DVec3::ZERO, radius, 5);
    // The input's own distance from the sphere: its faces' sagitta, at most.
    let sagitta = (0..input.triangles.len())
        .map(|t| {
            let c = input.corners(t);
            radius - ((c[0] + c[1] + c[2]) / 3.0).length()
        })
        .fold(0.0, f64::max);
    let tolerance = 0.002;
    let (output, report) = simplify(&input, &SimplifyOptions::new(tolerance)).unwrap();
    eprintln!("sphere: {report:?}");
    check_output(&input, &output, &report, tolerance);
    assert!(output.triangles.len() * 4 < input.triangles.len(), "{} triangles", output.triangles.len());
    let mut rng = Rng(1);
    for p in samples(&output, 8, &mut rng) {
        let off = (p.length() - radius).abs();
        assert!(off <= tolerance + 1.5 * sagitta, "{p} is {off} off the sphere");
    }
    // The bound is true: the input's points near the output and the output's near the
    // input, brute force on a smaller sphere.
    let small = generate::icosphere(DVec3::ZERO, radius, 3);
    let (out, report) = simplify(&small, &SimplifyOptions::new(0.02)).unwrap();
    check_output(&small, &out, &report, 0.02);
    assert!(out.triangles.len() < small.triangles.len() / 2, "{report:?}");
    let there = one_sided_distance(&out, &small, &mut rng);
    let back = one_sided_distance(&small, &out, &mut rng);
    assert!(there <= report.max_distance_bound && back <= report.max_distance_bound, "{there} {back} {report:?}");
}

#[test]
fn a_cylinder_keeps_its_rims_and_stays_on_the_cylinder() {
    let (radius, half) = (1.0, 1.0);
    let input = cylinder(radius, half, 256, 64, 16);
    let sagitta = radius * (1.0 - (std::f64::consts::PI / 256.0).cos());
    let tolerance = 0.002;
    let (output, report) = simplify(&input, &SimplifyOptions::new(tolerance)).unwrap();
    eprintln!("cylinder: {report:?}");
    check_output(&input, &output, &report, tolerance);
    assert!(output.triangles.len() * 8 < input.triangles.len(), "{} triangles", output.triangles.len());
    let mut rng = Rng(2);
    for p in samples(&output, 8, &mut rng) {
        // Distance to the capped cylinder's surface.
        let (r, z) = (p.truncate().length() - radius, p.z.abs() - half);
        let distance =
            if r <= 0.0 && z <= 0.0 { r.max(z).abs() } else { DVec3::new(r.max(0.0), z.max(0.0), 0.0).length() };
        assert!(distance <= tolerance + sagitta, "{p} is {distance} off the cylinder");
    }
}

/// The largest angle between a face's normal and the cylinder's outward radial
/// direction at its corners, over the wall faces whose corners all lie at least `away`
/// from the caps' planes (on the wall the angle is largest at a corner).
fn wall_normal_error(mesh: &TriangleMesh, half: f64, away: f64) -> f64 {
    (0..mesh.triangles.len())
        .filter_map(|t| {
            let c = mesh.corners(t);
            if c.iter().any(|p| p.z.abs() > half - away) {
                return None;
            }
            let n = (c[1] - c[0]).cross(c[2] - c[0]).normalize();
            Some(c.iter().map(|p| n.angle_between(p.truncate().extend(0.0).normalize())).fold(0.0, f64::max))
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_normal_tolerance_keeps_the_cylinders_normals_and_threads_agree() {
    // Oracle: an input wall face's normal is within half a side's angle of the radial
    // direction at each of its points; an output point lies within the distance bound
    // d of input points whose faces' normals its face's normal is within the normal
    // tolerance of, and radial directions of points d apart, both at least r from the
    // axis, differ by at most asin(d / r), r = radius cos(side) - d (chords and bound).
    let (radius, half, sides) = (1.0, 1.0, 256);
    let input = cylinder(radius, half, sides, 64, 16);
    let tolerance = 0.002;
    let side = std::f64::consts::PI / f64::from(sides);
    let plain = simplify(&input, &SimplifyOptions::new(tolerance)).unwrap();
    let angle = 1f64.to_radians();
    let options = SimplifyOptions { normal_tolerance: Some(angle), ..SimplifyOptions::new(tolerance) };
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| simplify(&input, &options).unwrap())
    };
    let ((output, report), (two, report_two)) = (run(1), run(2));
    assert_eq!(report, report_two);
    assert!(output.triangles == two.triangles && output.vertices == two.vertices);
    check_output(&input, &output, &report, tolerance);
    let bound = report.max_normal_bound.unwrap();
    assert!(bound <= angle && plain.1.max_normal_bound.is_none(), "{report:?}");
    let d = report.max_distance_bound;
    let oracle = bound + side + (d / (radius * side.cos() - d)).asin() + 1e-9;
    let error = wall_normal_error(&output, half, 2.0 * d);
    assert!(error <= oracle, "{} > {} degrees", error.to_degrees(), oracle.to_degrees());
    // The bound is what holds the normals: without it the strips widen past the
    // oracle, with it the mesh is still simplified.
    let plain_error = wall_normal_error(&plain.0, half, 2.0 * plain.1.max_distance_bound);
    assert!(plain_error > oracle, "{} degrees without the bound", plain_error.to_degrees());
    assert!(output.triangles.len() * 4 < input.triangles.len(), "{report:?}");
    // A bad normal tolerance is refused.
    for bad in [f64::NAN, -1.0, f64::INFINITY] {
        let options = SimplifyOptions { normal_tolerance: Some(bad), ..SimplifyOptions::new(tolerance) };
        assert!(simplify(&input, &options).is_err());
    }
}

#[test]
fn a_finely_cut_cube_becomes_twelve_triangles_on_its_corners() {
    let input = fine_cube(12);
    let (output, report) = simplify(&input, &SimplifyOptions::new(1e-6)).unwrap();
    check_output(&input, &output, &report, 1e-6);
    assert_eq!(output.triangles.len(), 12, "{report:?}");
    for v in &output.vertices {
        assert!(v.abs().cmpeq(DVec3::ONE).all(), "{v} is not a corner");
    }
    assert!((output.volume() - 8.0).abs() < 1e-12);
}

/// Records a job's progress.
#[derive(Default)]
struct Recorded {
    starts: std::sync::Mutex<Vec<u64>>,
    done: std::sync::atomic::AtomicU64,
    finishes: std::sync::atomic::AtomicU64,
}

impl crate::progress::Progress for Recorded {
    fn start(&self, total: u64) {
        self.starts.lock().unwrap().push(total);
    }
    fn advance(&self, n: u64) {
        self.done.fetch_add(n, std::sync::atomic::Ordering::Relaxed);
    }
    fn finish(&self) {
        self.finishes.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    }
}

#[test]
fn progress_runs_once_within_four_units_a_face_and_gives_the_same_mesh() {
    use std::sync::atomic::Ordering::Relaxed;
    let input = cylinder(1.0, 1.0, 48, 24, 4);
    let options = SimplifyOptions::new(1e-3);
    let recorded = Recorded::default();
    let (output, report) = super::simplify_with_progress(&input, &options, &recorded).unwrap();
    let total = 4 * input.triangles.len() as u64;
    assert_eq!(*recorded.starts.lock().unwrap(), vec![total]);
    assert_eq!(recorded.finishes.load(Relaxed), 1);
    // The first round's blocks report three units a face they own, every later round
    // half of what is left: past three quarters, never past the total.
    let done = recorded.done.load(Relaxed);
    assert!(done <= total && done > total / 2, "{done} of {total} ({} rounds)", report.rounds);
    assert_eq!((output, report), simplify(&input, &options).unwrap());
}

/// Staircases of random voxel sets, with voxels touching along edges and at corners
/// (sheets): manifold, no self-intersection, within the bound both ways.
#[test]
fn staircases_of_random_voxels_stay_manifold_and_intersection_free() {
    let mut rng = Rng(38);
    let domain = Domain::new(DVec3::ZERO, 1.0, 3).unwrap();
    let voxel = domain.voxel_size();
    let mut sheets = 0;
    for case in 0..12 {
        let fill = 0.2 + 0.05 * f64::from(case % 6);
        let voxels: Vec<[u32; 3]> =
            (0..512u32).filter(|_| rng.unit() < fill).map(|i| [i & 7, (i >> 3) & 7, i >> 6]).collect();
        let tree = LinearOctree::from_voxels(domain, voxels).unwrap();
        let input = boundary_mesh(&tree, &BoundaryOptions { unit_faces: true });
        if input.triangles.is_empty() {
            continue;
        }
        let mut positions: Vec<[u64; 3]> = input.vertices.iter().map(|v| v.to_array().map(f64::to_bits)).collect();
        positions.sort_unstable();
        sheets += positions.windows(2).filter(|w| w[0] == w[1]).count();
        let tolerance = 0.5 * voxel;
        let (output, report) = simplify(&input, &SimplifyOptions::new(tolerance)).unwrap();
        check_output(&input, &output, &report, tolerance);
        assert!(output.triangles.len() < input.triangles.len(), "case {case}: {report:?}");
        let there = one_sided_distance(&output, &input, &mut rng);
        let back = one_sided_distance(&input, &output, &mut rng);
        assert!(
            there <= report.max_distance_bound && back <= report.max_distance_bound,
            "case {case}: {there} {back} {report:?}"
        );
    }
    assert!(sheets > 10, "{sheets} sheet vertices: the cases do not touch along edges");
}

/// The voxel faces of a ball of radius 6.5 voxels at depth 4 with a twentieth of its
/// voxels missing (some of them touching only along edges: sheets).
fn holed_ball() -> TriangleMesh {
    let domain = Domain::new(DVec3::ZERO, 1.0, 4).unwrap();
    let mut rng = Rng(3);
    let voxels: Vec<[u32; 3]> = (0..4096u32)
        .filter(|&i| {
            let p = DVec3::new(f64::from(i & 15), f64::from((i >> 4) & 15), f64::from(i >> 8)) - 7.5;
            p.length() < 6.5 && rng.unit() < 0.95
        })
        .map(|i| [i & 15, (i >> 4) & 15, i >> 8])
        .collect();
    boundary_mesh(&LinearOctree::from_voxels(domain, voxels).unwrap(), &BoundaryOptions { unit_faces: true })
}

#[test]
fn one_and_two_threads_give_the_same_mesh() {
    for (input, tolerance) in [(generate::icosphere(DVec3::ZERO, 1.0, 5), 0.002), (holed_ball(), 0.5 / 16.0)] {
        let run = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            pool.install(|| simplify(&input, &SimplifyOptions::new(tolerance)).unwrap())
        };
        let ((one, report_one), (two, report_two)) = (run(1), run(2));
        assert_eq!(report_one, report_two);
        assert!(one.triangles == two.triangles);
        assert!(
            one.vertices
                .iter()
                .zip(&two.vertices)
                .all(|(a, b)| a.to_array().map(f64::to_bits) == b.to_array().map(f64::to_bits))
        );
        assert!(report_one.collapses > 0);
    }
}

#[test]
fn bad_options_and_open_meshes_are_refused() {
    let cube = generate::cuboid(DVec3::ZERO, DVec3::ONE);
    assert!(simplify(&cube, &SimplifyOptions::new(f64::NAN)).is_err());
    assert!(simplify(&cube, &SimplifyOptions::new(-1.0)).is_err());
    let mut open = cube.clone();
    open.triangles.pop();
    assert!(simplify(&open, &SimplifyOptions::new(0.1)).is_err());
    let (same, report) = simplify(&cube, &SimplifyOptions::new(0.1)).unwrap();
    assert_eq!((same.triangles.len(), report.collapses), (12, 0));
}

/// The mesh a block gives back: the snapshot's positions with its moved vertices,
/// its own faces.
fn block_result(positions: &[DVec3], out: &super::block::BlockOutput) -> TriangleMesh {
    let mut vertices = positions.to_vec();
    for &(v, p, _, _) in &out.moved {
        vertices[v as usize] = p;
    }
    TriangleMesh { vertices, triangles: out.faces.clone(), ..TriangleMesh::default() }
}

/// A block whose first result clashes is simplified again testing the collapses
/// near the clashes only, and that result is checked again: every result a block
/// gives back is free of clashes, whether its second try watched the cells near
/// the clashes or every cell (oracle: every pair of output faces through the exact
/// test).
#[test]
fn a_block_whose_result_clashes_is_tried_again_near_the_clashes() {
    use super::block::{BlockInput, Limits, simplify_block_trying};
    // Its holes make sheets, which the untested collapses fold into each other.
    let mesh = holed_ball();
    let state = super::State::new(&mesh);
    let own: Vec<u32> = (0..mesh.triangles.len() as u32).collect();
    let input = BlockInput {
        min: DVec3::splat(-0.25),
        max: DVec3::splat(1.25),
        positions: &state.positions,
        quadrics: &state.quadrics,
        bounds: &state.bounds,
        faces: &state.faces,
        cones: &state.cones,
        own: &own,
        halo: &[],
        moved_in: &state.moved_in,
        refused: &state.refused,
    };
    let limits = Limits { tolerance: 0.5 / 16.0, min_normal_cosine: 30f64.to_radians().cos(), max_turn: None };
    let near = simplify_block_trying(&input, &limits, 1);
    let every = simplify_block_trying(&input, &limits, 0);
    assert!(near.tries >= 2 && every.tries == 2, "{} {}", near.tries, every.tries);
    assert!(near.watched > 0 && near.watched < every.watched, "{} of {}", near.watched, every.watched);
    for out in [&near, &every] {
        let result = block_result(&state.positions, out);
        assert!(result.is_watertight(), "not watertight");
        assert_eq!(self_intersections(&result), 0, "self-intersections");
    }
}
