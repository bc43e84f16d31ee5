//! Radiosity against independent oracles: closed-form form factors (parallel and
//! perpendicular unit squares), reciprocity, form factors summing to one inside a
//! closed box (visibility through the octree decides how an occluder shares it), the
//! furnace (a closed box that emits E and reflects rho everywhere shows E / (1 - rho)),
//! the energy book, the same bits on 1 and 2 threads, `.rad` files (reloaded bit for
//! bit, refused for another scene, refused when damaged or claiming what no solver
//! writes), a sphere's elements taking the sphere's own normal, the furnace again in
//! a room turned off the lattice whose patches come from its true surface (its walls'
//! analytic area, no light lost), the furnace once more in a room of six overlapping
//! slabs, each its own solid (the faces where they touch are no patch: the elements'
//! area is the union's exposed surface), patches shooting near receivers by their
//! elements against patches of one element each on the same grid (brute force), and
//! adaptive
//! subdivision (closer to a solution on much finer uniform elements than the base
//! elements alone, the furnace still exact, the energy book balanced).

use std::path::PathBuf;

mod common;

use common::radiosity_room::{cuboid, diffuse, tree};
use glam::DVec3;
use octsolid::octree::LinearOctree;
use octsolid::render::radiosity::{Radiosity, RadiosityOptions};
use octsolid::render::{Illumination, Light, Material, Scene};
use octsolid::{Error, MemoryBudget, NoProgress};

fn options(patch_size: f64, elements: u32) -> RadiosityOptions {
    RadiosityOptions { patch_size: Some(patch_size), elements, ..RadiosityOptions::default() }
}

/// The closed form for parallel coaxial rectangles `a x b`, `c` apart (Siegel and Howell).
fn parallel_rectangles(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (x1, y1) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    2.0 / (std::f64::consts::PI * x * y)
        * (((1.0 + x * x) * (1.0 + y * y) / (1.0 + x * x + y * y)).sqrt().ln()
            + x * y1 * (x / y1).atan()
            + y * x1 * (y / x1).atan()
            - x * x.atan()
            - y * y.atan())
}

/// The closed form for perpendicular rectangles sharing an edge of length `l`, widths
/// `w` (the emitter's, from the edge) and `h` (Siegel and Howell; 0.20004 for unit
/// squares).
fn perpendicular_rectangles(w: f64, h: f64, l: f64) -> f64 {
    let (hh, ww) = (h / l, w / l);
    let pi = std::f64::consts::PI;
    let a = ((1.0 + ww * ww) * (1.0 + hh * hh)) / (1.0 + ww * ww + hh * hh);
    let b = (ww * ww * (1.0 + ww * ww + hh * hh)) / ((1.0 + ww * ww) * (ww * ww + hh * hh));
    let c = (hh * hh * (1.0 + hh * hh + ww * ww)) / ((1.0 + hh * hh) * (hh * hh + ww * ww));
    1.0 / (pi * ww)
        * (ww * (1.0 / ww).atan() + hh * (1.0 / hh).atan()
            - (hh * hh + ww * ww).sqrt() * (1.0 / (hh * hh + ww * ww).sqrt()).atan()
            + 0.25 * (a * b.powf(ww * ww) * c.powf(hh * hh)).ln())
}

/// Two plates whose facing faces are the unit square at z = -0.5 (facing +z) and the
/// square of side `side` centred over it at z = 0.5 (facing -z), and the patch of each.
fn facing_plates(side: f64) -> (Scene, Radiosity, usize, usize) {
    let mut scene = Scene::new();
    scene.lights.clear();
    scene.add("lower", tree(&cuboid([-0.5, -0.5, -0.75], [0.5, 0.5, -0.5])), diffuse(0.5, 1.0));
    let h = side / 2.0;
    scene.add("upper", tree(&cuboid([-h, -h, 0.5], [h, h, 0.75])), diffuse(0.5, 0.0));
    let r =
        Radiosity::solve(&scene, &RadiosityOptions { max_shots: Some(0), ..options(1.0, 16) }, &NoProgress).unwrap();
    let lower = r.patch_at(0, DVec3::new(0.0, 0.0, -0.5), DVec3::Z).unwrap();
    let upper = r.patch_at(1, DVec3::new(0.0, 0.0, 0.5), -DVec3::Z).unwrap();
    (scene, r, lower, upper)
}

