//! Rendering: silhouettes against analytic discs, Phong highlights against the
//! formula, thread-count independence (scene files themselves: `scene_file.rs`).

mod common;

use std::f64::consts::PI;

use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::NoProgress;
use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
use octsolid::render::to_srgb8;
use octsolid::render::*;
use octsolid::scene_file::read_scene;
use octsolid::shape::{Cuboid, Sphere};
use octsolid::{Ray, RayCast};

fn sphere_scene(depth: u8, r: f64) -> Scene {
    let d = Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap();
    let tree =
        voxelize(&Sphere::new(DVec3::new(0.003, -0.002, 0.001), r).unwrap(), d, &VoxelizeOptions::default()).unwrap();
    let mut scene = Scene::new();
    scene.add("sphere", tree, Material::default());
    scene
}

fn top_camera(height: f64) -> Camera {
    Camera {
        eye: DVec3::new(0.0, 0.0, 5.0),
        target: DVec3::ZERO,
        up: DVec3::Y,
        projection: Projection::Orthographic { height },
    }
}

#[test]
fn orthographic_sphere_covers_the_analytic_disc() {
    let r = 0.8;
    let mut scene = sphere_scene(9, r);
    scene.lights.clear();
    let options = RenderOptions {
        width: 500,
        height: 500,
        spp: 1,
        shade: ShadeOptions { shadows: false, ..Default::default() },
        ..Default::default()
    };
    let (_, stats) = render(&scene, &top_camera(2.0), &options, &NoProgress).unwrap();
    let pixel_area = (2.0 / 500.0) * (2.0 / 500.0);
    let want = PI * r * r / pixel_area;
    let error = stats.hits as f64 / want - 1.0;
    assert!(error.abs() < 0.01, "{} covered pixels vs {want:.0} ({:+.3}%)", stats.hits, error * 100.0);
}

#[test]
fn brightest_pixel_follows_the_phong_formula() {
    let mut scene = sphere_scene(8, 0.8);
    let l = DVec3::new(0.25, 0.15, 1.0).normalize();
    scene.lights = vec![Light::Directional { direction: -l, color: DVec3::ONE }];
    scene.ambient = DVec3::splat(0.2);
    scene.background = DVec3::ZERO;
    let m = scene.solids[0].material.clone();
    let options = RenderOptions {
        width: 200,
        height: 200,
        spp: 1,
        shade: ShadeOptions { shadows: true, normals: Normals::Axis, ..Default::default() },
        ..Default::default()
    };
    let (img, _) = render(&scene, &top_camera(2.0), &options, &NoProgress).unwrap();
    // With axis normals the visible faces are +z, +x, -x, +y, -y; Phong says which is
    // brightest and how bright: I = ka Ia C + kd C (N.L) + ks (R.V)^n, V = +z.
    let v = DVec3::Z;
    let intensity = |n: DVec3| {
        let cos_a = n.dot(l).max(0.0);
        let r = n * 2.0 * cos_a - l;
        let spec = if cos_a > 0.0 { m.ks * r.dot(v).max(0.0).powf(m.shininess) } else { 0.0 };
        m.color * (m.ka * 0.2) + m.color * (m.kd * cos_a) + DVec3::splat(spec)
    };
    let normals = [DVec3::Z, DVec3::X, -DVec3::X, DVec3::Y, -DVec3::Y];
    let best =
        normals.iter().copied().max_by(|a, b| intensity(*a).length().total_cmp(&intensity(*b).length())).unwrap();
    assert_eq!(best, DVec3::Z);
    let want = intensity(best);
    let want = [to_srgb8(want.x), to_srgb8(want.y), to_srgb8(want.z)];
    let (mut brightest, mut at) = (0u32, (0, 0));
    for (x, y, p) in img.enumerate_pixels() {
        let s = p.0.iter().map(|&c| u32::from(c)).sum::<u32>();
        if s > brightest {
            brightest = s;
            at = (x, y);
        }
    }
    assert_eq!(img.get_pixel(at.0, at.1).0, want, "brightest pixel {at:?}");
    // Where the sphere's true normal is near +z (the disc's centre), +z voxel faces are
    // nearly all one sees; towards the rim, terraces show side faces too.
    let share = |lo: f64, hi: f64| {
        let (mut bright, mut all) = (0, 0);
        for (x, y, p) in img.enumerate_pixels() {
            let r = (f64::from(x) - 99.5).hypot(f64::from(y) - 99.5) / 80.0;
            if (lo..hi).contains(&r) {
                all += 1;
                bright += usize::from(p.0 == want);
            }
        }
        bright as f64 / all as f64
    };
    let (centre, rim) = (share(0.0, 0.3), share(0.7, 0.95));
    assert!(centre > 0.95 && rim < centre - 0.1, "brightest share: centre {centre}, rim {rim}");
}

