//! What a new user meets in the first hour (the walkthrough's pieces, one test each):
//! csg over different domains, `transform`, camera flags and framing, the up axis kept
//! in `.oct` files, output extensions honoured or refused, ignored flags and empty
//! results said, stage timings and plain progress lines. Oracles: analytic volumes,
//! the library's own exact operations, pixel counts of the pictures.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn octsolid(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_octsolid")).current_dir(dir).args(args).output().unwrap()
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("cli/ has a parent").to_path_buf()
}

/// Runs a command that must succeed; returns stdout and stderr.
fn ok(dir: &Path, args: &[&str]) -> (String, String) {
    let out = octsolid(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "octsolid {args:?} failed: {stderr}");
    (String::from_utf8(out.stdout).unwrap(), stderr)
}

/// Runs a command that must fail; returns its error line.
fn fails(dir: &Path, args: &[&str]) -> String {
    let out = octsolid(dir, args);
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(!out.status.success(), "octsolid {args:?} should fail");
    assert!(!stderr.contains("panicked"), "octsolid {args:?} panicked: {stderr}");
    stderr
}

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("first-hour", name)
}

fn json(dir: &Path, file: &str) -> serde_json::Value {
    serde_json::from_str(&ok(dir, &["info", file, "--json"]).0).unwrap()
}

fn volume(dir: &Path, file: &str) -> f64 {
    json(dir, file)["volume"].as_f64().unwrap()
}

#[test]
fn csg_brings_operands_into_one_domain_and_says_how() {
    let dir = scratch("csg");
    // The README's pair: a sphere in its own default domain, a box in a given one.
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "7", "-o", "ball.oct"]);
    ok(
        &dir,
        &[
            "shape",
            "box",
            "--size",
            "1.6,1.6,1.6",
            "--depth",
            "7",
            "--domain",
            "-1.05,-1.05,-1.05,2.1",
            "-o",
            "cube.oct",
        ],
    );
    let (out, _) = ok(&dir, &["csg", "difference", "cube.oct", "ball.oct", "-o", "hollow.oct"]);
    assert!(
        out.contains("ball.oct: resampled (voxels do not nest) into cube at (-1.05, -1.05, -1.05) edge 2.1 depth 7"),
        "{out}"
    );
    assert!(!out.contains("cube.oct:"), "the box is already in the common domain: {out}");
    // Analytic: the box minus the unit ball (the ball pokes out of the box's faces,
    // so the removed part is the ball clipped to the box), within the voxel shell.
    let v = volume(&dir, "hollow.oct");
    let clipped_ball = {
        // Monte Carlo-free: the ball minus six caps of height 1 - 0.8.
        let h: f64 = 0.2;
        4.0 / 3.0 * std::f64::consts::PI - 6.0 * std::f64::consts::PI * h * h * (3.0 - h) / 3.0
    };
    let want = 1.6f64.powi(3) - clipped_ball;
    assert!((v - want).abs() < 0.08 * want, "{v} vs {want}");
    // Voxel for voxel: the ball carries its crossings, so it is resampled from its
    // smooth surface, and the difference is the common lattice's voxels whose centres
    // lie in the box and outside the unit ball, counted densely here (to the voxels
    // whose centres lie within a hair of the sphere).
    let (n, edge) = (128, 2.1 / 128.0);
    let centres: Vec<f64> =
        (0..n).map(|i| -1.05 + (f64::from(i) + 0.5) * edge).filter(|c: &f64| c.abs() <= 0.8).collect();
    let mut outside = 0u64;
    for &x in &centres {
        for &y in &centres {
            outside += centres.iter().filter(|&&z| x * x + y * y + z * z > 1.0).count() as u64;
        }
    }
    let dense = outside as f64 * edge.powi(3);
    assert!((v - dense).abs() < 1e-3 * dense, "{v} vs {dense} counted densely");
    // An octant-aligned pair nests: exact, one level deeper, volumes add.
    ok(
        &dir,
        &[
            "shape",
            "box",
            "--size",
            "1,1,1",
            "--center",
            "0.5,0.5,0.5",
            "--depth",
            "5",
            "--domain",
            "0,0,0,2",
            "-o",
            "a.oct",
        ],
    );
    ok(
        &dir,
        &[
            "shape",
            "box",
            "--size",
            "1,1,1",
            "--center",
            "1.5,1.5,1.5",
            "--depth",
            "5",
            "--domain",
            "1,1,1,1",
            "-o",
            "b.oct",
        ],
    );
    let (out, _) = ok(&dir, &["csg", "union", "a.oct", "b.oct", "-o", "ab.oct"]);
    assert!(out.contains("a.oct: exact (voxels nest, refined 1 level)"), "{out}");
    assert!(out.contains("b.oct: exact (voxels nest, moved by [32, 32, 32] voxels)"), "{out}");
    let info = json(&dir, "ab.oct");
    assert_eq!(info["depth"], 6);
    assert!((info["volume"].as_f64().unwrap() - 2.0).abs() < 1e-12, "{info}");
    // --domain and --depth choose the common domain; an empty result is said.
    let (out, _) =
        ok(&dir, &["csg", "union", "a.oct", "b.oct", "--domain", "-1,-1,-1,4", "--depth", "7", "-o", "big.oct"]);
    assert!(out.contains("a.oct: exact") && out.contains("b.oct: exact"), "{out}");
    assert!((volume(&dir, "big.oct") - 2.0).abs() < 1e-12);
    let (_, err) = ok(&dir, &["csg", "intersect", "a.oct", "b.oct", "-o", "none.oct"]);
    assert!(err.contains("warning: the intersect is empty"), "{err}");
}

