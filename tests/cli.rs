//! The `octsolid` binary end to end: exact command forms, JSON keys, and one-line
//! errors with a non-zero exit and no panic.

mod common;

use common::mesh_checks::stl_triangles;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn octsolid(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_octsolid")).current_dir(dir).args(args).output().unwrap()
}

/// The repository's top folder (this test belongs to the cli package in `cli/`).
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("cli/ has a parent").to_path_buf()
}

fn ok(dir: &Path, args: &[&str]) -> String {
    let out = octsolid(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "octsolid {args:?} failed: {stderr}");
    String::from_utf8(out.stdout).unwrap()
}

/// Runs a command that must fail; returns its one-line error.
fn fails(dir: &Path, args: &[&str]) -> String {
    let out = octsolid(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "octsolid {args:?} should fail");
    assert!(!stderr.contains("panicked"), "octsolid {args:?} panicked: {stderr}");
    assert_eq!(stderr.trim().lines().count(), 1, "one line expected: {stderr}");
    stderr
}

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("cli", name)
}

fn info_json(dir: &Path, file: &str) -> serde_json::Value {
    serde_json::from_str(&ok(dir, &["info", file, "--json"])).unwrap()
}

#[test]
fn shape_csg_info_slice_round_trip() {
    let dir = scratch("round-trip");
    let domain = "-1.5,-1.5,-1.5,3";
    ok(&dir, &["shape", "sphere", "--radius", "1.2", "--depth", "7", "--domain", domain, "-o", "ball.oct"]);
    ok(&dir, &["shape", "box", "--size", "2,2,2", "--depth", "7", "--domain", domain, "-o", "cube.oct"]);
    for axis in ["x", "y", "z"] {
        let name = format!("bore_{axis}.oct");
        ok(
            &dir,
            &["shape", "cylinder", "--radius", "0.5", "--height", "3", "--axis", axis, "--depth", "7"]
                .into_iter()
                .chain(["--domain", domain, "-o", &name])
                .collect::<Vec<_>>(),
        );
    }
    ok(&dir, &["csg", "intersect", "ball.oct", "cube.oct", "-o", "rounded.oct"]);
    ok(&dir, &["csg", "difference", "rounded.oct", "bore_x.oct", "bore_y.oct", "bore_z.oct", "-o", "part.oct"]);
    ok(&dir, &["csg", "union", "bore_x.oct", "bore_y.oct", "bore_z.oct", "-o", "bores.oct"]);
    ok(&dir, &["csg", "xor", "ball.oct", "cube.oct", "-o", "xor.oct"]);

    let [ball, cube, rounded, part, bores, xor] =
        ["ball", "cube", "rounded", "part", "bores", "xor"].map(|n| info_json(&dir, &format!("{n}.oct")));
    let vol = |v: &serde_json::Value| v["volume"].as_f64().unwrap();
    // Every key of the JSON contract.
    for key in ["depth", "domain", "nodes", "voxels", "volume", "bounds", "bytes_memory", "bytes_file"]
        .into_iter()
        .chain(["surface_area", "voxel_face_area", "centre_of_mass", "inertia", "components"])
    {
        assert!(part.get(key).is_some(), "missing key {key}");
    }
    assert_eq!(part["depth"], 7);
    assert_eq!(part["domain"]["edge"].as_f64().unwrap(), 3.0);
    assert_eq!(part["domain"]["min"][0].as_f64().unwrap(), -1.5);
    assert!(part["bounds"]["min"].is_array() && part["bounds"]["max"].is_array());
    // Inclusion-exclusion on volumes: |A ^ B| = |A| + |B| - 2 |A & B|, and
    // rounded - bores = rounded - (rounded & bores).
    assert!((vol(&xor) - (vol(&ball) + vol(&cube) - 2.0 * vol(&rounded))).abs() < 1e-9);
    assert!(vol(&part) < vol(&rounded) && vol(&part) > vol(&rounded) - vol(&bores));
    // Cube of side 2 in a 3-wide domain at depth 7: 2 / (3/128) = 85.33 voxels a side,
    // so 85 or 86 voxels' worth a side.
    let side = vol(&cube).cbrt();
    assert!((side - 2.0).abs() < 2.0 * 3.0 / 128.0, "cube side {side}");

    let text = ok(&dir, &["info", "part.oct"]);
    assert!(text.contains("nodes") && text.contains("on disk"), "{text}");
    ok(&dir, &["slice", "part.oct", "--axis", "z", "--at", "0.8", "--size", "128", "-o", "part.png"]);
    let img = image::open(dir.join("part.png")).unwrap();
    assert_eq!((img.width(), img.height()), (128, 128));
}

#[test]
fn info_measures_a_sphere_against_its_analytic_values() {
    use std::f64::consts::PI;
    let dir = scratch("measures");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "8", "-o", "ball.oct"]);
    let info = info_json(&dir, "ball.oct");
    let num = |v: &serde_json::Value| v.as_f64().unwrap();
    // The default domain: the sphere's box grown by 2% a side, 256 voxels.
    let h = 2.08 / 256.0;
    assert!((num(&info["domain"]["edge"]) / 256.0 - h).abs() < 1e-12);
    let area = num(&info["surface_area"]);
    assert!((area / (4.0 * PI) - 1.0).abs() < 0.02, "surface_area {area}");
    // The staircase: 3/2 the sphere's area (the mean of |n_x| + |n_y| + |n_z|).
    assert!((num(&info["voxel_face_area"]) / (6.0 * PI) - 1.0).abs() < 0.01);
    // Voxelization errs only within sqrt(3) h / 2 of the surface: the shell bounds
    // the volume's error, the centre's offset and the inertia's.
    let delta = 3f64.sqrt() / 2.0 * h;
    let shell = 4.0 / 3.0 * PI * ((1.0 + delta).powi(3) - (1.0 - delta).powi(3));
    let mass = 4.0 / 3.0 * PI;
    let volume = num(&info["volume"]);
    assert!((volume - mass).abs() <= shell);
    let offset = (1.0 + delta) * shell / volume;
    let centre: Vec<f64> = info["centre_of_mass"].as_array().unwrap().iter().map(num).collect();
    assert!(centre.len() == 3 && centre.iter().map(|c| c * c).sum::<f64>().sqrt() <= offset, "{centre:?}");
    let tolerance = (1.0 + delta).powi(2) * shell + volume * offset * offset;
    let rows = info["inertia"].as_array().unwrap();
    assert_eq!(rows.len(), 3);
    for (i, row) in rows.iter().enumerate() {
        let row: Vec<f64> = row.as_array().unwrap().iter().map(num).collect();
        for (j, &value) in row.iter().enumerate() {
            let want = if i == j { 0.4 * mass } else { 0.0 };
            assert!((value - want).abs() <= tolerance, "inertia[{i}][{j}] = {value}, want {want}");
        }
    }
    assert_eq!(info["components"], 1);
    let text = ok(&dir, &["info", "ball.oct"]);
    for label in ["area ", "centre ", "inertia ", "components 1"] {
        assert!(text.contains(label), "{label}: {text}");
    }
    // Nothing left: no centre, no inertia, no components.
    ok(&dir, &["csg", "difference", "ball.oct", "ball.oct", "-o", "none.oct"]);
    let none = info_json(&dir, "none.oct");
    assert!(none["centre_of_mass"].is_null() && none["components"] == 0 && num(&none["surface_area"]) == 0.0);
}

#[test]
fn every_shape_kind_voxelizes_with_a_default_domain() {
    let dir = scratch("kinds");
    for kind in ["sphere", "ellipsoid", "box", "cylinder", "cone", "torus"] {
        let out = ok(&dir, &["shape", kind, "--depth", "6", "--center", "3,0,-1", "-o", "s.oct"]);
        assert!(out.contains("analytic"), "{kind}: {out}");
        let info = info_json(&dir, "s.oct");
        let b = &info["bounds"];
        let mid_x = (b["min"][0].as_f64().unwrap() + b["max"][0].as_f64().unwrap()) / 2.0;
        assert!((mid_x - 3.0).abs() < 0.1, "{kind} is not centred on x = 3: {b}");
    }
}

#[test]
fn bad_input_gives_one_line_errors() {
    let dir = scratch("errors");
    let e = fails(&dir, &["info", "missing.oct"]);
    assert!(e.contains("missing.oct"), "{e}");
    std::fs::write(dir.join("junk.oct"), b"not an octree at all, just some text").unwrap();
    let e = fails(&dir, &["info", "junk.oct"]);
    assert!(e.contains("junk.oct") && e.contains("byte"), "{e}");
    ok(&dir, &["shape", "sphere", "--depth", "5", "-o", "a.oct"]);
    ok(&dir, &["shape", "sphere", "--depth", "6", "-o", "b.oct"]);
    // Different depths over one domain: the shallower is refined, exactly.
    let out = ok(&dir, &["csg", "union", "a.oct", "b.oct", "-o", "c.oct"]);
    assert!(out.contains("a.oct: exact (voxels nest, refined 1 level)"), "{out}");
    let e = fails(&dir, &["shape", "sphere", "--radius", "-1", "-o", "x.oct"]);
    assert!(e.contains("radius"), "{e}");
    // A negative number is a value, not a flag: the command says what is wrong with it.
    let e = fails(&dir, &["shell", "a.oct", "--thickness", "-1", "-o", "x.oct"]);
    assert!(e.contains("--thickness must be positive, not -1"), "{e}");
    let e = fails(&dir, &["round", "a.oct", "--radius", "-0.5", "-o", "x.oct"]);
    assert!(e.contains("--radius") && e.contains("-0.5"), "{e}");
    let e = fails(&dir, &["shape", "sphere", "--depth", "22", "-o", "x.oct"]);
    assert!(e.contains("depth"), "{e}");
    let e = fails(&dir, &["shape", "sphere", "--depth", "21", "--memory-budget", "1GiB", "-o", "x.oct"]);
    assert!(e.contains("budget"), "{e}");
    // The surface fills honour the budget too: one triangle at depth 14 is gigabytes.
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 1\nf 1 2 3\n").unwrap();
    for fill in ["surface", "thin"] {
        let args = ["voxelize", "tri.obj", "--depth", "14", "--fill", fill, "--memory-budget", "256MiB", "-o", "t.oct"];
        let e = fails(&dir, &args);
        assert!(e.contains("tri.obj") && e.contains("budget"), "{fill}: {e}");
    }
    let e = fails(&dir, &["slice", "a.oct", "--at", "99", "-o", "s.png"]);
    assert!(e.contains("a.oct") && e.contains("99"), "{e}");
    // An unknown extension names the file and everything the command reads.
    let e = fails(&dir, &["render", "a.3ds"]);
    let all = "(use .toml, .oct, .octs, .vox, .binvox, .vdb, .obj, .stl, .ply or .patches)";
    assert!(e.contains("a.3ds") && e.contains(all), "{e}");
    let e = fails(&dir, &["voxelize", "a.oct", "-o", "v.oct"]);
    assert!(e.contains("a.oct") && e.contains("(use .obj, .stl, .ply or .patches)"), "{e}");
    let e = fails(&dir, &["render", "scene.toml", "--shading", "flat"]);
    assert!(e.contains("scene.toml") && e.contains("not a scene"), "{e}");
    // A scene's build error: the scene, the place, the solid and the cause, on one line.
    std::fs::write(dir.join("scene.toml"), "[[solid]]\nname = \"part\"\nmesh = \"gone.obj\"\n").unwrap();
    let e = fails(&dir, &["render", "scene.toml"]);
    assert!(e.contains("scene.toml:3:8: part: ") && e.contains("gone.obj: "), "{e}");
    // A failed write keeps the old file: the output's folder does not exist.
    let e = fails(&dir, &["shape", "sphere", "--depth", "4", "-o", "no/such/dir/x.oct"]);
    assert!(e.contains("x.oct"), "{e}");
}

#[test]
fn non_finite_numbers_on_the_command_line_are_refused_naming_the_flag() {
    let dir = scratch("finite");
    ok(&dir, &["shape", "sphere", "--depth", "4", "-o", "a.oct"]);
    for args in [
        &["shape", "sphere", "--radius", "nan", "-o", "x.oct"][..],
        &["shape", "torus", "--tube", "inf", "-o", "x.oct"],
        &["shape", "box", "--size", "1,nan,1", "-o", "x.oct"],
        &["shape", "sphere", "--domain", "0,0,0,inf", "-o", "x.oct"],
        &["slice", "a.oct", "--at", "NaN", "-o", "s.png"],
        &["transform", "a.oct", "--scale", "inf", "-o", "t.oct"],
        &["transform", "a.oct", "--rotate", "z,nan", "-o", "t.oct"],
        &["render", "a.oct", "--fov", "nan", "-o", "r.png"],
        &["render", "a.oct", "--elevation", "-inf", "-o", "r.png"],
        &["render", "a.oct", "--eye", "1,1,1e999", "-o", "r.png"],
    ] {
        // The argument parser's error: its first line names the flag and the value.
        let out = octsolid(&dir, args);
        let e = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!out.status.success() && !e.contains("panicked"), "{args:?}: {e}");
        let flag = args.iter().find(|a| a.starts_with("--")).unwrap();
        let first = e.lines().next().unwrap_or_default();
        assert!(first.contains(flag) && first.contains("not a finite number"), "{args:?}: {e}");
    }
    // A mesh past the supported scale: refused with the range, naming the file.
    let tiny = "v 0 0 0\nv 1e-200 0 0\nv 0 1e-200 0\nv 0 0 1e-200\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(dir.join("tiny.obj"), tiny).unwrap();
    for (command, out) in [("voxelize", "tiny.oct"), ("render", "tiny.png")] {
        let e = fails(&dir, &[command, "tiny.obj", "-o", out]);
        assert!(e.contains("tiny.obj: cannot voxelize: invalid domain: edge"), "{command}: {e}");
    }
    // Finite values past what the command can use are refused by the command.
    let e = fails(&dir, &["transform", "a.oct", "--scale", "1e300", "-o", "t.oct"]);
    assert!(e.contains("not finite and invertible"), "{e}");
    let e = fails(&dir, &["render", "a.oct", "--fov", "180", "-o", "r.png"]);
    assert!(e.contains("--fov 180"), "{e}");
}

