//! Colour models, reflection and refraction directions, texture coordinates and solid
//! textures against their defining formulas.

use glam::DVec3;
use octsolid::color::{Hsi, cmy_to_rgb, hsi_to_rgb, rgb_to_cmy, rgb_to_hsi};
use octsolid::render::{Mapping, Texture};
use octsolid::render::{reflect, refract};
use octsolid::shape::Axis;

mod common;

use common::Rng;

fn close(a: DVec3, b: DVec3, tol: f64) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn colour_models_have_the_known_values_and_round_trip() {
    let third = 1.0 / 3.0;
    let known = [
        (DVec3::new(1.0, 0.0, 0.0), 0.0, 1.0, third),
        (DVec3::new(1.0, 1.0, 0.0), 60.0, 1.0, 2.0 * third),
        (DVec3::new(0.0, 1.0, 0.0), 120.0, 1.0, third),
        (DVec3::new(0.0, 1.0, 1.0), 180.0, 1.0, 2.0 * third),
        (DVec3::new(0.0, 0.0, 1.0), 240.0, 1.0, third),
        (DVec3::new(1.0, 0.0, 1.0), 300.0, 1.0, 2.0 * third),
        (DVec3::splat(0.5), 0.0, 0.0, 0.5),
        (DVec3::ZERO, 0.0, 0.0, 0.0),
        (DVec3::ONE, 0.0, 0.0, 1.0),
    ];
    for (rgb, h, s, i) in known {
        let hsi = rgb_to_hsi(rgb);
        assert!((hsi.h - h).abs() < 1e-9 && (hsi.s - s).abs() < 1e-12 && (hsi.i - i).abs() < 1e-12, "{rgb} {hsi:?}");
        assert!(close(hsi_to_rgb(hsi), rgb, 1e-12), "{rgb} back {}", hsi_to_rgb(hsi));
    }
    assert_eq!(rgb_to_cmy(DVec3::new(1.0, 0.25, 0.0)), DVec3::new(0.0, 0.75, 1.0));
    let mut rng = Rng(31);
    for _ in 0..10_000 {
        let rgb = DVec3::new(rng.unit(), rng.unit(), rng.unit());
        assert_eq!(cmy_to_rgb(rgb_to_cmy(rgb)), rgb);
        let hsi = rgb_to_hsi(rgb);
        assert!((0.0..360.0).contains(&hsi.h) && (0.0..=1.0).contains(&hsi.s), "{hsi:?}");
        assert!(close(hsi_to_rgb(hsi), rgb, 1e-9), "{rgb} -> {hsi:?} -> {}", hsi_to_rgb(hsi));
    }
    // Hue is taken modulo 360.
    let h = Hsi { h: 420.0, s: 0.5, i: 0.4 };
    assert!(close(hsi_to_rgb(h), hsi_to_rgb(Hsi { h: 60.0, ..h }), 1e-12));
}

/// A random unit vector.
fn unit(rng: &mut Rng) -> DVec3 {
    loop {
        let v = rng.vec(-1.0, 1.0);
        if (0.01..=1.0).contains(&v.length_squared()) {
            return v.normalize();
        }
    }
}

#[test]
fn reflection_and_refraction_follow_the_laws() {
    let mut rng = Rng(7);
    for _ in 0..10_000 {
        let n = unit(&mut rng);
        let mut d = unit(&mut rng);
        if d.dot(n) > 0.0 {
            d = -d;
        }
        let cos_i = -d.dot(n);
        let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
        // Mirror: same angle on the other side, in the plane of d and n, unit.
        let r = reflect(d, n);
        assert!((r.length() - 1.0).abs() < 1e-12 && (r.dot(n) - cos_i).abs() < 1e-12);
        assert!(d.cross(n).dot(r).abs() < 1e-12, "coplanar");
        let (eta1, eta2) = (rng.range(1.0, 2.5), rng.range(1.0, 2.5));
        match refract(d, n, eta1, eta2) {
            Some(t) => {
                let cos_t = -t.dot(n);
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                assert!((t.length() - 1.0).abs() < 1e-12 && cos_t >= 0.0, "goes through");
                assert!((eta1 * sin_i - eta2 * sin_t).abs() < 1e-9, "Snell: {eta1} {sin_i} {eta2} {sin_t}");
                assert!(d.cross(n).dot(t).abs() < 1e-9, "coplanar");
                // The normal may be given facing either way.
                assert!(close(refract(d, -n, eta1, eta2).unwrap(), t, 1e-15));
            }
            None => assert!(eta1 * sin_i > eta2 * (1.0 - 1e-12), "total reflection below the critical angle"),
        }
    }
}