#[test]
fn transform_is_exact_for_whole_voxel_moves_and_resamples_others() {
    let dir = scratch("transform");
    ok(&dir, &["shape", "torus", "--radius", "1", "--tube", "0.3", "--depth", "7", "-o", "ring.oct"]);
    let before = json(&dir, "ring.oct");
    let (out, _) = ok(
        &dir,
        &["transform", "ring.oct", "-o", "turned.oct", "--rotate", "x,90", "--translate", "0.3,-2,5", "--scale", "2"],
    );
    assert!(out.contains("ring.oct: exact"), "{out}");
    let after = json(&dir, "turned.oct");
    // A quarter turn and a power-of-two scale keep every node; the volume scales by 8.
    assert_eq!(after["nodes"], before["nodes"]);
    assert!((after["volume"].as_f64().unwrap() / before["volume"].as_f64().unwrap() - 8.0).abs() < 1e-9);
    // The torus's axis was z; turned about x it lies along y: its y extent is the
    // tube's, 2 x 0.3 x 2 (scaled), around the translated centre -2.
    let b = &after["bounds"];
    let (ymin, ymax) = (b["min"][1].as_f64().unwrap(), b["max"][1].as_f64().unwrap());
    let h = after["domain"]["edge"].as_f64().unwrap() / 128.0;
    assert!((ymin + 2.0 + 0.6).abs() < 2.0 * h && (ymax + 2.0 - 0.6).abs() < 2.0 * h, "{ymin} {ymax}");
    let (out, _) = ok(&dir, &["transform", "ring.oct", "-o", "tilted.oct", "--rotate", "y,30"]);
    assert!(out.contains("ring.oct: resampled"), "{out}");
    let analytic = 2.0 * std::f64::consts::PI.powi(2) * 1.0 * 0.3f64.powi(2);
    assert!((volume(&dir, "tilted.oct") / analytic - 1.0).abs() < 0.03);
    let e = fails(&dir, &["transform", "ring.oct", "-o", "bad.oct", "--rotate", "w,30"]);
    assert!(e.contains("w,30"), "{e}");
    let e = fails(&dir, &["transform", "ring.oct", "-o", "bad.oct", "--scale", "0"]);
    assert!(e.contains("scale 0 must be finite and positive"), "{e}");
}

/// The bounding box of the pixels that differ from the top-left (background) pixel,
/// as fractions of the image's width and height.
fn coverage(path: &Path) -> (f64, f64) {
    let img = image::open(path).unwrap().to_rgb8();
    let bg = *img.get_pixel(0, 0);
    let (mut x0, mut y0, mut x1, mut y1) = (u32::MAX, u32::MAX, 0, 0);
    for (x, y, p) in img.enumerate_pixels() {
        if p.0.iter().zip(bg.0).any(|(a, b)| a.abs_diff(b) > 8) {
            (x0, y0, x1, y1) = (x0.min(x), y0.min(y), x1.max(x), y1.max(y));
        }
    }
    (f64::from(x1 + 1 - x0) / f64::from(img.width()), f64::from(y1 + 1 - y0) / f64::from(img.height()))
}

