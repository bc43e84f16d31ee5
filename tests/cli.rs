//! The `octsolid` binary end to end: exact command forms, JSON keys, and one-line
//! errors with a non-zero exit and no panic.

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
    let dir = std::env::temp_dir().join(format!("octsolid-cli-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
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
    assert!(e.contains("a.3ds") && e.contains("(use .toml, .oct, .obj, .stl, .ply or .patches)"), "{e}");
    let e = fails(&dir, &["voxelize", "a.oct", "-o", "v.oct"]);
    assert!(e.contains("a.oct") && e.contains("(use .obj, .stl, .ply or .patches)"), "{e}");
    let e = fails(&dir, &["render", "scene.toml", "--shading", "flat"]);
    assert!(e.contains("scene.toml") && e.contains("(use .oct, .obj, .stl, .ply or .patches)"), "{e}");
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
    assert!(out.contains("Parity rule (auto)") && out.contains("5856 triangles"), "{out}");
    let info = info_json(&dir, "spot.oct");
    let volume = info["volume"].as_f64().unwrap();
    assert!((volume / 0.718259 - 1.0).abs() < 0.01, "spot volume {volume}");
    let out = ok(&dir, &["voxelize", spot, "--depth", "7", "--inside", "winding", "-o", "spot_w.oct"]);
    assert!(out.contains("Winding rule") && !out.contains("auto"), "{out}");
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
    ok(&dir, &["render", scene.to_str().unwrap(), "--size", "64x48", "-o", "flange.png"]);
    let img = image::open(dir.join("flange.png")).unwrap();
    assert_eq!((img.width(), img.height()), (64, 48));
    std::fs::write(dir.join("bad.toml"), "[image]\nsize = [64, 48\n").unwrap();
    let e = fails(&dir, &["render", "bad.toml"]);
    assert!(e.contains("bad.toml:2:15: unclosed array"), "{e}");
    let e = fails(&dir, &["render", "ring.oct", "--size", "0x10"]);
    assert!(e.contains("image size"), "{e}");
}

#[test]
fn export_writes_closed_meshes_with_the_octree_volume() {
    let dir = scratch("export");
    ok(&dir, &["shape", "torus", "--radius", "1", "--tube", "0.4", "--depth", "6", "-o", "ring.oct"]);
    let volume = info_json(&dir, "ring.oct")["volume"].as_f64().unwrap();
    for (name, extra) in [("ring.obj", None), ("ring.stl", None), ("ring.ply", Some("--unit-faces"))] {
        let out = ok(&dir, &["export", "ring.oct", "-o", name].into_iter().chain(extra).collect::<Vec<_>>());
        assert!(out.contains("triangles") && out.contains("enclosed") && out.contains(name), "{out}");
        let report: serde_json::Value = serde_json::from_str(&ok(&dir, &["mesh-info", name, "--json"])).unwrap();
        assert_eq!(report["watertight"], true, "{name}: {report}");
        let enclosed = report["volume"].as_f64().unwrap();
        assert!((enclosed / volume - 1.0).abs() < 1e-6, "{name}: {enclosed} vs {volume}");
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
    let out = ok(&dir, &["export", "touch.oct", "-o", "touch.stl"]);
    assert!(out.contains("stl        4 vertices where voxels touch moved apart"), "{out}");
    ok(&dir, &["export", "touch.oct", "-o", "touch.obj"]);
    let [stl, obj] = ["touch.stl", "touch.obj"]
        .map(|f| serde_json::from_str::<serde_json::Value>(&ok(&dir, &["mesh-info", f, "--json"])).unwrap());
    assert_eq!((stl["watertight"].clone(), stl["non_manifold_edges"].clone()), (true.into(), 0.into()), "{stl}");
    assert_eq!(stl["vertices"], obj["vertices"]);
    let e = fails(&dir, &["export", "ring.oct", "-o", "ring.xyz"]);
    assert!(e.contains("ring.xyz") && e.contains(".obj"), "{e}");
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
fn radiosity_solves_saves_and_renders_from_any_camera() {
    let dir = scratch("radiosity");
    std::fs::write(dir.join("room.toml"), room_scene(4.0)).unwrap();
    std::fs::write(dir.join("other.toml"), room_scene(5.0)).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&ok(&dir, &["radiosity", "room.toml", "-o", "room.rad", "--json"])).unwrap();
    let keys: Vec<&str> = json.as_object().unwrap().keys().map(String::as_str).collect();
    assert_eq!(keys.len(), 5, "{json}");
    for key in ["patches", "elements", "shots", "unshot_fraction", "seconds"] {
        assert!(json.get(key).is_some(), "missing {key}: {json}");
    }
    assert!(json["unshot_fraction"].as_f64().unwrap() <= 0.01);
    assert!(json["elements"].as_u64().unwrap() > json["patches"].as_u64().unwrap());
    let capped: serde_json::Value =
        serde_json::from_str(&ok(&dir, &["radiosity", "room.toml", "-o", "capped.rad", "--max-shots", "3", "--json"]))
            .unwrap();
    assert_eq!(capped["shots"], 3);
    assert!(capped["unshot_fraction"].as_f64().unwrap() > 0.01);
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