/// The RGB pixels of an OpenEXR file as the `exr` crate reads them, row-major.
fn exr_pixels(path: &Path) -> Vec<[f32; 3]> {
    let image = exr::prelude::read_first_rgba_layer_from_file(
        path,
        |size, _| (size.width(), vec![[0.0f32; 3]; size.width() * size.height()]),
        |(w, pixels): &mut (usize, Vec<[f32; 3]>), at, (r, g, b, _): (f32, f32, f32, f32)| {
            pixels[at.y() * *w + at.x()] = [r, g, b];
        },
    )
    .unwrap();
    image.layer_data.channel_data.pixels.1
}

#[test]
fn render_writes_linear_exr_and_exposes_png_and_exr_alike() {
    let dir = scratch("exr");
    ok(&dir, &["shape", "sphere", "--depth", "5", "-o", "a.oct"]);
    let size = ["--size", "40x30", "--spp", "1"];
    let render = |extra: &[&str]| ok(&dir, &[&["render", "a.oct"][..], &size, extra].concat());
    render(&["-o", "plain.png"]);
    render(&["-o", "zero.png", "--exposure", "0"]);
    render(&["-o", "plain.exr"]);
    render(&["-o", "up.EXR", "--exposure", "1"]);
    let out = render(&["-o", "down.png", "--exposure", "-1.5"]);
    assert!(out.contains("exposure -1.5 stops"), "{out}");
    // --exposure 0 is no exposure at all, to the byte.
    assert_eq!(std::fs::read(dir.join("plain.png")).unwrap(), std::fs::read(dir.join("zero.png")).unwrap());
    // The EXR is the PNG's radiance before encoding: it encodes to the PNG's pixels.
    let (plain, up) = (exr_pixels(&dir.join("plain.exr")), exr_pixels(&dir.join("up.EXR")));
    let png = image::open(dir.join("plain.png")).unwrap().to_rgb8();
    assert_eq!(plain.len(), 40 * 30);
    for (p, q) in plain.iter().zip(png.pixels()) {
        assert_eq!(p.map(|c| octsolid::render::to_srgb8(f64::from(c))), q.0, "{p:?}");
    }
    // One stop up doubles every value exactly; the darker PNG is darker.
    assert!(plain.iter().zip(&up).all(|(a, b)| a.map(|c| 2.0 * c) == *b));
    let down = image::open(dir.join("down.png")).unwrap().to_rgb8();
    let sum = |img: &image::RgbImage| img.pixels().map(|p| p.0.iter().map(|&c| u64::from(c)).sum::<u64>()).sum::<u64>();
    assert!(sum(&down) < sum(&png));
    // Polygons write EXR too.
    ok(&dir, &["render", "a.oct", "--shading", "gouraud", "--size", "40x30", "-o", "poly.exr"]);
    assert_eq!(exr_pixels(&dir.join("poly.exr")).len(), 40 * 30);
    // Refused: a format that is not a picture, and exposures that are not numbers.
    let e = fails(&dir, &["render", "a.oct", "-o", "a.jpg"]);
    assert!(e.contains("a.jpg") && e.contains("png, exr"), "{e}");
    assert!(!dir.join("a.jpg").exists());
    let e = fails(&dir, &["demo", "-o", "demo.tiff"]);
    assert!(e.contains("demo.tiff") && e.contains("png, exr"), "{e}");
    for bad in ["nan", "inf", "x"] {
        let out = octsolid(&dir, &["render", "a.oct", "--exposure", bad, "-o", "x.png"]);
        let e = String::from_utf8_lossy(&out.stderr).into_owned();
        assert!(!out.status.success() && !e.contains("panicked"), "{bad}: {e}");
        assert!(e.lines().next().unwrap_or_default().contains("--exposure"), "{bad}: {e}");
    }
    let e = fails(&dir, &["render", "a.oct", "--exposure", "100", "-o", "x.exr"]);
    assert!(e.contains("exposure") && e.contains("100"), "{e}");
    assert!(!dir.join("x.exr").exists() && !dir.join("x.png").exists());
}

#[test]
fn demo_writes_its_picture() {
    let dir = scratch("demo");
    let out = ok(&dir, &["demo", "--depth", "7"]);
    assert!(out.contains("demo.png"), "{out}");
    let img = image::open(dir.join("demo.png")).unwrap();
    assert!(img.width() > 0 && img.height() > 0);
}

#[test]
fn voxelize_meshes_and_patches_and_report_the_rule() {
    let dir = scratch("voxelize");
    let models = repo().join("models");
    let spot = models.join("spot.obj");
    let spot = spot.to_str().unwrap();
    let out = ok(&dir, &["voxelize", spot, "--depth", "7", "-o", "spot.oct"]);
    assert!(out.contains("parity rule (auto)") && out.contains("5856 triangles"), "{out}");
    let info = info_json(&dir, "spot.oct");
    let volume = info["volume"].as_f64().unwrap();
    assert!((volume / 0.718259 - 1.0).abs() < 0.01, "spot volume {volume}");
    let out = ok(&dir, &["voxelize", spot, "--depth", "7", "--inside", "winding", "-o", "spot_w.oct"]);
    assert!(out.contains("winding rule") && !out.contains("auto"), "{out}");
    let out = ok(&dir, &["voxelize", spot, "--depth", "7", "--fill", "surface", "-o", "spot_s.oct"]);
    assert!(!out.contains("rule"), "{out}");
    let teapot = models.join("teapot.patches");
    ok(&dir, &["voxelize", teapot.to_str().unwrap(), "--depth", "6", "--fill", "surface", "-o", "t.oct"]);

    let report: serde_json::Value = serde_json::from_str(&ok(&dir, &["mesh-info", spot, "--json"])).unwrap();
    assert_eq!(report["triangles"], 5856);
    assert_eq!(report["watertight"], true);
    let bunny = models.join("stanford-bunny.obj");
    let text = ok(&dir, &["mesh-info", bunny.to_str().unwrap()]);
    assert!(text.contains("boundary edges     223") && text.contains("watertight         no"), "{text}");

    std::fs::write(dir.join("broken.obj"), "v 0 0 0\nv 1 0 0\nf 1 2 3\n").unwrap();
    let e = fails(&dir, &["voxelize", "broken.obj", "--depth", "5", "-o", "b.oct"]);
    assert!(e.contains("broken.obj") && e.contains("line 3"), "{e}");
}

#[test]
fn loader_warnings_go_to_stderr_with_the_file_and_line() {
    let dir = scratch("warnings");
    // A unit tetrahedron whose material library is missing and whose group name is
    // Latin-1: it loads, and each warning is one stderr line naming the file and line.
    let obj = b"mtllib gone.mtl\ng T\xe9tra\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    std::fs::write(dir.join("t.obj"), obj).unwrap();
    for args in [&["mesh-info", "t.obj"][..], &["voxelize", "t.obj", "--depth", "5", "-o", "t.oct"]] {
        let out = octsolid(&dir, args);
        assert!(out.status.success(), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        let warnings: Vec<&str> = stderr.lines().filter(|l| l.starts_with("warning: ")).collect();
        assert_eq!(warnings.len(), 2, "{stderr}");
        assert!(warnings[0].starts_with("warning: t.obj: line 2: lines that are not UTF-8"), "{stderr}");
        assert!(warnings[1].starts_with("warning: t.obj: line 1: material library 'gone.mtl'"), "{stderr}");
    }
    let report: serde_json::Value = serde_json::from_str(&ok(&dir, &["mesh-info", "t.obj", "--json"])).unwrap();
    assert_eq!(report["triangles"], 4);
    assert_eq!(report["groups"][0][0], "T\u{e9}tra");
    assert!((report["volume"].as_f64().unwrap() - 1.0 / 6.0).abs() < 1e-15, "{report}");
}

#[test]
fn render_solids_meshes_and_scenes_by_every_method() {
    let dir = scratch("render");
    let root = &repo();
    ok(&dir, &["shape", "torus", "--radius", "1", "--tube", "0.3", "--depth", "6", "-o", "ring.oct"]);
    let mut images = Vec::new();
    for method in ["trace", "front-to-back", "painter", "zbuffer", "scanline"] {
        let name = format!("ring_{method}.png");
        let out = ok(&dir, &["render", "ring.oct", "--size", "96x72", "--spp", "1", "--method", method, "-o", &name]);
        assert!(out.contains("samples/s"), "{out}");
        assert_eq!(out.contains("faces drawn"), method != "trace", "{out}");
        images.push(std::fs::read(dir.join(&name)).unwrap());
    }
    assert!(images.windows(2).all(|w| w[0] == w[1]), "every method gives the same picture");
    ok(&dir, &["render", "ring.oct", "--size", "64x48"]);
    assert!(dir.join("ring.png").exists(), "default output name");
    let spot = root.join("models/spot.obj");
    let spot_with = |name: &str, up: Option<&str>| {
        let args = ["render", spot.to_str().unwrap(), "--depth", "6", "--size", "64x48", "-o", name];
        ok(&dir, &args.into_iter().chain(up.into_iter().flat_map(|a| ["--up", a])).collect::<Vec<_>>());
        std::fs::read(dir.join(name)).unwrap()
    };
    let spot_default = spot_with("spot.png", None);
    assert!(spot_default == spot_with("spot_y.png", Some("y")), "an OBJ is y-up unless told");
    assert!(spot_default != spot_with("spot_z.png", Some("z")), "--up z turns the view");
    let scene = root.join("scenes/flange.toml");
    ok(&dir, &["render", scene.to_str().unwrap(), "--size", "64x48", "--no-cache", "-o", "flange.png"]);
    let img = image::open(dir.join("flange.png")).unwrap();
    assert_eq!((img.width(), img.height()), (64, 48));
    std::fs::write(dir.join("bad.toml"), "[image]\nsize = [64, 48\n").unwrap();
    let e = fails(&dir, &["render", "bad.toml"]);
    assert!(e.contains("bad.toml:2:15: unclosed array"), "{e}");
    let e = fails(&dir, &["render", "ring.oct", "--size", "0x10"]);
    assert!(e.contains("image size"), "{e}");
    // A size or sample count out of range is refused at its place, before any solid is
    // voxelized.
    std::fs::write(dir.join("big.toml"), "[image]\nsize = [64, 20000]\nsamples = 2\n").unwrap();
    let e = fails(&dir, &["render", "big.toml"]);
    assert!(e.contains("big.toml:2:8: image size 64x20000 is outside 1..=16384 a side"), "{e}");
    std::fs::write(dir.join("many.toml"), "[image]\nsize = [64, 48]\nsamples = 17\n").unwrap();
    let e = fails(&dir, &["render", "many.toml"]);
    assert!(e.contains("many.toml:3:11: samples 17 a side is outside 1..=16"), "{e}");
}

#[test]
fn render_keeps_a_scenes_solids_in_its_cache_unless_told_not_to() {
    let dir = scratch("scene-cache");
    let scene = "[image]\nsize = [48, 36]\n\n[[solid]]\nshape = { sphere = { center = [0, 0, 0], radius = 1 } }\n";
    std::fs::write(dir.join("ball.toml"), scene).unwrap();
    let cache = dir.join(".octsolid-cache");
    let entries = || -> Vec<PathBuf> {
        let Ok(read) = std::fs::read_dir(&cache) else { return Vec::new() };
        read.map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|x| x == "octcache")).collect()
    };
    let png = |name: &str| std::fs::read(dir.join(name)).unwrap();
    let out = ok(&dir, &["render", "ball.toml", "--no-cache", "-o", "plain.png"]);
    assert!(out.contains("loading and voxelizing the scene") && !cache.exists(), "{out}");
    let out = ok(&dir, &["render", "ball.toml", "-o", "cold.png"]);
    assert!(out.contains("loading and voxelizing the scene") && entries().len() == 1, "{out}");
    let out = ok(&dir, &["render", "ball.toml", "-o", "warm.png"]);
    assert!(out.contains("loading the scene (1 solid from its cache)"), "{out}");
    assert!(png("cold.png") == png("plain.png") && png("warm.png") == png("plain.png"));
    // A corrupt entry: a warning naming it, the same picture, the entry rewritten.
    let entry = entries().remove(0);
    std::fs::write(&entry, b"OCTCACHE garbage").unwrap();
    let run = octsolid(&dir, &["render", "ball.toml", "-o", "rebuilt.png"]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{stderr}");
    let name = entry.file_name().unwrap().to_string_lossy();
    assert!(
        stderr.contains("warning: ") && stderr.contains(&*name) && stderr.contains("cache entry not used"),
        "{stderr}"
    );
    assert!(png("rebuilt.png") == png("plain.png"));
    let out = ok(&dir, &["render", "ball.toml", "-o", "warm.png"]);
    assert!(out.contains("(1 solid from its cache)"), "{out}");
    let out = ok(&dir, &["render", "ball.toml", "--clear-cache", "--no-cache", "-o", "cleared.png"]);
    assert!(out.contains("cleared    1 cached solid of ball.toml") && !cache.exists(), "{out}");
}