#[test]
fn camera_flags_frame_and_orient_the_picture() {
    let dir = scratch("camera");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "7", "-o", "ball.oct"]);
    // Auto-framing fills the picture: the ball spans nearly the full height.
    ok(&dir, &["render", "ball.oct", "--size", "160x120", "--spp", "1", "-o", "ball.png"]);
    let (w, h) = coverage(&dir.join("ball.png"));
    assert!(h > 0.88 && h <= 1.0 && w > 0.6, "{w} {h}");
    // Orthographic from the top: a disc as tall as the picture (within the margin).
    ok(&dir, &["render", "ball.oct", "--size", "120x120", "--spp", "1", "--view", "top", "--ortho", "-o", "top.png"]);
    let (w, h) = coverage(&dir.join("top.png"));
    assert!((w - h).abs() < 0.03 && h > 0.9, "{w} {h}");
    // --zoom 2 halves what is shown: the ball overflows the picture.
    ok(&dir, &["render", "ball.oct", "--size", "120x120", "--spp", "1", "--zoom", "2", "--ortho", "-o", "zoom.png"]);
    assert_eq!(coverage(&dir.join("zoom.png")), (1.0, 1.0));
    // A far eye and a narrow field of view show the ball small, centred.
    ok(
        &dir,
        &["render", "ball.oct", "--size", "120x120", "--spp", "1", "--eye", "0,-40,0", "--fov", "10", "-o", "far.png"],
    );
    let (_, h) = coverage(&dir.join("far.png"));
    let want = 1.0 / (40.0 * (5f64).to_radians().tan());
    assert!((h - want).abs() < 0.05, "{h} vs {want}");
    // Front and azimuth 0 are one view; back differs from front for an asymmetric solid.
    ok(&dir, &["shape", "cone", "--radius", "1", "--height", "2", "--axis", "x", "--depth", "6", "-o", "cone.oct"]);
    let render = |name: &str, extra: &[&str]| {
        let args: Vec<&str> =
            ["render", "cone.oct", "--size", "64x48", "--spp", "1", "-o", name].iter().chain(extra).copied().collect();
        ok(&dir, &args);
        std::fs::read(dir.join(name)).unwrap()
    };
    let front = render("front.png", &["--view", "front"]);
    assert_eq!(front, render("az0.png", &["--azimuth", "0", "--elevation", "0"]));
    assert_ne!(front, render("right.png", &["--view", "right"]));
    let e = fails(&dir, &["render", "cone.oct", "--eye", "1,2,3", "--view", "top"]);
    assert!(e.contains("--eye") && e.contains("--view"), "{e}");
    let e = fails(&dir, &["render", "cone.oct", "--view", "sideways"]);
    assert!(e.contains("front, back, left, right, top, bottom or iso"), "{e}");
    let e = fails(&dir, &["render", "cone.oct", "--fov", "200"]);
    assert!(e.contains("--fov"), "{e}");
    // Scenes take the flags too; without flags their own camera is kept.
    let scene = repo().join("scenes/classic.toml");
    let scene = scene.to_str().unwrap();
    ok(&dir, &["render", scene, "--size", "64x48", "--spp", "1", "--no-cache", "-o", "s1.png"]);
    ok(&dir, &["render", scene, "--size", "64x48", "--spp", "1", "--view", "top", "--no-cache", "-o", "s2.png"]);
    assert_ne!(std::fs::read(dir.join("s1.png")).unwrap(), std::fs::read(dir.join("s2.png")).unwrap());
}

#[test]
fn the_up_axis_travels_in_the_oct_file() {
    let dir = scratch("up");
    let spot = repo().join("models/spot.obj");
    let spot = spot.to_str().unwrap();
    ok(&dir, &["voxelize", spot, "--depth", "6", "-o", "spot.oct"]);
    ok(&dir, &["voxelize", spot, "--depth", "6", "--up", "z", "--units", "mm", "-o", "spot-z.oct"]);
    let bytes = std::fs::read(dir.join("spot.oct")).unwrap();
    assert_eq!((bytes[8], bytes[13], bytes[14]), (2, 2, 0), "version 2, up +y, no unit");
    assert_eq!((json(&dir, "spot.oct")["up"].as_str(), json(&dir, "spot.oct")["units"].as_str()), (Some("y"), None));
    assert_eq!(json(&dir, "spot-z.oct")["units"].as_str(), Some("mm"));
    let bytes = std::fs::read(dir.join("spot-z.oct")).unwrap();
    assert_eq!((bytes[13], bytes[14]), (3, 2), "up +z, millimetres");
    // Rendering the .oct uses the recorded axis: the same picture as --up y.
    let render = |file: &str, name: &str, up: Option<&str>| {
        let mut args = vec!["render", file, "--size", "64x48", "--spp", "1", "-o", name];
        args.extend(up.iter().flat_map(|u| ["--up", *u]));
        ok(&dir, &args);
        std::fs::read(dir.join(name)).unwrap()
    };
    let recorded = render("spot.oct", "a.png", None);
    assert_eq!(recorded, render("spot.oct", "b.png", Some("y")));
    assert_ne!(recorded, render("spot.oct", "c.png", Some("z")));
    assert_eq!(render("spot-z.oct", "d.png", None), render("spot.oct", "e.png", Some("z")));
    // csg and transform keep the first input's metadata.
    ok(&dir, &["transform", "spot.oct", "--translate", "1,0,0", "-o", "moved.oct"]);
    assert_eq!(std::fs::read(dir.join("moved.oct")).unwrap()[13], 2);
}

