//! Every loader: round trips through our writers, and truncated, corrupted and random
//! files give errors with a place, never a panic.

mod common;

use std::path::{Path, PathBuf};

use common::Rng;
use glam::DVec3;
use octsolid::Error;
use octsolid::mesh::generate::icosphere;
use octsolid::mesh::*;
use octsolid::patch::load_patches;

/// A folder of its own for each test (tests run in parallel).
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("octsolid-loaders-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn ascii_stl(mesh: &TriangleMesh) -> String {
    let mut s = String::from("solid test\n");
    for t in 0..mesh.triangles.len() {
        s += "facet normal 0 0 0\nouter loop\n";
        for v in mesh.corners(t) {
            s += &format!("vertex {} {} {}\n", v.x, v.y, v.z);
        }
        s += "endloop\nendfacet\n";
    }
    s + "endsolid test\n"
}

fn ascii_ply(mesh: &TriangleMesh) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.vertices.len(),
        mesh.triangles.len()
    );
    for v in &mesh.vertices {
        s += &format!("{} {} {}\n", v.x, v.y, v.z);
    }
    for t in &mesh.triangles {
        s += &format!("3 {} {} {}\n", t[0], t[1], t[2]);
    }
    s
}

/// Every format as bytes, for one mesh.
fn files(mesh: &TriangleMesh) -> Vec<(&'static str, Vec<u8>)> {
    let mut obj = Vec::new();
    write_obj(mesh, &mut obj).unwrap();
    let mut stl = Vec::new();
    write_stl(mesh, &mut stl).unwrap();
    let mut ply = Vec::new();
    write_ply(mesh, &mut ply).unwrap();
    vec![
        ("m.obj", obj),
        ("m.stl", stl),
        ("a.stl", ascii_stl(mesh).into_bytes()),
        ("m.ply", ply),
        ("a.ply", ascii_ply(mesh).into_bytes()),
    ]
}