#[test]
fn parallel_unit_squares_one_apart_have_the_closed_form_factor_both_ways() {
    let (scene, r, lower, upper) = facing_plates(1.0);
    let want = parallel_rectangles(1.0, 1.0, 1.0);
    assert!((want - 0.1998).abs() < 1e-4, "the closed form itself: {want}");
    for (i, j) in [(lower, upper), (upper, lower)] {
        let f = r.form_factor(&scene, i, j);
        assert!((f - want).abs() < 0.02 * want, "F = {f}, closed form {want}");
    }
}

#[test]
fn form_factors_of_unequal_squares_are_reciprocal() {
    let (scene, r, lower, upper) = facing_plates(0.5);
    let (a1, a2) = (r.patch_area(lower), r.patch_area(upper));
    assert!((a1 - 1.0).abs() < 1e-12 && (a2 - 0.25).abs() < 1e-12);
    let (f12, f21) = (r.form_factor(&scene, lower, upper), r.form_factor(&scene, upper, lower));
    assert!(f12 > 0.0 && f21 > 0.0);
    let (left, right) = (a1 * f12, a2 * f21);
    assert!((left - right).abs() < 0.02 * right, "A1 F12 = {left}, A2 F21 = {right}");
}

#[test]
fn perpendicular_unit_squares_sharing_an_edge_have_the_closed_form_factor() {
    // An L: a floor whose top face x in [0, 1] meets a wall's face x = 0, z in [0, 1].
    let shape = cuboid([-0.25, 0.0, -0.25], [1.0, 1.0, 0.0]) | cuboid([-0.25, 0.0, 0.0], [0.0, 1.0, 1.0]);
    let mut scene = Scene::new();
    scene.lights.clear();
    scene.add("corner", tree(&shape), diffuse(0.5, 1.0));
    let r =
        Radiosity::solve(&scene, &RadiosityOptions { max_shots: Some(0), ..options(1.0, 32) }, &NoProgress).unwrap();
    let floor = r.patch_at(0, DVec3::new(0.5, 0.5, 0.0), DVec3::Z).unwrap();
    let wall = r.patch_at(0, DVec3::new(0.0, 0.5, 0.5), DVec3::X).unwrap();
    assert!((r.patch_area(floor) - 1.0).abs() < 1e-12 && (r.patch_area(wall) - 1.0).abs() < 1e-12);
    let want = perpendicular_rectangles(1.0, 1.0, 1.0);
    assert!((want - 0.2000).abs() < 2e-4, "the closed form itself: {want}");
    for (i, j) in [(floor, wall), (wall, floor)] {
        let f = r.form_factor(&scene, i, j);
        assert!((f - want).abs() < 0.02 * want, "F = {f}, closed form {want}");
    }
}

/// A closed room: the hollow between [-0.5, 0.5]^3 and [-0.875, 0.875]^3.
fn room() -> LinearOctree {
    tree(&(cuboid([-0.875; 3], [0.875; 3]) - cuboid([-0.5; 3], [0.5; 3])))
}

/// Whether `p` lies on the room's inner walls (not its outside).
fn inside_room(p: DVec3) -> bool {
    p.abs().max_element() <= 0.5 + 1e-9
}

