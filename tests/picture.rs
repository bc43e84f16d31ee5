//! Pictures of linear radiance and their files, against independent oracles: an
//! OpenEXR file read back with the `exr` crate's own reader holds the radiance the
//! scene's physics gives (a black emitter shows exactly its emission, a radiosity
//! furnace `E / (1 - rho)`), values above 1 and below an 8-bit step included; the
//! exposure scales by `2^stops` in both formats; bad exposures and unknown extensions
//! are refused by name before anything is written.

mod common;

use std::path::{Path, PathBuf};

use glam::DVec3;
use octsolid::io::write_picture;
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::radiosity::{Radiosity, RadiosityOptions};
use octsolid::render::{Camera, Material, Picture, RenderOptions, Scene, render, render_picture, to_srgb8};
use octsolid::shape::Cuboid;
use octsolid::{Error, FileKind, NoProgress};

/// A closed room: the hollow between [-0.5, 0.5]^3 and [-0.875, 0.875]^3, voxels of
/// 1/32 (every face on the lattice).
fn room() -> LinearOctree {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let cube = |h: f64| Cuboid::new(DVec3::ZERO, DVec3::splat(2.0 * h)).unwrap();
    voxelize(&(cube(0.875) - cube(0.5)), domain, &VoxelizeOptions::default()).unwrap()
}

/// From the room's centre towards a corner: every ray meets an inner wall.
fn inside() -> Camera {
    Camera::look_at(DVec3::ZERO, DVec3::new(1.0, 0.7, 0.4), DVec3::Z, 60.0)
}

fn options(exposure: f64) -> RenderOptions {
    RenderOptions { width: 24, height: 18, spp: 2, exposure, ..RenderOptions::default() }
}

/// A room whose walls reflect nothing (no ambient, diffuse or specular term) and emit
/// `emission`: every pixel's radiance is the emission itself.
fn black_emitter(emission: DVec3) -> Scene {
    let mut scene = Scene::new();
    scene.lights.clear();
    let material = Material { color: DVec3::ZERO, ka: 0.0, kd: 0.0, ks: 0.0, emission, ..Material::default() };
    scene.add("room", room(), material);
    scene
}

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("picture", name)
}

/// The pixels of an OpenEXR file as the `exr` crate reads them: width, height and
/// RGB row-major.
fn read_exr(path: &Path) -> (usize, usize, Vec<[f32; 3]>) {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| (size.width(), size.height(), vec![[0.0f32; 3]; size.width() * size.height()]),
        |(w, _, pixels): &mut (usize, usize, Vec<[f32; 3]>), at, (r, g, b, _): (f32, f32, f32, f32)| {
            pixels[at.y() * *w + at.x()] = [r, g, b];
        },
    )
    .unwrap();
    image.layer_data.channel_data.pixels
}