#[test]
fn total_internal_reflection_starts_at_the_critical_angle() {
    let (glass, air): (f64, f64) = (1.5, 1.0);
    let critical = (air / glass).asin();
    let n = DVec3::Z;
    let at = |angle: f64| DVec3::new(angle.sin(), 0.0, -angle.cos());
    // Just below: it passes, ever closer to grazing; at and past: it reflects.
    let below = refract(at(critical - 1e-6), n, glass, air).expect("below the critical angle");
    assert!(below.z < 0.0 && below.z > -0.01, "{below}");
    for past in [1e-9, 1e-3, 0.3] {
        assert!(refract(at(critical + past), n, glass, air).is_none(), "{past}");
    }
    let grazing = refract(at(critical), n, glass, air);
    assert!(grazing.is_none_or(|t| t.z.abs() < 1e-6), "{grazing:?}");
}

#[test]
fn a_glass_slab_shifts_a_ray_parallel_to_itself() {
    // Slab 0 <= z <= w; the ray enters at the origin from above (+z side going down).
    let (eta, w) = (1.5, 0.3);
    for angle in [0.0f64, 0.2, 0.5, 0.9, 1.3] {
        let d = DVec3::new(angle.sin(), 0.0, -angle.cos());
        let inside = refract(d, DVec3::Z, 1.0, eta).unwrap();
        let exit = DVec3::new(0.0, 0.0, 0.0) + inside * (w / -inside.z);
        let out = refract(inside, -DVec3::Z, eta, 1.0).unwrap();
        assert!(close(out, d, 1e-12), "parallel: {out} vs {d}");
        // Perpendicular offset from the unrefracted line: w sin(i - t) / cos t.
        let t = (angle.sin() / eta).asin();
        let offset = exit.cross(d).length();
        assert!((offset - w * (angle - t).sin() / t.cos()).abs() < 1e-12, "{angle}: {offset}");
    }
}

#[test]
fn projections_give_the_known_coordinates() {
    let c = DVec3::new(1.0, 2.0, 3.0);
    let planar = Mapping::Planar { axis: Axis::Z, origin: c, scale: 2.0 };
    let (u, v) = planar.uv(c + DVec3::new(0.5, 1.5, 7.0));
    assert!((u - 0.25).abs() < 1e-12 && (v - 0.75).abs() < 1e-12);
    let (u, v) = planar.uv(c + DVec3::new(-0.5, 4.5, 0.0));
    assert!((u - 0.75).abs() < 1e-12 && (v - 0.25).abs() < 1e-12, "repeats");
    let cylinder = Mapping::Cylindrical { axis: Axis::Z, center: c, scale: 4.0 };
    for (p, want) in [
        (DVec3::new(1.0, 0.0, 1.0), (0.0, 0.25)),
        (DVec3::new(0.0, 2.0, 2.0), (0.25, 0.5)),
        (DVec3::new(-3.0, 0.0, 0.0), (0.5, 0.0)),
        (DVec3::new(0.0, -1.0, -1.0), (0.75, 0.75)),
    ] {
        let (u, v) = cylinder.uv(c + p);
        assert!((u - want.0).abs() < 1e-12 && (v - want.1).abs() < 1e-12, "{p}: {u} {v}");
    }
    // About y the cyclic other axes are (z, x): longitude 0 on +z, 0.25 on +x.
    let sphere = Mapping::Spherical { axis: Axis::Y, center: c };
    for (p, want) in [
        (DVec3::new(0.0, 2.0, 0.0), (0.0, 0.0)),
        (DVec3::new(0.0, -1.0, 0.0), (0.0, 1.0)),
        (DVec3::new(0.0, 0.0, 5.0), (0.0, 0.5)),
        (DVec3::new(3.0, 0.0, 0.0), (0.25, 0.5)),
        (DVec3::new(0.0, 1.0, -1.0), (0.5, 0.25)),
    ] {
        let (u, v) = sphere.uv(c + p);
        assert!((u - want.0).abs() < 1e-12 && (v - want.1).abs() < 1e-12, "{p}: {u} {v}");
    }
}

