//! Scene files: every bundled scene loads; a misspelt key or value, a refused value and
//! a file that cannot be built are errors that name the scene file, the place
//! (`line:column`, found here from the text) and the solid, keeping the cause's kind
//! (I/O, format, over budget, refused value), nested patterns past the copies and
//! shapes past the nesting among them, at their node; emission read as given (emitters replace
//! the default lights); colour forms against hand-computed RGB;
//! transformed mesh and `.oct` solids against analytic volumes and exact moves; a CSG
//! scene of a shape, a mesh and an `.oct` file against the brute-force predicate; the
//! solid cache against loads without it (the same solids bit for bit, read without
//! voxelizing, rebuilt when an input changes or an entry is corrupt).

use std::path::{Path, PathBuf};

use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::color::COLOR_FORMS;
use octsolid::io::oct;
use octsolid::mesh::generate::cuboid;
use octsolid::mesh::write_mesh;
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, estimate_bytes, voxelize};
use octsolid::render::{AntiAliasing, DEFAULT_AA_DEPTH, DEFAULT_AA_THRESHOLD, Light, RenderOptions};
use octsolid::scene_file::{
    CACHE_DIR, CachePolicy, SceneFile, SceneReadOptions, clear_cache, read_scene, read_scene_with,
};
use octsolid::shape::{Cuboid, Sphere};
use octsolid::{Error, Result};

mod common;

/// A folder of its own for each test (tests run in parallel).
fn scratch(test: &str) -> PathBuf {
    common::scratch_dir("scenes", test)
}

/// Writes `text` to `dir/name` and loads it as a scene.
fn load(dir: &Path, name: &str, text: &str, budget: MemoryBudget) -> (PathBuf, Result<SceneFile>) {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let loaded = read_scene(&path, budget);
    (path, loaded)
}

/// The error of a scene that must fail.
fn error(dir: &Path, name: &str, text: &str) -> (PathBuf, Error) {
    let (path, loaded) = load(dir, name, text, MemoryBudget::default());
    (path, loaded.err().expect("an error"))
}

/// One-based line and column of the first `needle` in `text`: the oracle of a place.
fn place_of(text: &str, needle: &str) -> (usize, usize) {
    let at = text.find(needle).unwrap_or_else(|| panic!("{needle:?} is not in the scene"));
    let before = &text[..at];
    (before.matches('\n').count() + 1, at - before.rfind('\n').map_or(0, |i| i + 1) + 1)
}

/// The cause inside the [`Error::Scene`] of a scene that must fail, after checking it
/// names `path`, the place of `needle` in `text` (`None`: no place) and `solid`, and
/// that its message says all three as `file:line:column: solid: `.
fn scene_cause(e: Error, path: &Path, text: &str, needle: Option<&str>, solid: Option<&str>) -> Error {
    scene_cause_at(e, path, needle.map(|n| place_of(text, n)), solid)
}

/// [`scene_cause`] with the place `want` given as line and column.
fn scene_cause_at(e: Error, path: &Path, want: Option<(usize, usize)>, solid: Option<&str>) -> Error {
    let message = e.to_string();
    let Error::Scene { path: p, place, solid: s, source } = e else { panic!("not a scene error: {e:?}") };
    assert_eq!((p.as_path(), place, s.as_deref()), (path, want, solid), "{message}");
    let mut prefix = path.display().to_string();
    if let Some((line, column)) = want {
        prefix += &format!(":{line}:{column}");
    }
    prefix += ": ";
    if let Some(solid) = solid {
        prefix += &format!("{solid}: ");
    }
    assert!(message.starts_with(&prefix), "{message:?} does not start with {prefix:?}");
    *source
}

const BALL: &str = "shape = { sphere = { center = [0, 0, 0], radius = 1 } }";

#[test]
fn bundled_scenes_load() {
    for name in ["classic", "flange", "showcase", "menger", "displaced", "whitted", "whitted-classic", "teapot"] {
        let file = read_scene(format!("scenes/{name}.toml"), MemoryBudget::default()).unwrap();
        assert!(!file.scene.solids.is_empty() && !file.scene.lights.is_empty(), "{name}");
    }
}

#[test]
fn syntax_errors_and_misspelt_keys_say_line_and_column() {
    let dir = scratch("syntax");
    let text = "[image]\nsize = [640, 480\n";
    let (path, e) = error(&dir, "syntax.toml", text);
    // The reader stops at the end of the unclosed array's line.
    let end_of_line_2 = (2, text.lines().nth(1).unwrap().len() + 1);
    let cause = scene_cause_at(e, &path, Some(end_of_line_2), None);
    assert!(matches!(&cause, Error::Toml { reason } if reason.contains("unclosed array")), "{cause:?}");
    let text = format!("[image]\nsize = [64, 48]\n\n[[solid]]\n{BALL}\ncolour = [1, 0, 0]\n");
    let (path, e) = error(&dir, "field.toml", &text);
    let cause = scene_cause(e, &path, &text, Some("colour"), Some("solid 1"));
    assert!(cause.to_string().contains("unknown field `colour`"), "{cause}");
    let (_, e) = error(&dir, "none.toml", "[image]\nsize = [64, 48]\n");
    assert!(e.to_string().contains("missing field `solid`"), "{e}");
}

#[test]
fn misspelt_values_are_refused_at_their_place() {
    let dir = scratch("values");
    // (file text, the misspelt value as written, the solid it lies in)
    let cases = [
        (format!("[image]\nsize = [64, 48]\nnormals = \"smoth\"\n\n[[solid]]\n{BALL}\n"), "smoth", None),
        (format!("[camera]\nprojection = \"ortho\"\n\n[[solid]]\n{BALL}\n"), "ortho", None),
        (format!("[[light]]\ntype = \"spot\"\nposition = [1, 1, 1]\n\n[[solid]]\n{BALL}\n"), "spot", None),
        ("[[solid]]\nmesh = \"bunny.obj\"\ninside = \"odd\"\n".into(), "odd", Some("solid 1")),
        (
            "[[solid]]\nname = \"rod\"\nshape = { cylinder = { center = [0, 0, 0], axis = \"w\", radius = 1, height = 1 } }\n"
                .into(),
            "w",
            Some("rod"),
        ),
        (
            format!(
                "[[solid]]\n{BALL}\nmaterial = {{ texture = {{ image = {{ file = \"t.png\", mapping = \"polar\" }} }} }}\n"
            ),
            "polar",
            Some("solid 1"),
        ),
        (
            format!(
                "[[solid]]\n{BALL}\n\n[[solid]]\n{BALL}\nmaterial = {{ texture = {{ wood = {{ axis = \"q\", size = 1, a = [1, 1, 1], b = [0, 0, 0] }} }} }}\n"
            ),
            "q",
            Some("solid 2"),
        ),
        ("[[solid]]\nshape = { union = [\n  { blob = { radius = 1 } },\n] }\nname = \"late\"\n".into(), "blob", Some("late")),
    ];
    for (i, (text, word, solid)) in cases.iter().enumerate() {
        let (path, e) = error(&dir, &format!("value{i}.toml"), text);
        // The place is the value itself: inside its quotes, or the bare key.
        let needle = if text.contains(&format!("\"{word}\"")) { format!("\"{word}\"") } else { word.to_string() };
        match scene_cause(e, &path, text, Some(&needle), *solid) {
            Error::Toml { reason } => assert!(reason.contains(&format!("unknown variant `{word}`")), "{reason}"),
            other => panic!("case {i}: not the reader's error: {other:?}"),
        }
    }
}

