//! Whitted ray tracing on octree solids: refraction through a slab walked by the octree,
//! energy bounds, and the classic scene rendering.

use glam::DVec3;
use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
use octsolid::render::radiance;
use octsolid::render::refract;
use octsolid::render::{Light, Material, Normals, Scene, ShadeOptions};
use octsolid::shape::{Cuboid, Sphere};
use octsolid::{Ray, RayCast};

mod common;

use common::Rng;

#[test]
fn a_ray_through_a_voxel_slab_comes_out_parallel_and_offset_as_snell_says() {
    // A slab 0.25 thick between lattice planes of a depth-6 domain (voxel 1/32).
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let slab = Cuboid::from_corners(DVec3::new(-0.9, -0.9, 0.0), DVec3::new(0.9, 0.9, 0.25)).unwrap();
    let mut scene = Scene::new();
    let glass = Material { transmittance: 1.0, ior: 1.5, ..Material::default() };
    scene.add("slab", voxelize(&slab, domain, &VoxelizeOptions::default()).unwrap(), glass);
    let mut rng = Rng(3);
    for _ in 0..200 {
        let angle = rng.range(0.0, 1.4);
        let phi = rng.range(0.0, std::f64::consts::TAU);
        let d = DVec3::new(angle.sin() * phi.cos(), angle.sin() * phi.sin(), -angle.cos());
        let origin = DVec3::new(rng.range(-0.2, 0.2), rng.range(-0.2, 0.2), 0.25) - d * 0.5;
        let sh = scene.hit(&Ray::new(origin, d)).expect("the slab is below");
        let p = origin + d * sh.hit.t;
        assert!((p.z - 0.25).abs() < 1e-12, "enters the top face: {p}");
        let inside = refract(d, sh.hit.normal(d), 1.0, 1.5).unwrap();
        let exit = scene.solids[0].exit(&Ray::new(p + inside * 1e-9, inside)).expect("leaves through the bottom");
        let q = p + inside * (1e-9 + exit.t);
        assert_eq!(exit.axis, Some(2), "{exit:?} from {p} along {inside}");
        assert!(q.z.abs() < 1e-12, "leaves the bottom face: {q}");
        let out = refract(inside, DVec3::Z, 1.5, 1.0).unwrap();
        assert!((out - d).length() < 1e-12, "parallel: {out} vs {d}");
        // The offset from the unrefracted line: thickness sin(i - t) / cos(t).
        let t = (angle.sin() / 1.5).asin();
        let offset = (q - p).cross(d).length();
        assert!((offset - 0.25 * (angle - t).sin() / t.cos()).abs() < 1e-9, "angle {angle}: {offset}");
    }
}

#[test]
fn whitted_never_returns_more_light_than_comes_in() {
    // Lights summing to 1, materials with ka + kd + ks <= 1 and kr + kt <= 1, a
    // background of 1: no ray may carry more than 1 in any channel.
    let domain = Domain::new(DVec3::splat(-2.0), 4.0, 7).unwrap();
    let mut rng = Rng(11);
    let mut scene = Scene::new();
    for i in 0..5 {
        let sphere = Sphere::new(rng.vec(-1.2, 1.2), rng.range(0.3, 0.7)).unwrap();
        let (ka, kd) = (rng.range(0.0, 0.3), rng.range(0.0, 0.5));
        let kr = rng.range(0.0, 1.0);
        let material = Material {
            color: DVec3::new(rng.unit(), rng.unit(), rng.unit()),
            ka,
            kd,
            ks: rng.range(0.0, 1.0 - ka - kd),
            shininess: rng.range(1.0, 64.0),
            reflectance: kr,
            transmittance: rng.range(0.0, 1.0 - kr),
            ior: rng.range(1.0, 2.4),
            ..Material::default()
        };
        material.check().unwrap();
        scene.add(format!("ball {i}"), voxelize(&sphere, domain, &VoxelizeOptions::default()).unwrap(), material);
    }
    scene.lights = vec![
        Light::Point { position: DVec3::new(3.0, -2.0, 4.0), color: DVec3::splat(0.6) },
        Light::Directional { direction: DVec3::new(-1.0, 0.5, -1.0), color: DVec3::splat(0.4) },
    ];
    scene.ambient = DVec3::ONE;
    scene.background = DVec3::ONE;
    let mut seen = 0;
    for normals in [Normals::Axis, Normals::Smooth] {
        let options = ShadeOptions { normals, max_depth: 8, ..ShadeOptions::default() };
        for _ in 0..3000 {
            let origin = rng.vec(-1.0, 1.0).normalize() * 5.0;
            let dir = (rng.vec(-1.0, 1.0) - origin).normalize();
            let ray = Ray::new(origin, dir);
            if let Some(sh) = scene.hit(&ray) {
                seen += 1;
                let (c, _) = radiance(&scene, &ray, &sh, &options);
                assert!(c.max_element() <= 1.0 + 1e-9 && c.min_element() >= 0.0, "{c}");
            }
        }
    }
    assert!(seen > 1000, "{seen} rays hit");
}