/// A mesh voxelized into an `.oct` file carries its triangles' crossings: `info`
/// measures the true surface's area (against the mesh's own, which `mesh-info` sums)
/// and `export` says its crossings are exact; so for a `.vdb` level set; a surface
/// fill carries none.
#[test]
fn a_voxelized_mesh_carries_its_crossings_to_info_and_export() {
    let dir = scratch("mesh_crossings");
    let spot = repo().join("models/spot.obj");
    let spot = spot.to_str().unwrap();
    let out = ok(&dir, &["voxelize", spot, "--depth", "7", "-o", "spot.oct"]);
    assert!(out.contains("crossings and normals from the triangles"), "{out}");
    let info = info_json(&dir, "spot.oct");
    let mesh: serde_json::Value = serde_json::from_str(&ok(&dir, &["mesh-info", spot, "--json"])).unwrap();
    let (area, mesh_area) = (info["surface_area"].as_f64().unwrap(), mesh["area"].as_f64().unwrap());
    assert_eq!(info["area_from"], "true surface");
    assert!((area / mesh_area - 1.0).abs() < 5e-3, "area {area} against the mesh's {mesh_area}");
    let out = ok(&dir, &["export", "spot.oct", "-o", "spot.obj"]);
    assert!(out.contains("exact crossings") && !out.contains("estimated"), "{out}");
    // A sphere with a hole: the winding rule closes it, where no triangle crosses a
    // face's segment and the export estimates.
    let mut open = octsolid::mesh::generate::icosphere(octsolid::glam::DVec3::ZERO, 1.0, 3);
    open.retain_triangles(|t| t >= 40);
    octsolid::mesh::write_mesh(&open, dir.join("open.obj")).unwrap();
    ok(&dir, &["voxelize", "open.obj", "--depth", "6", "-o", "open.oct"]);
    let out = ok(&dir, &["export", "open.oct", "-o", "open.ply"]);
    assert!(out.contains("exact crossings") && out.contains("where the file has no crossing"), "{out}");
    // A level set's distances give crossings too: OpenVDB's sphere of radius 6.3.
    let sphere = repo().join("tests/data/vdb/sphere.vdb");
    let info = info_json(&dir, sphere.to_str().unwrap());
    let (area, exact) = (info["surface_area"].as_f64().unwrap(), 4.0 * std::f64::consts::PI * 6.3 * 6.3);
    assert_eq!(info["area_from"], "true surface");
    assert!((area / exact - 1.0).abs() < 2e-3, "area {area} against {exact}");
    let out = ok(&dir, &["export", sphere.to_str().unwrap(), "-o", "vdb.obj"]);
    assert!(out.contains("exact crossings") && !out.contains("estimated"), "{out}");
    let out = ok(&dir, &["voxelize", spot, "--depth", "5", "--fill", "surface", "-o", "shell.oct"]);
    assert!(!out.contains("crossings"), "{out}");
    assert_eq!(info_json(&dir, "shell.oct")["area_from"], "voxel estimate");
}

#[test]
fn export_writes_closed_meshes_with_the_octree_volume() {
    let dir = scratch("export");
    ok(&dir, &["shape", "torus", "--radius", "1", "--tube", "0.4", "--depth", "6", "-o", "ring.oct"]);
    let info = info_json(&dir, "ring.oct");
    let volume = info["volume"].as_f64().unwrap();
    // The area from the file's crossings (the true surface), against 4 pi^2 R r.
    let (area, exact_area) = (info["surface_area"].as_f64().unwrap(), 4.0 * std::f64::consts::PI.powi(2) * 0.4);
    assert_eq!(info["area_from"], "true surface");
    assert!((area / exact_area - 1.0).abs() < 2e-3, "area {area} against {exact_area}");
    // A negative tolerance or normal tolerance is refused by its own check, not taken
    // for a flag.
    assert!(fails(&dir, &["export", "ring.oct", "-o", "n.obj", "--tolerance", "-1"]).contains("tolerance"));
    assert!(
        fails(&dir, &["export", "ring.oct", "-o", "n.obj", "--tolerance", "0.1", "--normal-tolerance", "-1"])
            .contains("-1")
    );
    // The staircase encloses the octree's volume exactly.
    for (name, extra) in [("ring.obj", None), ("ring.stl", None), ("ring.ply", Some("--unit-faces"))] {
        let args = ["export", "ring.oct", "-o", name, "--surface", "voxels"];
        let out = ok(&dir, &args.into_iter().chain(extra).collect::<Vec<_>>());
        assert!(out.contains("triangles") && out.contains("enclosed") && out.contains(name), "{out}");
        let report: serde_json::Value = serde_json::from_str(&ok(&dir, &["mesh-info", name, "--json"])).unwrap();
        assert_eq!(report["watertight"], true, "{name}: {report}");
        let enclosed = report["volume"].as_f64().unwrap();
        assert!((enclosed / volume - 1.0).abs() < 1e-6, "{name}: {enclosed} vs {volume}");
    }
    // The smooth surface (the default) from the file's crossings: closed, and nearer the
    // torus's exact volume 2 pi^2 R r^2 than the voxels are.
    let exact = 2.0 * std::f64::consts::PI.powi(2) * 1.0 * 0.4f64.powi(2);
    for name in ["smooth.obj", "smooth.stl"] {
        let out = ok(&dir, &["export", "ring.oct", "-o", name]);
        assert!(out.contains("smooth") && out.contains("exact crossings") && out.contains("voxel of their"), "{out}");
        let report: serde_json::Value = serde_json::from_str(&ok(&dir, &["mesh-info", name, "--json"])).unwrap();
        assert_eq!((report["watertight"].clone(), report["non_manifold_edges"].clone()), (true.into(), 0.into()));
        let enclosed = report["volume"].as_f64().unwrap();
        assert!(
            (enclosed / exact - 1.0).abs() < 2e-3 && (enclosed - exact).abs() < (volume - exact).abs(),
            "{name}: {enclosed}, the octree {volume}, the torus {exact}"
        );
    }
    // Two boxes touching along an edge: STL moves the shared corners apart and reads
    // back closed, with as many vertices as the OBJ keeps.
    for (name, center) in [("a.oct", "0.5,0.5,0.5"), ("b.oct", "1.5,1.5,0.5")] {
        ok(
            &dir,
            &[
                "shape",
                "box",
                "--size",
                "1,1,1",
                "--center",
                center,
                "--domain",
                "-2,-2,-2,4",
                "--depth",
                "3",
                "-o",
                name,
            ],
        );
    }
    ok(&dir, &["csg", "union", "a.oct", "b.oct", "-o", "touch.oct"]);
    let out = ok(&dir, &["export", "touch.oct", "-o", "touch.stl", "--surface", "voxels"]);
    assert!(out.contains("stl        4 vertices where voxels touch moved apart"), "{out}");
    ok(&dir, &["export", "touch.oct", "-o", "touch.obj", "--surface", "voxels"]);
    let [stl, obj] = ["touch.stl", "touch.obj"]
        .map(|f| serde_json::from_str::<serde_json::Value>(&ok(&dir, &["mesh-info", f, "--json"])).unwrap());
    assert_eq!((stl["watertight"].clone(), stl["non_manifold_edges"].clone()), (true.into(), 0.into()), "{stl}");
    assert_eq!(stl["vertices"], obj["vertices"]);
    let e = fails(&dir, &["export", "ring.oct", "-o", "ring.xyz"]);
    assert!(e.contains("ring.xyz") && e.contains("accepted: obj, stl, ply, 3mf, glb"), "{e}");
    let e = fails(&dir, &["export", "missing.oct", "-o", "m.obj"]);
    assert!(e.contains("missing.oct"), "{e}");
    std::fs::write(dir.join("junk.oct"), b"not an octree").unwrap();
    let e = fails(&dir, &["export", "junk.oct", "-o", "j.obj"]);
    assert!(e.contains("junk.oct") && e.contains("byte"), "{e}");
    ok(&dir, &["csg", "difference", "ring.oct", "ring.oct", "-o", "none.oct"]);
    let e = fails(&dir, &["export", "none.oct", "-o", "n.obj"]);
    assert!(e.contains("none.oct") && e.contains("empty"), "{e}");
    assert!(!dir.join("n.obj").exists() && !dir.join("j.obj").exists());
}

#[test]
fn render_meshes_as_polygons_with_each_shading() {
    let dir = scratch("polygons");
    let root = &repo();
    let teapot = root.join("models/teapot.patches");
    let mut images = Vec::new();
    for shading in ["flat", "gouraud", "phong"] {
        let name = format!("teapot_{shading}.png");
        let args = ["render", teapot.to_str().unwrap(), "--shading", shading, "--size", "80x60", "-o", &name];
        let out = ok(&dir, &args);
        assert!(out.contains("triangles"), "{out}");
        let img = image::open(dir.join(&name)).unwrap().to_rgb8();
        let background = *img.get_pixel(0, 0);
        assert!(img.pixels().filter(|p| **p != background).count() > 500, "{shading}: the teapot shows");
        images.push(img);
    }
    assert!(images[0] != images[1] && images[1] != images[2], "the three shadings differ");
    // A solid is drawn by its exported boundary mesh.
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "5", "-o", "ball.oct"]);
    let out = ok(&dir, &["render", "ball.oct", "--shading", "gouraud", "--size", "64x48", "-o", "ball.png"]);
    assert!(out.contains("triangles") && dir.join("ball.png").exists(), "{out}");
    let bad = octsolid(&dir, &["render", teapot.to_str().unwrap(), "--shading", "shiny"]);
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("shiny"));
}

#[test]
fn build_voxelizes_scene_solids_and_csg_merges_any_number_of_operands() {
    let dir = scratch("build");
    let scene = "[domain]\nmin = [-2, -2, -2]\nedge = 4\ndepth = 6\n\n\
        [[solid]]\nname = \"a\"\nshape = { sphere = { center = [-0.4, 0, 0], radius = 1 } }\n\n\
        [[solid]]\nname = \"b\"\nshape = { sphere = { center = [0.4, 0, 0], radius = 1 } }\n\n\
        [[solid]]\nname = \"c\"\nshape = { polar = { count = 3, axis = \"z\", shape = \
        { sphere = { center = [0, 0.5, 0], radius = 0.6 } } } }\n";
    std::fs::write(dir.join("three.toml"), scene).unwrap();
    for name in ["a", "b", "c"] {
        let out = ok(&dir, &["build", "three.toml", "--solid", name, "-o", &format!("{name}.oct")]);
        assert!(out.contains(&format!("built solid '{name}' at depth 6")), "{out}");
    }
    // The union of the shape solids, one pruned tree, is the k-way union of the three.
    ok(&dir, &["build", "three.toml", "-o", "all.oct"]);
    ok(&dir, &["csg", "union", "a.oct", "b.oct", "c.oct", "-o", "merged.oct"]);
    let voxels = |f: &str| info_json(&dir, f)["voxels"].as_u64().unwrap();
    assert_eq!(voxels("all.oct"), voxels("merged.oct"));
    // Byte for byte, the surface sections too: the union's crossings taken from the
    // three files' data are the ones the whole tree gives (to the 16-bit codes).
    assert_eq!(std::fs::read(dir.join("all.oct")).unwrap(), std::fs::read(dir.join("merged.oct")).unwrap());
    let surface_line = |f: &str| ok(&dir, &["info", f]).lines().find(|l| l.starts_with("surface ")).map(str::to_owned);
    assert!(surface_line("merged.oct").is_some_and(|l| l.contains("boundary faces")));
    // A quarter turn carries the data; an eighth resamples from the moved smooth
    // surface, with new crossings, and keeps the true surface's area (an eighth turn
    // about z keeps areas).
    let out = ok(&dir, &["transform", "merged.oct", "--rotate", "z,90", "-o", "turned.oct"]);
    assert!(!out.contains("left out") && surface_line("turned.oct") == surface_line("merged.oct"), "{out}");
    let out = ok(&dir, &["transform", "merged.oct", "--rotate", "z,45", "-o", "eighth.oct"]);
    assert!(out.contains("resampled from the moved smooth surface"), "{out}");
    assert!(surface_line("eighth.oct").is_some_and(|l| l.contains("boundary faces")));
    let area = |f: &str| info_json(&dir, f)["surface_area"].as_f64().unwrap();
    let (before, after) = (area("merged.oct"), area("eighth.oct"));
    assert!((after / before - 1.0).abs() < 5e-3, "area {before} turned to {after}");
    // xor of three: |A ^ B ^ C| = sum |X| - 2 sum |X & Y| + 4 |A & B & C|.
    ok(&dir, &["csg", "xor", "a.oct", "b.oct", "c.oct", "-o", "odd.oct"]);
    ok(&dir, &["csg", "intersect", "a.oct", "b.oct", "c.oct", "-o", "abc.oct"]);
    let mut pairs = 0;
    for (x, y) in [("a", "b"), ("a", "c"), ("b", "c")] {
        let name = format!("{x}{y}.oct");
        ok(&dir, &["csg", "intersect", &format!("{x}.oct"), &format!("{y}.oct"), "-o", &name]);
        pairs += voxels(&name);
    }
    let singles = voxels("a.oct") + voxels("b.oct") + voxels("c.oct");
    assert_eq!(voxels("odd.oct") + 2 * pairs, singles + 4 * voxels("abc.oct"));
    // Errors: an unknown solid, a pattern without copies, at their place.
    let e = fails(&dir, &["build", "three.toml", "--solid", "d", "-o", "d.oct"]);
    assert!(e.contains("three.toml") && e.contains("no solid is named 'd'") && e.contains("a, b, c"), "{e}");
    std::fs::write(dir.join("none.toml"), scene.replace("count = 3", "count = 0")).unwrap();
    let e = fails(&dir, &["build", "none.toml", "-o", "none.oct"]);
    assert!(e.contains("none.toml") && e.contains("none.toml:16:") && e.contains("0 copies"), "{e}");
}