#[test]
fn value_errors_name_the_file_the_place_and_the_solid() {
    let dir = scratch("refused");
    std::fs::write(dir.join("open.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\n").unwrap();
    write_mesh(&cuboid(DVec3::ZERO, DVec3::ONE), dir.join("cube.obj")).unwrap();
    let part = |material: &str| format!("[[solid]]\nname = \"part\"\n{BALL}\nmaterial = {{ {material} }}\n");
    // (scene text, where the error is, the solid, words of the message)
    let cases: Vec<(String, &str, Option<&str>, Vec<&str>)> = vec![
        (part("color = \"red\""), "\"red\"", Some("part"), vec!["invalid colour", COLOR_FORMS]),
        (part("color = 0.5"), "0.5", Some("part"), vec!["expected a colour", COLOR_FORMS]),
        (part("color = [0.5, 0.5]"), "[0.5, 0.5]", Some("part"), vec!["2 components", COLOR_FORMS]),
        (part("color = { rbg = [1, 0, 0] }"), "{ rbg", Some("part"), vec!["unknown model `rbg`", COLOR_FORMS]),
        (part("color = \"#12345g\""), "\"#12345g\"", Some("part"), vec!["#12345g", COLOR_FORMS]),
        (part("color = [1.5, 0, 0]"), "[1.5", Some("part"), vec!["component 1.5", "outside 0..1"]),
        (part("color = { cmy = [0, -0.1, 0] }"), "{ cmy", Some("part"), vec!["component -0.1", "outside 0..1"]),
        (part("color = { hsi = [400, 0.5, 0.5] }"), "{ hsi", Some("part"), vec!["hue 400", "0..360"]),
        // I (1 + S cos 0 / cos 60) = 0.9 (1 + 2) > 1: that saturation is out of reach.
        (part("color = { hsi = [0, 1, 0.9] }"), "{ hsi", Some("part"), vec!["hsi [0.0, 1.0, 0.9] gives rgb", "outside 0..1"]),
        (
            part("texture = { checker = { size = 1, a = [1, 1, 1], b = [0, 0, 2] } }"),
            "[0, 0, 2]",
            Some("part"),
            vec!["component 2", "outside 0..1"],
        ),
        (
            "[[solid]]\nname = \"drilled\"\nshape = { difference = [\n  { box = { center = [0, 0, 0], size = [2, 2, 2] } },\n  { sphere = { center = [0, 0, 0], radius = -1 } },\n] }\n".into(),
            "{ sphere = { center = [0, 0, 0], radius = -1",
            Some("drilled"),
            vec!["invalid radius: -1"],
        ),
        (
            "[[solid]]\nname = \"ring\"\nshape = { torus = { center = [0, 0, 0], axis = \"z\", radius = 1, tube = 2 } }\n".into(),
            "{ torus",
            Some("ring"),
            vec!["tube radius"],
        ),
        ("[[solid]]\nname = \"none\"\nshape = { union = [] }\n".into(), "{ union", Some("none"), vec!["at least one operand"]),
        (
            format!("[[light]]\ntype = \"point\"\nposition = [1, 1, 1]\ncolor = [2, 2, 2]\n\n[[solid]]\n{BALL}\n"),
            "[2, 2, 2]",
            None,
            vec!["component 2"],
        ),
        (format!("[image]\nbackground = \"#zz0000\"\n\n[[solid]]\n{BALL}\n"), "\"#zz0000\"", None, vec![COLOR_FORMS]),
    ];
    for (i, (text, needle, solid, words)) in cases.iter().enumerate() {
        let (path, e) = error(&dir, &format!("refused{i}.toml"), text);
        let message = e.to_string();
        let cause = scene_cause(e, &path, text, Some(needle), *solid);
        assert!(matches!(cause, Error::Toml { .. }), "case {i}: {cause:?}");
        for word in words {
            assert!(message.contains(word), "case {i}: {message:?} lacks {word:?}");
        }
    }
    // Refused while building: at the key that names what failed.
    let built: Vec<(String, &str, Vec<&str>)> = vec![
        (
            "[[solid]]\nname = \"part\"\nshape = { union = [{ mesh = \"gone.obj\" }] }\n".into(),
            "{ union",
            vec!["gone.obj", "No such file"],
        ),
        (
            "[[solid]]\nname = \"part\"\nshape = { difference = [{ mesh = \"open.obj\" }, { sphere = { center = [0, 0, 0], radius = 0.1 } }] }\n".into(),
            "{ difference",
            vec!["open.obj", "closed", "3 boundary"],
        ),
        (
            "[[solid]]\nname = \"part\"\nmesh = \"cube.obj\"\ntransform = { rotate_degrees = 30 }\n".into(),
            "{ rotate_degrees",
            vec!["rotate_axis and rotate_degrees together"],
        ),
        (
            "[[solid]]\nname = \"part\"\nmesh = \"cube.obj\"\ntransform = { scale = [1, 0, 1] }\n".into(),
            "{ scale",
            vec!["not finite and invertible"],
        ),
        ("[[solid]]\nname = \"part\"\nmesh = \"cube.obj\"\nmaterial = { ka = 2 }\n".into(), "{ ka", vec!["invalid ka"]),
        (
            "[[solid]]\nname = \"part\"\nmesh = \"cube.obj\"\nmaterial = { emission = [1, -0.5, 0] }\n".into(),
            "{ emission",
            vec!["invalid emission"],
        ),
        (
            "[[solid]]\nname = \"part\"\nshape = { half_space = { normal = [0, 0, 1], offset = 0 } }\n".into(),
            "{ half_space",
            vec!["unbounded"],
        ),
        (format!("[[solid]]\nname = \"part\"\n{BALL}\nmesh = \"cube.obj\"\n"), "[[solid]]", vec!["exactly one of"]),
        // A mesh's keys on a shape: they used to be dropped without a word.
        (format!("[[solid]]\nname = \"part\"\n{BALL}\ndepth = 3\n"), "3", vec!["only a mesh solid", "depth"]),
        (
            format!("[[solid]]\nname = \"part\"\n{BALL}\ninside = \"winding\"\n"),
            "\"winding\"",
            vec!["only a mesh solid", "inside rule"],
        ),
    ];
    for (i, (text, needle, words)) in built.iter().enumerate() {
        let (path, e) = error(&dir, &format!("built{i}.toml"), text);
        let message = e.to_string();
        let cause = scene_cause(e, &path, text, Some(needle), Some("part"));
        assert!(!matches!(cause, Error::Toml { .. }), "case {i}: {cause:?}");
        for word in words {
            assert!(message.contains(word), "case {i}: {message:?} lacks {word:?}");
        }
    }
}

#[test]
fn half_a_domain_and_a_light_pointing_nowhere_are_refused() {
    // Each used to be dropped without a word: the domain fitted around the shapes, the
    // light lighting nothing.
    let dir = scratch("halves");
    for (text, words) in [
        (format!("[domain]\nmin = [0, 0, 0]\n\n[[solid]]\n{BALL}\n"), ["min without edge", "give both"]),
        (format!("[domain]\nedge = 4\n\n[[solid]]\n{BALL}\n"), ["edge without min", "give both"]),
        (
            format!("[[light]]\ntype = \"directional\"\ndirection = [0, 0, 0]\n\n[[solid]]\n{BALL}\n"),
            ["direction [0, 0, 0]", "points nowhere"],
        ),
    ] {
        let (path, e) = error(&dir, "half.toml", &text);
        let message = e.to_string();
        assert!(message.starts_with(&format!("{}:", path.display())), "{message}");
        for word in words {
            assert!(message.contains(word), "{message:?} lacks {word:?}");
        }
    }
}

#[test]
fn a_camera_looking_nowhere_is_refused_at_its_key() {
    // A zero up or view left the eye at the target; the camera's error blamed the eye
    // and gave no place.
    let dir = scratch("camera");
    for key in ["up", "view"] {
        let text = format!("[camera]\n{key} = [0, 0, 0]\n\n[[solid]]\n{BALL}\n");
        let (path, e) = error(&dir, "camera.toml", &text);
        let cause = scene_cause(e, &path, &text, Some("[0, 0, 0]"), None);
        assert!(cause.to_string().contains("points nowhere"), "{cause}");
    }
}

#[test]
fn render_settings_out_of_range_are_refused_at_their_value() {
    // They used to pass the reader and fail when the render began, with no place.
    let dir = scratch("image");
    for (key, value, words) in [
        ("max_depth", "100000000", "above the limit of 64"),
        ("cutoff", "-1", "outside 0..=1"),
        ("aa_depth", "100", "outside 1..="),
        ("aa_depth", "0", "outside 1..="),
        ("aa_threshold", "-1", "anti-aliasing threshold -1 must be at least 0"),
    ] {
        let text = format!("[image]\n{key} = {value}\n\n[[solid]]\n{BALL}\n");
        let (path, e) = error(&dir, "image.toml", &text);
        let cause = scene_cause(e, &path, &text, Some(&format!("= {value}")[2..]), None);
        assert!(cause.to_string().contains(words), "{key}: {cause}");
    }
}

#[test]
fn a_missing_mesh_keeps_its_io_error_and_the_solids_name() {
    let dir = scratch("missing");
    let text = "[[solid]]\nname = \"bunny\"\nmesh = \"missing.obj\"\n";
    let (path, e) = error(&dir, "mesh.toml", text);
    match scene_cause(e, &path, text, Some("\"missing.obj\""), Some("bunny")) {
        Error::Io { path, source } => {
            assert_eq!(path, dir.join("missing.obj"));
            assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
        }
        other => panic!("not an I/O error: {other:?}"),
    }
    // Unnamed solids are named by their place; a missing texture is an I/O error too.
    let text = format!(
        "[[solid]]\n{BALL}\n\n[[solid]]\n{BALL}\nmaterial = {{ texture = {{ image = {{ file = \"gone.png\", mapping = \"planar\" }} }} }}\n"
    );
    let (path, e) = error(&dir, "texture.toml", &text);
    let cause = scene_cause(e, &path, &text, Some("{ texture"), Some("solid 2"));
    assert!(matches!(cause, Error::Io { path, .. } if path.ends_with("gone.png")));
}

#[test]
fn a_folder_or_a_device_as_a_mesh_and_a_scene_not_utf8_are_refused_at_their_place() {
    let dir = scratch("not-files");
    std::fs::create_dir_all(dir.join("d.obj")).unwrap();
    for mesh in ["d.obj", "/dev/zero"] {
        let text = format!("[[solid]]\nname = \"m\"\nmesh = \"{mesh}\"\n");
        let (path, e) = error(&dir, "mesh.toml", &text);
        match scene_cause(e, &path, &text, Some(&format!("\"{mesh}\"")), Some("m")) {
            Error::Io { source, .. } => assert!(source.to_string().contains("not a regular file"), "{source}"),
            other => panic!("not an I/O error: {other:?}"),
        }
    }
    // A byte that is not UTF-8 on line 3, column 3.
    let path = dir.join("latin1.toml");
    std::fs::write(&path, b"[[solid]]\nname = \"m\"\n# \xff\n").unwrap();
    let e = read_scene(&path, MemoryBudget::default()).err().expect("refused");
    let cause = scene_cause_at(e, &path, Some((3, 3)), None);
    assert!(cause.to_string().contains("0xff is not UTF-8"), "{cause}");
}

#[test]
fn an_over_budget_solid_keeps_over_budget() {
    let dir = scratch("budget");
    let small = MemoryBudget(1 << 10);
    let text = format!("[domain]\ndepth = 8\n\n[[solid]]\nname = \"ball\"\n{BALL}\n");
    let (path, loaded) = load(&dir, "shape.toml", &text, small);
    let cause = scene_cause(loaded.err().expect("refused"), &path, &text, Some("{ sphere"), Some("ball"));
    assert!(matches!(cause, Error::OverBudget { budget: 1024, .. }), "{cause:?}");
    // The same refusal of an .oct file the scene names.
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let tree = voxelize(&Sphere::new(DVec3::ZERO, 0.9).unwrap(), domain, &VoxelizeOptions::default()).unwrap();
    oct::write(&tree, dir.join("ball.oct")).unwrap();
    let text = "[[solid]]\noct = \"ball.oct\"\n";
    let (path, loaded) = load(&dir, "oct.toml", text, small);
    let cause = scene_cause(loaded.err().expect("refused"), &path, text, Some("\"ball.oct\""), Some("solid 1"));
    assert!(matches!(cause, Error::OverBudget { budget: 1024, .. }), "{cause:?}");
    // Within the budget it loads.
    let (_, loaded) = load(&dir, "oct.toml", text, MemoryBudget::default());
    assert_eq!(loaded.unwrap().scene.solids[0].tree, tree);
}

#[test]
fn a_corrupt_file_keeps_its_format_error() {
    let dir = scratch("corrupt");
    std::fs::write(dir.join("junk.oct"), b"not an octree at all, just some text").unwrap();
    let text = "[[solid]]\nname = \"junk\"\noct = \"junk.oct\"\n";
    let (path, e) = error(&dir, "junk.toml", text);
    let cause = scene_cause(e, &path, text, Some("\"junk.oct\""), Some("junk"));
    assert!(matches!(cause, Error::Format { path, .. } if path.ends_with("junk.oct")));
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let text = "[[solid]]\nmesh = \"bad.obj\"\n";
    let (path, e) = error(&dir, "obj.toml", text);
    assert!(matches!(scene_cause(e, &path, text, Some("\"bad.obj\""), Some("solid 1")), Error::Parse { line: 4, .. }));
}

/// The material colours of a scene whose solids are balls of the given materials.
fn colours(dir: &Path, name: &str, materials: &[&str]) -> Vec<DVec3> {
    let text: String = materials.iter().map(|m| format!("[[solid]]\n{BALL}\nmaterial = {{ {m} }}\n\n")).collect();
    let (_, loaded) = load(dir, name, &text, MemoryBudget::default());
    loaded.unwrap().scene.solids.iter().map(|s| s.material.color).collect()
}

#[test]
fn colour_forms_parse_to_their_rgb() {
    let dir = scratch("colours");
    // (form, linear RGB by hand)
    let cases = [
        ("[0.25, 0.5, 1]", DVec3::new(0.25, 0.5, 1.0)),
        ("{ rgb = [0.25, 0.5, 1] }", DVec3::new(0.25, 0.5, 1.0)),
        // cmy = 1 - rgb.
        ("{ cmy = [0.25, 0.5, 1] }", DVec3::new(0.75, 0.5, 0.0)),
        ("\"#ff8000\"", DVec3::new(1.0, 128.0 / 255.0, 0.0)),
        ("\"#0A141e\"", DVec3::new(10.0, 20.0, 30.0) / 255.0),
        // HSI by the sector formulas: H = 60 in the first sector, B = I (1 - S) = 0.2,
        // R = I (1 + S cos 60 / cos 0) = 0.5, G = 3 I - R - B = 0.5.
        ("{ hsi = [60, 0.5, 0.4] }", DVec3::new(0.5, 0.5, 0.2)),
        // H = 120 starts the second sector: R = I (1 - S) = 0.2, G = I (1 + S / cos 60) = 0.8.
        ("{ hsi = [120, 0.5, 0.4] }", DVec3::new(0.2, 0.8, 0.2)),
        // H = 240: G = I (1 - S) = 0.3, B = I (1 + S / cos 60) = 0.6, R = 0.3.
        ("{ hsi = [240, 0.25, 0.4] }", DVec3::new(0.3, 0.3, 0.6)),
        // Grey: no saturation, every channel the intensity, whatever the hue.
        ("{ hsi = [300, 0, 0.7] }", DVec3::splat(0.7)),
    ];
    let materials: Vec<String> = cases.iter().map(|(form, _)| format!("color = {form}")).collect();
    let got = colours(&dir, "forms.toml", &materials.iter().map(String::as_str).collect::<Vec<_>>());
    for ((form, want), got) in cases.iter().zip(got) {
        assert!((got - *want).abs().max_element() < 1e-12, "{form}: {got} vs {want}");
    }
    // Textures, lights, the ambient light and the background take the same forms.
    let text = format!(
        "ambient = {{ cmy = [0.5, 0.5, 0.5] }}\n[image]\nbackground = \"#336699\"\n\n[[light]]\ntype = \"directional\"\n\
         direction = [0, 0, -1]\ncolor = {{ hsi = [0, 0, 0.8] }}\n\n[[solid]]\n{BALL}\n\
         material = {{ texture = {{ checker = {{ size = 1, a = \"#ffffff\", b = {{ cmy = [1, 1, 1] }} }} }} }}\n"
    );
    let (_, loaded) = load(&dir, "others.toml", &text, MemoryBudget::default());
    let scene = loaded.unwrap().scene;
    assert_eq!(scene.ambient, DVec3::splat(0.5));
    assert_eq!(scene.background, DVec3::new(0x33 as f64, 0x66 as f64, 0x99 as f64) / 255.0);
    assert!(
        matches!(scene.lights[..], [Light::Directional { color, .. }] if (color - DVec3::splat(0.8)).length() < 1e-12)
    );
    let texture = format!("{:?}", scene.solids[0].material.texture);
    assert!(texture.contains("a: DVec3(1.0, 1.0, 1.0), b: DVec3(0.0, 0.0, 0.0)"), "{texture}");
}

/// Writes the closed mesh of the box `center`, `size` to `dir/name`.
fn write_box(dir: &Path, name: &str, center: DVec3, size: DVec3) {
    write_mesh(&cuboid(center, size), dir.join(name)).unwrap();
}

#[test]
fn a_transformed_mesh_solid_has_the_volume_of_the_transformed_mesh() {
    let dir = scratch("mesh-transform");
    let (center, size) = (DVec3::new(0.1, 0.2, -0.3), DVec3::new(1.0, 0.8, 0.6));
    write_box(&dir, "box.obj", center, size);
    let depth = 6;
    let (cos, sin) = (30f64.to_radians().cos(), 30f64.to_radians().sin());
    // (transform, its scale, inside rule, where the box's centre goes); the winding rule,
    // unlike parity, would see a mirrored mesh turned inside out.
    let cases = [
        ("scale = [2, 2, 2]", DVec3::splat(2.0), "auto", center * 2.0),
        ("scale = [-2, 2, 2], translate = [5, 0, 0]", DVec3::new(-2.0, 2.0, 2.0), "auto", DVec3::new(4.8, 0.4, -0.6)),
        (
            "scale = [-2, 2, 2], translate = [5, 0, 0]",
            DVec3::new(-2.0, 2.0, 2.0),
            "winding",
            DVec3::new(4.8, 0.4, -0.6),
        ),
        (
            "scale = [2, 1, 1], rotate_axis = [0, 0, 1], rotate_degrees = 30, translate = [0, 0, 1]",
            DVec3::new(2.0, 1.0, 1.0),
            "auto",
            DVec3::new(0.2 * cos - 0.2 * sin, 0.2 * sin + 0.2 * cos, 0.7),
        ),
    ];
    for (transform, scale, inside, moved_center) in cases {
        let text = format!(
            "[[solid]]\nmesh = \"box.obj\"\ndepth = {depth}\ninside = \"{inside}\"\ntransform = {{ {transform} }}\n"
        );
        let (_, loaded) = load(&dir, "moved.toml", &text, MemoryBudget::default());
        let tree = loaded.unwrap().scene.solids.remove(0).tree;
        // The analytic volume and area of the moved box (a rotation keeps both).
        let edges = (size * scale).abs();
        let want = edges.x * edges.y * edges.z;
        let area = 2.0 * (edges.x * edges.y + edges.y * edges.z + edges.x * edges.z);
        // Centre sampling errs only in voxels the surface crosses, within sqrt(3) h / 2
        // of it: at most the shell of area x sqrt(3) h (1.8 for the edges' share).
        let h = tree.domain().voxel_size();
        let bound = 1.8 * area * h;
        assert!((tree.volume() - want).abs() < bound, "{transform}: {} vs {want} (bound {bound})", tree.volume());
        let b = tree.bounds().unwrap();
        assert!((b.center() - moved_center).abs().max_element() < 2.0 * h, "{transform}: centre {}", b.center());
    }
}

#[test]
fn a_transformed_oct_solid_moves_exactly_or_resamples() {
    let dir = scratch("oct-transform");
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let box_shape = Cuboid::new(DVec3::new(0.1, 0.0, 0.0), DVec3::new(1.2, 0.7, 0.5)).unwrap();
    let tree = voxelize(&box_shape, domain, &VoxelizeOptions::default()).unwrap();
    oct::write(&tree, dir.join("box.oct")).unwrap();
    let moved = |transform: &str| -> LinearOctree {
        let text = format!("[[solid]]\noct = \"box.oct\"\ntransform = {{ {transform} }}\n");
        let (_, loaded) = load(&dir, "moved.toml", &text, MemoryBudget::default());
        loaded.unwrap().scene.solids.remove(0).tree
    };
    // A translation by a fraction of a voxel and a uniform scale move the domain, not the keys.
    let shifted = moved("scale = [3, 3, 3], translate = [0.3, 0, -7]");
    assert_eq!(shifted.keys(), tree.keys());
    assert_eq!(*shifted.domain(), Domain::new(DVec3::new(-2.7, -3.0, -10.0), 6.0, 6).unwrap());
    // A quarter turn about z: the voxel (x, y, z) of the box is at (-y, x, z).
    let turned = moved("rotate_axis = [0, 0, 1], rotate_degrees = 90");
    assert_eq!(turned.voxel_count(), tree.voxel_count());
    for v in [[40u32, 30, 33], [20, 30, 30], [36, 40, 31]] {
        let p = domain.voxel_center(v);
        let image = DVec3::new(-p.y, p.x, p.z);
        assert_eq!(turned.contains_point(image), tree.contains_voxel(v), "{v:?}");
    }
    // An eighth turn is resampled: the volume within a voxel layer of the box's area.
    let eighth = moved("rotate_axis = [0, 0, 1], rotate_degrees = 45");
    let h = domain.voxel_size();
    let area = 2.0 * (1.2 * 0.7 + 0.7 * 0.5 + 1.2 * 0.5);
    assert!((eighth.volume() - tree.volume()).abs() < 1.8 * area * h, "{} vs {}", eighth.volume(), tree.volume());
}

#[test]
fn a_csg_scene_of_a_shape_a_mesh_and_an_oct_is_the_predicate_voxel_by_voxel() {
    let dir = scratch("mixed");
    // The .oct: a slab voxelized in the scene's domain, so the scene samples it exactly.
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let (slab_center, slab_size) = (DVec3::new(-0.2, 0.1, -0.5), DVec3::new(1.4, 1.1, 0.3));
    let slab = Cuboid::new(slab_center, slab_size).unwrap();
    oct::write(&voxelize(&slab, domain, &VoxelizeOptions::default()).unwrap(), dir.join("slab.oct")).unwrap();
    let (cube_center, cube_size) = (DVec3::new(0.13, 0.07, 0.21), DVec3::new(0.9, 0.8, 0.7));
    write_box(&dir, "cube.obj", cube_center, cube_size);
    let (ball_center, radius) = (DVec3::new(0.3, 0.2, 0.1), 0.45);
    // 0.25 is eight voxels: the moved slab is still sampled at its voxel centres.
    let text = format!(
        "[domain]\nmin = [-1, -1, -1]\nedge = 2\ndepth = 6\n\n[[solid]]\nname = \"mixed\"\nshape = {{ difference = [\n  \
         {{ union = [\n    {{ mesh = \"cube.obj\" }},\n    {{ transform = {{ shape = {{ oct = \"slab.oct\" }}, translate = [0.25, 0, 0] }} }},\n  ] }},\n  \
         {{ sphere = {{ center = [{}, {}, {}], radius = {radius} }} }},\n] }}\n",
        ball_center.x, ball_center.y, ball_center.z
    );
    let (_, loaded) = load(&dir, "mixed.toml", &text, MemoryBudget::default());
    let got = loaded.unwrap().scene.solids.remove(0).tree;
    // The oracle: the analytic predicate at every voxel centre.
    let in_box = |p: DVec3, c: DVec3, s: DVec3| ((p - c).abs() - s * 0.5).max_element() <= 0.0;
    let n = domain.resolution();
    let voxels = (0..n).flat_map(|z| (0..n).flat_map(move |y| (0..n).map(move |x| [x, y, z]))).filter(|&v| {
        let p = domain.voxel_center(v);
        let solid = in_box(p, cube_center, cube_size) || in_box(p - DVec3::new(0.25, 0.0, 0.0), slab_center, slab_size);
        solid && (p - ball_center).length_squared() > radius * radius
    });
    let want = LinearOctree::from_voxels(domain, voxels).unwrap();
    assert!(want.voxel_count() > 5000, "{}", want.voxel_count());
    assert_eq!(got, want, "{} voxels differ", (&got ^ &want).voxel_count());
}

/// A scene of one ball whose `[image]` table holds `image`.
fn ball_scene(image: &str) -> String {
    format!("[image]\n{image}\n\n[[solid]]\nshape = {{ sphere = {{ center = [0, 0, 0], radius = 1 }} }}\n")
}

#[test]
fn anti_aliasing_keys_choose_uniform_adaptive_or_recursive() {
    let dir = scratch("aa");
    let aa = |image: &str| load(&dir, "aa.toml", &ball_scene(image), MemoryBudget::default()).1.unwrap().options.aa;
    assert_eq!(aa(""), AntiAliasing::Uniform);
    assert_eq!(aa("aa = \"adaptive\""), AntiAliasing::Adaptive { threshold: DEFAULT_AA_THRESHOLD });
    assert_eq!(aa("aa_threshold = 0.1"), AntiAliasing::Adaptive { threshold: 0.1 });
    assert_eq!(aa("aa = \"adaptive\"\naa_threshold = 0"), AntiAliasing::Adaptive { threshold: 0.0 });
    assert_eq!(aa("aa = \"uniform\"\naa_threshold = 0.1"), AntiAliasing::Uniform);
    let recursive = |threshold, depth| AntiAliasing::Recursive { threshold, depth };
    assert_eq!(aa("aa = \"recursive\""), recursive(DEFAULT_AA_THRESHOLD, DEFAULT_AA_DEPTH));
    assert_eq!(aa("aa_depth = 2"), recursive(DEFAULT_AA_THRESHOLD, 2));
    assert_eq!(aa("aa_depth = 4\naa_threshold = 0.2"), recursive(0.2, 4));
    assert_eq!(aa("aa = \"adaptive\"\naa_depth = 4"), AntiAliasing::Adaptive { threshold: DEFAULT_AA_THRESHOLD });
    let text = ball_scene("aa = \"jittered\"");
    let (path, e) = error(&dir, "aa.toml", &text);
    let cause = scene_cause(e, &path, &text, Some("\"jittered\""), None);
    let cause = cause.to_string();
    assert!(["uniform", "adaptive", "recursive"].iter().all(|k| cause.contains(k)), "{cause}");
}

#[test]
fn the_cutoff_key_sets_the_share_below_which_rays_stop() {
    let dir = scratch("cutoff");
    let cutoff = |image: &str| {
        load(&dir, "cutoff.toml", &ball_scene(image), MemoryBudget::default()).1.unwrap().options.shade.cutoff
    };
    assert_eq!(cutoff(""), RenderOptions::default().shade.cutoff);
    assert_eq!(cutoff("cutoff = 0.0039"), 0.0039);
}

/// Writes a scene of every kind of solid the cache keeps into `dir` as `name`: a shape
/// whose CSG tree reads a mesh and an `.oct` file, a mesh solid, and a moved `.oct`
/// solid. Returns its path.
fn write_cached_scene(dir: &Path, name: &str) -> PathBuf {
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let slab = Cuboid::new(DVec3::new(-0.2, 0.1, -0.5), DVec3::new(1.4, 1.1, 0.3)).unwrap();
    oct::write(&voxelize(&slab, domain, &VoxelizeOptions::default()).unwrap(), dir.join("slab.oct")).unwrap();
    write_box(dir, "cube.obj", DVec3::new(0.13, 0.07, 0.21), DVec3::new(0.9, 0.8, 0.7));
    let text = "[domain]\nmin = [-1, -1, -1]\nedge = 2\ndepth = 6\n\n\
        [[solid]]\nname = \"mixed\"\nshape = { difference = [\n  \
        { union = [{ mesh = \"cube.obj\" }, { oct = \"slab.oct\" }] },\n  \
        { sphere = { center = [0.3, 0.2, 0.1], radius = 0.45 } },\n] }\n\n\
        [[solid]]\nname = \"meshed\"\nmesh = \"cube.obj\"\ndepth = 5\ntransform = { translate = [3, 0, 0] }\n\n\
        [[solid]]\nname = \"moved\"\noct = \"slab.oct\"\ntransform = { rotate_axis = [0, 0, 1], rotate_degrees = 30 }\n";
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Loads `path` with the solid cache and `budget`.
fn load_cached(path: &Path, budget: MemoryBudget) -> Result<SceneFile> {
    read_scene_with(path, &SceneReadOptions { budget, cache: CachePolicy::ReadWrite, ..Default::default() })
}

/// The solids' octrees of a loaded scene.
fn trees(file: &SceneFile) -> Vec<LinearOctree> {
    file.scene.solids.iter().map(|s| s.tree.clone()).collect()
}

/// The cache entries in `dir`'s cache folder, sorted.
fn entries(dir: &Path) -> Vec<PathBuf> {
    let Ok(read) = std::fs::read_dir(dir.join(CACHE_DIR)) else { return Vec::new() };
    let mut found: Vec<PathBuf> =
        read.map(|e| e.unwrap().path()).filter(|p| p.extension().is_some_and(|x| x == "octcache")).collect();
    found.sort();
    found
}

#[test]
fn a_second_load_reads_every_solid_from_the_cache_bit_for_bit() {
    let dir = scratch("cache-hit");
    let path = write_cached_scene(&dir, "cached.toml");
    // The oracle: the scene built without the cache.
    let want = trees(&read_scene(&path, MemoryBudget::default()).unwrap());
    assert!(entries(&dir).is_empty(), "read_scene writes no cache");
    let first = load_cached(&path, MemoryBudget::default()).unwrap();
    assert_eq!((first.cache.hits, first.cache.misses), (0, 3));
    assert_eq!(entries(&dir).len(), 3);
    assert!(dir.join(CACHE_DIR).join("CACHEDIR.TAG").is_file());
    let second = load_cached(&path, MemoryBudget::default()).unwrap();
    assert_eq!((second.cache.hits, second.cache.misses), (3, 0));
    assert!(second.warnings.is_empty(), "{:?}", second.warnings);
    assert_eq!(trees(&first), want);
    assert_eq!(trees(&second), want);
    for tree in trees(&second) {
        tree.validate().unwrap();
    }
}

#[test]
fn a_solid_read_from_the_cache_is_not_voxelized() {
    // A budget below the voxelizer's estimate but above what reading the entry needs:
    // a load without the cache is refused before voxelizing, one from the cache works.
    let dir = scratch("cache-no-voxelizing");
    let path = dir.join("ball.toml");
    let text = "[domain]\nmin = [-1, -1, -1]\nedge = 2\ndepth = 7\n\n[[solid]]\nshape = { sphere = { center = [0.1, 0, 0], radius = 0.5 } }\n";
    std::fs::write(&path, text).unwrap();
    let first = load_cached(&path, MemoryBudget::default()).unwrap();
    let tree = first.scene.solids[0].tree.clone();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 7).unwrap();
    let estimate = estimate_bytes(&Sphere::new(DVec3::new(0.1, 0.0, 0.0), 0.5).unwrap(), &domain);
    let tight = MemoryBudget(estimate - 1);
    let entry_bytes = std::fs::metadata(&entries(&dir)[0]).unwrap().len();
    assert!(tree.node_count() as u64 * 8 < tight.0 && entry_bytes < tight.0, "the test needs room to read the entry");
    match read_scene(&path, tight) {
        Err(Error::Scene { source, .. }) => assert!(matches!(*source, Error::OverBudget { .. }), "{source}"),
        other => panic!("voxelizing under the tight budget should be refused: {:?}", other.err()),
    }
    let cached = load_cached(&path, tight).unwrap();
    assert_eq!(cached.cache.hits, 1);
    assert_eq!(cached.scene.solids[0].tree, tree);
}

#[test]
fn a_changed_input_is_built_again() {
    let dir = scratch("cache-invalidated");
    let path = write_cached_scene(&dir, "cached.toml");
    load_cached(&path, MemoryBudget::default()).unwrap();
    let check = |misses: usize, what: &str| {
        let got = load_cached(&path, MemoryBudget::default()).unwrap();
        assert_eq!((got.cache.hits, got.cache.misses), (3 - misses, misses), "{what}");
        assert_eq!(trees(&got), trees(&read_scene(&path, MemoryBudget::default()).unwrap()), "{what}");
        // Entries of the earlier inputs are gone: one a solid.
        assert_eq!(entries(&dir).len(), 3, "{what}");
    };
    // The mesh edited in place to the same length (one vertex coordinate's digit):
    // the shape reading it and the mesh solid.
    let obj = std::fs::read_to_string(dir.join("cube.obj")).unwrap();
    let at = obj.find("\nv ").unwrap()
        + 3
        + obj[obj.find("\nv ").unwrap() + 3..].find(|c: char| c.is_ascii_digit()).unwrap();
    let mut edited = obj.clone().into_bytes();
    edited[at] = if edited[at] == b'1' { b'2' } else { b'1' };
    std::fs::write(dir.join("cube.obj"), &edited).unwrap();
    assert_eq!(edited.len(), obj.len());
    check(2, "mesh edited");
    // The .oct file: the shape reading it and the moved solid.
    let slab = Cuboid::new(DVec3::new(-0.1, 0.1, -0.5), DVec3::new(1.4, 1.1, 0.3)).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    oct::write(&voxelize(&slab, domain, &VoxelizeOptions::default()).unwrap(), dir.join("slab.oct")).unwrap();
    check(2, "oct file rewritten");
    // The scene's text of one solid: that solid only; of the domain every shape shares:
    // the shape solid; of what does not decide a solid (a material, a name): none.
    let edits = [
        ("radius = 0.45", "radius = 0.4", 1),
        ("rotate_degrees = 30", "rotate_degrees = 31", 1),
        ("edge = 2\n", "edge = 2.5\n", 1),
        ("name = \"meshed\"", "name = \"renamed\"\nmaterial = { kd = 0.5 }", 0),
    ];
    for (from, to, misses) in edits {
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, text.replace(from, to)).unwrap();
        check(misses, from);
    }
}

