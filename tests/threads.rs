//! Every command that writes output gives the same bytes with one thread and with two:
//! the same session of commands runs twice, each in its own folder, with
//! `RAYON_NUM_THREADS=1` and `=2` (the CLI runs on rayon's global pool, which reads
//! it), and after each command its standard output (timings and rates masked) and the
//! files it wrote must be identical. `bench` is left out: its output is timings.
//!
//! The session covers `shape` (every kind; `.oct`, `.vox`, `.binvox`, `.vdb`, `.glb`,
//! `.obj`, `.stl`, `.ply`), `csg` (every operation, nested and resampled domains),
//! `transform` (exact and resampled), `info` (text and JSON), `slice` (each axis),
//! `voxelize` (OBJ, STL, PLY and `.patches`; every fill and inside rule), `export`
//! (each mesh format, both face modes), `mesh-info`, `render` (a Whitted scene with
//! every texture, mesh, `.oct` and CSG leaves; an `.oct` by every method and normal
//! kind; a mesh voxelized; a mesh and patches as polygons by every shading),
//! `radiosity` (the Cornell box, saved and rendered) and `demo` (in optimized builds
//! only).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository's top folder (this test belongs to the cli package in `cli/`).
fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().expect("cli/ has a parent").to_path_buf()
}

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("threads", name)
}

/// `stdout` with every number that a time unit or a rate follows replaced by `#`:
/// `12.5 ms`, `0.42 s`, `3.10 M rays/s`.
fn mask_timings(stdout: &str) -> String {
    let mut lines = Vec::new();
    for line in stdout.lines() {
        let words: Vec<&str> = line.split(' ').collect();
        let mut out = Vec::with_capacity(words.len());
        for (i, w) in words.iter().enumerate() {
            let next = words.get(i + 1).copied().unwrap_or("");
            let unit = ["ms", "s", "s:", "s,", "s)", "s;", "M"].contains(&next);
            let number = w.trim_start_matches('(').parse::<f64>().is_ok();
            out.push(if unit && number { if w.starts_with('(') { "(#" } else { "#" } } else { w });
        }
        lines.push(out.join(" "));
    }
    lines.join("\n")
}

/// One session's folder and thread count.
struct Session {
    dir: PathBuf,
    threads: &'static str,
}

impl Session {
    /// Runs `octsolid args` in the session's folder; returns its masked stdout.
    fn run(&self, args: &[&str]) -> String {
        let out = Command::new(env!("CARGO_BIN_EXE_octsolid"))
            .current_dir(&self.dir)
            .env("RAYON_NUM_THREADS", self.threads)
            .args(args)
            .output()
            .unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "octsolid {args:?} with {} threads failed: {stderr}", self.threads);
        mask_timings(&String::from_utf8(out.stdout).unwrap())
    }
}

/// Runs `args` in both sessions and compares stdout and the files named in `args`
/// (every argument that names a file in the session's folder after the command).
fn same(sessions: &[Session; 2], args: &[&str]) {
    let [one, two] = sessions.each_ref().map(|s| s.run(args));
    assert_eq!(one, two, "octsolid {args:?}: stdout differs between 1 and 2 threads");
    for a in args {
        let [p, q] = sessions.each_ref().map(|s| s.dir.join(a));
        if p.is_file() && !a.ends_with(".toml") {
            let (x, y) = (std::fs::read(&p).unwrap(), std::fs::read(&q).unwrap());
            assert!(
                x == y,
                "octsolid {args:?}: {a} differs between 1 and 2 threads ({} vs {} bytes)",
                x.len(),
                y.len()
            );
        }
    }
}