#[test]
fn form_factors_from_a_wall_of_a_closed_box_sum_to_one_with_and_without_an_occluder() {
    for occluder in [false, true] {
        let mut scene = Scene::new();
        scene.lights.clear();
        scene.add("room", room(), diffuse(0.5, 1.0));
        if occluder {
            // A block in the middle of the room takes its share of every wall's view.
            scene.add("block", tree(&cuboid([-0.25, -0.25, -0.5], [0.25, 0.25, 0.0])), diffuse(0.5, 0.0));
        }
        let r = Radiosity::solve(&scene, &RadiosityOptions { max_shots: Some(0), ..options(0.25, 4) }, &NoProgress)
            .unwrap();
        // A patch of the wall x = -0.5 (facing +x), and every patch any element can see.
        let wall = r.patch_at(0, DVec3::new(-0.5, 0.1, 0.1), DVec3::X).unwrap();
        let patches = r.stats().patches;
        let sum: f64 = (0..patches).filter(|&j| j != wall).map(|j| r.form_factor(&scene, wall, j)).sum();
        assert!((sum - 1.0).abs() < 0.02, "occluder {occluder}: sum of form factors {sum}");
    }
}

#[test]
fn the_furnace_shows_e_over_one_minus_rho_and_exactly_e_without_reflection() {
    let emission = 0.8;
    for rho in [0.0, 0.5] {
        let mut scene = Scene::new();
        scene.lights.clear();
        scene.add("room", room(), diffuse(rho, emission));
        let r = Radiosity::solve(&scene, &RadiosityOptions { until: 1e-4, ..options(0.25, 4) }, &NoProgress).unwrap();
        let want = emission / (1.0 - rho);
        let mut seen = 0;
        for (center, _, _, shown) in r.elements().filter(|e| inside_room(e.0)) {
            seen += 1;
            for c in shown.to_array() {
                if rho == 0.0 {
                    assert_eq!(c, emission, "at {center}");
                } else {
                    assert!((c - want).abs() < 0.01 * want, "{c} at {center}, want {want}");
                }
            }
        }
        assert_eq!(seen, 6 * 16 * 16, "the inner walls' elements");
    }
}

/// A closed room made from a shape, turned off the lattice (17 degrees about z, 9 about
/// x): the hollow between the cubes of half sides 0.5 and 0.8, as a scene solid with
/// its shape (so its patches are tiles of its true surface's planar regions), and
/// whether a point lies on its inner walls.
fn turned_room(rho: f64, emission: f64) -> (Scene, impl Fn(DVec3) -> bool) {
    use octsolid::shape::Transformed;
    let map = glam::DAffine3::from_rotation_x(9f64.to_radians()) * glam::DAffine3::from_rotation_z(17f64.to_radians());
    let room = Transformed::new(cuboid([-0.8; 3], [0.8; 3]) - cuboid([-0.5; 3], [0.5; 3]), map).unwrap();
    let mut scene = Scene::new();
    scene.lights.clear();
    scene.add_shaped("room", tree(&room), diffuse(rho, emission), std::sync::Arc::new(room));
    let back = map.inverse();
    (scene, move |p: DVec3| back.transform_point3(p).abs().max_element() <= 0.5 + 1e-6)
}

#[test]
fn a_turned_furnace_of_true_surface_patches_shows_e_over_one_minus_rho_over_the_walls_whole_area() {
    let emission = 0.8;
    for rho in [0.0, 0.5] {
        let (scene, inside) = turned_room(rho, emission);
        let r = Radiosity::solve(&scene, &RadiosityOptions { until: 1e-4, ..options(0.25, 4) }, &NoProgress).unwrap();
        let want = emission / (1.0 - rho);
        let mut area = 0.0;
        for (center, normal, a, shown) in r.elements().filter(|e| inside(e.0)) {
            area += a;
            if a == 0.0 {
                continue;
            }
            // The element is on the surface, facing into the room.
            assert!(normal.dot(-center) > 0.0, "{normal} at {center}");
            for c in shown.to_array() {
                if rho == 0.0 {
                    assert_eq!(c, emission, "at {center}");
                } else {
                    // Light leaking out of the room (rays slipping between the voxels of
                    // the turned walls) would show here as a deficit.
                    assert!((c - want).abs() < 0.02 * want, "{c} at {center}, want {want}");
                }
            }
        }
        // The inner walls' elements cover the six unit faces, not their staircase
        // (whose area is larger by the normals' 1-norm).
        assert!((area - 6.0).abs() < 0.01 * 6.0, "inner area {area}");
        // What escapes is what the outer walls (6 faces of side 1.6) emit into the
        // open: pi E A over the three channels; nothing of the room's inside.
        let s = r.stats();
        let outer = std::f64::consts::PI * emission * 6.0 * 1.6 * 1.6 * 3.0;
        assert!(
            (s.escaped - outer).abs() < 0.01 * s.emitted,
            "escaped {} of {}, outer walls {outer}",
            s.escaped,
            s.emitted
        );
    }
}