#[test]
fn a_shape_written_as_sub_tables_is_built_again_when_a_value_changes() {
    // Regression: the key once held the scene's text of the `shape` value, and the span
    // of a shape written as `[solid.shape.sphere]` sub-tables does not cover its keys,
    // so a changed radius read the old solid (with a fixed [domain], which does not
    // change with it).
    let dir = scratch("cache-sub-tables");
    let path = dir.join("ball.toml");
    let text = "[domain]\nmin = [-2, -2, -2]\nedge = 4\ndepth = 6\n\n[[solid]]\nname = \"b\"\n\n\
                [solid.shape.sphere]\ncenter = [0, 0, 0]\nradius = 1\n\n[solid.transform]\ntranslate = [0.5, 0, 0]\n";
    std::fs::write(&path, text).unwrap();
    assert_eq!(load_cached(&path, MemoryBudget::default()).unwrap().cache.misses, 1);
    for (from, to) in [("radius = 1", "radius = 0.5"), ("translate = [0.5, 0, 0]", "translate = [0.25, 0, 0]")] {
        let text = std::fs::read_to_string(&path).unwrap();
        std::fs::write(&path, text.replace(from, to)).unwrap();
        let got = load_cached(&path, MemoryBudget::default()).unwrap();
        assert_eq!((got.cache.hits, got.cache.misses), (0, 1), "{to}");
        assert_eq!(trees(&got), trees(&read_scene(&path, MemoryBudget::default()).unwrap()), "{to}");
    }
    // Written inline instead, the same values: the same key.
    let inline = "[domain]\nmin = [-2, -2, -2]\nedge = 4\ndepth = 6\n\n[[solid]]\nname = \"b\"\n\
                  shape = { sphere = { center = [0, 0, 0], radius = 0.5 } }\ntransform = { translate = [0.25, 0, 0] }\n";
    std::fs::write(&path, inline).unwrap();
    assert_eq!(load_cached(&path, MemoryBudget::default()).unwrap().cache.hits, 1);
}