#[test]
fn same_image_for_any_thread_count() {
    let file = read_scene("scenes/classic.toml", MemoryBudget::default()).unwrap();
    let options = RenderOptions {
        width: 160,
        height: 120,
        spp: 2,
        shade: ShadeOptions { shadows: true, ..Default::default() },
        ..Default::default()
    };
    let run = |threads| {
        let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
        pool.install(|| render(&file.scene, &file.camera, &options, &NoProgress).unwrap().0)
    };
    assert!(run(1) == run(2));
}

#[test]
fn streamed_rows_are_the_picture_in_order_and_encode_to_its_png() {
    // Strips drawn in order by the pool while this thread takes them (front-to-back at
    // 1 and 2 samples a pixel), and the paths that hand every row over at the end (3
    // samples: strips are not whole pixel rows; adaptive; recursive, even at one sample
    // a pixel; the tracer): the rows are the
    // one-thread `render`'s picture, and `render_png` its PNG. 150 rows: two whole
    // strips and a part.
    let file = read_scene("scenes/classic.toml", MemoryBudget::default()).unwrap();
    let one_thread = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let adaptive = AntiAliasing::Adaptive { threshold: 0.3 };
    for (spp, aa, method) in [
        (1, AntiAliasing::Uniform, Method::FrontToBack),
        (2, AntiAliasing::Uniform, Method::FrontToBack),
        (3, AntiAliasing::Uniform, Method::FrontToBack),
        (2, adaptive, Method::FrontToBack),
        (1, AntiAliasing::Recursive { threshold: 0.3, depth: 2 }, Method::FrontToBack),
        (1, AntiAliasing::Uniform, Method::Trace),
    ] {
        let options = RenderOptions { width: 130, height: 150, spp, aa, method, ..Default::default() };
        let (reference, stats) =
            one_thread.install(|| render(&file.scene, &file.camera, &options, &NoProgress).unwrap());
        let mut rows = Vec::new();
        let mut sink = |r: &[[u8; 3]]| rows.extend_from_slice(r.as_flattened());
        let (img, streamed) =
            render_streamed(&file.scene, &file.camera, &options, &NoProgress, Some(&mut sink)).unwrap();
        assert!(img == reference, "{options:?}: the picture differs");
        assert!(rows == *reference.as_raw(), "{options:?}: the rows differ from the picture's");
        assert_eq!(streamed, stats);
        let (png, _) = octsolid::io::png::render_png(&file.scene, &file.camera, &options, &NoProgress).unwrap();
        assert!(png == octsolid::io::png::encode(&reference).unwrap(), "{options:?}: the PNG differs");
    }
}

#[test]
fn adaptive_anti_aliasing_at_threshold_zero_is_the_uniform_picture() {
    // Every contrast is at least 0: every pixel takes the uniform n x n samples, with
    // the same rays in the same order, whatever the first pass's method.
    let file = read_scene("scenes/whitted.toml", MemoryBudget::default()).unwrap();
    let uniform = RenderOptions { width: 96, height: 72, spp: 3, ..file.options };
    let (want, _) = render(&file.scene, &file.camera, &uniform, &NoProgress).unwrap();
    for method in [Method::Trace, Method::FrontToBack] {
        let adaptive = RenderOptions { aa: AntiAliasing::Adaptive { threshold: 0.0 }, method, ..uniform };
        let (got, stats) = render(&file.scene, &file.camera, &adaptive, &NoProgress).unwrap();
        assert!(got == want, "{method:?}");
        assert_eq!(stats.supersampled, 96 * 72);
    }
    // Adaptive at one sample a pixel is the one-sample picture; bad thresholds are refused.
    let one = RenderOptions { spp: 1, ..uniform };
    let adaptive_one = RenderOptions { aa: AntiAliasing::Adaptive { threshold: 0.3 }, ..one };
    let (a, _) = render(&file.scene, &file.camera, &one, &NoProgress).unwrap();
    let (b, _) = render(&file.scene, &file.camera, &adaptive_one, &NoProgress).unwrap();
    assert!(a == b);
    for threshold in [-0.1, f64::NAN] {
        let bad = RenderOptions { aa: AntiAliasing::Adaptive { threshold }, ..uniform };
        assert!(render(&file.scene, &file.camera, &bad, &NoProgress).is_err(), "{threshold}");
    }
}