#[test]
fn a_patch_size_far_under_the_surfaces_is_refused_by_the_budget_before_its_tiles_are_made() {
    // Side 1e-9 on walls of side 1 to 1.6: about 1e19 tiles, far past any memory. They
    // used to be allocated before anything was checked (an abort, not an error).
    let (scene, _) = turned_room(0.5, 0.8);
    let budget = MemoryBudget(64 << 20);
    for side in [1e-9, 1e-3] {
        let e = Radiosity::solve(&scene, &RadiosityOptions { budget, ..options(side, 1) }, &NoProgress).unwrap_err();
        assert!(matches!(e, Error::OverBudget { .. }), "{e}");
        assert!(e.to_string().contains("patches of side"), "{e}");
    }
}

/// A closed room of six slabs, each its own solid made from a shape, overlapping at the
/// room's edges as walls are modelled: slab `a, sign` is `[-0.75, 0.75]^2` across axis
/// `a` and `0.5..0.75` along it on the `sign` side; the room is `[-0.5, 0.5]^3`.
fn slab_room(rho: f64, emission: f64) -> Scene {
    let mut scene = Scene::new();
    scene.lights.clear();
    for a in 0..3 {
        for sign in [-1.0, 1.0] {
            let (mut min, mut max) = ([-0.75; 3], [0.75; 3]);
            (min[a], max[a]) = if sign > 0.0 { (0.5, 0.75) } else { (-0.75, -0.5) };
            let slab = cuboid(min, max);
            scene.add_shaped(
                format!("slab {a} {sign}"),
                tree(&slab),
                diffuse(rho, emission),
                std::sync::Arc::new(slab),
            );
        }
    }
    scene
}

#[test]
fn a_furnace_of_overlapping_slabs_shows_e_over_one_minus_rho_and_only_the_exposed_surface_has_patches() {
    let (rho, emission) = (0.5, 0.8);
    let scene = slab_room(rho, emission);
    // Tiles of 0.3 straddle the lines where the slabs meet (a face of 1.5 is five of
    // them; the room's inside starts 0.25 in), so a face against another slab that
    // kept its patches would dim the room's borders.
    let r = Radiosity::solve(&scene, &RadiosityOptions { until: 1e-4, ..options(0.3, 4) }, &NoProgress).unwrap();
    // The elements cover the exposed surface of the slabs' union, the hollow between
    // the cubes of half sides 0.5 and 0.75: 6 (1^2 + 1.5^2) = 19.5 (each slab's own
    // surface is 6, 36 in all).
    let area: f64 = r.elements().map(|e| e.2).sum();
    assert!((area - 19.5).abs() < 0.005 * 19.5, "element area {area}, exposed surface 19.5");
    let want = emission / (1.0 - rho);
    let mut seen = 0.0;
    for (center, _, a, shown) in r.elements().filter(|e| inside_room(e.0) && e.2 > 0.0) {
        seen += a;
        for c in shown.to_array() {
            assert!((c - want).abs() < 0.01 * want, "{c} at {center}, want {want}");
        }
    }
    assert!((seen - 6.0).abs() < 0.005 * 6.0, "inner area {seen}");
}