#[test]
fn a_corrupt_cache_entry_is_ignored_and_rewritten() {
    let dir = scratch("cache-corrupt");
    let path = write_cached_scene(&dir, "cached.toml");
    let want = trees(&read_scene(&path, MemoryBudget::default()).unwrap());
    load_cached(&path, MemoryBudget::default()).unwrap();
    /// What a corruption does to an entry's bytes.
    type Corrupt = fn(&mut Vec<u8>);
    let corruptions: [(&str, Corrupt); 5] = [
        ("a payload byte flipped", |b| *b.last_mut().unwrap() ^= 0x40),
        ("a key byte flipped", |b| b[20] ^= 1),
        ("truncated", |b| b.truncate(b.len() / 2)),
        ("empty", Vec::clear),
        ("another file", |b| *b = b"OCTSOLID not an entry".to_vec()),
    ];
    for (what, corrupt) in corruptions {
        for entry in entries(&dir) {
            let mut bytes = std::fs::read(&entry).unwrap();
            corrupt(&mut bytes);
            std::fs::write(&entry, bytes).unwrap();
        }
        let got = load_cached(&path, MemoryBudget::default()).unwrap();
        assert_eq!((got.cache.hits, got.cache.misses), (0, 3), "{what}");
        assert_eq!(trees(&got), want, "{what}");
        assert_eq!(got.warnings.len(), 3, "{what}: {:?}", got.warnings);
        let mut named: Vec<PathBuf> = got.warnings.iter().map(|w| w.path.clone()).collect();
        named.sort();
        assert_eq!(named, entries(&dir), "{what}: each warning names its entry");
        for w in &got.warnings {
            assert!(w.to_string().contains("cache entry not used"), "{what}: {w}");
        }
        // Rewritten: the next load reads them.
        let again = load_cached(&path, MemoryBudget::default()).unwrap();
        assert_eq!((again.cache.hits, again.cache.misses), (3, 0), "{what}");
        assert_eq!(trees(&again), want, "{what}");
    }
}