// ---------------------------------------------------------------------------------
// The voxel interchange formats on the command line: `convert`, and every command
// that reads a solid reading `.vox`, `.binvox` and `.vdb`, against files other tools
// wrote (tests/data: dot_vox's MagicaVoxel samples, OpenVDB 10, the PyPI binvox
// package) and what they or their makers say of them.

/// A file of tests/data, as an argument.
fn data(path: &str) -> String {
    repo().join("tests/data").join(path).to_str().unwrap().to_string()
}

fn read_json(path: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(data(path)).unwrap()).unwrap()
}

/// sRGB byte to linear, the IEC 61966-2-1 formula.
fn srgb_to_linear(c: u8) -> f64 {
    let c = f64::from(c) / 255.0;
    if c <= 0.04045 { c / 12.92 } else { ((c + 0.055) / 1.055).powf(2.4) }
}

#[test]
fn convert_oct_through_every_voxel_format_and_back_is_bit_identical() {
    let dir = scratch("convert-round-trip");
    // Off-origin domains at depths 3, 6 and 9; the rod spans 486 voxels, so .vox
    // writes it as several models of at most 256 a side placed by the scene graph.
    let solids: [(&str, &[&str]); 3] = [
        ("block", &["box", "--size", "1,2,0.5", "--depth", "3"]),
        ("ball", &["sphere", "--radius", "1.3", "--depth", "6", "--domain", "-0.7,-2.1,0.35,2.9"]),
        ("rod", &["box", "--size", "1.9,0.05,0.05", "--depth", "9", "--domain", "-1,-1,-1,2"]),
    ];
    for (name, shape) in solids {
        let oct = format!("{name}.oct");
        ok(&dir, &[&["shape"], shape, &["-o", oct.as_str()]].concat());
        // The solid's bytes: the voxel formats carry no surface data, so the file
        // `shape` wrote without its surface section.
        let (tree, meta) =
            octsolid::io::oct::read_and_metadata(dir.join(&oct), octsolid::MemoryBudget::unlimited()).unwrap();
        let original = octsolid::io::oct::encode_with(&tree, &meta);
        let voxels = info_json(&dir, &oct)["voxels"].clone();
        for ext in ["vox", "binvox", "vdb"] {
            let (there, back) = (format!("{name}.{ext}"), format!("{name}-from-{ext}.oct"));
            let out = ok(&dir, &["convert", &oct, &there]);
            assert!(out.contains(&format!("wrote      {there}")), "{out}");
            assert_eq!(info_json(&dir, &there)["voxels"], voxels, "{there}");
            ok(&dir, &["convert", &there, &back]);
            assert!(
                std::fs::read(dir.join(&back)).unwrap() == original,
                "{name}: .oct -> .{ext} -> .oct changed the file"
            );
        }
    }
    // --depth brings the solid to another depth first: one level finer nests exactly,
    // eight voxels a voxel.
    let out = ok(&dir, &["convert", "ball.oct", "ball7.vdb", "--depth", "7"]);
    assert!(out.contains("exact"), "{out}");
    let fine = info_json(&dir, "ball7.vdb");
    assert_eq!(fine["voxels"].as_u64().unwrap(), 8 * info_json(&dir, "ball.oct")["voxels"].as_u64().unwrap());
    assert_eq!(fine["depth"], 7);
    // The output may not be the input, and a format written only is not read.
    let e = fails(&dir, &["convert", "ball.oct", "./ball.oct"]);
    assert!(e.contains("the output is the input"), "{e}");
    ok(&dir, &["convert", "ball.oct", "ball.glb"]);
    let e = fails(&dir, &["convert", "ball.glb", "b.oct"]);
    assert!(e.contains("ball.glb") && e.contains("(use .oct, .octs, .vox, .binvox or .vdb)"), "{e}");
    // `-o OUT`, as in the other commands, writes what the positional OUT does; not both.
    ok(&dir, &["convert", "ball.oct", "-o", "ball-o.vdb"]);
    ok(&dir, &["convert", "ball.oct", "ball-p.vdb"]);
    assert!(std::fs::read(dir.join("ball-o.vdb")).unwrap() == std::fs::read(dir.join("ball-p.vdb")).unwrap());
    let e = fails(&dir, &["convert", "ball.oct", "x.vdb", "-o", "y.vdb"]);
    assert!(e.contains("cannot be used with"), "{e}");
}

#[test]
fn vox_samples_are_read_by_every_command_with_their_counts_and_colours() {
    let dir = scratch("vox-samples");
    let axes = data("vox/axes.vox");
    // The oracle: dot_vox's parse of the file, each model's voxels by palette index
    // once for every shape node placing it (the sample's placed models do not overlap).
    let file = dot_vox::load(&axes).unwrap();
    let mut expected = std::collections::BTreeMap::<u64, u64>::new();
    for node in &file.scenes {
        if let dot_vox::SceneNode::Shape { models, .. } = node {
            for v in &file.models[models[0].model_id as usize].voxels {
                *expected.entry(u64::from(v.i) + 1).or_default() += 1;
            }
        }
    }
    assert_eq!(expected.len(), 4, "axes.vox: red x, green y, blue z and a dark origin");
    let info = info_json(&dir, &axes);
    assert_eq!(info["format"], "vox");
    let solids = info["solids"].as_array().unwrap();
    let counts: std::collections::BTreeMap<u64, u64> =
        solids.iter().map(|s| (s["palette_index"].as_u64().unwrap(), s["voxels"].as_u64().unwrap())).collect();
    assert_eq!(counts, expected);
    let total: u64 = expected.values().sum();
    assert_eq!(info["voxels"].as_u64().unwrap(), total);
    for s in solids {
        let c = file.palette[s["palette_index"].as_u64().unwrap() as usize - 1];
        let want = [c.r, c.g, c.b].map(srgb_to_linear);
        for (got, want) in s["color"].as_array().unwrap().iter().zip(want) {
            assert!((got.as_f64().unwrap() - want).abs() < 1e-12, "{s}: {want}");
        }
    }
    let text = ok(&dir, &["info", &axes]);
    assert!(text.contains("format     .vox, 4 solids") && text.contains("sRGB #dd0000"), "{text}");

    // Every command that reads a solid reads it: the union of its colours.
    ok(&dir, &["convert", &axes, "axes.oct"]);
    assert_eq!(info_json(&dir, "axes.oct")["voxels"].as_u64().unwrap(), total);
    ok(&dir, &["transform", &axes, "--translate", "3,0,0", "-o", "moved.oct"]);
    assert_eq!(info_json(&dir, "moved.oct")["voxels"].as_u64().unwrap(), total);
    // To .vox, each colour moves on its own, the same voxels in the same colours.
    ok(&dir, &["transform", &axes, "--translate", "3,0,0", "-o", "moved.vox"]);
    let moved = info_json(&dir, "moved.vox");
    let moved_solids = moved["solids"].as_array().unwrap();
    assert_eq!(moved_solids.len(), solids.len());
    for (m, s) in moved_solids.iter().zip(solids) {
        assert_eq!((&m["palette_index"], &m["voxels"], &m["color"]), (&s["palette_index"], &s["voxels"], &s["color"]));
    }
    let [x0, x1] = [&info, &moved].map(|i| i["bounds"]["min"][0].as_f64().unwrap());
    assert_eq!(x1 - x0, 3.0);
    ok(&dir, &["csg", "difference", &axes, "moved.oct", "-o", "diff.oct"]);
    let diff = info_json(&dir, "diff.oct")["voxels"].as_u64().unwrap();
    assert!(diff > 0 && diff < total, "a move of 3 voxels along x leaves part of the model");
    let out = ok(&dir, &["slice", &axes, "--axis", "z", "--at", "1.5", "--size", "64", "-o", "slice.png"]);
    assert!(out.contains("slice.png"), "{out}");

    // export .glb: one mesh and one material a colour, the palette's colour.
    ok(&dir, &["export", &axes, "-o", "axes.glb"]);
    let glb = std::fs::read(dir.join("axes.glb")).unwrap();
    assert_eq!(&glb[..4], b"glTF");
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let gltf: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    assert_eq!(gltf["meshes"].as_array().unwrap().len(), 4);
    for (material, (index, _)) in gltf["materials"].as_array().unwrap().iter().zip(&expected) {
        let c = file.palette[*index as usize - 1];
        let base = &material["pbrMetallicRoughness"]["baseColorFactor"];
        for (got, want) in base.as_array().unwrap().iter().zip([c.r, c.g, c.b].map(srgb_to_linear)) {
            assert!((got.as_f64().unwrap() - want).abs() < 1e-6, "{material}");
        }
    }
    // A .vox world is z-up: each node turns it to glTF's +Y (a quarter turn about x).
    let h = std::f64::consts::FRAC_1_SQRT_2;
    for node in gltf["nodes"].as_array().unwrap() {
        let q: Vec<f64> = node["rotation"].as_array().unwrap().iter().map(|c| c.as_f64().unwrap()).collect();
        assert_eq!(q, [-h, 0.0, 0.0, h], "{node}");
    }
    // A y-up solid (voxelized from an OBJ, its up recorded in the .oct) needs no turn.
    ok(
        &dir,
        &["voxelize", &repo().join("models/bunny-watertight.obj").to_string_lossy(), "--depth", "5", "-o", "bunny.oct"],
    );
    ok(&dir, &["export", "bunny.oct", "-o", "bunny.glb"]);
    let glb = std::fs::read(dir.join("bunny.glb")).unwrap();
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let gltf: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    assert!(gltf["nodes"][0]["rotation"].is_null(), "{}", gltf["nodes"]);
    // OBJ holds one mesh: the union, whose enclosed volume is the voxels'.
    let out = ok(&dir, &["export", &axes, "-o", "axes.obj"]);
    assert!(out.contains(&format!("{total}.000000 octree")), "{out}");
}

#[test]
fn export_glb_writes_the_true_surface_with_smooth_normals() {
    let dir = scratch("glb-smooth");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "6", "-o", "ball.oct"]);
    let obj = ok(&dir, &["export", "ball.oct", "-o", "ball.obj"]);
    let out = ok(&dir, &["export", "ball.oct", "-o", "ball.glb"]);
    assert!(out.contains("smooth: dual contouring") && out.contains("exact crossings"), "{out}");
    let glb = std::fs::read(dir.join("ball.glb")).unwrap();
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let gltf: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let bin = &glb[20 + json_len + 8..];
    // The three views: positions, normals (f32 VEC3), indices (u32).
    let view = |i: usize| {
        let v = &gltf["bufferViews"][i];
        let at = v["byteOffset"].as_u64().unwrap() as usize;
        &bin[at..at + v["byteLength"].as_u64().unwrap() as usize]
    };
    let floats = |b: &[u8]| -> Vec<f64> {
        b.chunks_exact(4).map(|c| f64::from(f32::from_le_bytes(c.try_into().unwrap()))).collect()
    };
    let (positions, normals) = (floats(view(0)), floats(view(1)));
    let indices: Vec<usize> =
        view(2).chunks_exact(4).map(|c| u32::from_le_bytes(c.try_into().unwrap()) as usize).collect();
    let p = |i: usize| octsolid::glam::DVec3::new(positions[3 * i], positions[3 * i + 1], positions[3 * i + 2]);
    // The OBJ's triangles, and its volume: the true surface, not the staircase.
    let triangles = indices.len() / 3;
    assert!(obj.contains(&format!("mesh       {triangles} triangles")), "{obj}");
    let volume: f64 = indices.chunks_exact(3).map(|t| p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0).sum();
    let exact = 4.0 / 3.0 * std::f64::consts::PI;
    assert!((volume / exact - 1.0).abs() < 2e-3, "{volume} enclosed, {exact} exact");
    // Smooth normals: unit, and within 5 degrees of the sphere's at every vertex.
    for (i, n) in normals.chunks_exact(3).enumerate() {
        let n = octsolid::glam::DVec3::new(n[0], n[1], n[2]);
        assert!((n.length() - 1.0).abs() < 1e-5, "vertex {i}: |n| = {}", n.length());
        assert!(n.dot(p(i).normalize()) > 5f64.to_radians().cos(), "vertex {i}: {n} at {}", p(i));
    }
    // Every command writing a .glb writes the true surface: `shape` and `convert`
    // the same triangles as `export` (the stored crossings round the vertices by a few
    // 1e-6 voxel, which may flip a nearly tied quad diagonal: the same count), and a
    // solid voxelized from an OBJ (y-up) stands without a turn.
    let of_glb = |f: &str| -> (usize, Option<Vec<f64>>) {
        let glb = std::fs::read(dir.join(f)).unwrap();
        let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
        let gltf: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
        let indices = gltf["accessors"][2]["count"].as_u64().unwrap() as usize;
        let turn: Option<Vec<f64>> =
            gltf["nodes"][0]["rotation"].as_array().map(|q| q.iter().map(|c| c.as_f64().unwrap()).collect());
        (indices / 3, turn)
    };
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "6", "-o", "direct.glb"]);
    ok(&dir, &["convert", "ball.oct", "-o", "converted.glb"]);
    let z_up = Some(vec![-std::f64::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f64::consts::FRAC_1_SQRT_2]);
    for f in ["direct.glb", "converted.glb"] {
        assert_eq!(of_glb(f), (triangles, z_up.clone()), "{f}");
    }
    let source = repo().join("models/bunny-watertight.obj");
    ok(&dir, &["voxelize", &source.to_string_lossy(), "--depth", "6", "-o", "bunny.glb"]);
    ok(&dir, &["voxelize", &source.to_string_lossy(), "--depth", "6", "-o", "bunny6.oct"]);
    let bunny = ok(&dir, &["export", "bunny6.oct", "-o", "bunny6.obj"]);
    let (bunny_triangles, turn) = of_glb("bunny.glb");
    assert!(bunny.contains(&format!("mesh       {bunny_triangles} triangles")), "{bunny}");
    assert_eq!(turn, None);
    // A sharp edge stays sharp: a box's corners are written once a face direction.
    ok(&dir, &["shape", "box", "--size", "1,1,1", "--depth", "5", "-o", "box.oct"]);
    ok(&dir, &["export", "box.oct", "-o", "box.glb"]);
    let glb = std::fs::read(dir.join("box.glb")).unwrap();
    let json_len = u32::from_le_bytes(glb[12..16].try_into().unwrap()) as usize;
    let gltf: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).unwrap();
    let bin = &glb[20 + json_len + 8..];
    let v = &gltf["bufferViews"][1];
    let at = v["byteOffset"].as_u64().unwrap() as usize;
    let normals = floats(&bin[at..at + v["byteLength"].as_u64().unwrap() as usize]);
    for n in normals.chunks_exact(3) {
        let largest = n.iter().map(|c| c.abs()).fold(0.0, f64::max);
        assert!(largest > 0.999, "a box's normal off its faces' axes: {n:?}");
    }
}