#[test]
fn image_textures_stand_upright() {
    // A 2x2 picture: top row red, green; bottom row blue, white (sRGB 0 or 255, so
    // linear 0 or 1). Sampled at texel centres, bilinear filtering returns them (up to rounding).
    let mut texels = image::RgbImage::new(2, 2);
    let (red, green, blue, white) = ([255, 0, 0], [0, 255, 0], [0, 0, 255], [255, 255, 255]);
    for (x, y, c) in [(0, 0, red), (1, 0, green), (0, 1, blue), (1, 1, white)] {
        texels.put_pixel(x, y, image::Rgb(c));
    }
    let linear = |c: [u8; 3]| DVec3::from_array(c.map(|v| f64::from(v) / 255.0));
    let texels = std::sync::Arc::new(texels);
    let at = |mapping: Mapping, p: DVec3| Texture::Image { texels: texels.clone(), mapping }.color(p);
    let planar = Mapping::Planar { axis: Axis::Z, origin: DVec3::ZERO, scale: 1.0 };
    let cylinder = Mapping::Cylindrical { axis: Axis::Z, center: DVec3::ZERO, scale: 1.0 };
    let sphere = Mapping::Spherical { axis: Axis::Z, center: DVec3::ZERO };
    for (mapping, p, want) in [
        // Up the plane's second axis is up the picture.
        (planar, DVec3::new(0.25, 0.25, 0.0), blue),
        (planar, DVec3::new(0.75, 0.75, 0.0), green),
        // Up the cylinder's axis is up the picture.
        (cylinder, DVec3::new(0.0, 1.0, 0.75), red),
        (cylinder, DVec3::new(0.0, 1.0, 0.25), blue),
        // The sphere's pole is the top row.
        (sphere, DVec3::new(0.0, 1.0, 1.0), red),
        (sphere, DVec3::new(0.0, 1.0, -1.0), blue),
    ] {
        assert!(close(at(mapping, p), linear(want), 1e-9), "{mapping:?} at {p}: {}", at(mapping, p));
    }
}

#[test]
fn solid_textures_are_bounded_and_follow_their_rules() {
    let (a, b) = (DVec3::new(0.9, 0.8, 0.6), DVec3::new(0.3, 0.2, 0.1));
    let checker = Texture::Checker { size: 0.5, a, b };
    assert_eq!(checker.color(DVec3::splat(0.1)), a);
    assert_eq!(checker.color(DVec3::new(0.6, 0.1, 0.1)), b);
    assert_eq!(checker.color(DVec3::new(-0.1, -0.1, 0.1)), a);
    let mut rng = Rng(99);
    let textures =
        [Texture::Wood { axis: Axis::Z, center: DVec3::ZERO, size: 0.1, a, b }, Texture::Marble { size: 0.3, a, b }];
    let (lo, hi) = (a.min(b), a.max(b));
    for _ in 0..20_000 {
        let p = rng.vec(-50.0, 50.0);
        for t in &textures {
            let c = t.color(p);
            assert!(c.cmpge(lo - 1e-12).all() && c.cmple(hi + 1e-12).all(), "{c}");
        }
    }
}