#[test]
fn clearing_a_scenes_cache_leaves_the_other_scenes() {
    let dir = scratch("cache-clear");
    let (a, b) = (write_cached_scene(&dir, "a.toml"), write_cached_scene(&dir, "a.b.toml"));
    load_cached(&a, MemoryBudget::default()).unwrap();
    load_cached(&b, MemoryBudget::default()).unwrap();
    assert_eq!(entries(&dir).len(), 6);
    assert_eq!(clear_cache(&a).unwrap(), 3);
    assert_eq!(load_cached(&b, MemoryBudget::default()).unwrap().cache.hits, 3);
    assert_eq!(clear_cache(&b).unwrap(), 3);
    assert!(!dir.join(CACHE_DIR).exists(), "an empty cache folder is removed");
    assert_eq!(clear_cache(&b).unwrap(), 0);
}

#[test]
fn emission_is_read_as_given_and_emitters_replace_the_default_lights() {
    let dir = scratch("emission");
    let lamp = format!(
        "[[solid]]\nname = \"lamp\"\n{BALL}\nmaterial = {{ color = [0.5, 0.25, 1], kd = 0.8, emission = [12, 3.5, 0] }}\n"
    );
    let (_, lit) = load(&dir, "lamp.toml", &lamp, MemoryBudget::default());
    let lit = lit.unwrap();
    let m = &lit.scene.solids[0].material;
    assert_eq!(m.emission, DVec3::new(12.0, 3.5, 0.0));
    assert_eq!(m.diffuse_reflectance(), DVec3::new(0.4, 0.2, 0.8));
    assert!(lit.scene.lights.is_empty(), "an emitter is the scene's light");
    let (_, dark) = load(&dir, "dark.toml", &format!("[[solid]]\n{BALL}\n"), MemoryBudget::default());
    let dark = dark.unwrap();
    assert_eq!(dark.scene.solids[0].material.emission, DVec3::ZERO);
    assert_eq!(dark.scene.lights.len(), 2, "no light and no emitter: the default lights");
}