/// A closed room lit by an emissive block and a point light, with an occluder.
fn lit_room() -> Scene {
    let mut scene = Scene::new();
    scene.lights = vec![Light::Point { position: DVec3::new(0.3, 0.3, 0.3), color: DVec3::new(0.05, 0.04, 0.03) }];
    scene.add("room", room(), Material { color: DVec3::new(0.7, 0.5, 0.3), ..diffuse(0.0, 0.0) });
    scene.add("lamp", tree(&cuboid([-0.125, -0.125, 0.375], [0.125, 0.125, 0.4375])), diffuse(0.6, 2.0));
    scene.add("block", tree(&cuboid([-0.3125, -0.3125, -0.5], [0.0, 0.0, -0.125])), diffuse(0.6, 0.0));
    scene
}

#[test]
fn unshot_energy_never_grows_and_the_energy_book_balances() {
    let scene = lit_room();
    let r = Radiosity::solve(&scene, &options(0.25, 4), &NoProgress).unwrap();
    let s = r.stats();
    assert!(s.unshot_fraction <= 0.01 && s.shots > 2);
    assert_eq!(s.history.len() as u64, s.shots + 1);
    for pair in s.history.windows(2) {
        assert!(pair[1] <= pair[0] * (1.0 + 1e-12), "unshot grew: {pair:?}");
    }
    // Emitted = absorbed + escaped + unshot; at the end, absorbed + escaped within 1%
    // of emitted, and in a closed room next to nothing escapes.
    let unshot = s.unshot_fraction * s.emitted;
    let book = (s.absorbed, s.escaped, unshot, s.emitted);
    assert!((s.absorbed + s.escaped + unshot - s.emitted).abs() < 1e-9 * s.emitted, "{book:?}");
    assert!((s.absorbed + s.escaped - s.emitted).abs() <= 0.01 * s.emitted);
    assert!(s.escaped < 0.02 * s.emitted, "escaped {} of {}", s.escaped, s.emitted);
}

#[test]
fn the_solution_is_the_same_bits_on_one_and_two_threads() {
    let scene = lit_room();
    for subdivide in [None, Some(0.25)] {
        let solve = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
            let options = RadiosityOptions { max_shots: Some(40), subdivide, ..options(0.25, 4) };
            pool.install(|| Radiosity::solve(&scene, &options, &NoProgress)).unwrap()
        };
        let (one, two) = (solve(1), solve(2));
        let bits =
            |r: &Radiosity| r.radiosities().iter().flat_map(|v| v.to_array().map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&one), bits(&two));
        assert_eq!(one.ambient().to_array().map(f64::to_bits), two.ambient().to_array().map(f64::to_bits));
        assert_eq!(one.stats(), two.stats());
        assert_eq!(one.stats().splits > 0, subdivide.is_some());
    }
}

/// A file `name` in a scratch folder of its own (tests run in parallel).
fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("radiosity", name).join(name)
}

/// The lit room solved for `shots` shots and saved as `name`.
fn saved(name: &str, shots: u64) -> (Scene, Radiosity, PathBuf) {
    let scene = lit_room();
    let options = RadiosityOptions { max_shots: Some(shots), ..options(0.25, 4) };
    let r = Radiosity::solve(&scene, &options, &NoProgress).unwrap();
    let path = scratch(name);
    r.write(&path).unwrap();
    (scene, r, path)
}

#[test]
fn a_saved_solution_reloads_bit_for_bit_and_shows_the_same_light() {
    let (scene, r, path) = saved("reload.rad", 30);
    let back = Radiosity::read(&path, &scene, MemoryBudget::default()).unwrap();
    let bits = |r: &Radiosity| r.radiosities().iter().flat_map(|v| v.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(&r), bits(&back));
    assert_eq!(r.ambient(), back.ambient());
    assert_eq!((back.stats().shots, back.stats().unshot_fraction), (r.stats().shots, r.stats().unshot_fraction));
    let p = DVec3::new(-0.5, 0.2, 0.1);
    assert_eq!(r.radiance(0, p, DVec3::X), back.radiance(0, p, DVec3::X));
    assert!(r.radiance(0, p, DVec3::X).unwrap().min_element() > 0.0);
}