/// A lit sphere against the background at 120 x 90 (8 x 8 samples a pixel), with its
/// uniform 8 x 8 picture (the reference) and its one-sample picture: the edges that
/// anti-aliasing tests measure.
struct EdgeScene {
    scene: Scene,
    camera: Camera,
    base: RenderOptions,
    reference: image::RgbImage,
    one: image::RgbImage,
}

impl EdgeScene {
    fn new() -> Self {
        let scene = sphere_scene(8, 0.8);
        let camera = Camera::look_at(DVec3::new(0.4, -3.0, 1.5), DVec3::ZERO, DVec3::Z, 40.0);
        let base = RenderOptions { width: 120, height: 90, spp: 8, ..RenderOptions::default() };
        let (reference, _) = render(&scene, &camera, &base, &NoProgress).unwrap();
        let (one, _) = render(&scene, &camera, &RenderOptions { spp: 1, ..base }, &NoProgress).unwrap();
        EdgeScene { scene, camera, base, reference, one }
    }

    /// The picture and stats with anti-aliasing `aa`.
    fn render(&self, aa: AntiAliasing) -> (image::RgbImage, RenderStats) {
        render(&self.scene, &self.camera, &RenderOptions { aa, ..self.base }, &NoProgress).unwrap()
    }

    /// The sum of `img`'s channel differences from the reference.
    fn error(&self, img: &image::RgbImage) -> f64 {
        img.pixels()
            .zip(self.reference.pixels())
            .map(|(a, b)| (0..3).map(|c| f64::from(a.0[c].abs_diff(b.0[c]))).sum::<f64>())
            .sum()
    }
}

#[test]
fn adaptive_anti_aliasing_supersamples_the_edges_and_matches_the_reference_there() {
    // A sphere against the background, lit: at a threshold of 0.1 the pixels that get
    // 8 x 8 samples are the edge pixels and a few on the shading's steepest slopes; they
    // equal the uniform 8 x 8 reference exactly, and the picture is far nearer to it
    // than the one-sample picture is.
    let edges = EdgeScene::new();
    let (got, stats) = edges.render(AntiAliasing::Adaptive { threshold: 0.1 });
    let pixels = u64::from(edges.base.width * edges.base.height);
    assert!(stats.supersampled > 0 && stats.supersampled < pixels / 4, "{} of {pixels}", stats.supersampled);
    assert!(edges.error(&got) < 0.25 * edges.error(&edges.one), "{} vs {}", edges.error(&got), edges.error(&edges.one));
    // Every pixel that differs from the one-sample picture was supersampled, and a
    // supersampled pixel is the reference's; the rest are the one-sample picture's.
    let mut same_as_reference = 0;
    for ((g, r), o) in got.pixels().zip(edges.reference.pixels()).zip(edges.one.pixels()) {
        assert!(g == o || g == r);
        same_as_reference += u64::from(g == r && g != o);
    }
    assert!(same_as_reference > stats.supersampled / 2, "{same_as_reference} of {}", stats.supersampled);
}

/// The radiance at the image point `(px, py)` pixels from the top-left corner, traced
/// here by the public API alone: the oracle of the recursive anti-aliasing tests.
fn radiance_at(file: &octsolid::scene_file::SceneFile, (w, h): (u32, u32), px: f64, py: f64) -> DVec3 {
    let view = file.camera.view(f64::from(w) / f64::from(h));
    let ray = view.ray(2.0 * px / f64::from(w) - 1.0, 1.0 - 2.0 * py / f64::from(h));
    let o = &file.options;
    let shading = o.shade;
    match file.scene.hit(&ray) {
        Some(hit) => radiance(&file.scene, &ray, &hit, &shading).0,
        None => file.scene.background,
    }
}