/// A scene with Whitted's glass and mirror, every texture, a mesh solid, an `.oct`
/// solid and CSG with mesh and `.oct` leaves, all small.
fn scene(root: &Path) -> String {
    let bunny = root.join("models/bunny-watertight.obj");
    let picture = root.join("assets/textures/whitted.png");
    format!(
        r#"[image]
size = [48, 36]
samples = 2
background = [0.45, 0.62, 0.85]
max_depth = 4

[domain]
min = [-2.4, -2.4, -1.2]
edge = 4.8
depth = 6

[camera]
eye = [-0.6, -4.6, 1.6]
target = [0.2, 0.2, -0.1]
fov = 40

[[light]]
type = "point"
position = [3, -4, 6]
color = [0.85, 0.85, 0.85]

[[light]]
type = "directional"
direction = [-0.5, 1, -1]
color = [0.2, 0.2, 0.2]

[[solid]]
name = "glass"
material = {{ color = [1, 1, 1], kd = 0.05, ks = 0.6, shininess = 96, reflectance = 0.08, transmittance = 0.88, ior = 1.5 }}
shape = {{ sphere = {{ center = [-0.35, -0.55, 0.15], radius = 0.75 }} }}

[[solid]]
name = "mirror"
material = {{ reflectance = 0.8, kd = 0.1, texture = {{ marble = {{ size = 0.4, a = [0.9, 0.9, 0.88], b = [0.3, 0.3, 0.35] }} }} }}
shape = {{ difference = [
    {{ sphere = {{ center = [1.05, 0.75, 0.0], radius = 0.6 }} }},
    {{ transform = {{ shape = {{ oct = "ball.oct" }}, scale = [0.3, 0.3, 0.3], translate = [1.05, 0.2, 0.0] }} }},
] }}

[[solid]]
name = "floor"
material = {{ texture = {{ checker = {{ size = 0.5, a = [0.9, 0.85, 0.2], b = [0.75, 0.1, 0.1] }} }} }}
shape = {{ box = {{ center = [0, 0, -0.7], size = [4.6, 4.6, 0.2] }} }}

[[solid]]
name = "bunny"
mesh = "{bunny}"
depth = 5
material = {{ texture = {{ wood = {{ axis = "z", center = [0, 0, 0], size = 0.05, a = [0.6, 0.4, 0.2], b = [0.35, 0.2, 0.1] }} }} }}
transform = {{ scale = [6, 6, 6], translate = [0.2, 1.4, -0.9] }}

[[solid]]
oct = "cube.oct"
material = {{ texture = {{ image = {{ file = "{picture}", mapping = "spherical", axis = "z", center = [-1.5, 1.2, 0] }} }} }}
transform = {{ scale = [0.5, 0.5, 0.5], translate = [-1.5, 1.2, -0.3] }}

[[solid]]
name = "carved"
shape = {{ difference = [
    {{ box = {{ center = [1.4, -1.2, -0.3], size = [0.6, 0.6, 0.6] }} }},
    {{ mesh = "{bunny}" }},
] }}
"#,
        bunny = bunny.display(),
        picture = picture.display()
    )
}

