//! Painter's algorithm for triangle meshes (the chapter's depth sort) against the
//! Z-buffer: at every pixel centre the same nearest triangle, or one whose depth there
//! is the Z-buffer's within rounding (coincident surfaces, shared edges). On random
//! soups with forced cycles and interpenetration, on every bundled mesh, and on pairs
//! that exactly one of the five tests settles.

use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::mesh::{TriangleMesh, read_mesh};
use octsolid::render::polygon::{DepthSortCounts, Fragment, MeshVisibility, visible_fragments};
use octsolid::render::{Camera, Projection};

mod common;

use common::Rng;

/// A mesh of separate triangles.
fn soup(triangles: &[[DVec3; 3]]) -> TriangleMesh {
    let vertices = triangles.iter().flatten().copied().collect();
    let indices = (0..triangles.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    TriangleMesh::new(vertices, indices).unwrap()
}

/// Painter's fragments checked against the Z-buffer's (see the module doc); the
/// depth sort's counts. `tolerance`: depths closer than this are a tie.
fn painter_matches_z_buffer(mesh: &TriangleMesh, camera: &Camera, w: u32, h: u32) -> DepthSortCounts {
    let budget = MemoryBudget::default();
    let (painted, counts) = visible_fragments(mesh, camera, w, h, budget, MeshVisibility::Painter).unwrap();
    let (buffered, _) = visible_fragments(mesh, camera, w, h, budget, MeshVisibility::ZBuffer).unwrap();
    let tolerance = 1e-9 * mesh.bounds().size().length().max(1.0) * 16.0;
    let mut differ = Vec::new();
    for (i, (p, z)) in painted.iter().zip(&buffered).enumerate() {
        let same = match (p, z) {
            (None, None) => true,
            (Some(p), Some(z)) => p.triangle == z.triangle || (p.depth - z.depth).abs() <= tolerance * p.depth.abs(),
            _ => false,
        };
        if !same {
            differ.push((
                i % w as usize,
                i / w as usize,
                p.map(|f: Fragment| (f.triangle, f.depth)),
                z.map(|f| (f.triangle, f.depth)),
            ));
        }
    }
    assert!(
        differ.is_empty(),
        "{} pixels differ, e.g. {:?}; counts {counts:?}",
        differ.len(),
        &differ[..differ.len().min(5)]
    );
    assert_eq!(counts.unresolved, 0, "{counts:?}");
    counts
}

/// The pictures from several perspective and parallel cameras around `centre`.
fn cameras(rng: &mut Rng, centre: DVec3, distance: f64, n: usize) -> Vec<Camera> {
    (0..n)
        .map(|k| {
            let eye = centre + rng.vec(-1.0, 1.0).normalize() * distance;
            let mut camera = Camera::look_at(eye, centre, DVec3::Z, 40.0);
            if k % 2 == 1 {
                camera.projection = Projection::Orthographic { height: distance * 0.8 };
            }
            camera
        })
        .collect()
}

#[test]
fn random_soups_match_the_z_buffer() {
    let mut rng = Rng(42);
    let mut total = DepthSortCounts::default();
    for _ in 0..12 {
        let triangles: Vec<[DVec3; 3]> = (0..30)
            .map(|_| {
                let c = rng.vec(-1.0, 1.0);
                [c + rng.vec(-0.8, 0.8), c + rng.vec(-0.8, 0.8), c + rng.vec(-0.8, 0.8)]
            })
            .collect();
        let mesh = soup(&triangles);
        for camera in cameras(&mut rng, DVec3::ZERO, 6.0, 2) {
            let c = painter_matches_z_buffer(&mesh, &camera, 64, 48);
            total.swaps += c.swaps;
            total.splits += c.splits;
        }
    }
    // Random soups interpenetrate: the sort must have split and swapped.
    assert!(total.splits > 0 && total.swaps > 0, "{total:?}");
}

/// Three long triangles each lying over the next: no order exists until one is split.
fn cycle_of_three() -> Vec<[DVec3; 3]> {
    (0..3)
        .map(|k| {
            let turn = |p: DVec3| {
                let a = f64::from(k) * std::f64::consts::TAU / 3.0;
                DVec3::new(p.x * a.cos() - p.y * a.sin(), p.x * a.sin() + p.y * a.cos(), p.z)
            };
            // From high (z = 0.3) at one end to low (z = -0.3) at the other, passing over
            // the next one's low end and under the previous one's high end.
            [turn(DVec3::new(-1.0, -0.35, 0.3)), turn(DVec3::new(-1.0, 0.05, 0.3)), turn(DVec3::new(1.2, -0.15, -0.3))]
        })
        .collect()
}

#[test]
fn a_cycle_of_three_triangles_is_split() {
    let mesh = soup(&cycle_of_three());
    let mut rng = Rng(7);
    let mut looks = cameras(&mut rng, DVec3::ZERO, 5.0, 4);
    looks.push(Camera::look_at(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO, DVec3::Y, 40.0));
    for camera in &looks {
        painter_matches_z_buffer(&mesh, camera, 80, 60);
    }
    // Seen from straight above the three overlap cyclically.
    let above = looks.last().unwrap();
    let counts = painter_matches_z_buffer(&mesh, above, 80, 60);
    assert!(counts.splits >= 1, "{counts:?}");
}

#[test]
fn interpenetrating_triangles_are_split() {
    let a = [DVec3::new(-1.0, -1.0, -0.5), DVec3::new(1.0, -1.0, -0.5), DVec3::new(0.0, 1.0, 0.5)];
    let b = [DVec3::new(-1.0, 1.0, -0.5), DVec3::new(1.0, 1.0, -0.5), DVec3::new(0.0, -1.0, 0.5)];
    let mesh = soup(&[a, b]);
    let camera = Camera::look_at(DVec3::new(0.3, -0.2, 5.0), DVec3::ZERO, DVec3::Y, 40.0);
    let counts = painter_matches_z_buffer(&mesh, &camera, 80, 60);
    assert!(counts.splits >= 1, "{counts:?}");
    let mut rng = Rng(3);
    for camera in cameras(&mut rng, DVec3::ZERO, 5.0, 6) {
        painter_matches_z_buffer(&mesh, &camera, 80, 60);
    }
}

#[test]
fn every_bundled_mesh_matches_the_z_buffer() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("models");
    let mut meshes: Vec<(String, TriangleMesh)> = std::fs::read_dir(&root)
        .unwrap()
        .filter_map(|e| {
            let path = e.unwrap().path();
            let name = path.file_name()?.to_string_lossy().into_owned();
            match path.extension()?.to_str()? {
                "obj" | "stl" | "ply" => Some((name, read_mesh(&path).unwrap())),
                "patches" => {
                    Some((name, octsolid::patch::tessellate(&octsolid::patch::read_patches(&path).unwrap(), 8)))
                }
                _ => None,
            }
        })
        .collect();
    meshes.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(meshes.len() >= 4, "bundled meshes: {:?}", meshes.iter().map(|m| &m.0).collect::<Vec<_>>());
    let mut rng = Rng(11);
    for (name, mesh) in &meshes {
        let bounds = mesh.bounds();
        for view in [DVec3::new(1.0, -2.0, 0.7), rng.vec(-1.0, 1.0)] {
            let camera = Camera::frame(&bounds, view, DVec3::Z, 4.0 / 3.0);
            let counts = painter_matches_z_buffer(mesh, &camera, 64, 48);
            eprintln!("{name}: {counts:?}");
        }
    }
}