#[test]
fn recursive_anti_aliasing_at_threshold_zero_weights_the_whole_lattice() {
    // Every square splits `depth` times: a pixel is the mean of its 4^depth smallest
    // squares, each the mean of its corners, so lattice point (i, j) of the pixel's
    // (2^depth + 1)^2 weighs a_i a_j / 4^(depth + 1), a = 1 at the pixel's edges and 2
    // inside. Each point traced here by the public API; every corner of every pixel
    // traced once for the picture, the other points of a pixel once for the pixel.
    let file = read_scene("scenes/whitted.toml", MemoryBudget::default()).unwrap();
    let (w, h) = (20, 15);
    for depth in [1, 2] {
        let options = RenderOptions {
            width: w,
            height: h,
            aa: AntiAliasing::Recursive { threshold: 0.0, depth },
            ..file.options
        };
        let (picture, stats) = render_picture(&file.scene, &file.camera, &options, &NoProgress).unwrap();
        let n = 1u32 << depth;
        let weight = |i: u32| if i == 0 || i == n { 1.0 } else { 2.0 };
        let mut worst: f64 = 0.0;
        for row in 0..h {
            for col in 0..w {
                let mut want = DVec3::ZERO;
                for j in 0..=n {
                    for i in 0..=n {
                        let (px, py) = (
                            f64::from(col) + f64::from(i) / f64::from(n),
                            f64::from(row) + f64::from(j) / f64::from(n),
                        );
                        want += radiance_at(&file, (w, h), px, py) * (weight(i) * weight(j));
                    }
                }
                want /= f64::from(4 * n * n);
                worst = worst.max((picture.get(col, row) - want).abs().max_element());
            }
        }
        assert!(worst < 1e-12, "depth {depth}: off by {worst}");
        let per_pixel = u64::from((n + 1) * (n + 1) - 4);
        let corners = u64::from((w + 1) * (h + 1));
        assert_eq!(stats.samples, corners + u64::from(w * h) * per_pixel, "depth {depth}");
        assert_eq!(stats.supersampled, u64::from(w * h));
    }
}

#[test]
fn recursive_anti_aliasing_above_every_contrast_is_the_mean_of_the_corners() {
    // No two samples differ by more than 3 (the sum of three full channels): no square
    // splits, every pixel is the mean of its four corner samples, one ray a corner.
    let file = read_scene("scenes/whitted.toml", MemoryBudget::default()).unwrap();
    let (w, h) = (24, 18);
    let options = RenderOptions {
        width: w,
        height: h,
        aa: AntiAliasing::Recursive { threshold: 3.01, depth: 3 },
        ..file.options
    };
    let (picture, stats) = render_picture(&file.scene, &file.camera, &options, &NoProgress).unwrap();
    for row in 0..h {
        for col in 0..w {
            let (x, y) = (f64::from(col), f64::from(row));
            let want = (radiance_at(&file, (w, h), x, y)
                + radiance_at(&file, (w, h), x + 1.0, y)
                + radiance_at(&file, (w, h), x, y + 1.0)
                + radiance_at(&file, (w, h), x + 1.0, y + 1.0))
                * 0.25;
            assert!((picture.get(col, row) - want).abs().max_element() < 1e-12, "pixel {col}, {row}");
        }
    }
    assert_eq!(stats.samples, u64::from((w + 1) * (h + 1)));
    assert_eq!(stats.supersampled, 0);
    // Bad depths and thresholds are refused.
    for aa in [
        AntiAliasing::Recursive { threshold: 0.3, depth: 0 },
        AntiAliasing::Recursive { threshold: 0.3, depth: MAX_AA_DEPTH + 1 },
        AntiAliasing::Recursive { threshold: -0.1, depth: 3 },
        AntiAliasing::Recursive { threshold: f64::NAN, depth: 3 },
    ] {
        let bad = RenderOptions { aa, ..options };
        assert!(render(&file.scene, &file.camera, &bad, &NoProgress).is_err(), "{aa:?}");
    }
}

#[test]
fn recursive_anti_aliasing_splits_the_edges_and_nears_the_reference_there() {
    // The lit sphere of the adaptive test: at a threshold of 0.1 and depth 3 the split
    // pixels are few (edges and the shading's steepest slopes), and the picture is far
    // nearer to the uniform 8 x 8 reference than the one-sample picture is, and nearer
    // than at depth 1.
    let edges = EdgeScene::new();
    let pixels = u64::from(edges.base.width * edges.base.height);
    let mut errors = Vec::new();
    for depth in [1, 3] {
        let (got, stats) = edges.render(AntiAliasing::Recursive { threshold: 0.1, depth });
        assert!(stats.supersampled > 0 && stats.supersampled < pixels / 4, "{} of {pixels}", stats.supersampled);
        errors.push(edges.error(&got));
    }
    let one = edges.error(&edges.one);
    assert!(errors[1] < 0.25 * one, "{errors:?} vs {one}");
    assert!(errors[1] < errors[0], "{errors:?}");
}