#[test]
fn outputs_are_written_as_their_extension_says_or_refused() {
    let dir = scratch("extensions");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "5", "-o", "ball.oct"]);
    let oct_volume = volume(&dir, "ball.oct");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "5", "-o", "ball.stl"]);
    assert!(std::fs::read(dir.join("ball.stl")).unwrap().len() > 84, "a binary STL");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "5", "-o", "ball.vox"]);
    assert_eq!(&std::fs::read(dir.join("ball.vox")).unwrap()[..4], b"VOX ");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "5", "-o", "ball.binvox"]);
    assert!(std::fs::read(dir.join("ball.binvox")).unwrap().starts_with(b"#binvox"));
    // The mesh written is the sphere's true surface (mesh-info's volume): nearer the
    // exact volume than the octree's staircase, within 0.5%.
    let (out, _) = ok(&dir, &["mesh-info", "ball.stl"]);
    let line = out.lines().find(|l| l.starts_with("volume")).unwrap();
    let v: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
    let exact = 4.0 / 3.0 * std::f64::consts::PI;
    assert!((v - exact).abs() < 5e-3 * exact && (v - exact).abs() < (oct_volume - exact).abs(), "{line}: {oct_volume}");
    for (args, accepted) in [
        (vec!["shape", "sphere", "-o", "x.txt"], "oct, octs, vox, binvox, vdb, glb, obj, stl, ply"),
        (vec!["render", "ball.oct", "-o", "x.jpg"], "accepted: png"),
        (vec!["slice", "ball.oct", "-o", "x.bmp"], "accepted: png"),
        (vec!["csg", "union", "ball.oct", "ball.oct", "-o", "x"], "has no extension"),
    ] {
        let e = fails(&dir, &args);
        assert!(e.contains(accepted), "{args:?}: {e}");
    }
    assert!(!dir.join("x.txt").exists() && !dir.join("x.jpg").exists());
    let (_, err) = ok(&dir, &["render", "ball.oct", "--depth", "4", "--size", "32x24", "-o", "d.png"]);
    assert!(err.contains("warning: --depth is ignored for ball.oct"), "{err}");
}

#[test]
fn render_reports_every_stage_and_prints_progress_lines_off_a_terminal() {
    let dir = scratch("stages");
    let spot = repo().join("models/spot.obj");
    let out = Command::new(env!("CARGO_BIN_EXE_octsolid"))
        .current_dir(&dir)
        .env("OCTSOLID_PROGRESS_SECONDS", "0")
        .args(["render", spot.to_str().unwrap(), "--depth", "6", "--size", "64x48", "--spp", "1", "-o", "s.png"])
        .output()
        .unwrap();
    assert!(out.status.success());
    let (stdout, stderr) = (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let time = stdout.lines().find(|l| l.starts_with("time")).unwrap_or_else(|| panic!("{stdout}"));
    for stage in ["loading", "voxelizing", "building the traversal", "rendering", "writing"] {
        assert!(time.contains(stage), "{time}");
    }
    // The total is the sum of the stages (to rounding) and not less than any of them.
    let numbers: Vec<f64> = time.split([' ', ',', ':']).filter_map(|t| t.parse().ok()).collect();
    let (total, parts) = (numbers[0], &numbers[1..]);
    assert!((total - parts.iter().sum::<f64>()).abs() <= 0.011 * parts.len() as f64, "{time}");
    assert!(stderr.contains("voxelizing: ") && stderr.contains("rendering: "), "{stderr}");
    assert!(stderr.lines().any(|l| l.starts_with("rendering: 100%")), "{stderr}");
}

/// The percentages of each bar's progress lines, in order, by the bar's name.
fn progress_lines(stderr: &str) -> Vec<(String, u32)> {
    stderr
        .lines()
        .filter_map(|l| {
            let (name, rest) = l.split_once(": ")?;
            Some((name.to_string(), rest.split_once('%')?.0.parse().ok()?))
        })
        .collect()
}

#[test]
fn jobs_of_several_stages_fill_their_bar_once() {
    let dir = scratch("one-bar");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "6", "-o", "ball.oct"]);
    // A round is four offsets; a turn by an eighth resamples from the smooth surface
    // (extraction, then voxelization).
    for args in [
        vec!["round", "ball.oct", "--radius", "0.1", "-o", "r.oct"],
        vec!["transform", "ball.oct", "--rotate", "z,45", "-o", "t.oct"],
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_octsolid"))
            .current_dir(&dir)
            .env("OCTSOLID_PROGRESS_SECONDS", "0")
            .args(&args)
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}");
        let lines = progress_lines(&String::from_utf8_lossy(&out.stderr));
        assert!(lines.len() > 4, "{args:?}: {lines:?}");
        assert!(lines.iter().all(|(name, _)| *name == lines[0].0), "{args:?}: one bar: {lines:?}");
        assert!(lines.windows(2).all(|w| w[0].1 <= w[1].1), "{args:?}: the bar went back: {lines:?}");
        assert_eq!(lines.last().unwrap().1, 100, "{args:?}");
    }
}