#[test]
fn ctrl_c_stops_an_export_and_writes_nothing_not_even_a_temporary() {
    use std::io::{BufRead, BufReader};
    let dir = scratch("ctrl-c");
    ok(&dir, &["shape", "sphere", "--depth", "8", "-o", "ball.oct"]);
    std::fs::write(dir.join("ball.obj"), b"kept").unwrap();
    // Interrupted once its progress shows it working (every update printed).
    let mut command = Command::new(env!("CARGO_BIN_EXE_octsolid"));
    command
        .current_dir(&dir)
        .args(["export", "ball.oct", "-o", "ball.obj", "--tolerance", "0.04"])
        .env("OCTSOLID_PROGRESS_SECONDS", "0")
        .stderr(std::process::Stdio::piped());
    // SIGINT as a terminal's foreground job has it: this suite may run as a background
    // job, whose SIGINT is ignored (and then left ignored by octsolid).
    // SAFETY: only an async-signal-safe call between fork and exec.
    unsafe {
        std::os::unix::process::CommandExt::pre_exec(&mut command, || {
            libc::signal(libc::SIGINT, libc::SIG_DFL);
            Ok(())
        });
    }
    let mut child = command.spawn().unwrap();
    let mut stderr = BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    stderr.read_line(&mut line).unwrap();
    assert!(line.contains('%'), "{line}");
    // SAFETY: signalling our own child.
    assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) }, 0);
    let mut rest = String::new();
    std::io::Read::read_to_string(&mut stderr, &mut rest).unwrap();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{rest}");
    assert!(rest.trim_end().ends_with("octsolid: interrupted; nothing written"), "{rest}");
    // The old output stands and no temporary is left beside it.
    assert_eq!(std::fs::read(dir.join("ball.obj")).unwrap(), b"kept");
    let names: Vec<String> =
        std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name().to_string_lossy().into_owned()).collect();
    assert!(names.iter().all(|n| !n.contains("octsolid-tmp")), "{names:?}");
}

#[test]
fn every_command_writing_a_mesh_writes_the_true_surface_and_refuses_a_missing_folder_first() {
    let dir = scratch("mesh-outputs");
    // `shape -o X.obj` is `shape -o X.oct` then `export`: the true surface, the same
    // triangles (the .oct's stored crossings round the vertices by a few 1e-6 voxel).
    let direct = ok(&dir, &["shape", "sphere", "--depth", "5", "-o", "ball.obj"]);
    assert!(direct.contains("crossings and normals from the shape"), "{direct}");
    ok(&dir, &["shape", "sphere", "--depth", "5", "-o", "ball.oct"]);
    ok(&dir, &["export", "ball.oct", "-o", "exported.obj"]);
    let staircase = ok(&dir, &["export", "ball.oct", "-o", "stairs.obj", "--surface", "voxels"]);
    // The OBJs' vertex and face lines as written (a reader would weld the sheets).
    let lines = |f: &str, tag: &str| -> Vec<Vec<f64>> {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        text.lines()
            .filter(|l| l.starts_with(tag))
            .map(|l| l.split_whitespace().skip(1).map(|x| x.parse().unwrap()).collect())
            .collect()
    };
    let (a, b) = (lines("ball.obj", "v "), lines("exported.obj", "v "));
    // (A quad's diagonal, chosen by its crossing, may flip where the two are nearly
    // tied: the same count.)
    assert_eq!(a.len(), b.len());
    assert_eq!(lines("ball.obj", "f ").len(), lines("exported.obj", "f ").len());
    let apart = |p: &Vec<f64>, q: &Vec<f64>| p.iter().zip(q).map(|(x, y)| (x - y).powi(2)).sum::<f64>().sqrt();
    assert!(a.iter().zip(&b).all(|(p, q)| apart(p, q) < 1e-4 * 0.065));
    let stairs = lines("stairs.obj", "f ").len();
    assert!(staircase.contains(&format!("mesh       {stairs} triangles")) && stairs != lines("ball.obj", "f ").len());
    // An output folder that does not exist is refused before any work, naming it.
    for args in [
        &["export", "ball.oct", "-o", "nodir/ball.3mf"][..],
        &["shape", "sphere", "--depth", "5", "-o", "nodir/ball.octs"],
        &["render", "ball.oct", "--size", "32x32", "-o", "nodir/ball.png"],
    ] {
        let e = fails(&dir, args);
        assert!(e.contains("the folder nodir does not exist"), "{args:?}: {e}");
    }
    // A growth past the domain is said; the result is clipped to it.
    ok(
        &dir,
        &["shape", "sphere", "--radius", "1", "--depth", "5", "--domain", "-1.05,-1.05,-1.05,2.1", "-o", "tight.oct"],
    );
    let out = octsolid(&dir, &["offset", "tight.oct", "--by", "0.3", "-o", "grown.oct"]);
    assert!(out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("the offset reaches the edge of the domain"), "{stderr}");
    // A scene `build` refuses what `render` refuses: a solid of two sources, two
    // solids of one name.
    std::fs::write(
        dir.join("two.toml"),
        "[[solid]]\nshape = { sphere = { center = [0, 0, 0], radius = 1 } }\nmesh = \"x.obj\"\n",
    )
    .unwrap();
    let e = fails(&dir, &["build", "two.toml", "-o", "two.oct"]);
    assert!(e.contains("give exactly one of shape, mesh or oct"), "{e}");
    std::fs::write(
        dir.join("same.toml"),
        "[[solid]]\nname = \"a\"\nshape = { sphere = { center = [0, 0, 0], radius = 1 } }\n\
         [[solid]]\nname = \"a\"\nshape = { sphere = { center = [0, 0, 0], radius = 2 } }\n",
    )
    .unwrap();
    let e = fails(&dir, &["build", "same.toml", "--solid", "a", "-o", "same.oct"]);
    assert!(e.contains("another solid is named 'a' too"), "{e}");
}

/// Pixels where channel `c` stands out: above twice the other two and 40.
fn dominant(img: &image::RgbImage, c: usize) -> usize {
    let stands_out = |p: &image::Rgb<u8>| {
        let v = p.0.map(u32::from);
        v[c] > 40 && (0..3).filter(|&o| o != c).all(|o| v[c] > 2 * v[o].max(4))
    };
    img.pixels().filter(|p| stands_out(p)).count()
}

#[test]
fn render_shows_a_vox_model_in_its_palette_colours() {
    let dir = scratch("vox-render");
    let axes = data("vox/axes.vox");
    ok(&dir, &["render", &axes, "--size", "160x120", "--spp", "1", "-o", "axes.png"]);
    let img = image::open(dir.join("axes.png")).unwrap().to_rgb8();
    // The palette's red x, green y and blue z (sRGB dd0000, 00aa00, 0000aa) all show.
    for c in 0..3 {
        assert!(dominant(&img, c) > 20, "channel {c}: {} pixels", dominant(&img, c));
    }
    // The same voxels as one .oct solid are drawn in the default orange: no green, no blue.
    ok(&dir, &["convert", &axes, "axes.oct"]);
    ok(&dir, &["render", "axes.oct", "--size", "160x120", "--spp", "1", "-o", "plain.png"]);
    let plain = image::open(dir.join("plain.png")).unwrap().to_rgb8();
    assert_eq!((dominant(&plain, 1), dominant(&plain, 2)), (0, 0));
    // A scene's `oct =` reads the .vox file as the union of its solids: the same
    // picture as the .oct file's.
    for (scene, file) in [("vox.toml", axes.as_str()), ("oct.toml", "axes.oct")] {
        std::fs::write(dir.join(scene), format!("[[solid]]\noct = {file:?}\n")).unwrap();
        ok(&dir, &["render", scene, "--size", "80x60", "--spp", "1", "-o", &format!("{scene}.png")]);
    }
    let [a, b] = ["vox.toml.png", "oct.toml.png"].map(|f| std::fs::read(dir.join(f)).unwrap());
    assert!(a == b, "the scene's .vox and .oct solids differ");
}