#[test]
fn an_exr_holds_an_emitters_radiance_above_one_and_below_an_8_bit_step() {
    let emission = DVec3::new(2.5, 0.75, 1e-3);
    let (picture, stats) = render_picture(&black_emitter(emission), &inside(), &options(0.0), &NoProgress).unwrap();
    assert_eq!(stats.hits, stats.samples, "every sample meets a wall");
    assert!(picture.pixels().iter().all(|&p| p == emission), "the picture is the emission");
    let dir = scratch("emitter");
    let path = dir.join("room.exr");
    let bytes = write_picture(&picture, &path).unwrap();
    assert_eq!(bytes, std::fs::metadata(&path).unwrap().len());
    let (w, h, pixels) = read_exr(&path);
    assert_eq!((w, h), (24, 18));
    let want = emission.to_array().map(|c| c as f32);
    assert!(pixels.iter().all(|&p| p == want), "{:?} against {want:?}", pixels[0]);
    // The PNG of the same picture clamps and encodes: 255 for 2.5, and 1e-3 is below
    // the first 8-bit step of sRGB.
    let png = dir.join("room.png");
    write_picture(&picture, &png).unwrap();
    let img = image::open(&png).unwrap().to_rgb8();
    let srgb = emission.to_array().map(to_srgb8);
    assert_eq!(srgb[0], 255);
    assert!(img.pixels().all(|p| p.0 == srgb), "{:?} against {srgb:?}", img.get_pixel(0, 0));
    assert_eq!(img, render(&black_emitter(emission), &inside(), &options(0.0), &NoProgress).unwrap().0);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_radiosity_furnace_shows_e_over_one_minus_rho_in_the_exr() {
    // Every wall emits E and reflects rho: the radiance everywhere is E / (1 - rho) = 2.
    let (emission, rho) = (0.8, 0.6);
    let mut scene = Scene::new();
    scene.lights.clear();
    let material =
        Material { color: DVec3::splat(rho), kd: 1.0, emission: DVec3::splat(emission), ..Material::default() };
    scene.add("room", room(), material);
    let options_r = RadiosityOptions { until: 1e-4, patch_size: Some(0.25), ..RadiosityOptions::default() };
    let solution = Radiosity::solve(&scene, &options_r, &NoProgress).unwrap();
    scene.illumination = Some(std::sync::Arc::new(solution));
    let (picture, _) = render_picture(&scene, &inside(), &options(0.0), &NoProgress).unwrap();
    let dir = scratch("furnace");
    let path = dir.join("furnace.exr");
    write_picture(&picture, &path).unwrap();
    let want = emission / (1.0 - rho);
    for p in read_exr(&path).2 {
        for c in p {
            assert!((f64::from(c) - want).abs() < 0.01 * want, "{c} against {want}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn exposure_scales_by_two_to_the_stops_in_both_formats() {
    let emission = DVec3::new(0.3, 0.12, 0.05);
    let scene = black_emitter(emission);
    let at = |stops: f64| render_picture(&scene, &inside(), &options(stops), &NoProgress).unwrap().0;
    let (plain, brighter, darker) = (at(0.0), at(1.0), at(-2.5));
    let dir = scratch("exposure");
    for (stops, picture) in [(1.0, &brighter), (-2.5, &darker)] {
        let scale = f64::exp2(stops);
        for (a, b) in plain.pixels().iter().zip(picture.pixels()) {
            assert!((*a * scale - *b).abs().max_element() <= 1e-15, "{a} x {scale} against {b}");
        }
        // The EXR file holds the scaled values; the PNG their sRGB encoding.
        let path = dir.join(format!("room{stops}.exr"));
        write_picture(picture, &path).unwrap();
        let want = (emission * scale).to_array().map(|c| c as f32);
        assert!(read_exr(&path).2.iter().all(|&p| p == want));
        let png = dir.join(format!("room{stops}.png"));
        write_picture(picture, &png).unwrap();
        let srgb = (emission * scale).to_array().map(to_srgb8);
        let img = image::open(&png).unwrap().to_rgb8();
        assert!(img.pixels().all(|p| p.0 == srgb), "{:?} against {srgb:?}", img.get_pixel(0, 0));
    }
    // +1 stop is exactly twice the radiance, bit for bit.
    assert!(plain.pixels().iter().zip(brighter.pixels()).all(|(a, b)| *a * 2.0 == *b));
    assert_ne!(plain.to_srgb8(), brighter.to_srgb8(), "the PNG changes");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn bad_exposures_and_unknown_extensions_are_refused_by_name() {
    let scene = black_emitter(DVec3::ONE);
    for stops in [f64::NAN, f64::INFINITY, -f64::INFINITY, 65.0, -1e9] {
        let e = render_picture(&scene, &inside(), &options(stops), &NoProgress).unwrap_err();
        assert!(matches!(e, Error::InvalidArgument { what: "exposure", .. }), "{stops}: {e}");
        assert!(e.to_string().contains("exposure"), "{e}");
    }
    for stops in [64.0, -64.0] {
        assert!(render_picture(&scene, &inside(), &options(stops), &NoProgress).is_ok());
    }
    let picture = Picture::new(4, 3);
    let dir = scratch("extensions");
    for name in ["room.jpg", "room", "room.exr.tmp"] {
        let path = dir.join(name);
        let e = write_picture(&picture, &path).unwrap_err().to_string();
        assert!(e.contains(&path.display().to_string()) && e.contains("(use .png or .exr)"), "{e}");
        assert!(!path.exists(), "{name} was written");
    }
    assert_eq!(FileKind::of("ROOM.EXR", FileKind::PICTURES).unwrap(), FileKind::Exr);
    assert_eq!(FileKind::of("a.Png", FileKind::PICTURES).unwrap(), FileKind::Png);
    assert!(write_picture(&Picture::new(0, 0), dir.join("empty.exr")).is_err());
    assert!(!dir.join("empty.exr").exists());
    std::fs::remove_dir_all(&dir).ok();
}