/// A random scene of up to three CSG solids sharing one small domain.
fn random_scene(rng: &mut common::Rng, depth: u8) -> Scene {
    use octsolid::shape::{Axis, Csg, Cuboid, Cylinder, Torus};
    let d = Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap();
    let mut scene = Scene::new();
    for i in 0..1 + rng.below(3) {
        let c = rng.vec(-0.5, 0.5);
        let a: Csg = match rng.below(3) {
            0 => Sphere::new(c, rng.range(0.2, 0.6)).unwrap().into(),
            1 => Cuboid::new(c, rng.vec(0.2, 0.9)).unwrap().into(),
            _ => Torus::new(c, Axis::Z, 0.5, rng.range(0.1, 0.3)).unwrap().into(),
        };
        let b: Csg = Cylinder::new(rng.vec(-0.5, 0.5), Axis::X, rng.range(0.1, 0.3), 2.0).unwrap().into();
        let shape = if rng.below(2) == 0 { a - b } else { a | b };
        let tree = voxelize(&shape, d, &VoxelizeOptions::default()).unwrap();
        scene.add(format!("solid {i}"), tree, Material::default());
    }
    scene.lights = vec![Light::Point { position: DVec3::new(3.0, -2.0, 4.0), color: DVec3::ONE }];
    scene
}

#[test]
fn all_visibility_methods_agree_on_random_scenes() {
    let mut rng = common::Rng(77);
    let mut seen_any = 0;
    // One frame buffer for all rounds, as a viewer keeps it: the sizes change (it
    // shrinks and grows) and it holds the last method's hits when the next one starts.
    let mut frame = Vec::new();
    for round in 0..16 {
        let scene = random_scene(&mut rng, 4 + (round % 2) as u8);
        let eye = rng.vec(-1.0, 1.0).normalize() * rng.range(3.0, 6.0);
        let camera = if round % 3 == 2 {
            Camera {
                eye,
                target: DVec3::ZERO,
                up: DVec3::new(0.1, 0.2, 1.0),
                projection: Projection::Orthographic { height: 3.0 },
            }
        } else {
            Camera::look_at(eye, rng.vec(-0.2, 0.2), DVec3::new(0.1, 0.2, 1.0), 40.0)
        };
        let samples = SampleGrid { width: 48 - 8 * (round % 2), height: 36, spp: 2 };
        let (trace, _) = visibility(&scene, &camera, &samples, Method::Trace);
        seen_any += trace.iter().filter(|s| s.is_some()).count();
        for method in [Method::FrontToBack, Method::Painter, Method::ZBuffer, Method::ScanLine] {
            visibility_into(&scene, &camera, &samples, method, &mut frame);
            assert_eq!(frame.len(), trace.len());
            for (i, (a, b)) in trace.iter().zip(&frame).enumerate() {
                assert_eq!(a, b, "round {round}, {method:?}, sample {i}");
            }
        }
        let options = RenderOptions { width: 48, height: 36, spp: 2, ..RenderOptions::default() };
        let image = |method| render(&scene, &camera, &RenderOptions { method, ..options }, &NoProgress).unwrap().0;
        let traced = image(Method::Trace);
        for method in [Method::FrontToBack, Method::Painter, Method::ZBuffer, Method::ScanLine] {
            assert!(image(method) == traced, "round {round}: {method:?} image differs");
        }
    }
    assert!(seen_any > 5000, "the scenes should be in view: {seen_any} samples hit");
}