#[test]
fn every_format_round_trips() {
    let dir = scratch("round-trip");
    let mesh = icosphere(DVec3::new(0.5, -1.0, 2.0), 1.5, 2);
    let want = PolygonTables::new(&mesh).report();
    for (name, bytes) in files(&mesh) {
        let loaded = load_mesh(write(&dir, name, &bytes)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let got = PolygonTables::new(&loaded).report();
        assert_eq!((got.vertices, got.triangles, got.edges), (want.vertices, want.triangles, want.edges), "{name}");
        assert!(got.watertight, "{name}: welding restores the connectivity");
        assert!((got.volume / want.volume - 1.0).abs() < 1e-6, "{name}: {} vs {}", got.volume, want.volume);
    }
    // Saving by extension, atomically.
    let path = dir.join("saved.ply");
    save_mesh(&mesh, &path).unwrap();
    assert_eq!(load_mesh(&path).unwrap().triangles.len(), mesh.triangles.len());
}

#[test]
fn bad_files_give_errors_with_a_place_never_panics() {
    let dir = scratch("bad");
    let mesh = icosphere(DVec3::ZERO, 1.0, 1);
    let mut rng = Rng(31337);
    for (name, bytes) in files(&mesh) {
        // Truncations at many lengths.
        for len in (0..bytes.len()).step_by((bytes.len() / 97).max(1)) {
            let path = write(&dir, name, &bytes[..len]);
            if let Ok(m) = load_mesh(&path) {
                // A text file cut at a line end can still be a valid, smaller mesh.
                assert!(m.triangles.len() <= mesh.triangles.len(), "{name} cut at {len}");
            }
        }
        // Random byte corruptions: an error or a valid mesh, never a panic.
        for _ in 0..200 {
            let mut bad = bytes.clone();
            for _ in 0..1 + rng.below(4) {
                let i = rng.below(bad.len() as u64) as usize;
                bad[i] = rng.below(256) as u8;
            }
            let _ = load_mesh(write(&dir, name, &bad));
        }
        // Random garbage.
        for len in [0, 1, 10, 84, 100, 1000] {
            let garbage: Vec<u8> = (0..len).map(|_| rng.below(256) as u8).collect();
            assert!(load_mesh(write(&dir, name, &garbage)).is_err(), "{name}: garbage of {len} bytes loaded");
        }
    }
}

fn error(name: &str, text: &str) -> String {
    let dir = scratch("errors");
    load_mesh(write(&dir, name, text.as_bytes())).unwrap_err().to_string()
}

#[test]
fn errors_name_the_line_or_offset_and_reason() {
    let e = error("bad.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n");
    assert!(e.contains("bad.obj") && e.contains("line 4") && e.contains("out of range"), "{e}");
    let e = error("nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    assert!(e.contains("line 2") && e.contains("NaN"), "{e}");
    let e = error("empty.obj", "# nothing\n");
    assert!(e.contains("no faces"), "{e}");
    let e = error("x.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 zero 0\n");
    assert!(e.contains("line 5") && e.contains("'zero' is not a number"), "{e}");
    let e = error("t.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n");
    assert!(e.contains("truncated"), "{e}");
    let e = error(
        "i.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n",
    );
    assert!(e.contains("line 13") && e.contains("vertex index 9"), "{e}");
    let e = error("b.ply", "ply\nformat binary_big_endian 1.0\nend_header\n");
    assert!(e.contains("binary_big_endian"), "{e}");
    let e = error(
        "inf.ply",
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n",
    );
    assert!(e.contains("line 11") && e.contains("NaN or infinite"), "{e}");
    // Binary STL: a count that does not match the size.
    let mut stl = vec![0u8; 84 + 50];
    stl[80] = 2;
    let dir = scratch("errors");
    let e = load_mesh(write(&dir, "short.stl", &stl)).unwrap_err();
    assert!(matches!(e, Error::Format { offset: 80, .. }), "{e}");
    let e = load_mesh(dir.join("missing.stl")).unwrap_err().to_string();
    assert!(e.contains("missing.stl"), "{e}");
    // An unknown extension: its own error, listing every extension the reader takes
    // (the importer reads patch sets too), with no byte offset.
    let e = load_mesh(write(&dir, "x.3ds", b"")).unwrap_err();
    match &e {
        Error::UnknownExtension { path, found, accepted } => {
            assert!(path.ends_with("x.3ds") && found == "3ds" && accepted == &["obj", "stl", "ply"], "{e:?}")
        }
        other => panic!("{other:?}"),
    }
    let e = octsolid::import::Input::load(write(&dir, "x.3ds", b"")).err().expect("an error").to_string();
    assert!(e.contains("x.3ds") && e.contains("(use .obj, .stl, .ply or .patches)") && !e.contains("byte"), "{e}");
}

#[test]
fn patch_files_load_and_bad_ones_are_refused() {
    let teapot = load_patches(Path::new("models/teapot.patches")).unwrap();
    assert_eq!(teapot.len(), 32);
    let dir = scratch("patches");
    let text = std::fs::read_to_string("models/teapot.patches").unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // Truncated after the patches.
    let cut = lines[..34].join("\n");
    let e = load_patches(write(&dir, "cut.patches", cut.as_bytes())).unwrap_err().to_string();
    assert!(e.contains("truncated"), "{e}");
    // An index out of range.
    let mut bad = lines.clone();
    bad[1] = "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,999";
    let e = load_patches(write(&dir, "bad.patches", bad.join("\n").as_bytes())).unwrap_err().to_string();
    assert!(e.contains("line 2") && e.contains("999"), "{e}");
    let mut bad = lines.clone();
    bad[40] = "1.0,abc,2.0";
    let e = load_patches(write(&dir, "nan.patches", bad.join("\n").as_bytes())).unwrap_err().to_string();
    assert!(e.contains("line 41") && e.contains("abc"), "{e}");
}