#[test]
fn every_command_writes_the_same_bytes_with_one_and_two_threads() {
    let root = repo();
    let sessions = [Session { dir: scratch("one"), threads: "1" }, Session { dir: scratch("two"), threads: "2" }];
    let s = &sessions;
    let model = |name: &str| root.join("models").join(name).display().to_string();
    let (bunny, teapot) = (model("bunny-watertight.obj"), model("teapot.patches"));
    let domain = ["--domain", "-1.5,-1.5,-1.5,3"];

    // shape: every kind, into every format a solid is written as.
    let kinds: [(&str, &[&str]); 6] = [
        ("sphere", &["--radius", "1.2"]),
        ("ellipsoid", &["--size", "2.4,1.6,1.2"]),
        ("box", &["--size", "2,2,2"]),
        ("cylinder", &["--radius", "0.5", "--height", "3", "--axis", "x"]),
        ("cone", &["--radius", "1", "--height", "2", "--axis", "y"]),
        ("torus", &["--radius", "1", "--tube", "0.35"]),
    ];
    for (kind, flags) in kinds {
        let out = format!("{kind}.oct");
        same(s, &[&["shape", kind, "--depth", "6", "-o", out.as_str()][..], flags, &domain[..]].concat());
    }
    for ext in ["oct", "vox", "binvox", "vdb", "glb", "obj", "stl", "ply"] {
        let out = format!("ring.{ext}");
        same(
            s,
            &["shape", "torus", "--radius", "1", "--tube", "0.4", "--depth", "5", "--center", "0.1,0.2,0", "-o", &out],
        );
    }
    std::fs::copy(s[0].dir.join("sphere.oct"), s[0].dir.join("ball.oct")).unwrap();
    std::fs::copy(s[1].dir.join("sphere.oct"), s[1].dir.join("ball.oct")).unwrap();
    same(s, &["shape", "box", "--size", "1,1,1", "--depth", "4", "-o", "cube.oct"]);

    // csg: every operation in one domain, then operands from other domains (nested
    // and resampled), a chosen domain and depth, and a mesh and voxel output.
    for op in ["union", "intersect", "difference", "xor"] {
        let out = format!("{op}.oct");
        same(s, &["csg", op, "sphere.oct", "box.oct", "cylinder.oct", "-o", &out]);
    }
    same(s, &["csg", "union", "sphere.oct", "ring.oct", "-o", "resampled.oct"]);
    same(s, &["csg", "difference", "torus.oct", "cube.oct", "--depth", "5", "-o", "nested.oct"]);
    same(
        s,
        &["csg", "intersect", "cone.oct", "ellipsoid.oct", "--domain", "-2,-2,-2,4", "--depth", "6", "-o", "d.oct"],
    );
    same(s, &["csg", "xor", "sphere.oct", "torus.oct", "-o", "xor.glb"]);
    same(s, &["csg", "union", "box.oct", "cone.oct", "-o", "union.vdb"]);

    // transform: exact turns, mirrors by scale, resampled turns, another domain or depth.
    same(s, &["transform", "difference.oct", "--rotate", "z,90", "--translate", "0.5,0,0", "-o", "t1.oct"]);
    same(s, &["transform", "difference.oct", "--rotate", "x,30", "--rotate", "z,45", "-o", "t2.oct"]);
    same(s, &["transform", "torus.oct", "--scale", "1.5", "-o", "t3.oct"]);
    same(s, &["transform", "torus.oct", "--scale", "0.5", "--rotate", "y,180", "-o", "t4.binvox"]);
    same(s, &["transform", "ellipsoid.oct", "--domain", "-2,-2,-2,4", "--depth", "5", "-o", "t5.oct"]);

    // info, slice.
    for file in ["difference.oct", "t2.oct", "resampled.oct"] {
        same(s, &["info", file]);
        same(s, &["info", file, "--json"]);
    }
    for (axis, at) in [("x", None), ("y", Some("0.3")), ("z", Some("-0.2"))] {
        let out = format!("slice-{axis}.png");
        let at: Vec<&str> = at.map(|a| vec!["--at", a]).unwrap_or_default();
        same(
            s,
            &[&["slice", "difference.oct", "--axis", axis, "--size", "96", "-o", out.as_str()][..], &at[..]].concat(),
        );
    }

    // export: each mesh format, both face modes.
    for ext in ["obj", "stl", "ply"] {
        let (merged, unit) = (format!("part.{ext}"), format!("part-unit.{ext}"));
        same(s, &["export", "difference.oct", "-o", &merged]);
        same(s, &["export", "xor.oct", "-o", &unit, "--unit-faces"]);
    }

    // voxelize: each mesh format and patches; every fill and inside rule.
    for (input, depth) in [(bunny.as_str(), "6"), ("part.stl", "5"), ("part-unit.ply", "5"), ("part.obj", "5")] {
        let name = Path::new(input).file_name().unwrap().to_string_lossy().replace('.', "-");
        for inside in ["auto", "parity", "winding"] {
            let out = format!("v-{name}-{inside}.oct");
            same(s, &["voxelize", input, "--depth", depth, "--inside", inside, "-o", &out]);
        }
        for fill in ["surface", "thin"] {
            let out = format!("v-{name}-{fill}.oct");
            same(s, &["voxelize", input, "--depth", depth, "--fill", fill, "-o", &out]);
        }
    }
    for fill in ["solid", "surface", "thin"] {
        let out = format!("teapot-{fill}.oct");
        same(s, &["voxelize", &teapot, "--depth", "6", "--fill", fill, "-o", &out]);
    }
    same(s, &["voxelize", &bunny, "--depth", "5", "--up", "y", "--units", "mm", "-o", "bunny.vox"]);
    // The interchange formats read and converted: every solid file to every format,
    // a file of several colours kept apart, and read by the other commands.
    for (from, to) in [("bunny.vox", "bunny-vox.oct"), ("t4.binvox", "t4.vdb"), ("union.vdb", "union.vox")] {
        same(s, &["convert", from, to]);
    }
    same(s, &["convert", "bunny.vox", "bunny-d6.binvox", "--depth", "6"]);
    same(s, &["info", "bunny.vox", "--json"]);
    same(s, &["render", "bunny.vox", "--size", "48x36", "--spp", "1", "-o", "bunny-vox.png"]);
    same(s, &["export", "t4.binvox", "-o", "t4.glb"]);

    // mesh-info: every input kind.
    for input in [bunny.as_str(), "part.stl", "part-unit.ply", "part.obj", teapot.as_str()] {
        same(s, &["mesh-info", input]);
        same(s, &["mesh-info", input, "--json"]);
    }

    // render: a Whitted scene; an .oct by every method and normal kind; meshes.
    for session in s {
        std::fs::write(session.dir.join("scene.toml"), scene(&root)).unwrap();
    }
    same(s, &["render", "scene.toml", "-o", "scene.png"]);
    same(s, &["render", "scene.toml", "--normals", "axis", "--spp", "1", "-o", "scene-axis.png"]);
    same(s, &["render", "scene.toml", "--aa", "adaptive", "--spp", "3", "-o", "scene-adaptive.png"]);
    same(s, &["render", "scene.toml", "--aa-depth", "2", "--size", "160x120", "-o", "scene-recursive.png"]);
    for method in ["trace", "front-to-back", "painter", "zbuffer", "scanline"] {
        let out = format!("part-{method}.png");
        same(s, &["render", "difference.oct", "--method", method, "--size", "64x48", "--spp", "2", "-o", &out]);
    }
    for normals in ["axis", "smooth", "octree"] {
        let out = format!("t2-{normals}.png");
        same(s, &["render", "t2.oct", "--normals", normals, "--size", "64x48", "--view", "iso", "-o", &out]);
    }
    same(s, &["render", "torus.oct", "--ortho", "--view", "top", "--no-shadows", "--size", "48x48", "-o", "top.png"]);
    same(s, &["render", &bunny, "--depth", "5", "--size", "48x36", "--spp", "1", "-o", "bunny.png"]);
    for shading in ["flat", "gouraud", "phong"] {
        let (mesh, patches) = (format!("bunny-{shading}.png"), format!("teapot-{shading}.png"));
        same(s, &["render", &bunny, "--shading", shading, "--size", "64x48", "-o", &mesh]);
        same(s, &["render", &teapot, "--shading", shading, "--size", "64x48", "-o", &patches]);
    }

    // radiosity: 60 shots of the Cornell box, saved and rendered.
    let cornell = root.join("scenes").join("cornell.toml").display().to_string();
    same(s, &["radiosity", &cornell, "-o", "cornell.rad", "--max-shots", "60"]);
    same(s, &["render", &cornell, "--radiosity", "cornell.rad", "--size", "48x48", "--no-cache", "-o", "cornell.png"]);

    // And every file the two sessions wrote, whatever wrote it.
    // (Files only: a scene's solid cache folder holds what the renders read back.)
    let files = |dir: &Path| {
        let mut names: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap())
            .filter(|e| e.file_type().unwrap().is_file())
            .map(|e| e.file_name())
            .collect();
        names.sort();
        names
    };
    let (names, theirs) = (files(&s[0].dir), files(&s[1].dir));
    assert_eq!(names, theirs);
    for name in names {
        let [a, b] = s.each_ref().map(|x| std::fs::read(x.dir.join(&name)).unwrap());
        assert!(a == b, "{name:?} differs between 1 and 2 threads");
    }
}

/// `demo` renders 1200x720 at 3x3 samples whatever the depth: about 5 s optimized, a
/// minute and a half without, so only optimized builds (`cargo test --release`, as
/// `.ci/run` runs) run it.
#[test]
fn demo_writes_the_same_bytes_with_one_and_two_threads() {
    if cfg!(debug_assertions) {
        eprintln!("skipped: the demo's fixed 1200x720 render takes minutes unoptimized; run with --release");
        return;
    }
    let sessions =
        [Session { dir: scratch("demo-one"), threads: "1" }, Session { dir: scratch("demo-two"), threads: "2" }];
    same(&sessions, &["demo", "--depth", "5", "-o", "demo.png"]);
}

#[test]
fn timings_are_masked_and_nothing_else() {
    let masked = mask_timings("time       0.52 s: load 0.01 s, trace 12.5 ms\nin 1.5 s (3.25 M samples/s; 9 M rays/s)");
    assert_eq!(masked, "time       # s: load # s, trace # ms\nin # s (# M samples/s; # M rays/s)");
    let kept = "volume     3.183084 enclosed, 12832 triangles, 6 solids at depth 6";
    assert_eq!(mask_timings(kept), kept);
}