/// `[domain] voxel_size`: the shapes' shared domain on that grid, so dimensions on its
/// multiples are exact; refused beside `min` and `edge`, and when the depth is too small.
#[test]
fn a_scene_domain_by_voxel_size_keeps_dimensions_exact() {
    let dir = scratch("voxel-size");
    let scene = |domain: &str| {
        format!(
            "[domain]\n{domain}\n\n[[solid]]\nshape = {{ box = {{ center = [40, 20, 15], size = [80, 40, 30] }} }}\n"
        )
    };
    let (_, loaded) = load(&dir, "grid.toml", &scene("voxel_size = 0.5"), MemoryBudget::default());
    let file = loaded.unwrap();
    let tree = &file.scene.solids[0].tree;
    assert_eq!(tree.domain().voxel_size(), 0.5);
    let b = tree.bounds().unwrap();
    assert_eq!((b.min, b.max), (DVec3::ZERO, DVec3::new(80.0, 40.0, 30.0)));
    let (path, e) = error(&dir, "both.toml", &scene("voxel_size = 0.5\nmin = [0, 0, 0]\nedge = 100\ndepth = 8"));
    assert!(e.to_string().contains("either min and edge or voxel_size"), "{e}");
    assert!(e.to_string().starts_with(&path.display().to_string()), "{e}");
    let (_, e) = error(&dir, "shallow.toml", &scene("voxel_size = 0.1\ndepth = 8"));
    assert!(e.to_string().contains("use depth 10 or more"), "{e}");
}