#[test]
fn a_solution_of_another_scene_is_refused_by_name() {
    let (_, _, path) = saved("other.rad", 3);
    let mut other = lit_room();
    other.solids[1].material.emission = DVec3::splat(3.0);
    let e = Radiosity::read(&path, &other, MemoryBudget::default()).unwrap_err();
    let text = e.to_string();
    assert!(matches!(e, Error::Format { .. }), "{e:?}");
    assert!(text.contains("other.rad") && text.contains("another scene"), "{text}");
}

#[test]
fn damaged_solution_files_are_refused_by_name_never_a_panic() {
    let (scene, _, path) = saved("good.rad", 3);
    let good = std::fs::read(&path).unwrap();
    let mut cases: Vec<(&str, Vec<u8>, &str)> = Vec::new();
    let mut flipped = good.clone();
    let middle = good.len() / 2;
    flipped[middle] ^= 0x10;
    cases.push(("flipped.rad", flipped, "checksum"));
    cases.push(("truncated.rad", good[..good.len() - 9].to_vec(), "truncated"));
    cases.push(("empty.rad", Vec::new(), "magic"));
    cases.push(("text.rad", b"this is not a solution at all, only words".to_vec(), "magic"));
    let mut version = good.clone();
    version[8] = 9;
    cases.push(("version.rad", version, "version"));
    let mut counts = good.clone();
    counts[36] ^= 1;
    cases.push(("counts.rad", counts, "patches"));
    let mut huge = good[..88].to_vec();
    huge[40..48].copy_from_slice(&u64::MAX.to_le_bytes());
    cases.push(("huge.rad", huge, "elements"));
    // Header values no solver writes, under a checksum that matches (as a writer of
    // damaged files would compute it).
    let with_crc = |mut bytes: Vec<u8>| {
        let body = bytes.len() - 4;
        let crc = crc32fast::hash(&bytes[..body]);
        bytes[body..].copy_from_slice(&crc.to_le_bytes());
        bytes
    };
    let mut nan = good.clone();
    nan[56..64].copy_from_slice(&f64::NAN.to_le_bytes());
    cases.push(("nan-unshot.rad", with_crc(nan), "unshot fraction NaN"));
    let mut negative = good.clone();
    negative[56..64].copy_from_slice(&(-0.5f64).to_le_bytes());
    cases.push(("negative-unshot.rad", with_crc(negative), "unshot fraction -0.5"));
    let mut shots = good.clone();
    shots[48..56].copy_from_slice(&u64::MAX.to_le_bytes());
    cases.push(("shots.rad", with_crc(shots), "18446744073709551615 shots"));
    for (name, bytes, says) in cases {
        let path = scratch(name);
        std::fs::write(&path, bytes).unwrap();
        let e = Radiosity::read(&path, &scene, MemoryBudget::default()).unwrap_err();
        let text = e.to_string();
        assert!(text.contains(name) && text.contains(says), "{name}: {text}");
    }
}

#[test]
fn a_spheres_elements_take_the_spheres_normal_and_a_bare_octrees_the_faces() {
    let center = DVec3::new(0.03, -0.02, 0.01);
    let sphere = octsolid::shape::Sphere::new(center, 0.6).unwrap();
    let ball = tree(&sphere);
    for shaped in [true, false] {
        let mut scene = Scene::new();
        scene.lights = vec![Light::Point { position: DVec3::new(0.0, 0.0, 0.9), color: DVec3::ONE }];
        if shaped {
            scene.add_shaped("ball", ball.clone(), diffuse(0.5, 0.0), std::sync::Arc::new(sphere.clone()));
        } else {
            scene.add("ball", ball.clone(), diffuse(0.5, 0.0));
        }
        let r = Radiosity::solve(&scene, &RadiosityOptions { max_shots: Some(0), ..options(0.25, 4) }, &NoProgress)
            .unwrap();
        for (p, n, _, _) in r.elements() {
            let radial = (p - center).normalize();
            if shaped {
                // The shape's normal at the element is the radial direction (its nearest
                // sphere point lies on the ray from the centre).
                assert!(n.angle_between(radial) < 1e-9, "{n} against {radial} at {p}");
            } else {
                assert_eq!(n.abs().max_element(), 1.0, "an axis normal: {n}");
                assert!(n.dot(radial) > 0.0);
            }
        }
    }
}