/// Rays through voxel edges: the Cornell box's eye sits on the room's mirror plane, and
/// many of its rays meet the seams of the walls and the ceiling exactly on voxel edges,
/// where the position at a face's time and the times of the edge's planes round to
/// different sides. Every method must still find the walk's voxel and solid there (216
/// of these samples differed before the face rule compared plane times).
#[test]
fn every_method_finds_the_walks_hits_where_rays_cross_voxel_edges() {
    let file =
        read_scene(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell.toml"), MemoryBudget::default()).unwrap();
    let samples = SampleGrid { width: 480, height: 360, spp: 2 };
    let (trace, _) = visibility(&file.scene, &file.camera, &samples, Method::Trace);
    let view = file.camera.view(samples.aspect());
    for (i, seen) in trace.iter().enumerate().step_by(7) {
        let (x, y) = samples.point(i as u32 % samples.columns(), i as u32 / samples.columns());
        let ray = view.ray(x, y);
        let nearest = file.scene.solids.iter().enumerate().filter_map(|(k, s)| Some((k, s.traversal.hit(&ray)?))).fold(
            None,
            |best: Option<(usize, Hit)>, (k, h)| {
                if best.is_some_and(|(_, b)| b.t <= h.t) { best } else { Some((k, h)) }
            },
        );
        assert_eq!(seen.map(|s| (s.solid, s.hit)), nearest, "sample {i}: the tracer and the walks of the solids");
    }
    for method in [Method::FrontToBack, Method::Painter, Method::ZBuffer, Method::ScanLine] {
        let (seen, _) = visibility(&file.scene, &file.camera, &samples, method);
        let differ = trace.iter().zip(&seen).filter(|(a, b)| a != b).count();
        assert_eq!(differ, 0, "{method:?}: {differ} samples differ from the tracer's");
    }
}

#[test]
fn front_to_back_matches_the_tracer_near_the_eye_at_odd_sizes_on_any_thread_count() {
    // Eyes inside the domain (footprints reaching behind the eye), image sizes that are
    // not whole tiles or strips, and 1 or 2 threads: the display must still give the
    // tracer's bits; the face counts of the baselines agree (they all draw every face
    // looking at the viewer).
    let mut rng = common::Rng(5);
    let mut rounds = 0;
    while rounds < 6 {
        let scene = random_scene(&mut rng, 5);
        let eye = rng.vec(-0.9, 0.9);
        if scene.solids.iter().any(|s| s.traversal.hit(&Ray::new(eye, DVec3::Z)).is_some_and(|h| h.t == 0.0)) {
            continue; // the eye inside a solid: every method sees nothing but the tracer
        }
        rounds += 1;
        let camera = Camera::look_at(eye, rng.vec(-0.3, 0.3) * 0.1, DVec3::new(0.1, 0.2, 1.0), 70.0);
        let samples = SampleGrid { width: 37, height: 71, spp: 1 };
        let (trace, stats) = visibility(&scene, &camera, &samples, Method::Trace);
        assert_eq!(stats.faces_drawn, 0);
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let (seen, stats) = pool.install(|| visibility(&scene, &camera, &samples, Method::FrontToBack));
            assert!(seen == trace, "round {rounds}, {threads} threads: front-to-back differs from the tracer");
            assert!(stats.faces_drawn > 0 || trace.iter().all(Option::is_none));
        }
        let count = |method| visibility(&scene, &camera, &samples, method).1.faces_drawn;
        let painter = count(Method::Painter);
        assert_eq!(count(Method::ZBuffer), painter);
        assert_eq!(count(Method::ScanLine), painter);
    }
}

#[test]
fn pictures_over_the_budget_and_endless_mirrors_are_refused_before_work() {
    let scene = sphere_scene(5, 0.5);
    let camera = top_camera(1.2);
    // 4096 x 4096 at 16 x 16 samples: 4.3 G samples, refused by the estimate (never
    // allocated); the estimate counts at least a hit record a sample.
    let huge = RenderOptions { width: 4096, height: 4096, spp: 16, ..RenderOptions::default() };
    let samples = SampleGrid { width: 4096, height: 4096, spp: 16 };
    assert!(estimate_bytes(&samples) >= 4096u64 * 4096 * 256 * std::mem::size_of::<Option<SceneHit>>() as u64);
    let e = render(&scene, &camera, &huge, &NoProgress).unwrap_err();
    assert!(matches!(e, octsolid::Error::OverBudget { .. }), "{e}");
    // A small budget refuses even a small picture; the same picture fits without it.
    let small =
        RenderOptions { width: 64, height: 48, spp: 4, budget: MemoryBudget(1 << 10), ..RenderOptions::default() };
    assert!(render(&scene, &camera, &small, &NoProgress).is_err());
    let fits = RenderOptions { budget: MemoryBudget::unlimited(), ..small };
    assert!(render(&scene, &camera, &fits, &NoProgress).is_ok());
    // Secondary rays are bounded: a recursion deeper than the limit is refused.
    let deep = RenderOptions { shade: ShadeOptions { max_depth: MAX_RAY_DEPTH + 1, ..fits.shade }, ..fits };
    assert!(render(&scene, &camera, &deep, &NoProgress).unwrap_err().to_string().contains("max depth"));
    assert!(
        render(
            &scene,
            &camera,
            &RenderOptions { shade: ShadeOptions { max_depth: MAX_RAY_DEPTH, ..fits.shade }, ..fits },
            &NoProgress
        )
        .is_ok()
    );
}