/// The one-based line and column of the `n`th (from 0) `needle` in `text`.
fn place_of_nth(text: &str, needle: &str, n: usize) -> (usize, usize) {
    let at = text.match_indices(needle).nth(n).unwrap_or_else(|| panic!("{needle:?} #{n} is not in the scene")).0;
    let before = &text[..at];
    (before.matches('\n').count() + 1, at - before.rfind('\n').map_or(0, |i| i + 1) + 1)
}

#[test]
fn nested_patterns_past_the_copies_and_shapes_past_the_nesting_are_refused_at_their_node() {
    let dir = scratch("nested");
    let ball = "{ sphere = { center = [0.5, 0.5, 0.5], radius = 0.3 } }";
    // Three nested arrays of 100: 1,000,000 copies, refused at the outermost.
    let cubic = format!(
        "[[solid]]\nname = \"balls\"\nshape = {{ array = {{ count = [1, 1, 100], step = [0, 0, 1], shape = {{ array = {{ \
         count = [1, 100, 1], step = [0, 1, 0], shape = {{ array = {{ count = [100, 1, 1], step = [1, 0, 0], shape = \
         {ball} }} }} }} }} }} }}\n"
    );
    let (path, e) = error(&dir, "cubic.toml", &cubic);
    let message = e.to_string();
    scene_cause(e, &path, &cubic, Some("{ array"), Some("balls"));
    assert!(message.contains("1000000 copies"), "{message}");
    // 30 nested mirrors: the 17th from the inside makes 2^17 = 131072 copies.
    let mut shape = ball.to_owned();
    for i in 1..=30 {
        shape = format!("{{ mirror = {{ normal = [{i}, 1, 0], shape = {shape} }} }}");
    }
    let mirrors = format!("[[solid]]\nname = \"mirrors\"\nshape = {shape}\n");
    let (path, e) = error(&dir, "mirrors.toml", &mirrors);
    let message = e.to_string();
    scene_cause_at(e, &path, Some(place_of_nth(&mirrors, "{ mirror", 30 - 17)), Some("mirrors"));
    assert!(message.contains("131072 copies"), "{message}");
    // 70 nested complements: the 65th node from the root is one too deep.
    let mut shape = ball.to_owned();
    for _ in 0..70 {
        shape = format!("{{ complement = {shape} }}");
    }
    let deep = format!("[[solid]]\nname = \"deep\"\nshape = {{ union = [{ball}, {shape}] }}\n");
    let (path, e) = error(&dir, "deep.toml", &deep);
    let message = e.to_string();
    scene_cause_at(e, &path, Some(place_of_nth(&deep, "{ complement", 63)), Some("deep"));
    assert!(message.contains("nested 65 deep; at most 64"), "{message}");
}