#[test]
fn vdb_and_binvox_files_of_the_reference_tools_read_as_their_makers_say() {
    let dir = scratch("vdb-binvox");
    let vdb = data("vdb/fog_and_mask.vdb");
    let shapes = read_json("vdb/shapes.json");
    // OpenVDB's own count of the fog volume's active voxels: every one of them is
    // inside at a threshold below all values; above, the changed voxels at or below the
    // threshold leave.
    let grids = &shapes["grids"]["fog_and_mask.vdb"];
    let active = grids[0]["active_voxels"].as_u64().unwrap();
    let changed: Vec<f64> =
        shapes["density"]["voxels"].as_array().unwrap().iter().map(|v| v[1].as_f64().unwrap()).collect();
    for threshold in [0.1, 0.3, 0.5, 0.65] {
        let out_file = format!("fog-{threshold}.oct");
        ok(&dir, &["convert", &vdb, &out_file, "--threshold", &threshold.to_string()]);
        let below = changed.iter().filter(|&&v| v <= threshold).count() as u64;
        assert_eq!(info_json(&dir, &out_file)["voxels"].as_u64().unwrap(), active - below, "threshold {threshold}");
    }
    // The bool grid by name: OpenVDB's active (true) voxels.
    let mask: serde_json::Value = serde_json::from_str(&ok(&dir, &["info", &vdb, "--grid", "mask", "--json"])).unwrap();
    assert_eq!(mask["voxels"], grids[1]["active_voxels"]);
    assert_eq!(mask["solids"][0]["name"], "mask");
    let e = fails(&dir, &["info", &vdb, "--grid", "nope"]);
    assert!(e.contains("fog_and_mask.vdb") && e.contains("density") && e.contains("mask"), "{e}");
    // A flag for another format is said to be ignored, and does nothing.
    let out = octsolid(&dir, &["info", &data("binvox/torus64.binvox"), "--threshold", "0.9", "--json"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("--threshold is for .vdb files"));

    // binvox: the voxel count the PyPI tool's grid had, and the world placement kept
    // (translate and scale are the domain's corner and edge).
    let binvox = read_json("binvox/shapes.json");
    for name in ["torus64.binvox", "ellipsoid50.binvox"] {
        let (want, info) = (&binvox[name], info_json(&dir, &data(&format!("binvox/{name}"))));
        assert_eq!(info["voxels"], want["voxels"], "{name}");
        assert_eq!(info["domain"]["min"], want["translate"], "{name}");
        assert_eq!(info["format"], "binvox");
    }
    let info = info_json(&dir, &data("binvox/torus64.binvox"));
    assert_eq!((info["depth"].as_u64(), info["domain"]["edge"].as_f64()), (Some(6), Some(3.0)));
    // voxelize -o writes any format: the same voxels as its .oct.
    let block = repo().join("tests/data/boundary/block-unit.obj");
    let block = block.to_str().unwrap();
    ok(&dir, &["voxelize", block, "--depth", "5", "-o", "block.oct"]);
    let want = info_json(&dir, "block.oct")["voxels"].clone();
    for ext in ["vox", "binvox", "vdb"] {
        let name = format!("block.{ext}");
        ok(&dir, &["voxelize", block, "--depth", "5", "-o", &name]);
        assert_eq!(info_json(&dir, &name)["voxels"], want, "{name}");
    }
}

#[test]
fn damaged_interchange_files_are_refused_by_name_and_place() {
    let dir = scratch("interchange-damage");
    let sources = ["vox/axes.vox", "binvox/torus64.binvox", "vdb/sphere.vdb"];
    for source in sources {
        let bytes = std::fs::read(data(source)).unwrap();
        let ext = source.rsplit('.').next().unwrap();
        let mut corrupt = bytes.clone();
        for b in corrupt.iter_mut().skip(8).step_by(97) {
            *b ^= 0xa5;
        }
        let mut rng = common::Rng(0x5eed);
        let random: Vec<u8> = (0..4096).map(|_| (rng.next() >> 33) as u8).collect();
        let cases = [
            ("truncated", bytes[..bytes.len() / 3].to_vec()),
            ("corrupt", corrupt),
            ("random", random),
            ("empty", Vec::new()),
        ];
        for (kind, damaged) in cases {
            let name = format!("{kind}.{ext}");
            std::fs::write(dir.join(&name), &damaged).unwrap();
            for command in [&["convert", &name, "out.oct"][..], &["info", &name], &["render", &name, "-o", "r.png"]] {
                let out = octsolid(&dir, command);
                let stderr = String::from_utf8_lossy(&out.stderr);
                assert!(!stderr.contains("panicked"), "{command:?}: {stderr}");
                if out.status.success() {
                    // A flipped byte may land in a voxel's value: still a solid file.
                    assert_eq!(kind, "corrupt", "{command:?} read a {kind} file");
                    continue;
                }
                assert_eq!(stderr.trim().lines().count(), 1, "{stderr}");
                assert!(stderr.contains(&name), "{command:?}: {stderr}");
                assert!(stderr.contains("byte") || stderr.contains("chunk"), "{command:?}: no place: {stderr}");
            }
            assert!(!dir.join("out.oct").exists() || kind == "corrupt");
        }
    }
    // dot_vox's sample of a file that is not a .vox file.
    let e = fails(&dir, &["convert", &data("vox/not_a.vox"), "n.oct"]);
    assert!(e.contains("not_a.vox: byte 0: not a MagicaVoxel file"), "{e}");
    // A header's claim is checked against the budget before anything is allocated.
    let e = fails(&dir, &["--memory-budget", "4KiB", "convert", &data("vox/axes.vox"), "a.oct"]);
    assert!(e.contains("axes.vox") && e.contains("memory budget"), "{e}");
}

/// A closed room (depth 5) with an emissive lamp, as a scene file; `emission` the lamp's.
fn room_scene(emission: f64) -> String {
    format!(
        r#"
[image]
size = [48, 48]
samples = 1
[domain]
min = [-1, -1, -1]
edge = 2
depth = 5
[camera]
eye = [0, -0.4, 0]
target = [0, 0.5, 0]
fov = 80
[[solid]]
name = "room"
material = {{ color = [0.7, 0.5, 0.3], kd = 1 }}
shape = {{ difference = [ {{ box = {{ center = [0, 0, 0], size = [1.75, 1.75, 1.75] }} }}, {{ box = {{ center = [0, 0, 0], size = [1, 1, 1] }} }} ] }}
[[solid]]
name = "lamp"
material = {{ color = [0.5, 0.5, 0.5], kd = 1, emission = [{emission}, {emission}, {emission}] }}
shape = {{ box = {{ center = [0, 0, 0.45], size = [0.25, 0.25, 0.0625] }} }}
"#
    )
}

#[test]
fn radiosity_gathers_by_gauss_seidel_and_agrees_with_shooting() {
    let dir = scratch("gathering");
    std::fs::write(dir.join("room.toml"), room_scene(4.0)).unwrap();
    let solve = |solver: &str, out: &str| -> serde_json::Value {
        let args = ["radiosity", "room.toml", "--solver", solver, "--until", "1e-4", "-o", out, "--json"];
        serde_json::from_str(&ok(&dir, &args)).unwrap()
    };
    let gathered = solve("gathering", "g.rad");
    assert_eq!(gathered["solver"], "gathering");
    assert!(gathered["iterations"].as_u64().unwrap() >= 1 && gathered["residual"].as_f64().unwrap() <= 1e-6);
    let shot = solve("shooting", "s.rad");
    assert_eq!((shot["solver"].as_str(), shot["iterations"].as_u64()), (Some("shooting"), Some(0)));
    // Both solutions render to nearly the same picture.
    let picture = |rad: &str, png: &str| {
        ok(&dir, &["render", "room.toml", "--radiosity", rad, "--size", "40x30", "--no-cache", "-o", png]);
        image::open(dir.join(png)).unwrap().to_rgb8()
    };
    let (g, s) = (picture("g.rad", "g.png"), picture("s.rad", "s.png"));
    let worst = g.pixels().zip(s.pixels()).flat_map(|(a, b)| (0..3).map(move |c| a[c].abs_diff(b[c]))).max().unwrap();
    assert!(worst <= 3, "the pictures differ by up to {worst} of 255");
    let text = ok(&dir, &["radiosity", "room.toml", "--solver", "gathering", "-o", "t.rad"]);
    assert!(text.contains("Gauss-Seidel iterations, residual"), "{text}");
    let e = String::from_utf8_lossy(
        &octsolid(&dir, &["radiosity", "room.toml", "--solver", "gathering", "--max-shots", "3", "-o", "x.rad"]).stderr,
    )
    .into_owned();
    assert!(e.contains("--max-shots"), "{e}");
    let tight = ["--memory-budget", "64KiB", "radiosity", "room.toml", "--solver", "gathering", "-o", "x.rad"];
    let e = String::from_utf8_lossy(&octsolid(&dir, &tight).stderr).into_owned();
    assert!(e.contains("form-factor matrix") || e.contains("budget"), "{e}");
}

#[test]
fn render_meshes_by_the_depth_sort_the_z_buffer_and_the_scan_line() {
    let dir = scratch("mesh-methods");
    let spot = repo().join("models/spot.obj");
    let mut pictures = Vec::new();
    for method in ["painter", "zbuffer", "scanline"] {
        let png = format!("spot_{method}.png");
        let out = ok(
            &dir,
            &[
                "render",
                spot.to_str().unwrap(),
                "--shading",
                "phong",
                "--method",
                method,
                "--size",
                "80x60",
                "-o",
                &png,
            ],
        );
        assert!(out.contains(&format!("by {method}")), "{out}");
        assert_eq!(out.contains("pairs settled by x extents"), method == "painter", "{out}");
        pictures.push(image::open(dir.join(&png)).unwrap().to_rgb8());
    }
    // The same picture but where two triangles meet within rounding.
    for other in &pictures[1..] {
        let differ = pictures[0].pixels().zip(other.pixels()).filter(|(a, b)| a != b).count();
        assert!(differ <= 10, "{differ} pixels differ");
    }
    let bad =
        octsolid(&dir, &["render", spot.to_str().unwrap(), "--shading", "flat", "--method", "trace", "-o", "x.png"]);
    assert!(!bad.status.success() && String::from_utf8_lossy(&bad.stderr).contains("painter, zbuffer or scanline"));
}

#[test]
fn radiosity_solves_saves_and_renders_from_any_camera() {
    let dir = scratch("radiosity");
    std::fs::write(dir.join("room.toml"), room_scene(4.0)).unwrap();
    std::fs::write(dir.join("other.toml"), room_scene(5.0)).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&ok(&dir, &["radiosity", "room.toml", "-o", "room.rad", "--json"])).unwrap();
    let keys: Vec<&str> = json.as_object().unwrap().keys().map(String::as_str).collect();
    assert_eq!(keys.len(), 8, "{json}");
    for key in ["solver", "patches", "elements", "shots", "unshot_fraction", "iterations", "residual", "seconds"] {
        assert!(json.get(key).is_some(), "missing {key}: {json}");
    }
    assert!(json["unshot_fraction"].as_f64().unwrap() <= 0.01);
    assert!(json["elements"].as_u64().unwrap() > json["patches"].as_u64().unwrap());
    let capped: serde_json::Value =
        serde_json::from_str(&ok(&dir, &["radiosity", "room.toml", "-o", "capped.rad", "--max-shots", "3", "--json"]))
            .unwrap();
    assert_eq!(capped["shots"], 3);
    assert!(capped["unshot_fraction"].as_f64().unwrap() > 0.01);
    // Adaptive subdivision: more elements where the light changes, and a solution that
    // renders like any other.
    let count = |extra: &[&str]| -> u64 {
        let args = [&["radiosity", "room.toml", "--patch-size", "0.5", "--json"][..], extra].concat();
        let json: serde_json::Value = serde_json::from_str(&ok(&dir, &args)).unwrap();
        json["elements"].as_u64().unwrap()
    };
    let (base, subdivided) = (count(&["-o", "base.rad"]), count(&["-o", "sub.rad", "--subdivide", "0.3"]));
    assert!(subdivided > base, "{subdivided} against {base} elements");
    let capped = count(&["-o", "capped-sub.rad", "--subdivide", "0.3", "--max-elements", &(base + 30).to_string()]);
    assert!(capped > base && capped <= base + 30, "{capped} elements, at most {}", base + 30);
    ok(&dir, &["render", "room.toml", "--radiosity", "sub.rad", "-o", "sub.png"]);
    let out = ok(&dir, &["render", "room.toml", "--illumination", "radiosity", "--subdivide", "0.3", "-o", "x.png"]);
    assert!(out.contains("radiosity:"), "{out}");
    let e = fails(&dir, &["render", "room.toml", "--subdivide", "0.3", "-o", "x.png"]);
    assert!(e.contains("--subdivide"), "{e}");
    let e = fails(&dir, &["radiosity", "room.toml", "-o", "x.rad", "--subdivide", "0"]);
    assert!(e.contains("subdivision threshold"), "{e}");
    // A saved solution and one solved on the spot give the same picture.
    ok(&dir, &["render", "room.toml", "--radiosity", "room.rad", "-o", "saved.png"]);
    ok(&dir, &["render", "room.toml", "--illumination", "radiosity", "-o", "solved.png"]);
    assert_eq!(std::fs::read(dir.join("saved.png")).unwrap(), std::fs::read(dir.join("solved.png")).unwrap());
    // Another camera: other pixels.
    ok(
        &dir,
        &["render", "room.toml", "--radiosity", "room.rad", "--eye", "0.3,0.3,-0.3", "--target", "-0.5,-0.5,0.5"]
            .into_iter()
            .chain(["--fov", "60", "-o", "turned.png"])
            .collect::<Vec<_>>(),
    );
    assert_ne!(std::fs::read(dir.join("saved.png")).unwrap(), std::fs::read(dir.join("turned.png")).unwrap());
    // The elements picture: flat elements with their borders, another picture.
    ok(&dir, &["render", "room.toml", "--radiosity", "room.rad", "--show-elements", "-o", "elements.png"]);
    assert_ne!(std::fs::read(dir.join("saved.png")).unwrap(), std::fs::read(dir.join("elements.png")).unwrap());
    let e = fails(&dir, &["render", "room.toml", "--show-elements", "-o", "x.png"]);
    assert!(e.contains("--show-elements"), "{e}");
    // Refused: another scene's solution, a damaged one, and direct with a solution.
    let e = fails(&dir, &["render", "other.toml", "--radiosity", "room.rad", "-o", "x.png"]);
    assert!(e.contains("room.rad") && e.contains("another scene"), "{e}");
    let mut bytes = std::fs::read(dir.join("room.rad")).unwrap();
    let middle = bytes.len() / 2;
    bytes[middle] ^= 0x40;
    std::fs::write(dir.join("damaged.rad"), bytes).unwrap();
    let e = fails(&dir, &["render", "room.toml", "--radiosity", "damaged.rad", "-o", "x.png"]);
    assert!(e.contains("damaged.rad") && e.contains("checksum"), "{e}");
    let e = fails(&dir, &["render", "room.toml", "--radiosity", "room.rad", "--illumination", "direct"]);
    assert!(e.contains("--radiosity"), "{e}");
    let e = fails(&dir, &["radiosity", "room.toml", "-o", "room.png"]);
    assert!(e.contains("room.png"), "{e}");
    let e = fails(&dir, &["radiosity", "room.rad", "-o", "again.rad"]);
    assert!(e.contains("room.rad") && e.contains("toml"), "{e}");
}