#[test]
fn flat_faces_shade_flat_with_the_default_normals() {
    // A box whose faces lie on lattice planes (voxels of 1/128), seen straight down by
    // an orthographic camera at a voxel a pixel, lit by one directional light with no
    // highlight: with one normal, Lambert gives one colour. Every pixel of the top face
    // farther than the estimate's reach (7 voxels) from its edges must have exactly the
    // colour of the axis-normal picture there.
    let d = Domain::new(DVec3::splat(-1.0), 2.0, 8).unwrap();
    let half = DVec3::new(0.5, 0.375, 0.25);
    let tree = voxelize(&Cuboid::new(DVec3::ZERO, half * 2.0).unwrap(), d, &VoxelizeOptions::default()).unwrap();
    let mut scene = Scene::new();
    scene.add("box", tree, Material::phong(DVec3::new(0.7, 0.5, 0.3), 0.2, 0.8, 0.0, 1.0));
    scene.lights = vec![Light::Directional { direction: DVec3::new(-0.3, -0.2, -1.0), color: DVec3::ONE }];
    let options = RenderOptions { width: 256, height: 256, spp: 1, ..Default::default() };
    assert_eq!(options.shade.normals, Normals::Smooth);
    let (smooth, _) = render(&scene, &top_camera(2.0), &options, &NoProgress).unwrap();
    let axis = RenderOptions { shade: ShadeOptions { normals: Normals::Axis, ..options.shade }, ..options };
    let (flat, _) = render(&scene, &top_camera(2.0), &axis, &NoProgress).unwrap();
    let reach = 7.0 * d.voxel_size();
    let mut face = Vec::new();
    for (col, row, pixel) in smooth.enumerate_pixels() {
        let x = -1.0 + (f64::from(col) + 0.5) * 2.0 / 256.0;
        let y = 1.0 - (f64::from(row) + 0.5) * 2.0 / 256.0;
        if x.abs() < half.x - reach && y.abs() < half.y - reach {
            assert_eq!(pixel, flat.get_pixel(col, row), "pixel ({col}, {row})");
            face.push(*pixel);
        }
    }
    assert!(face.len() > 9_000, "{} pixels of the face checked", face.len());
    assert!(face.iter().all(|p| *p == face[0]), "the face has more than one colour");
}

#[test]
fn quick_writes_a_default_size_picture_of_the_solid() {
    // A ball at the centre of its domain: the default camera request frames its
    // silhouette from DEFAULT_VIEW (as `octsolid render` does), so it projects to a disc at the image centre of radius f tan(asin(r
    // / D)), D the eye's distance and f the focal length in pixels. The pixels that are
    // not the background must cover that disc (within the voxels' 1% in radius).
    let r = 0.8;
    let d = Domain::new(DVec3::splat(-1.0), 2.0, 7).unwrap();
    let tree = voxelize(&Sphere::new(DVec3::ZERO, r).unwrap(), d, &VoxelizeOptions::default()).unwrap();
    let dir = common::scratch_dir("render", "quick");
    let path = dir.join("ball.png");
    let stats = octsolid::quick(&tree, &path).unwrap();
    let img = image::open(&path).unwrap().to_rgb8();
    std::fs::remove_dir_all(&dir).unwrap();
    let defaults = RenderOptions::default();
    assert_eq!(img.dimensions(), (defaults.width, defaults.height));
    let background = image::Rgb(Scene::new().background.to_array().map(to_srgb8));
    let covered = img.pixels().filter(|p| **p != background).count() as f64;
    let aspect = f64::from(defaults.width) / f64::from(defaults.height);
    let framing = Framing::of_solid(&tree, Up::default());
    let camera = CameraRequest::default().camera(&framing, aspect).unwrap();
    assert!(((camera.eye - camera.target).normalize() - DEFAULT_VIEW.normalize()).length() < 1e-12);
    let Projection::Perspective { fov_y } = camera.projection else { panic!("a framing camera is perspective") };
    let focal = f64::from(defaults.height) / 2.0 / (fov_y.to_radians() / 2.0).tan();
    let radius = focal * (r / camera.eye.length()).asin().tan();
    let want = PI * radius * radius;
    assert!((covered / want - 1.0).abs() < 0.03, "{covered} pixels show the ball, the disc has {want:.0}");
    assert!(stats.hits > 0 && stats.secondary_rays > 0, "{stats:?}");
    // An empty solid has nothing to frame: an error, no file.
    let empty = octsolid::octree::LinearOctree::empty(d);
    assert!(octsolid::quick(&empty, dir.join("empty.png")).is_err());
    assert!(!dir.join("empty.png").exists());
}

