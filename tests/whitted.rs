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
        material.validate().unwrap();
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
        assert!(m.validate().is_err(), "{m:?}");
    }
    assert!(Material::default().validate().is_ok());
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
    let options = RenderOptions { width: 160, height: 160, spp: 1, shade: smooth(), ..Default::default() };
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
    let base = RenderOptions { width: 64, height: 64, spp: 1, shade: smooth(), ..Default::default() };
    let ball = |cutoff: f64| {
        let (img, stats) = render(
            &scene,
            &camera,
            &RenderOptions { shade: ShadeOptions { cutoff, ..base.shade }, ..base },
            &NoProgress,
        )
        .unwrap();
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
        let err = render(
            &scene,
            &camera,
            &RenderOptions { shade: ShadeOptions { cutoff, ..base.shade }, ..base },
            &NoProgress,
        )
        .unwrap_err();
        assert!(err.to_string().contains("ray cutoff"), "{err}");
    }
}

/// A ball of radius 0.5 (its own normals) hovering over a large thin floor that is a
/// solid of its own coarser domain (normals estimated from its octree, as an `.oct`
/// floor's), lit by one directional light from 35 degrees above the horizon; the
/// floor's top is at z = 0, on its voxel lattice.
struct BallOverFloor {
    scene: Scene,
    camera: octsolid::render::Camera,
    center: DVec3,
    radius: f64,
    /// Unit vector towards the light.
    to_light: DVec3,
    /// The coarser voxel: the floor's.
    voxel: f64,
}

impl BallOverFloor {
    fn new(ball: Material, floor: Material) -> Self {
        use octsolid::render::Camera;
        use std::sync::Arc;
        let (center, radius) = (DVec3::new(0.05, 0.02, 0.75), 0.5);
        let sphere = Sphere::new(center, radius).unwrap();
        let ball_domain = Domain::new(center - DVec3::splat(0.6), 1.2, 8).unwrap();
        // 8 units at depth 8: voxels of 1/32, the top at z = 0 on a lattice plane.
        let floor_domain = Domain::new(DVec3::new(-4.0, -4.0, -4.0), 8.0, 8).unwrap();
        let slab = Cuboid::from_corners(DVec3::new(-4.0, -4.0, -0.25), DVec3::new(4.0, 4.0, 0.0)).unwrap();
        let mut scene = Scene::new();
        scene.add_shaped(
            "ball",
            voxelize(&sphere, ball_domain, &VoxelizeOptions::default()).unwrap(),
            ball,
            Arc::new(sphere),
        );
        scene.add("floor", voxelize(&slab, floor_domain, &VoxelizeOptions::default()).unwrap(), floor);
        let to_light = DVec3::new(-0.6, -0.45, 35f64.to_radians().tan()).normalize();
        scene.lights = vec![Light::Directional { direction: -to_light, color: DVec3::ONE }];
        scene.ambient = DVec3::ZERO;
        scene.background = DVec3::ZERO;
        let camera = Camera::look_at(DVec3::new(1.2, -3.4, 2.4), DVec3::new(-0.3, 0.3, 0.2), DVec3::Z, 45.0);
        BallOverFloor { scene, camera, center, radius, to_light, voxel: 8.0 / 256.0 }
    }

    /// Where the ray first meets the exact ball, if it does.
    fn ball_hit(&self, ray: &Ray) -> Option<f64> {
        let oc = ray.origin - self.center;
        let b = oc.dot(ray.dir);
        let disc = b * b - (oc.length_squared() - self.radius * self.radius);
        (disc >= 0.0).then(|| -b - disc.sqrt()).filter(|&t| t > 0.0)
    }

    /// The exact scene along the primary ray of pixel `(x, y)` of a `size` picture:
    /// `Some(point on the floor's top)` when it meets the floor before the ball.
    fn floor_point(&self, size: (u32, u32), x: u32, y: u32) -> Option<DVec3> {
        let samples = octsolid::render::SampleGrid { width: size.0, height: size.1, spp: 1 };
        let (u, v) = samples.point(x, y);
        let ray = self.camera.view(samples.aspect()).ray(u, v);
        // Not the ball, nor within 1.5 of its voxels of it (its staircase).
        let oc = self.center - ray.origin;
        let passes = (oc - ray.dir * oc.dot(ray.dir)).length() - self.radius;
        if passes < 1.5 * 1.2 / 256.0 || ray.dir.z >= 0.0 {
            return None;
        }
        let p = ray.at(-ray.origin.z / ray.dir.z);
        (p.x.abs() < 3.5 && p.y.abs() < 3.5).then_some(p)
    }

    /// How far the shadow ray from the floor point `p` passes from the ball's
    /// surface (negative: through the ball, so `p` is in its shadow).
    fn shadow_margin(&self, p: DVec3) -> f64 {
        let oc = self.center - p;
        let along = oc.dot(self.to_light);
        if along <= 0.0 {
            return f64::INFINITY;
        }
        (oc - self.to_light * along).length() - self.radius
    }
}