#[test]
fn offsets_take_a_metric_and_say_what_it_leaves_out() {
    let dir = scratch("metric");
    // A box of 16 voxels at depth 6 (64 a side), with its surface data.
    ok(&dir, &["shape", "box", "--size", "0.5,0.5,0.5", "--depth", "6", "--domain", "-1,-1,-1,2", "-o", "box.oct"]);
    let (out, _) = ok(&dir, &["offset", "box.oct", "--voxels", "3", "--metric", "chebyshev", "-o", "grown.oct"]);
    assert!(out.contains("chebyshev distance is measured over the voxels"), "{out}");
    // Grown by a cube of reach 3: a box of 22 voxels a side.
    let (info, _) = ok(&dir, &["info", "grown.oct", "--json"]);
    assert!(info.contains(&format!("\"voxels\":{}", 22u64.pow(3))), "{info}");
    let e = fails(&dir, &["round", "box.oct", "--radius", "0.1", "--metric", "l2", "-o", "r.oct"]);
    assert!(e.contains("\"l2\" is not euclidean, manhattan or chebyshev"), "{e}");
    ok(&dir, &["shape", "box", "--size", "0.5,0.5,0.5", "--depth", "6", "--shard-level", "1", "-o", "box.octs"]);
    let e = fails(&dir, &["shell", "box.octs", "--thickness", "0.1", "--metric", "manhattan", "-o", "s.octs"]);
    assert!(e.contains("euclidean distance only"), "{e}");
}

#[test]
fn outputs_never_replace_inputs_and_stdout_failures_are_errors() {
    let dir = scratch("safety");
    ok(&dir, &["shape", "sphere", "--radius", "1", "--depth", "4", "-o", "ball.oct"]);
    let before = std::fs::read(dir.join("ball.oct")).unwrap();
    for args in [
        vec!["transform", "ball.oct", "--scale", "2", "-o", "./ball.oct"],
        vec!["csg", "union", "ball.oct", "ball.oct", "-o", "ball.oct"],
        vec!["export", "ball.oct", "-o", "ball.oct"],
    ] {
        let e = fails(&dir, &args);
        let refused = ["the output is the input", "unexpected extension", "names no mesh format"];
        assert!(refused.iter().any(|r| e.contains(r)), "{args:?}: {e}");
    }
    assert_eq!(std::fs::read(dir.join("ball.oct")).unwrap(), before);
    if Path::new("/dev/full").exists() {
        let full = std::fs::File::create("/dev/full").unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_octsolid"))
            .current_dir(&dir)
            .args(["info", "ball.oct"])
            .stdout(full)
            .output()
            .unwrap();
        assert!(!out.status.success(), "a lost output is an error");
        assert!(String::from_utf8_lossy(&out.stderr).contains("cannot write the output to stdout"));
        // The help too (clap's exit ignored the failed write: status 0).
        let full = std::fs::File::create("/dev/full").unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_octsolid")).arg("--help").stdout(full).output().unwrap();
        assert!(!out.status.success(), "a lost help is an error");
        assert!(String::from_utf8_lossy(&out.stderr).contains("cannot write the help to stdout"));
    }
}