#[path = "../benches/common/hard_views.rs"]
mod hard_views;

/// Views with the eye inside a solid's domain (a large floor behind and below it, a
/// grazing floor, the eye inside a bore, a close-up): the display gives the walk's
/// hits and draws a few faces a sample. Before it culled boxes behind the eye and
/// outside the strip's planes it drew 95 faces a sample over the floor (2.86 M for
/// 30,000 samples, at 200x150).
#[test]
fn front_to_back_draws_a_few_faces_a_sample_with_the_eye_inside_a_domain() {
    let samples = SampleGrid { width: 200, height: 150, spp: 1 };
    for view in hard_views::hard_views(9) {
        let (trace, _) = visibility(&view.scene, &view.camera, &samples, Method::Trace);
        let (seen, stats) = visibility(&view.scene, &view.camera, &samples, Method::FrontToBack);
        let hits = trace.iter().filter(|s| s.is_some()).count();
        assert!(hits > 10_000, "{}: the view should see the solids ({hits} samples hit)", view.name);
        assert!(seen == trace, "{}: front-to-back differs from the tracer", view.name);
        let count = f64::from(samples.columns() * samples.rows());
        let per_sample = stats.faces_drawn as f64 / count;
        assert!(per_sample < 4.0, "{}: {} faces drawn for {count} samples", view.name, stats.faces_drawn);
    }
}

/// A section view keeps what lies below the plane and caps the cut; when none of the
/// scene's lights reaches the cap's side (they lit the part the cut took away), one
/// that does is added, so the cap is not left to the ambient light.
#[test]
fn a_section_view_lights_its_cap() {
    use octsolid::shape::Axis;
    let mut scene = sphere_scene(6, 0.8);
    scene.lights = vec![
        Light::Point { position: DVec3::new(1.0, -5.0, 2.0), color: DVec3::ONE },
        Light::Directional { direction: DVec3::new(0.2, 1.0, -0.3), color: DVec3::ONE },
    ];
    let cut = scene.sectioned(Axis::Y, 0.1);
    let reaches = |l: &Light| match *l {
        Light::Point { position, .. } => position.y > 0.1,
        Light::Directional { direction, .. } => direction.y < 0.0,
    };
    assert_eq!(cut.lights.len(), 3);
    assert!(cut.lights.iter().filter(|l| reaches(l)).count() == 1 && reaches(&cut.lights[2]));
    assert!(cut.solids[0].tree.bounds().unwrap().max.y <= 0.1 + scene.solids[0].tree.domain().voxel_size());
    // A light already on the cap's side: nothing added.
    scene.lights.push(Light::Point { position: DVec3::new(0.0, 4.0, 1.0), color: DVec3::ONE });
    assert_eq!(scene.sectioned(Axis::Y, 0.1).lights, scene.lights);
}

#[test]
fn render_options_validate_names_each_option_out_of_its_range() {
    use octsolid::render::ShadeOptions;
    assert!(RenderOptions::default().validate().is_ok());
    let refused = |options: RenderOptions, option: &str| {
        let e = options.validate().unwrap_err().to_string();
        assert!(e.contains(option), "{e}");
    };
    refused(RenderOptions { width: 0, ..Default::default() }, "image size");
    refused(RenderOptions { spp: 17, ..Default::default() }, "samples");
    refused(
        RenderOptions { shade: ShadeOptions { cutoff: 2.0, ..Default::default() }, ..Default::default() },
        "cutoff",
    );
    refused(RenderOptions { exposure: f64::NAN, ..Default::default() }, "exposure");
}