#[test]
fn shadows_on_a_floor_fall_where_the_exact_ball_casts_them() {
    // White floor, kd 1, no ambient: a floor pixel is cos(theta) lit, 0 in shadow. The
    // ball's exact shadow decides every pixel but those whose shadow ray passes within
    // two of the ball's voxels of it (its staircase), at one sample a pixel. Shadow
    // rays that started two floor voxels along the floor's normal (as they did) moved
    // the shadow's edge by 2 h / tan(35 degrees), 14 of the ball's voxels.
    use octsolid::NoProgress;
    use octsolid::render::{RenderOptions, render_picture};
    let white = Material { color: DVec3::ONE, ka: 0.0, kd: 1.0, ks: 0.0, ..Material::default() };
    let world = BallOverFloor::new(white.clone(), white);
    let size = (200, 150);
    let options = RenderOptions { width: size.0, height: size.1, spp: 1, shade: smooth(), ..RenderOptions::default() };
    let (picture, _) = render_picture(&world.scene, &world.camera, &options, &NoProgress).unwrap();
    let lit = world.to_light.z;
    let (mut judged, mut shadowed, mut wrong) = (0, 0, Vec::new());
    for y in 0..size.1 {
        for x in 0..size.0 {
            let Some(p) = world.floor_point(size, x, y) else { continue };
            let margin = world.shadow_margin(p);
            if margin.abs() < 2.0 * 1.2 / 256.0 {
                continue;
            }
            judged += 1;
            shadowed += usize::from(margin < 0.0);
            let want = if margin < 0.0 { 0.0 } else { lit };
            if (picture.get(x, y).x - want).abs() > 1e-6 {
                wrong.push((x, y, margin / world.voxel));
            }
        }
    }
    assert!(judged > 15_000 && shadowed > 500, "{judged} floor pixels judged, {shadowed} in shadow");
    assert!(
        wrong.is_empty(),
        "{} of {judged} floor pixels wrong, e.g. {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(5)]
    );
}

#[test]
fn a_mirror_ball_reflects_the_checkered_floor_as_the_exact_ball_does() {
    // The ball a perfect mirror (no local light), the floor a checker shown as it is
    // (ambient 1, ka 1): each ball pixel is the checker colour where the exact ball's
    // reflected ray meets the floor, or the black background. Judged: the pixels whose
    // reflection lands clear of checker edges by a tenth of a checker plus what three
    // of the ball's voxels move it (a ray leaves the staircase, not the ball), and
    // whose whole pixel reflects into one checker (no aliasing). Of those at most 0.5%
    // may differ; a reflected ray caught by the ball's own voxels shows black.
    use octsolid::NoProgress;
    use octsolid::render::{RenderOptions, SampleGrid, Texture, render_picture};
    let mirror = Material { color: DVec3::ZERO, ka: 0.0, kd: 0.0, ks: 0.0, reflectance: 1.0, ..Material::default() };
    let (a, b) = (DVec3::new(0.9, 0.8, 0.1), DVec3::new(0.1, 0.2, 0.7));
    let size = 0.4;
    let checker =
        Material { ka: 1.0, kd: 0.0, ks: 0.0, texture: Some(Texture::Checker { size, a, b }), ..Material::default() };
    let mut world = BallOverFloor::new(mirror, checker);
    world.scene.ambient = DVec3::ONE;
    world.camera = octsolid::render::Camera::look_at(DVec3::new(0.4, -2.2, 1.6), world.center, DVec3::Z, 30.0);
    let ball_voxel = 1.2 / 256.0;
    let dims = (160, 160);
    let options = RenderOptions { width: dims.0, height: dims.1, spp: 1, shade: smooth(), ..RenderOptions::default() };
    let (picture, _) = render_picture(&world.scene, &world.camera, &options, &NoProgress).unwrap();
    let samples = SampleGrid { width: dims.0, height: dims.1, spp: 1 };
    let view = world.camera.view(samples.aspect());
    // Where the exact ball reflects the ray through image point (u, v): its reflected
    // ray's landing on the floor (None: the sky, or the ball missed) and the slope
    // 1 / |r.z| by which an offset of the start moves it.
    let land = |u: f64, v: f64| {
        let ray = view.ray(u, v);
        let t = world.ball_hit(&ray)?;
        let p = ray.at(t);
        let n = (p - world.center) / world.radius;
        let r = ray.dir - n * (2.0 * ray.dir.dot(n));
        Some((r.z < 0.0).then(|| (p + r * (-p.z / r.z), 1.0 / -r.z)))
    };
    let colour = |q: DVec3| {
        let f = (q / size).floor();
        if (f.x + f.y + f.z).rem_euclid(2.0) == 0.0 { a } else { b }
    };
    let (du, dv) = (1.0 / f64::from(dims.0), 1.0 / f64::from(dims.1));
    let (mut judged, mut wrong) = (0, Vec::new());
    for y in 0..dims.1 {
        for x in 0..dims.0 {
            let (u, v) = samples.point(x, y);
            let Some(centre) = land(u, v) else { continue };
            let corners = [(-du, -dv), (du, -dv), (-du, dv), (du, dv)].map(|(a, b)| land(u + a, v + b));
            let want = match centre {
                None if corners.iter().all(|c| c == &Some(None)) => DVec3::ZERO,
                Some((q, slope)) => {
                    let c = q / size;
                    let edge = (c - c.round()).abs().min_element() * size;
                    let same = corners.iter().all(|c| c.flatten().is_some_and(|(k, _)| colour(k) == colour(q)));
                    if edge < 0.1 * size + 3.0 * ball_voxel * slope || !same || q.x.abs().max(q.y.abs()) > 3.9 {
                        continue;
                    }
                    colour(q)
                }
                None => continue,
            };
            judged += 1;
            if (picture.get(x, y) - want).abs().max_element() > 1e-6 {
                wrong.push((x, y));
            }
        }
    }
    assert!(judged > 2_000, "{judged} ball pixels judged");
    let share = wrong.len() as f64 / judged as f64;
    assert!(
        share < 0.005,
        "{} of {judged} ball pixels show the wrong colour, e.g. {:?}",
        wrong.len(),
        &wrong[..wrong.len().min(8)]
    );
}

/// Shading with the smooth normals (the default options otherwise).
fn smooth() -> ShadeOptions {
    ShadeOptions { normals: Normals::Smooth, ..ShadeOptions::default() }
}