/// The lit room's inner surface seen by `r`, against the reference `fine`: the
/// area-weighted mean over `fine`'s elements of the difference (red + green + blue)
/// between the two displays (both interpolated) at each fine element's centre.
fn display_error(scene: &Scene, r: &Radiosity, fine: &Radiosity) -> f64 {
    let (mut sum, mut area) = (0.0, 0.0);
    for (center, normal, a, want) in fine.elements() {
        if fine.patch_at(0, center, normal).is_none() || !inside_room(center) {
            continue;
        }
        let got = r.radiance(0, center, normal).unwrap();
        sum += a * (got - want).abs().element_sum();
        area += a;
    }
    assert!(area > 0.0 && scene.solids.len() == 3);
    sum / area
}

#[test]
fn patches_of_four_by_four_elements_shoot_as_their_elements_would_where_receivers_are_near() {
    // The reference shoots from every element itself: patches of one element each, on
    // the same element grid (the room's faces: 16 x 16 elements of 2 voxels either way).
    let scene = lit_room();
    let solve = |patch, elements| {
        let options = RadiosityOptions { until: 1e-4, ..options(patch, elements) };
        Radiosity::solve(&scene, &options, &NoProgress).unwrap()
    };
    let (patches, elements) = (solve(0.25, 4), solve(0.0625, 1));
    let error = display_error(&scene, &patches, &elements);
    let mean = {
        let inner = elements.elements().filter(|e| inside_room(e.0) && elements.patch_at(0, e.0, e.1).is_some());
        let (sum, area) = inner.fold((0.0, 0.0), |(s, a), e| (s + e.2 * e.3.element_sum(), a + e.2));
        sum / area
    };
    // Patches shooting their mean light to every receiver, near ones too, were 3.3%
    // off (the far field's remaining 2.4% is each patch's sampled visibility and mean).
    assert!(error < 0.028 * mean, "mean difference {error} against a mean of {mean}");
}