#[test]
fn sharded_solids_made_combined_converted_and_read_by_every_command() {
    let dir = scratch("sharded");
    let scene = repo().join("scenes/large_part.toml");
    let scene = scene.to_str().unwrap();
    // Built cell by cell (--depth overrides the scene's), and whole for comparison.
    for (solid, level) in [("body", "2"), ("bores", "1")] {
        let octs = format!("{solid}.octs");
        let out = ok(&dir, &["build", scene, "--solid", solid, "--depth", "7", "--shard-level", level, "-o", &octs]);
        assert!(out.contains("shards") && out.contains("peak mem."), "{out}");
        ok(&dir, &["build", scene, "--solid", solid, "--depth", "7", "-o", &format!("{solid}.oct")]);
    }
    // `info` of a sharded solid: its index, the same counts and bounds as the file's.
    let sharded = info_json(&dir, "body.octs");
    let single = info_json(&dir, "body.oct");
    for key in ["depth", "domain", "nodes", "voxels", "bounds"] {
        assert_eq!(sharded[key], single[key], "{key}");
    }
    assert_eq!((sharded["format"].as_str(), sharded["shard_level"].as_u64()), (Some("octs"), Some(2)));
    assert!(sharded["shards"].as_u64().unwrap() > 1);
    // A set operation merged cell by cell, against the one in memory.
    ok(&dir, &["csg", "difference", "body.octs", "bores.octs", "-o", "part.octs"]);
    ok(&dir, &["csg", "difference", "body.oct", "bores.oct", "-o", "part.oct"]);
    ok(&dir, &["convert", "part.octs", "back.oct"]);
    let read = |f: &str| std::fs::read(dir.join(f)).unwrap();
    // Shards carry no surface data: the solid's bytes, without part.oct's surface section.
    let solid = |f: &str| {
        let (tree, meta) =
            octsolid::io::oct::read_and_metadata(dir.join(f), octsolid::MemoryBudget::unlimited()).unwrap();
        octsolid::io::oct::encode_with(&tree, &meta)
    };
    assert_eq!(read("back.oct"), solid("part.oct"), "the sharded difference is the in-memory one");
    // One file into shards and back: the same bytes.
    ok(&dir, &["convert", "part.oct", "cut.octs", "--shard-level", "3"]);
    ok(&dir, &["convert", "cut.octs", "again.oct"]);
    assert_eq!(read("again.oct"), solid("part.oct"));
    // Tasks over ranges of cells, then the join: the same folder.
    for cells in ["0..100", "100..512"] {
        let out = ok(
            &dir,
            &[
                "build",
                scene,
                "--solid",
                "body",
                "--depth",
                "7",
                "--shard-level",
                "3",
                "--cells",
                cells,
                "-o",
                "tasks.octs",
            ],
        );
        assert!(out.contains("wrote a part"), "{out}");
    }
    ok(&dir, &["join", "tasks.octs"]);
    ok(&dir, &["build", scene, "--solid", "body", "--depth", "7", "--shard-level", "3", "-o", "one.octs"]);
    for entry in std::fs::read_dir(dir.join("one.octs")).unwrap() {
        let name = entry.unwrap().file_name();
        assert_eq!(
            read(&format!("tasks.octs/{}", name.to_string_lossy())),
            read(&format!("one.octs/{}", name.to_string_lossy()))
        );
    }
    // Drawn and sliced like any solid.
    ok(&dir, &["render", "part.octs", "-o", "part.png", "--size", "64x48", "--spp", "1"]);
    ok(&dir, &["slice", "part.octs", "--axis", "z", "--at", "0", "-o", "slice.png"]);
    // Errors: a flag for another output, a missing part, a damaged shard (named).
    assert!(
        fails(&dir, &["build", scene, "--solid", "body", "--shard-level", "2", "-o", "x.oct"])
            .contains("--shard-level")
    );
    ok(
        &dir,
        &["build", scene, "--solid", "body", "--depth", "7", "--shard-level", "3", "--cells", "0..7", "-o", "gap.octs"],
    );
    assert!(fails(&dir, &["join", "gap.octs"]).contains("no part covers cells 7..512"));
    let shard = std::fs::read_dir(dir.join("part.octs"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .find(|n| n.ends_with(".oct"))
        .unwrap();
    let mut bytes = read(&format!("part.octs/{shard}"));
    bytes[90] ^= 0xff;
    std::fs::write(dir.join("part.octs").join(&shard), bytes).unwrap();
    assert!(fails(&dir, &["convert", "part.octs", "broken.oct"]).contains(&shard));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `export BIG.octs`: cell by cell, the same triangles as the single file's export,
/// smooth and as the staircase in unit faces; what it cannot stream is refused.
#[test]
fn a_sharded_solid_exports_cell_by_cell_the_triangles_of_its_single_file() {
    let dir = scratch("sharded-export");
    let shape = ["shape", "torus", "--radius", "0.7", "--tube", "0.25", "--center", "0.03,0.01,-0.02", "--depth", "6"];
    ok(&dir, &[&shape[..], &["--shard-level", "2", "-o", "t.octs"]].concat());
    ok(&dir, &[&shape[..], &["-o", "t.oct"]].concat());
    let out = ok(&dir, &["export", "t.octs", "-o", "cells.stl"]);
    assert!(out.contains("cell by cell") && out.contains("seams") && out.contains("exact crossings"), "{out}");
    ok(&dir, &["export", "t.oct", "-o", "whole.stl"]);
    assert!(stl_triangles(&dir.join("cells.stl")) == stl_triangles(&dir.join("whole.stl")));
    ok(&dir, &["export", "t.octs", "-o", "cells-v.stl", "--surface", "voxels", "--unit-faces"]);
    ok(&dir, &["export", "t.oct", "-o", "whole-v.stl", "--surface", "voxels", "--unit-faces"]);
    assert!(stl_triangles(&dir.join("cells-v.stl")) == stl_triangles(&dir.join("whole-v.stl")));
    assert!(fails(&dir, &["export", "t.octs", "-o", "t.ply"]).contains(".stl or .obj"));
    assert!(fails(&dir, &["export", "t.octs", "-o", "t.stl", "--tolerance", "0.5"]).contains("cell by cell"));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `--voxel-size S`: the domain's lattice on the multiples of S, so a box and a mesh
/// whose faces lie on them keep their dimensions; `info` reports the voxel's edge; a
/// depth too small for the grid, or a voxel size with a domain, is refused.
#[test]
fn voxel_size_keeps_round_dimensions_exact() {
    let dir = scratch("voxel-size");
    ok(&dir, &["shape", "box", "--size", "80,40,30", "--center", "40,20,15", "--voxel-size", "0.5", "-o", "b.oct"]);
    let info = info_json(&dir, "b.oct");
    let v = |key: &str, i: usize| info["bounds"][key][i].as_f64().unwrap();
    assert_eq!(
        [v("min", 0), v("min", 1), v("min", 2), v("max", 0), v("max", 1), v("max", 2)],
        [0.0, 0.0, 0.0, 80.0, 40.0, 30.0]
    );
    assert_eq!(info["domain"]["voxel_size"].as_f64(), Some(0.5));
    assert_eq!(info["volume"].as_f64(), Some(96_000.0));
    // The same box as a mesh (OBJ), voxelized on the grid.
    let obj = "v 0 0 0\nv 80 0 0\nv 80 40 0\nv 0 40 0\nv 0 0 30\nv 80 0 30\nv 80 40 30\nv 0 40 30\n\
               f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
    std::fs::write(dir.join("b.obj"), obj).unwrap();
    ok(&dir, &["voxelize", "b.obj", "--voxel-size", "2", "-o", "m.oct"]);
    let mesh = info_json(&dir, "m.oct");
    assert_eq!(mesh["volume"].as_f64(), Some(96_000.0));
    assert_eq!(mesh["domain"]["voxel_size"].as_f64(), Some(2.0));
    let e = fails(&dir, &["shape", "box", "--size", "80,40,30", "--voxel-size", "0.1", "--depth", "8", "-o", "x.oct"]);
    assert!(e.contains("use depth 10 or more"), "{e}");
    let out = octsolid(&dir, &["shape", "box", "--voxel-size", "0.5", "--domain", "0,0,0,100", "-o", "x.oct"]);
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("cannot be used with"));
}

/// A mesh that encloses nothing (a flat polygon) voxelizes to an empty solid with a
/// warning that names the file and suggests a surface; an open mesh reports no volume
/// of its own (its signed sum measured nothing), and what bounds nothing is counted.
#[test]
fn voxelizing_a_mesh_that_encloses_nothing_warns_and_an_open_mesh_reports_no_volume() {
    let dir = scratch("encloses-nothing");
    let square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n";
    std::fs::write(dir.join("flat.obj"), square).unwrap();
    let out = octsolid(&dir, &["voxelize", "flat.obj", "--depth", "6", "-o", "flat.oct"]);
    assert!(out.status.success());
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    assert!(stderr.contains("flat.obj: the solid is empty") && stderr.contains("--fill surface"), "{stderr}");
    assert!(stdout.contains("mesh vol.  none: the mesh is open"), "{stdout}");
    let revisits = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1\nf 1 2 3 1 2 3 1 2 4 3 1 2 3 4\n";
    std::fs::write(dir.join("revisits.obj"), revisits).unwrap();
    let stdout = ok(&dir, &["voxelize", "revisits.obj", "--depth", "6", "-o", "r.oct"]);
    assert!(stdout.contains("left out") && stdout.contains("bound nothing"), "{stdout}");
}

/// A mesh of one point-sized triangle gets a domain (the unit cube around the point),
/// not an error about an edge of 1e-308: its surface is the voxels at the point.
#[test]
fn a_point_sized_mesh_voxelizes_round_its_point() {
    let dir = scratch("point-mesh");
    std::fs::write(dir.join("point.obj"), "v 3 4 5\nv 3 4 5\nv 3 4 5\nf 1 2 3\n").unwrap();
    ok(&dir, &["voxelize", "point.obj", "--depth", "6", "--fill", "surface", "-o", "p.oct"]);
    let info = info_json(&dir, "p.oct");
    assert_eq!(info["domain"]["edge"].as_f64(), Some(1.0));
    let b = |k: &str, i: usize| info["bounds"][k][i].as_f64().unwrap();
    assert!((0..3).all(|i| b("min", i) <= [3.0, 4.0, 5.0][i] && b("max", i) >= [3.0, 4.0, 5.0][i]), "{info}");
    assert!(info["voxels"].as_u64().unwrap() <= 8);
}

/// Every subcommand's help ends with an example of itself, and a command line clap
/// refuses is one line with status 2.
#[test]
fn every_subcommand_shows_an_example_and_usage_errors_are_one_line() {
    let dir = scratch("help");
    let subcommands = [
        "shape",
        "csg",
        "build",
        "transform",
        "info",
        "join",
        "convert",
        "slice",
        "voxelize",
        "export",
        "mesh-info",
        "render",
        "view",
        "radiosity",
        "bench",
        "demo",
    ];
    for sub in subcommands {
        let help = ok(&dir, &[sub, "--help"]);
        let example = help.split("Example").nth(1).unwrap_or_else(|| panic!("{sub} --help has no example"));
        assert!(example.contains(&format!("octsolid {sub}")), "{sub}: {example}");
    }
    for args in [&["render", "--method", "foo", "x.oct"][..], &["nosuch"], &["shape", "box", "--radius"]] {
        let out = octsolid(&dir, args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
        assert_eq!(stderr.trim().lines().count(), 1, "{args:?}: {stderr}");
        assert!(stderr.starts_with("octsolid: error: ") && !stderr.contains("panicked"), "{stderr}");
    }
}

/// `--front -z` turns the named views about the up axis: Spot's front (it faces -z)
/// is what the y-up convention's back view showed, byte for byte; across the up axis
/// it is refused.
#[test]
fn front_turns_the_named_views_to_a_models_face() {
    let dir = scratch("front");
    let spot = repo().join("models/spot.obj");
    let spot = spot.to_str().unwrap();
    let render = |extra: &[&str], out: &str| {
        let args: Vec<&str> = ["render", spot, "--depth", "6", "--size", "64x48", "--spp", "1"]
            .iter()
            .chain(extra)
            .copied()
            .chain(["-o", out])
            .collect();
        ok(&dir, &args);
        std::fs::read(dir.join(out)).unwrap()
    };
    assert!(render(&["--front", "-z", "--view", "front"], "a.png") == render(&["--view", "back"], "b.png"));
    assert!(render(&["--front", "-z", "--view", "left"], "c.png") == render(&["--view", "right"], "d.png"));
    let e = fails(&dir, &["render", spot, "--front", "y", "-o", "e.png"]);
    assert!(e.contains("--front must lie across the up axis"), "{e}");
}

/// `csg`'s memory budget is the whole job's, not each file's: four operands that each
/// fit it alone but not together are refused, saying so; with room for all four and
/// their result the output is the library's union of the four.
#[test]
fn csg_budget_is_for_the_whole_job() {
    use octsolid::MemoryBudget;
    use octsolid::octree::{LinearOctree, SetOp};
    let dir = scratch("csg-job-budget");
    let names: Vec<String> = (0..4).map(|i| format!("s{i}.oct")).collect();
    for (i, name) in names.iter().enumerate() {
        let center = format!("0.{i},0,0");
        let args = ["shape", "sphere", "--depth", "8", "--domain=-2,-2,-2,4", "--radius", "1.5", "--center", &center];
        ok(&dir, &[&args[..], &["-o", name]].concat());
    }
    // Each operand holds its tree and the surface data its file carries.
    let files: Vec<_> = names
        .iter()
        .map(|n| octsolid::io::oct::read_and_surface(dir.join(n), MemoryBudget::unlimited()).unwrap())
        .collect();
    let held: Vec<u64> =
        files.iter().map(|(t, _, s)| (t.bytes() + s.as_ref().map_or(0, |s| s.bytes())) as u64).collect();
    let trees: Vec<LinearOctree> = files.into_iter().map(|(t, _, _)| t).collect();
    let largest = held.iter().copied().max().unwrap();
    let all: u64 = held.iter().sum();
    let csg = |budget: u64| -> Vec<String> {
        let mut args: Vec<String> = vec!["--memory-budget".into(), format!("{budget}B"), "csg".into(), "union".into()];
        args.extend(names.iter().cloned());
        args.extend(["-o".into(), "u.oct".into()]);
        args
    };
    let args = csg(largest * 3 / 2);
    let e = fails(&dir, &args.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(e.contains("whole job") && e.contains("needs an estimated"), "{e}");
    assert!(!dir.join("u.oct").exists());
    let args = csg(2 * all + (1 << 20));
    ok(&dir, &args.iter().map(String::as_str).collect::<Vec<_>>());
    let union = LinearOctree::combine_all(&trees.iter().collect::<Vec<_>>(), SetOp::Union).unwrap();
    let pairwise = trees.iter().skip(1).fold(trees[0].clone(), |a, t| &a | t);
    assert_eq!(union, pairwise);
    assert_eq!(octsolid::io::oct::read(dir.join("u.oct"), MemoryBudget::unlimited()).unwrap(), union);
}

/// `octsolid::quick` is `octsolid render x.oct` without flags: the same bytes.
#[test]
fn quick_writes_the_bytes_render_writes_for_the_same_solid() {
    use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
    use octsolid::shape::{Cuboid, Sphere};
    let dir = scratch("quick-as-render");
    let domain = Domain::new(glam::DVec3::splat(-1.0), 2.0, 7).unwrap();
    let shape = Cuboid::new(glam::DVec3::new(-0.8, -0.5, -0.3), glam::DVec3::new(0.8, 0.5, 0.3)).unwrap()
        - Sphere::new(glam::DVec3::new(0.2, -0.1, 0.3), 0.4).unwrap();
    let solid = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
    octsolid::io::oct::write(&solid, dir.join("x.oct")).unwrap();
    let stats = octsolid::quick(&solid, dir.join("quick.png")).unwrap();
    assert!(stats.hits > 0, "{stats:?}");
    ok(&dir, &["render", "x.oct", "-o", "cli.png"]);
    let (quick, cli) = (std::fs::read(dir.join("quick.png")).unwrap(), std::fs::read(dir.join("cli.png")).unwrap());
    assert!(quick == cli, "quick wrote {} bytes, render {}: they differ", quick.len(), cli.len());
}

/// What `Drawing::open` draws with a request and overrides, written to `path`.
fn draw(
    input: &Path,
    request: &octsolid::render::CameraRequest,
    overrides: &octsolid::render::RenderOverrides,
    path: &Path,
) {
    use octsolid::{Drawing, DrawingOptions, MemoryBudget, NoProgress};
    let drawing = Drawing::open(input, &DrawingOptions::default()).unwrap();
    assert!(drawing.warnings().is_empty(), "{:?}", drawing.warnings());
    let camera = drawing.camera(request, overrides, None).unwrap();
    let options = drawing.options(overrides, MemoryBudget::default());
    let scene = drawing.into_scene(None);
    let (picture, stats) = octsolid::render::render_picture(&scene, &camera, &options, &NoProgress).unwrap();
    assert!(stats.hits > 0, "{stats:?}");
    octsolid::io::write_picture(&picture, path).unwrap();
}

/// `Drawing::open` on a bundled scene and on a solid file, with a camera request and
/// overrides, draws the bytes `octsolid render` writes with the same flags.
#[test]
fn a_drawing_renders_the_bytes_render_writes_with_the_same_flags() {
    use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
    use octsolid::render::{CameraRequest, RenderOverrides};
    use octsolid::shape::{Axis, Cylinder, Sphere};
    let dir = scratch("drawing-as-render");
    let overrides = RenderOverrides { size: Some([96, 72]), spp: Some(1), ..RenderOverrides::default() };
    let request = CameraRequest { azimuth: Some(30.0), elevation: Some(20.0), ..CameraRequest::default() };
    let flags = ["--size", "96x72", "--spp", "1", "--azimuth", "30", "--elevation", "20"];
    let same = |a: &str, b: &str| {
        let (a, b) = (std::fs::read(dir.join(a)).unwrap(), std::fs::read(dir.join(b)).unwrap());
        assert!(a == b, "the drawing wrote {} bytes, render {}: they differ", a.len(), b.len());
    };

    let scene = repo().join("scenes/classic.toml");
    draw(&scene, &request, &overrides, &dir.join("scene-lib.png"));
    let scene_arg = scene.to_str().unwrap();
    ok(&dir, &[&["render", scene_arg, "--no-cache", "-o", "scene-cli.png"][..], &flags].concat());
    same("scene-lib.png", "scene-cli.png");

    let domain = Domain::new(glam::DVec3::splat(-1.0), 2.0, 7).unwrap();
    let shape =
        Sphere::new(glam::DVec3::ZERO, 0.7).unwrap() - Cylinder::new(glam::DVec3::ZERO, Axis::Z, 0.3, 2.0).unwrap();
    let solid = voxelize(&shape, domain, &VoxelizeOptions::default()).unwrap();
    octsolid::io::oct::write(&solid, dir.join("x.oct")).unwrap();
    draw(&dir.join("x.oct"), &request, &overrides, &dir.join("solid-lib.png"));
    ok(&dir, &[&["render", "x.oct", "-o", "solid-cli.png"][..], &flags].concat());
    same("solid-lib.png", "solid-cli.png");
}

/// `Drawing::open` refuses a file it cannot draw with an error naming the file.
#[test]
fn a_drawing_that_cannot_open_names_the_file() {
    use octsolid::octree::{Domain, LinearOctree};
    use octsolid::{Drawing, DrawingOptions, Error};
    let dir = scratch("drawing-errors");
    let open = |name: &str| match Drawing::open(dir.join(name), &DrawingOptions::default()) {
        Ok(_) => panic!("{name} opened"),
        Err(e) => e,
    };
    let e = open("missing.oct");
    assert!(matches!(&e, Error::Io { path, .. } if path.ends_with("missing.oct")), "{e}");
    let e = open("notes.txt");
    assert!(matches!(&e, Error::UnknownExtension { .. }) && e.to_string().contains("notes.txt"), "{e}");
    let empty = LinearOctree::empty(Domain::new(glam::DVec3::ZERO, 1.0, 4).unwrap());
    octsolid::io::oct::write(&empty, dir.join("empty.oct")).unwrap();
    let e = open("empty.oct");
    assert!(matches!(&e, Error::Undrawable { .. }), "{e:?}");
    assert_eq!(e.to_string(), format!("{}: the solid is empty", dir.join("empty.oct").display()));
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    let e = open("bad.obj");
    assert!(e.to_string().starts_with(&dir.join("bad.obj").display().to_string()), "{e}");
}

/// `octsolid hull IN -o OUT` (issue 39): the hull of two separate boxes is the box
/// around both (their corners' hull), through `.oct` and `.binvox` alike.
#[test]
fn hull_of_a_solid_file_round_trips_through_formats() {
    let dir = scratch("hull");
    let domain = "0,0,0,4";
    ok(
        &dir,
        &["shape", "box", "--center", "1,1,1", "--size", "1,1,1", "--depth", "5", "--domain", domain, "-o", "a.oct"],
    );
    ok(
        &dir,
        &["shape", "box", "--center", "3,3,3", "--size", "1,1,1", "--depth", "5", "--domain", domain, "-o", "b.oct"],
    );
    ok(&dir, &["csg", "union", "a.oct", "b.oct", "-o", "two.oct"]);
    let out = ok(&dir, &["hull", "two.oct", "-o", "hull.oct"]);
    assert!(out.contains("wrote hull.oct"), "{out}");
    // The hull of the cubes [0.5, 1.5]^3 and [2.5, 3.5]^3: the cube minus two
    // corner prisms; its voxels are counted here by the planes x - y <= 1 and
    // the like, at the centres of the 32^3 lattice.
    let mut want = 0u64;
    for x in 0..32 {
        for y in 0..32 {
            for z in 0..32 {
                let c = [x, y, z].map(|v| (f64::from(v) + 0.5) / 8.0);
                let in_box = c.iter().all(|&v| (0.5..=3.5).contains(&v));
                let near = (0..3).all(|i| (0..3).all(|j| c[i] - c[j] <= 1.0));
                want += u64::from(in_box && near);
            }
        }
    }
    let info = info_json(&dir, "hull.oct");
    assert_eq!(info["voxels"].as_u64(), Some(want), "{info}");
    ok(&dir, &["hull", "two.oct", "-o", "hull.binvox"]);
    assert_eq!(info_json(&dir, "hull.binvox")["voxels"].as_u64(), Some(want));
    fails(&dir, &["hull", "missing.oct", "-o", "x.oct"]);
}

#[test]
fn a_shell_of_a_ball_with_surface_data_exports_a_true_wall() {
    // Issue 39, point 5: `shell --thickness 2` of a ball of radius 20 (a voxel of
    // 0.31 mm) measured on the exported mesh: its inner sheet at radius 18, not half a
    // voxel inside it as the staircase would put it.
    let dir = scratch("shell-wall");
    ok(&dir, &["shape", "sphere", "--radius", "20", "--depth", "7", "-o", "ball.oct"]);
    ok(&dir, &["shell", "ball.oct", "--thickness", "2", "-o", "wall.oct"]);
    ok(&dir, &["export", "wall.oct", "-o", "wall.obj"]);
    let obj = std::fs::read_to_string(dir.join("wall.obj")).unwrap();
    let radii: Vec<f64> = obj
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| l.split_whitespace().map(|c| c.parse::<f64>().unwrap()).map(|c| c * c).sum::<f64>().sqrt())
        .collect();
    let mean = |sheet: Vec<f64>| sheet.iter().sum::<f64>() / sheet.len() as f64;
    let inner = mean(radii.iter().copied().filter(|&r| r < 19.0).collect());
    let outer = mean(radii.iter().copied().filter(|&r| r >= 19.0).collect());
    assert!((outer - 20.0).abs() < 0.03, "outer sheet at {outer}");
    assert!((outer - inner - 2.0).abs() < 0.03, "wall {} mm thick", outer - inner);
}

#[test]
fn a_scenes_round_of_a_shell_is_the_shape_shell_and_round_commands_voxel_for_voxel() {
    // Issue 39, point 2: `round(shell(part, T), R)` as scene nodes against the commands
    // run one after the other on the files.
    let dir = scratch("offset-nodes");
    let scene = "[domain]\ndepth = 6\n[[solid]]\nshape = { round = { solid = { shell = { solid = { box = { center = \
                 [0, 0, 0], size = [4, 4, 4] } }, thickness = 1.0 } }, radius = 0.25 } }\n";
    std::fs::write(dir.join("part.toml"), scene).unwrap();
    let built = ok(&dir, &["build", "part.toml", "-o", "scene.oct"]);
    assert!(built.contains("offsets, shells and rounds at depth 6"), "{built}");
    ok(&dir, &["shape", "box", "--size", "4,4,4", "--depth", "6", "-o", "box.oct"]);
    ok(&dir, &["shell", "box.oct", "--thickness", "1.0", "-o", "wall.oct"]);
    ok(&dir, &["round", "wall.oct", "--radius", "0.25", "-o", "round.oct"]);
    let read = |f: &str| octsolid::io::oct::read(dir.join(f), octsolid::MemoryBudget::default()).unwrap();
    let (scene, commands) = (read("scene.oct"), read("round.oct"));
    assert_eq!(scene.domain(), commands.domain());
    assert!(scene.voxel_count() > 0 && scene.keys() == commands.keys());
    // Neither a plain box nor its shell: the operations were applied.
    assert!(scene.keys() != read("wall.oct").keys() && scene.keys() != read("box.oct").keys());
}

#[test]
fn offsets_over_the_memory_budget_are_refused_with_the_estimate_and_the_budget() {
    // Issue 39, point 1: `--memory-budget` honoured with an estimate before work.
    let dir = scratch("offset-budget");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "7", "-o", "ball.oct"]);
    for op in [
        &["offset", "ball.oct", "--by", "0.2"][..],
        &["shell", "ball.oct", "--thickness", "0.2"],
        &["round", "ball.oct", "--radius", "0.2"],
    ] {
        let mut args = vec!["--memory-budget", "3MiB"];
        args.extend_from_slice(op);
        args.extend_from_slice(&["-o", "out.oct"]);
        let e = fails(&dir, &args);
        // "... needs an estimated N MiB but the memory budget is 3.0 MiB ..."
        let estimate: f64 = e
            .split("needs an estimated ")
            .nth(1)
            .and_then(|rest| rest.split(" MiB").next())
            .and_then(|n| n.parse().ok())
            .unwrap_or_else(|| panic!("no estimate in {e}"));
        assert!(estimate > 3.0 && e.contains("the memory budget is 3.0 MiB"), "{e}");
        assert!(!dir.join("out.oct").exists(), "{op:?} wrote its output");
        args[1] = "1GiB";
        ok(&dir, &args);
        std::fs::remove_file(dir.join("out.oct")).unwrap();
    }
}

#[test]
fn a_sharded_solid_is_offset_shelled_and_rounded_cell_by_cell_into_a_sharded_solid() {
    // Issue 39, point 1: `.octs` in and out cell by cell with a halo of the distance,
    // the same voxels as the single file's, and the budget checked before any cell.
    let dir = scratch("offset-sharded");
    ok(&dir, &["shape", "torus", "--radius", "0.6", "--tube", "0.25", "--depth", "6", "-o", "ring.oct"]);
    ok(
        &dir,
        &[
            "shape",
            "torus",
            "--radius",
            "0.6",
            "--tube",
            "0.25",
            "--depth",
            "6",
            "--shard-level",
            "2",
            "-o",
            "ring.octs",
        ],
    );
    let read = |f: &str| octsolid::SolidFile::read(dir.join(f), &Default::default()).unwrap().into_union();
    for op in [
        &["offset", "--voxels", "3"][..],
        &["offset", "--by", "-0.05"],
        &["shell", "--thickness", "0.1"],
        &["round", "--radius", "0.05", "--convex"],
    ] {
        let mut args = vec![op[0], "ring.octs"];
        args.extend_from_slice(&op[1..]);
        args.extend_from_slice(&["-o", "out.octs"]);
        let said = ok(&dir, &args);
        assert!(said.contains("at cell level 2"), "{said}");
        args[1] = "ring.oct";
        *args.last_mut().unwrap() = "out.oct";
        ok(&dir, &args);
        let (cells, whole) = (read("out.octs"), read("out.oct"));
        assert!(whole.voxel_count() > 0 && cells.keys() == whole.keys(), "{op:?}");
        std::fs::remove_dir_all(dir.join("out.octs")).unwrap();
    }
    let e = fails(&dir, &["--memory-budget", "20KiB", "offset", "ring.octs", "--voxels", "3", "-o", "out.octs"]);
    assert!(e.contains("the window of cell") && e.contains("memory budget"), "{e}");
    assert!(!dir.join("out.octs").exists() && !dir.join("out.octs.partial").exists());
}