/// Two triangles seen from above (a parallel view down `-z`, y up); the one reaching
/// farther (lower) first in the list. Returns which test settled the pair.
fn settled_by(p: [[f64; 3]; 3], q: [[f64; 3]; 3]) -> [u64; 5] {
    let mesh = soup(&[p.map(DVec3::from_array), q.map(DVec3::from_array)]);
    let camera = Camera {
        eye: DVec3::new(0.0, 0.0, 10.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Orthographic { height: 6.0 },
    };
    let c = painter_matches_z_buffer(&mesh, &camera, 60, 60);
    assert_eq!((c.swaps, c.splits, c.drawn), (0, 0, 2), "{c:?}");
    [c.x_extents, c.y_extents, c.behind_plane, c.in_front_of_plane, c.projections_disjoint]
}

#[test]
fn each_of_the_five_tests_settles_a_pair_alone() {
    // In every pair the depth extents overlap and P (first) reaches farther.
    // 1: side by side in x.
    let p = [[-2.0, -1.0, -1.0], [-1.0, -1.0, 0.0], [-1.5, 1.0, -0.5]];
    let q = [[1.0, -1.0, -0.5], [2.0, -1.0, 0.5], [1.5, 1.0, 0.0]];
    assert_eq!(settled_by(p, q), [1, 0, 0, 0, 0]);
    // 2: x extents overlap, one above the other in y.
    let p = [[-1.0, -2.0, -1.0], [1.0, -2.0, 0.0], [0.0, -1.0, -0.5]];
    let q = [[-1.0, 1.0, -0.5], [1.0, 1.0, 0.5], [0.0, 2.0, 0.0]];
    assert_eq!(settled_by(p, q), [0, 1, 0, 0, 0]);
    // 3: overlapping projections, P below Q's tilted plane z = 0.2 x.
    let p = [[-1.0, -1.0, -0.5], [1.0, -1.0, -0.1], [0.0, 1.0, -0.3]];
    let q = [[-1.0, -1.0, -0.2], [1.0, -1.0, 0.2], [0.0, 1.0, 0.0]];
    assert_eq!(settled_by(p, q), [0, 0, 1, 0, 0]);
    // 4: P's plane z = x / 2 reaches above Q's steep plane, but Q lies above P's.
    let p = [[-2.0, -2.0, -1.0], [2.0, -2.0, 1.0], [0.0, 2.0, 0.0]];
    let q = [[-0.5, -0.5, 0.3], [0.5, -0.5, 0.6], [0.0, 0.5, 0.9]];
    assert_eq!(settled_by(p, q), [0, 0, 0, 1, 0]);
    // 5: boxes overlap, each plane cuts across the other, the triangles lie on either
    // side of the diagonal x + y = 0.
    let p = [[-2.0, -2.0, -4.0], [0.9, -2.0, -1.1], [-2.0, 0.9, -1.1]];
    let q = [[2.0, 2.0, -2.0], [-0.9, 2.0, -2.0], [2.0, -0.9, -2.0]];
    assert_eq!(settled_by(p, q), [0, 0, 0, 0, 1]);
}