#[test]
fn adaptive_subdivision_comes_closer_to_a_fine_solution_on_the_same_base_elements() {
    let scene = lit_room();
    let solve = |elements, subdivide| {
        let options = RadiosityOptions { until: 1e-3, subdivide, ..options(0.25, elements) };
        Radiosity::solve(&scene, &options, &NoProgress).unwrap()
    };
    // Base elements of 4 voxels; the reference has 1-voxel elements everywhere.
    let (coarse, adaptive, fine) = (solve(2, None), solve(2, Some(0.25)), solve(8, None));
    let (c, a, f) = (coarse.stats(), adaptive.stats(), fine.stats());
    assert_eq!(c.splits, 0);
    assert!(a.splits > 0 && a.elements == c.elements + 3 * a.splits, "{} splits, {} elements", a.splits, a.elements);
    assert!(a.elements < f.elements / 2, "adaptive {} against uniform {} elements", a.elements, f.elements);
    let (coarse_error, adaptive_error) =
        (display_error(&scene, &coarse, &fine), display_error(&scene, &adaptive, &fine));
    assert!(
        adaptive_error < 0.5 * coarse_error,
        "mean display error: subdivided {adaptive_error}, base elements only {coarse_error}"
    );
    // And closer than uniform elements of at least as many (4 a patch side, 2 voxels).
    let uniform = solve(4, None);
    assert!(uniform.stats().elements >= a.elements);
    let uniform_error = display_error(&scene, &uniform, &fine);
    assert!(adaptive_error < uniform_error, "subdivided {adaptive_error}, uniform {uniform_error}");
    // The energy book still balances, to 0.5% at the end: what is neither absorbed nor
    // escaped is unshot (some of it negative after the splits, so at most the unshot
    // power's magnitude, which the unshot fraction counts).
    let unshot = a.unshot_fraction * a.emitted;
    assert!((a.absorbed + a.escaped - a.emitted).abs() <= unshot + 1e-9 * a.emitted, "{a:?}");
    assert!((a.absorbed + a.escaped - a.emitted).abs() <= 0.005 * a.emitted, "{a:?}");
    assert!(a.unshot_fraction <= 1e-3);
    // A subdivided solution saves (version 2) and reloads bit for bit, splits and all.
    let path = scratch("subdivided.rad");
    adaptive.write(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap()[8], 2, "version 2");
    let back = Radiosity::read(&path, &scene, MemoryBudget::default()).unwrap();
    let bits = |r: &Radiosity| r.radiosities().iter().flat_map(|v| v.to_array().map(f64::to_bits)).collect::<Vec<_>>();
    assert_eq!(bits(&adaptive), bits(&back));
    assert_eq!((back.stats().elements, back.stats().splits), (a.elements, a.splits));
    for (x, y) in adaptive.elements().zip(back.elements()) {
        assert_eq!(x, y);
    }
    // A damaged split list is refused by name, never a panic.
    let mut bytes = std::fs::read(&path).unwrap();
    let at = 88 + 8;
    bytes[at..at + 4].copy_from_slice(&u32::MAX.to_le_bytes());
    let body = bytes.len() - 4;
    let crc = crc32fast::hash(&bytes[..body]);
    bytes[body..].copy_from_slice(&crc.to_le_bytes());
    std::fs::write(&path, &bytes).unwrap();
    let e = Radiosity::read(&path, &scene, MemoryBudget::default()).unwrap_err().to_string();
    assert!(e.contains("subdivided.rad") && e.contains("cannot be split"), "{e}");
    // An unsubdivided solution is still version 1.
    coarse.write(&path).unwrap();
    assert_eq!(std::fs::read(&path).unwrap()[8], 1, "version 1");
}

#[test]
fn subdivision_leaves_the_furnace_exact_and_refuses_bad_thresholds() {
    let emission = 0.8;
    for rho in [0.0, 0.5] {
        let mut scene = Scene::new();
        scene.lights.clear();
        scene.add("room", room(), diffuse(rho, emission));
        let options = RadiosityOptions { until: 1e-4, subdivide: Some(0.01), ..options(0.25, 4) };
        let r = Radiosity::solve(&scene, &options, &NoProgress).unwrap();
        assert_eq!(r.stats().splits, 0, "an even light splits nothing");
        let want = emission / (1.0 - rho);
        for (center, _, _, shown) in r.elements().filter(|e| inside_room(e.0)) {
            for c in shown.to_array() {
                if rho == 0.0 {
                    assert_eq!(c, emission, "at {center}");
                } else {
                    assert!((c - want).abs() < 0.01 * want, "{c} at {center}, want {want}");
                }
            }
        }
    }
    let scene = lit_room();
    for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = Radiosity::solve(&scene, &RadiosityOptions { subdivide: Some(t), ..options(0.25, 2) }, &NoProgress)
            .unwrap_err();
        assert!(e.to_string().contains("subdivision threshold"), "{e}");
    }
    // The element budget holds.
    let capped = RadiosityOptions { subdivide: Some(0.05), max_elements: Some(2000), ..options(0.25, 2) };
    let r = Radiosity::solve(&scene, &capped, &NoProgress).unwrap();
    assert!(r.stats().splits > 0 && r.stats().elements <= 2000, "{}", r.stats().elements);
}
