//! The polygon renderer: visibility against brute-force ray casting, the silhouette of
//! a sphere, and the three interpolation shadings against their definitions.

use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::mesh::TriangleMesh;
use octsolid::mesh::generate::{icosphere, torus};
use octsolid::render::polygon::{Interpolation, MeshRenderOptions, MeshScene, fragments, render_mesh, vertex_normals};
use octsolid::render::{Camera, Light, Material, Projection};

mod common;

use common::Rng;

/// One sample a pixel under the default budget.
fn options(width: u32, height: u32, interpolation: Interpolation) -> MeshRenderOptions {
    MeshRenderOptions { width, height, spp: 1, interpolation, budget: MemoryBudget::default(), exposure: 0.0 }
}

/// Nearest hit distance of the ray over all triangles (Moller-Trumbore), brute force.
fn nearest(mesh: &TriangleMesh, o: DVec3, d: DVec3) -> Option<f64> {
    (0..mesh.triangles.len())
        .filter_map(|i| {
            let [a, b, c] = mesh.corners(i);
            let (e1, e2) = (b - a, c - a);
            let p = d.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-15 {
                return None;
            }
            let s = o - a;
            let u = s.dot(p) / det;
            let q = s.cross(e1);
            let v = d.dot(q) / det;
            let t = e2.dot(q) / det;
            (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t > 0.0).then_some(t)
        })
        .min_by(f64::total_cmp)
}

fn camera(eye: DVec3) -> Camera {
    Camera::look_at(eye, DVec3::ZERO, DVec3::Z, 40.0)
}

#[test]
fn visibility_matches_brute_force_ray_casting() {
    let mut rng = Rng(12);
    let mut mesh = torus(0.8, 0.3, 24, 12);
    let ball = icosphere(DVec3::new(0.2, -0.3, 0.4), 0.5, 2);
    let offset = mesh.vertices.len() as u32;
    mesh.vertices.extend(ball.vertices);
    mesh.triangles.extend(ball.triangles.iter().map(|t| t.map(|v| v + offset)));
    let (w, h) = (96u32, 72u32);
    for _ in 0..4 {
        let cam = camera(rng.vec(-1.0, 1.0).normalize() * 4.0);
        let seen = fragments(&mesh, &cam, w, h, MemoryBudget::default()).unwrap();
        let forward = (cam.target - cam.eye).normalize();
        let (mut agree, mut total) = (0, 0);
        for (i, f) in seen.iter().enumerate() {
            let (x, y) = ((i as u32 % w) as f64 + 0.5, (i as u32 / w) as f64 + 0.5);
            let ray = cam.ray(2.0 * x / f64::from(w) - 1.0, 1.0 - 2.0 * y / f64::from(h), f64::from(w) / f64::from(h));
            let (o, d) = (ray.origin, ray.dir);
            let want = nearest(&mesh, o, d).map(|t| t * d.dot(forward));
            total += 1;
            match (f, want) {
                (Some(f), Some(t)) if (f.depth - t).abs() < 1e-9 => agree += 1,
                (None, None) => agree += 1,
                _ => {}
            }
        }
        // Pixel centres on a shared edge may go either way; nothing else may differ.
        assert!(agree as f64 >= 0.999 * total as f64, "{agree} of {total} pixels agree");
    }
}

#[test]
fn an_orthographic_sphere_covers_its_disc() {
    let mesh = icosphere(DVec3::ZERO, 0.8, 5);
    let cam = Camera { projection: Projection::Orthographic { height: 2.0 }, ..camera(DVec3::new(0.0, 0.0, 3.0)) };
    let cam = Camera { up: DVec3::Y, ..cam };
    let seen = fragments(&mesh, &cam, 400, 400, MemoryBudget::default()).unwrap();
    let covered = seen.iter().filter(|f| f.is_some()).count() as f64;
    let disc = std::f64::consts::PI * (0.8 * 200.0f64).powi(2);
    assert!((covered / disc - 1.0).abs() < 0.01, "{covered} pixels vs {disc}");
}

fn lit(mesh: &TriangleMesh, l: DVec3) -> MeshScene<'_> {
    MeshScene {
        mesh,
        material: Material::phong(DVec3::new(0.8, 0.6, 0.4), 0.2, 0.6, 0.4, 20.0),
        lights: vec![Light::Directional { direction: -l, color: DVec3::ONE }],
        ambient: DVec3::splat(0.2),
        background: DVec3::ZERO,
    }
}

#[test]
fn flat_shading_gives_one_colour_a_triangle_and_phong_finds_the_highlight() {
    let mesh = icosphere(DVec3::ZERO, 0.8, 2);
    let l = DVec3::new(0.3, 0.2, 1.0).normalize();
    let cam = Camera {
        projection: Projection::Orthographic { height: 2.0 },
        up: DVec3::Y,
        ..camera(DVec3::new(0.0, 0.0, 3.0))
    };
    let scene = lit(&mesh, l);
    let (w, h) = (200u32, 200u32);
    let seen = fragments(&mesh, &cam, w, h, MemoryBudget::default()).unwrap();
    let flat = render_mesh(&scene, &cam, &options(w, h, Interpolation::Flat)).unwrap().to_srgb8();
    let gouraud = render_mesh(&scene, &cam, &options(w, h, Interpolation::Gouraud)).unwrap().to_srgb8();
    let mut colour_of = std::collections::HashMap::new();
    let mut varies = 0;
    for (i, f) in seen.iter().enumerate() {
        let Some(f) = f else { continue };
        let (x, y) = (i as u32 % w, i as u32 / w);
        let c = flat.get_pixel(x, y).0;
        assert_eq!(*colour_of.entry(f.triangle).or_insert(c), c, "flat: triangle {} has two colours", f.triangle);
        varies += usize::from(gouraud.get_pixel(x, y).0 != c);
    }
    assert!(varies > 1000, "Gouraud colours vary inside triangles ({varies} pixels differ from flat)");
    // Phong on a fine sphere: the brightest pixel is where the analytic highlight is,
    // the normal halfway between the light and the viewer (+z).
    let fine = icosphere(DVec3::ZERO, 0.8, 5);
    let phong = render_mesh(&lit(&fine, l), &cam, &options(w, h, Interpolation::Phong)).unwrap().to_srgb8();
    let (mut best, mut at) = (0u32, (0u32, 0u32));
    for (x, y, p) in phong.enumerate_pixels() {
        let s = p.0.iter().map(|&c| u32::from(c)).sum::<u32>();
        if s > best {
            (best, at) = (s, (x, y));
        }
    }
    let half = (l + DVec3::Z).normalize() * 0.8;
    let want = (100.0 + half.x * 100.0, 100.0 - half.y * 100.0);
    let off = (f64::from(at.0) + 0.5 - want.0).hypot(f64::from(at.1) + 0.5 - want.1);
    assert!(off < 3.0, "brightest pixel {at:?}, analytic highlight at {want:?}");
}

#[test]
fn vertex_normals_of_a_sphere_point_outwards() {
    let mesh = icosphere(DVec3::new(1.0, 2.0, 3.0), 0.5, 3);
    for (v, n) in mesh.vertices.iter().zip(vertex_normals(&mesh)) {
        let radial = (*v - DVec3::new(1.0, 2.0, 3.0)).normalize();
        assert!(n.angle_between(radial) < 0.025, "{n} vs {radial}");
    }
}
