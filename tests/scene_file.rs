//! Scene files: every bundled scene loads; a misspelt key or value is a parse error at
//! its file, line and column; a scene that cannot be built keeps the cause's kind (I/O,
//! format, over budget, refused value) with the scene file and the solid's name.

use std::path::{Path, PathBuf};

use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::io::oct;
use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
use octsolid::scene_file::{SceneFile, load_scene};
use octsolid::shape::Sphere;
use octsolid::{Error, Result};

/// A folder of its own for each test (tests run in parallel).
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("octsolid-scenes-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes `text` to `dir/name` and loads it as a scene.
fn load(dir: &Path, name: &str, text: &str, budget: MemoryBudget) -> (PathBuf, Result<SceneFile>) {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    let loaded = load_scene(&path, budget);
    (path, loaded)
}

/// The error of a scene that must fail.
fn error(dir: &Path, name: &str, text: &str) -> (PathBuf, Error) {
    let (path, loaded) = load(dir, name, text, MemoryBudget::default());
    (path, loaded.err().expect("an error"))
}

/// The cause inside the [`Error::Scene`] of a scene that must fail to build, after
/// checking it names `path` and `solid`.
fn scene_cause(e: Error, path: &Path, solid: Option<&str>) -> Error {
    match e {
        Error::Scene { path: p, solid: s, source } => {
            assert_eq!((p.as_path(), s.as_deref()), (path, solid));
            *source
        }
        other => panic!("not a scene error: {other:?}"),
    }
}

const BALL: &str = "shape = { sphere = { center = [0, 0, 0], radius = 1 } }";

#[test]
fn bundled_scenes_load() {
    for name in ["classic", "flange", "showcase", "menger", "displaced", "whitted", "whitted-classic", "teapot"] {
        let file = load_scene(format!("scenes/{name}.toml"), MemoryBudget::default()).unwrap();
        assert!(!file.scene.solids.is_empty() && !file.scene.lights.is_empty(), "{name}");
    }
}

#[test]
fn syntax_errors_and_misspelt_keys_say_line_and_column() {
    let dir = scratch("syntax");
    let (_, e) = error(&dir, "syntax.toml", "[image]\nsize = [640, 480\n");
    let e = e.to_string();
    assert!(e.contains("syntax.toml") && e.contains("line 2") && e.contains("column"), "{e}");
    let (_, e) =
        error(&dir, "field.toml", &format!("[image]\nsize = [64, 48]\n\n[[solid]]\n{BALL}\ncolour = [1, 0, 0]\n"));
    let e = e.to_string();
    assert!(e.contains("line 6") && e.contains("colour"), "{e}");
    let (_, e) = error(&dir, "none.toml", "[image]\nsize = [64, 48]\n");
    assert!(e.to_string().contains("solid"), "{e}");
}

#[test]
fn misspelt_values_are_parse_errors_at_their_place() {
    let dir = scratch("values");
    // (file text, line, column of the value, the misspelling)
    let cases = [
        (format!("[image]\nsize = [64, 48]\nnormals = \"smoth\"\n\n[[solid]]\n{BALL}\n"), 3, 11, "smoth"),
        (format!("[camera]\nprojection = \"ortho\"\n\n[[solid]]\n{BALL}\n"), 2, 14, "ortho"),
        (format!("[[light]]\ntype = \"spot\"\nposition = [1, 1, 1]\n\n[[solid]]\n{BALL}\n"), 2, 8, "spot"),
        ("[[solid]]\nmesh = \"bunny.obj\"\ninside = \"odd\"\n".into(), 3, 10, "odd"),
        (
            "[[solid]]\nshape = { cylinder = { center = [0, 0, 0], axis = \"w\", radius = 1, height = 1 } }\n".into(),
            2,
            51,
            "w",
        ),
        (
            format!(
                "[[solid]]\n{BALL}\nmaterial = {{ texture = {{ image = {{ file = \"t.png\", mapping = \"polar\" }} }} }}\n"
            ),
            3,
            62,
            "polar",
        ),
        (
            format!(
                "[[solid]]\n{BALL}\nmaterial = {{ texture = {{ wood = {{ axis = \"q\", size = 1, a = [1, 1, 1], b = [0, 0, 0] }} }} }}\n"
            ),
            3,
            42,
            "q",
        ),
        ("[[solid]]\nshape = { blob = { radius = 1 } }\n".into(), 2, 11, "blob"),
    ];
    for (i, (text, line, column, word)) in cases.iter().enumerate() {
        let (path, e) = error(&dir, &format!("value{i}.toml"), text);
        match &e {
            Error::Parse { path: p, line: l, reason } => {
                assert_eq!((p, l), (&path, line), "{e}");
                assert!(reason.starts_with(&format!("column {column}: ")), "{e}");
                assert!(reason.contains(&format!("unknown variant `{word}`")), "{e}");
            }
            other => panic!("case {i}: not a parse error: {other}"),
        }
    }
}

#[test]
fn a_missing_mesh_keeps_its_io_error_and_the_solids_name() {
    let dir = scratch("missing");
    let (path, e) = error(&dir, "mesh.toml", "[[solid]]\nname = \"bunny\"\nmesh = \"missing.obj\"\n");
    assert!(e.to_string().contains("mesh.toml: bunny: ") && e.to_string().contains("missing.obj"), "{e}");
    match scene_cause(e, &path, Some("bunny")) {
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
    assert!(matches!(scene_cause(e, &path, Some("solid 2")), Error::Io { path, .. } if path.ends_with("gone.png")));
}

#[test]
fn an_over_budget_solid_keeps_over_budget() {
    let dir = scratch("budget");
    let small = MemoryBudget(1 << 10);
    let text = format!("[domain]\ndepth = 8\n\n[[solid]]\nname = \"ball\"\n{BALL}\n");
    let (path, loaded) = load(&dir, "shape.toml", &text, small);
    let cause = scene_cause(loaded.err().expect("refused"), &path, Some("ball"));
    assert!(matches!(cause, Error::OverBudget { budget: 1024, .. }), "{cause:?}");
    // The same refusal of an .oct file the scene names.
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let tree = voxelize(&Sphere::new(DVec3::ZERO, 0.9).unwrap(), domain, &VoxelizeOptions::default()).unwrap();
    oct::save(&tree, dir.join("ball.oct")).unwrap();
    let (path, loaded) = load(&dir, "oct.toml", "[[solid]]\noct = \"ball.oct\"\n", small);
    let cause = scene_cause(loaded.err().expect("refused"), &path, Some("solid 1"));
    assert!(matches!(cause, Error::OverBudget { budget: 1024, .. }), "{cause:?}");
    // Within the budget it loads.
    let (_, loaded) = load(&dir, "oct.toml", "[[solid]]\noct = \"ball.oct\"\n", MemoryBudget::default());
    assert_eq!(loaded.unwrap().scene.solids[0].tree, tree);
}

#[test]
fn a_corrupt_file_keeps_its_format_error_and_refused_values_their_name() {
    let dir = scratch("corrupt");
    std::fs::write(dir.join("junk.oct"), b"not an octree at all, just some text").unwrap();
    let (path, e) = error(&dir, "junk.toml", "[[solid]]\nname = \"junk\"\noct = \"junk.oct\"\n");
    assert!(matches!(scene_cause(e, &path, Some("junk")), Error::Format { path, .. } if path.ends_with("junk.oct")));
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    let (path, e) = error(&dir, "obj.toml", "[[solid]]\nmesh = \"bad.obj\"\n");
    assert!(matches!(scene_cause(e, &path, Some("solid 1")), Error::Parse { line: 4, .. }));
    let (path, e) = error(&dir, "radius.toml", "[[solid]]\nshape = { sphere = { center = [0, 0, 0], radius = -1 } }\n");
    assert!(matches!(scene_cause(e, &path, Some("solid 1")), Error::InvalidArgument { what: "radius", .. }));
    let (path, e) = error(&dir, "ka.toml", &format!("[[solid]]\n{BALL}\nmaterial = {{ ka = 2 }}\n"));
    assert!(matches!(scene_cause(e, &path, Some("solid 1")), Error::InvalidArgument { what: "ka", .. }));
    let (path, e) = error(&dir, "two.toml", &format!("[[solid]]\n{BALL}\noct = \"junk.oct\"\n"));
    assert!(matches!(scene_cause(e, &path, Some("solid 1")), Error::InvalidArgument { what: "solid", .. }));
    let (path, e) = error(
        &dir,
        "unbounded.toml",
        "[[solid]]\nname = \"floor\"\nshape = { half_space = { normal = [0, 0, 1], offset = 0 } }\n",
    );
    assert!(matches!(scene_cause(e, &path, Some("floor")), Error::InvalidArgument { what: "shape", .. }));
}