/// A scene's `oct = ` solid shades with the surface data its file carries, as the file
/// drawn alone does: its picture is the shape's, near enough, where the same voxels
/// without the data show the octree's estimate (rings on a ball). The scene dropped
/// the data, so a ball saved with its crossings rendered with rings in a scene.
#[test]
fn an_oct_solid_in_a_scene_shades_with_its_files_surface_data() {
    use octsolid::NoProgress;
    use octsolid::render::render;
    use octsolid::surface::HermiteData;
    let dir = scratch("oct-surface");
    let d = Domain::new(DVec3::splat(-1.1), 2.2, 6).unwrap();
    let ball = Sphere::new(DVec3::ZERO, 1.0).unwrap();
    let tree = voxelize(&ball, d, &VoxelizeOptions::default()).unwrap();
    let data = HermiteData::from_shape(&ball, &tree);
    oct::write_with_surface(&tree, &Default::default(), Some(&data), dir.join("with.oct")).unwrap();
    oct::write(&tree, dir.join("without.oct")).unwrap();
    let scene = |solid: &str| {
        format!(
            "[image]\nsize = [96, 96]\nsamples = 1\n\n[domain]\nmin = [-1.1, -1.1, -1.1]\nedge = 2.2\ndepth = 6\n\n\
             [[solid]]\nname = \"ball\"\n{solid}\n"
        )
    };
    let picture = |name: &str, solid: &str| {
        let (_, loaded) = load(&dir, name, &scene(solid), MemoryBudget::default());
        let file = loaded.unwrap();
        render(&file.scene, &file.camera, &file.options, &NoProgress).unwrap().0
    };
    let exact = picture("exact.toml", "shape = { sphere = { center = [0, 0, 0], radius = 1 } }");
    let with = picture("with.toml", "oct = \"with.oct\"");
    let without = picture("without.toml", "oct = \"without.oct\"");
    let off = |a: &image::RgbImage| -> u64 {
        a.as_raw().iter().zip(exact.as_raw()).map(|(&x, &y)| u64::from(x.abs_diff(y))).sum()
    };
    assert!(
        off(&with) * 2 < off(&without),
        "with the data {} off the shape's picture, without {}",
        off(&with),
        off(&without)
    );
    std::fs::remove_dir_all(dir).ok();
}