#[test]
fn materials_out_of_range_are_refused() {
    let bad = [
        Material { reflectance: 0.7, transmittance: 0.5, ..Material::default() },
        Material { ior: 0.0, ..Material::default() },
        Material { ka: -0.1, ..Material::default() },
        Material { transmittance: f64::NAN, ..Material::default() },
    ];
    for m in bad {
        assert!(m.check().is_err(), "{m:?}");
    }
    assert!(Material::default().check().is_ok());
}

/// A mirror ball (reflectance 0.9, no local light) alone before a blue background,
/// seen by a 160x160 camera.
fn mirror_ball() -> (Scene, octsolid::render::Camera) {
    use octsolid::render::Camera;
    use std::sync::Arc;
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 8).unwrap();
    let sphere = Sphere::new(DVec3::new(0.03, -0.02, 0.01), 0.7).unwrap();
    let mirror = Material { color: DVec3::ZERO, ka: 0.0, kd: 0.0, ks: 0.0, reflectance: 0.9, ..Material::default() };
    let mut scene = Scene::new();
    let tree = voxelize(&sphere, domain, &VoxelizeOptions::default()).unwrap();
    scene.add_shaped("mirror", tree, mirror, Arc::new(sphere));
    scene.background = DVec3::new(0.2, 0.5, 0.8);
    scene.lights = vec![Light::Directional { direction: DVec3::new(-1.0, -0.5, -1.0), color: DVec3::ONE }];
    (scene, Camera::look_at(DVec3::new(0.4, -3.0, 1.2), DVec3::ZERO, DVec3::Z, 35.0))
}

#[test]
fn a_voxelized_mirror_ball_reflects_only_the_background() {
    // Every ray reflected off a convex surface escapes, so with the sphere's own
    // normals every pixel shows the background B or 0.9 B exactly. A ray caught on the
    // voxel staircase (reflected into a neighbouring step) would show 0.81 B or less.
    use octsolid::NoProgress;
    use octsolid::render::to_srgb8;
    use octsolid::render::{RenderOptions, render};
    let (scene, camera) = mirror_ball();
    let options = RenderOptions { width: 160, height: 160, spp: 1, normals: Normals::Smooth, ..Default::default() };
    let (img, stats) = render(&scene, &camera, &options, &NoProgress).unwrap();
    let srgb = |c: DVec3| [to_srgb8(c.x), to_srgb8(c.y), to_srgb8(c.z)];
    let (background, reflected) = (srgb(scene.background), srgb(scene.background * 0.9));
    let on_ball = img.pixels().filter(|p| p.0 == reflected).count();
    let wrong = img.pixels().filter(|p| p.0 != background && p.0 != reflected).count();
    assert!(on_ball > 8_000 && on_ball as u64 <= stats.hits, "{on_ball} pixels show the reflection");
    assert_eq!(wrong, 0, "{wrong} pixels are neither the background nor its reflection");
}

#[test]
fn a_reflection_whose_share_is_at_the_cutoff_is_not_traced() {
    // The ball's reflected rays carry 0.9 of their pixel: traced with a cutoff just
    // below (0.9 B on the ball), not at 0.9 (the ball black: it has no local light),
    // and a cutoff outside 0..=1 is refused. (A primary ray through a sliver of the
    // staircase at the silhouette passes on to the background.)
    use octsolid::NoProgress;
    use octsolid::render::to_srgb8;
    use octsolid::render::{RenderOptions, render};
    let (scene, camera) = mirror_ball();
    let srgb = |c: DVec3| [to_srgb8(c.x), to_srgb8(c.y), to_srgb8(c.z)];
    let base = RenderOptions { width: 64, height: 64, spp: 1, normals: Normals::Smooth, ..Default::default() };
    let ball = |cutoff: f64| {
        let (img, stats) = render(&scene, &camera, &RenderOptions { cutoff, ..base }, &NoProgress).unwrap();
        let on_ball = img.pixels().filter(|p| p.0 != srgb(scene.background)).map(|p| p.0).collect::<Vec<_>>();
        (on_ball, stats.hits)
    };
    let (traced, hits) = ball(0.899);
    let most = |pixels: &[[u8; 3]], hits: u64| {
        hits > 1000 && pixels.len() as u64 <= hits && pixels.len() as u64 > hits * 99 / 100
    };
    assert!(most(&traced, hits), "{} of {hits}", traced.len());
    assert!(traced.iter().all(|&p| p == srgb(scene.background * 0.9)));
    let (cut, hits) = ball(0.9);
    assert!(most(&cut, hits), "{} of {hits}", cut.len());
    assert!(cut.iter().all(|&p| p == [0, 0, 0]));
    for cutoff in [-0.1, 1.5, f64::NAN] {
        let err = render(&scene, &camera, &RenderOptions { cutoff, ..base }, &NoProgress).unwrap_err();
        assert!(err.to_string().contains("ray cutoff"), "{err}");
    }
}
