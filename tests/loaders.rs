//! Every loader: round trips through our writers, and truncated, corrupted and random
//! files give errors with a place, never a panic.

mod common;

use std::path::{Path, PathBuf};

use common::Rng;
use glam::DVec3;
use octsolid::mesh::generate::icosphere;
use octsolid::mesh::*;
use octsolid::patch::read_patches;
use octsolid::{Error, Place};

/// A folder of its own for each test (tests run in parallel).
fn scratch(test: &str) -> PathBuf {
    common::scratch_dir("loaders", test)
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
        let loaded = read_mesh(write(&dir, name, &bytes)).unwrap_or_else(|e| panic!("{name}: {e}"));
        let got = PolygonTables::new(&loaded).report();
        assert_eq!((got.vertices, got.triangles, got.edges), (want.vertices, want.triangles, want.edges), "{name}");
        assert!(got.watertight, "{name}: welding restores the connectivity");
        assert!((got.volume / want.volume - 1.0).abs() < 1e-6, "{name}: {} vs {}", got.volume, want.volume);
    }
    // Saving by extension, atomically.
    let path = dir.join("saved.ply");
    write_mesh(&mesh, &path).unwrap();
    assert_eq!(read_mesh(&path).unwrap().triangles.len(), mesh.triangles.len());
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
            if let Ok(m) = read_mesh(&path) {
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
            let _ = read_mesh(write(&dir, name, &bad));
        }
        // Random garbage.
        for len in [0, 1, 10, 84, 100, 1000] {
            let garbage: Vec<u8> = (0..len).map(|_| rng.below(256) as u8).collect();
            assert!(read_mesh(write(&dir, name, &garbage)).is_err(), "{name}: garbage of {len} bytes loaded");
        }
    }
}

fn error(name: &str, text: &str) -> String {
    let dir = scratch("errors");
    read_mesh(write(&dir, name, text.as_bytes())).unwrap_err().to_string()
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
    let e = read_mesh(write(&dir, "short.stl", &stl)).unwrap_err();
    assert!(matches!(e, Error::Format { offset: 80, .. }), "{e}");
    let e = read_mesh(dir.join("missing.stl")).unwrap_err().to_string();
    assert!(e.contains("missing.stl"), "{e}");
    // An unknown extension: its own error, listing every extension the reader takes
    // (the importer reads patch sets too), with no byte offset.
    let e = read_mesh(write(&dir, "x.3ds", b"")).unwrap_err();
    match &e {
        Error::UnknownExtension { path, found, accepted } => {
            assert!(path.ends_with("x.3ds") && found == "3ds" && accepted == &["obj", "stl", "ply"], "{e:?}")
        }
        other => panic!("{other:?}"),
    }
    let e = octsolid::import::Input::read(write(&dir, "x.3ds", b"")).err().expect("an error").to_string();
    assert!(e.contains("x.3ds") && e.contains("(use .obj, .stl, .ply or .patches)") && !e.contains("byte"), "{e}");
}

#[test]
fn patch_files_load_and_bad_ones_are_refused() {
    let teapot = read_patches(Path::new("models/teapot.patches")).unwrap();
    assert_eq!(teapot.len(), 32);
    let dir = scratch("patches");
    let text = std::fs::read_to_string("models/teapot.patches").unwrap();
    let lines: Vec<&str> = text.lines().collect();
    // Truncated after the patches.
    let cut = lines[..34].join("\n");
    let e = read_patches(write(&dir, "cut.patches", cut.as_bytes())).unwrap_err().to_string();
    assert!(e.contains("truncated"), "{e}");
    // An index out of range.
    let mut bad = lines.clone();
    bad[1] = "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,999";
    let e = read_patches(write(&dir, "bad.patches", bad.join("\n").as_bytes())).unwrap_err().to_string();
    assert!(e.contains("line 2") && e.contains("999"), "{e}");
    let mut bad = lines.clone();
    bad[40] = "1.0,abc,2.0";
    let e = read_patches(write(&dir, "nan.patches", bad.join("\n").as_bytes())).unwrap_err().to_string();
    assert!(e.contains("line 41") && e.contains("abc"), "{e}");
}

// ---------------------------------------------------------------------------------
// Files other tools open: odd encodings, missing or broken material libraries,
// unknown PLY header lines, odd STL solid names. Each file is written here, and the
// loaded mesh is checked against what it holds: triangle count and the exact volume
// of the cube or tetrahedron written (signed tetrahedra of integer corners are exact).

/// A cube of edge `edge` at `min`, as OBJ lines: 8 vertices and 6 outward quads.
fn cube_obj(min: DVec3, edge: f64) -> String {
    let mut s = String::new();
    for k in 0..8 {
        let c = min + edge * DVec3::new(f64::from(k & 1), f64::from((k >> 1) & 1), f64::from((k >> 2) & 1));
        s += &format!("v {:?} {:?} {:?}\n", c.x, c.y, c.z);
    }
    // Corner k has bits (x, y, z); each face counter-clockwise seen from outside.
    for f in ["1 3 4 2", "5 6 8 7", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6"] {
        s += &format!("f {f}\n");
    }
    s
}

/// The tetrahedron (0,0,0), (1,0,0), (0,1,0), (0,0,1), outward: volume 1/6.
const TETRA: [[f64; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
const TETRA_FACES: [[usize; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];

fn tetra_facets(out: &mut Vec<u8>, faces: &[[usize; 3]]) {
    for f in faces {
        out.extend_from_slice(b"  facet normal 0 0 0\n    outer loop\n");
        for &i in f {
            let [x, y, z] = TETRA[i];
            out.extend_from_slice(format!("      vertex {x} {y} {z}\n").as_bytes());
        }
        out.extend_from_slice(b"    endloop\n  endfacet\n");
    }
}

fn assert_mesh(mesh: &TriangleMesh, triangles: usize, volume: f64, what: &str) {
    assert_eq!(mesh.triangles.len(), triangles, "{what}");
    assert!((mesh.volume() - volume).abs() < 1e-12, "{what}: volume {} vs {volume}", mesh.volume());
    assert!(PolygonTables::new(mesh).report().watertight, "{what}");
}

#[test]
fn obj_with_latin1_comment_and_group_name_loads_with_the_name_decoded() {
    let dir = scratch("latin1");
    let mut bytes = b"# Gr\xf6\xdfe: 1 m\xb3\ng W\xfcrfel\n".to_vec();
    bytes.extend_from_slice(cube_obj(DVec3::ZERO, 1.0).as_bytes());
    let (mesh, warnings) = read_mesh_and_warnings(write(&dir, "latin1.obj", &bytes)).unwrap();
    assert_mesh(&mesh, 12, 1.0, "latin1.obj");
    assert_eq!(mesh.groups.iter().map(|g| g.name.as_str()).collect::<Vec<_>>(), ["W\u{fc}rfel"]);
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0].place, Place::Line(1));
    assert!(warnings[0].to_string().contains("latin1.obj: line 1: lines that are not UTF-8"), "{}", warnings[0]);
}

#[test]
fn utf16_obj_with_a_byte_order_mark_loads() {
    let dir = scratch("utf16");
    let text = format!("# UTF-16\ng W\u{fc}rfel \u{1f9ca}\n{}", cube_obj(DVec3::ZERO, 2.0)).replace('\n', "\r\n");
    let units: Vec<u16> = std::iter::once(0xfeff).chain(text.encode_utf16()).collect();
    let le: Vec<u8> = units.iter().flat_map(|u| u.to_le_bytes()).collect();
    let be: Vec<u8> = units.iter().flat_map(|u| u.to_be_bytes()).collect();
    for (name, bytes) in [("le.obj", le), ("be.obj", be)] {
        let (mesh, warnings) = read_mesh_and_warnings(write(&dir, name, &bytes)).unwrap();
        assert_mesh(&mesh, 12, 8.0, name);
        assert_eq!(mesh.groups[0].name, "W\u{fc}rfel \u{1f9ca}", "{name}");
        assert!(warnings.is_empty(), "{name}: {warnings:?}");
    }
}

#[test]
fn obj_with_a_missing_or_broken_mtl_loads_with_a_warning() {
    let dir = scratch("mtl");
    let cube = cube_obj(DVec3::ZERO, 1.0);
    let missing = write(&dir, "missing.obj", format!("# cube\nmtllib missing.mtl\nusemtl red\n{cube}").as_bytes());
    let (mesh, warnings) = read_mesh_and_warnings(&missing).unwrap();
    assert_mesh(&mesh, 12, 1.0, "missing.obj");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = warnings[0].to_string();
    assert!(w.contains("missing.obj: line 2: material library 'missing.mtl' cannot be read"), "{w}");

    write(&dir, "broken.mtl", b"# broken\nnewmtl red\nKd 0.8 zero 0.8\nillum 2\n");
    let broken = write(&dir, "broken.obj", format!("mtllib broken.mtl\nusemtl red\n{cube}").as_bytes());
    let (mesh, warnings) = read_mesh_and_warnings(&broken).unwrap();
    assert_mesh(&mesh, 12, 1.0, "broken.obj");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = warnings[0].to_string();
    assert!(w.contains("broken.obj: line 1: material library 'broken.mtl': line 3: 'zero'"), "{w}");

    // A sound library: no warning. A library name with spaces is one file.
    write(&dir, "fine red.mtl", b"newmtl red\nKa 0.1 0.1 0.1\nKd 0.8 0 0\nNs 10\nd -halo 0.9\nmap_Kd red.png\n");
    let fine = write(&dir, "fine.obj", format!("mtllib fine red.mtl\nusemtl red\n{cube}").as_bytes());
    assert!(read_mesh_and_warnings(&fine).unwrap().1.is_empty());
}

fn tetra_ply(header_extra: &str) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\n{header_extra}element vertex 4\nproperty double x\nproperty double y\n\
         property double z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
    );
    for [x, y, z] in TETRA {
        s += &format!("{x} {y} {z}\n");
    }
    for [a, b, c] in TETRA_FACES {
        s += &format!("3 {a} {b} {c}\n");
    }
    s
}

#[test]
fn ply_with_obj_info_and_unknown_header_lines_loads_with_a_warning() {
    let dir = scratch("ply-header");
    let extra = "obj_info made by hand\ncomment a comment\nCreated by Blender3D 247 - www.blender.org\n";
    let (mesh, warnings) = read_mesh_and_warnings(write(&dir, "t.ply", tetra_ply(extra).as_bytes())).unwrap();
    assert_mesh(&mesh, 4, 1.0 / 6.0, "t.ply");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    let w = warnings[0].to_string();
    assert!(w.contains("t.ply: line 5: unknown header line 'Created by Blender3D 247"), "{w}");
    // Broken format, element and property lines are still refused, at their line.
    for (bad, line) in [
        ("format ascii\n", 3),
        ("element vertex\n", 3),
        ("element vertex four\n", 3),
        ("element vertex 4\nproperty float\n", 4),
        ("element vertex 4\nproperty quad x\n", 4),
        ("element vertex 4\nproperty list uchar x\n", 4),
        ("property float x\n", 3),
    ] {
        let e = read_mesh(write(&dir, "bad.ply", tetra_ply(bad).as_bytes())).unwrap_err();
        assert!(matches!(e, Error::Parse { line: l, .. } if l == line), "{bad:?}: {e}");
    }
}

#[test]
fn ascii_stl_solid_names_with_odd_bytes_load() {
    let dir = scratch("stl-names");
    for name in [&b"\xff\xfe odd \x00\x1b[31m bytes"[..], b"", b"facet normal in the name", "\u{fc}".as_bytes()] {
        let mut stl = b"solid ".to_vec();
        stl.extend_from_slice(name);
        stl.push(b'\n');
        tetra_facets(&mut stl, &TETRA_FACES[..2]);
        // A second solid in the same file, as some exporters write one a part.
        stl.extend_from_slice(b"endsolid \x80\x81\nsolid second\n");
        tetra_facets(&mut stl, &TETRA_FACES[2..]);
        stl.extend_from_slice(b"endsolid second\n");
        let (mesh, warnings) = read_mesh_and_warnings(write(&dir, "odd.stl", &stl)).unwrap();
        assert_mesh(&mesh, 4, 1.0 / 6.0, &String::from_utf8_lossy(name));
        assert!(warnings.iter().all(|w| w.message.contains("Latin-1")), "{warnings:?}");
    }
}

/// A binary STL of the tetrahedron with this 80-byte header.
fn binary_stl(header: &[u8]) -> Vec<u8> {
    let mut stl = header.to_vec();
    stl.resize(80, 0);
    stl.extend_from_slice(&(TETRA_FACES.len() as u32).to_le_bytes());
    for f in TETRA_FACES {
        stl.extend_from_slice(&[0; 12]);
        for i in f {
            stl.extend(TETRA[i].iter().flat_map(|&c| (c as f32).to_le_bytes()));
        }
        stl.extend_from_slice(&[0, 0]);
    }
    stl
}

#[test]
fn binary_stl_whose_header_starts_with_solid_loads() {
    let dir = scratch("stl-solid-header");
    for header in [&b"solid tetra"[..], b"solid\nfacet normal, but binary", b"  solid"] {
        let (mesh, warnings) = read_mesh_and_warnings(write(&dir, "b.stl", &binary_stl(header))).unwrap();
        assert_mesh(&mesh, 4, 1.0 / 6.0, &String::from_utf8_lossy(header));
        assert!(warnings.is_empty(), "{warnings:?}");
    }
    // Padding after the last triangle: read, with a warning at its offset.
    let mut padded = binary_stl(b"solid padded");
    padded.extend_from_slice(&[0; 7]);
    let (mesh, warnings) = read_mesh_and_warnings(write(&dir, "p.stl", &padded)).unwrap();
    assert_mesh(&mesh, 4, 1.0 / 6.0, "padded");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0].place, Place::Byte(84 + 4 * 50));
    // Cut short, it is refused as binary at the count, not misread as text.
    let stl = binary_stl(b"solid cut");
    let e = read_mesh(write(&dir, "c.stl", &stl[..stl.len() - 1])).unwrap_err();
    assert!(matches!(e, Error::Format { offset: 80, .. }), "{e}");
}

// ---------------------------------------------------------------------------------
// Hardening.

#[test]
fn ply_zero_property_element_is_refused_quickly() {
    let dir = scratch("ply-counts");
    let junk = "element junk 4000000000000\n";
    let e = read_mesh(write(&dir, "z.ply", tetra_ply(junk).as_bytes())).unwrap_err();
    assert!(matches!(e, Error::Parse { line: 3, .. }) && e.to_string().contains("no properties"), "{e}");
    // A few empty items are fine: they take no room.
    assert_mesh(
        &read_mesh(write(&dir, "few.ply", tetra_ply("element junk 5\n").as_bytes())).unwrap(),
        4,
        1.0 / 6.0,
        "few",
    );
    // Counts that cannot fit in what follows the header, ASCII and binary.
    let huge = tetra_ply("").replace("element vertex 4", "element vertex 4000000000");
    let e = read_mesh(write(&dir, "h.ply", huge.as_bytes())).unwrap_err();
    assert!(matches!(e, Error::Parse { line: 3, .. }) && e.to_string().contains("words after the header"), "{e}");
    let mut mesh =
        TriangleMesh::new(TETRA.map(DVec3::from_array).to_vec(), TETRA_FACES.map(|f| f.map(|i| i as u32)).to_vec())
            .unwrap();
    mesh.groups.clear();
    let mut ply = Vec::new();
    write_ply(&mesh, &mut ply).unwrap();
    let header_end = ply.windows(11).position(|w| w == b"end_header\n").unwrap();
    let header = String::from_utf8(ply[..header_end].to_vec()).unwrap();
    let line = header.lines().position(|l| l.starts_with("element face")).unwrap() + 1;
    let bloated = header.replace("element face 4", "element face 4000000000").into_bytes();
    let bytes = [&bloated[..], &ply[header_end..]].concat();
    let e = read_mesh(write(&dir, "b.ply", &bytes)).unwrap_err();
    assert!(matches!(e, Error::Parse { line: l, .. } if l == line) && e.to_string().contains("bytes after"), "{e}");
}

#[test]
fn obj_coordinates_keep_double_precision() {
    let dir = scratch("f64");
    let min = DVec3::splat(1e9);
    let text = cube_obj(min, 1.0);
    let mesh = read_mesh(write(&dir, "far.obj", text.as_bytes())).unwrap();
    // Every vertex exactly as the standard library parses the file's text.
    let written: Vec<DVec3> = text
        .lines()
        .filter_map(|l| l.strip_prefix("v "))
        .map(|l| {
            let c: Vec<f64> = l.split(' ').map(|t| t.parse().unwrap()).collect();
            DVec3::new(c[0], c[1], c[2])
        })
        .collect();
    let sorted = |v: &[DVec3]| {
        let mut v = v.to_vec();
        v.sort_by(|a, b| a.to_array().partial_cmp(&b.to_array()).unwrap());
        v
    };
    assert_eq!(sorted(&mesh.vertices), sorted(&written));
    assert_eq!((mesh.bounds().min, mesh.bounds().max), (min, min + 1.0));
    // Moved to the origin (exact: 1e9 + 1 - 1e9 is 1), it is the unit cube.
    let mut moved = mesh.clone();
    moved.vertices.iter_mut().for_each(|v| *v -= min);
    assert_eq!(moved.volume(), 1.0);
    // Through to voxelization: the cube's faces lie on voxel planes of this domain, so
    // the voxelized volume is exactly the cube's, and the solid is the one the same
    // cube at the origin gives (in single precision the cube is a point).
    let voxelized = |mesh: &TriangleMesh, min: DVec3| {
        let domain = octsolid::octree::Domain::new(min - 0.5, 2.0, 6).unwrap();
        voxelize_mesh(mesh, domain, &MeshVoxelizeOptions::default()).unwrap().0
    };
    let (far, near) = (voxelized(&mesh, min), voxelized(&moved, DVec3::ZERO));
    assert_eq!(far.volume(), 1.0);
    assert_eq!(far.keys(), near.keys());
    // A coordinate single precision cannot hold.
    let mesh = read_mesh(write(&dir, "tenth.obj", b"v 0.1 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")).unwrap();
    assert_eq!(mesh.vertices[0].x, 0.1);
}

/// `n` corners alternating between radii `r_even` and `r_odd` around the origin.
fn star(n: usize, r_even: f64, r_odd: f64) -> Vec<DVec3> {
    (0..n)
        .map(|k| {
            let r = if k % 2 == 0 { r_even } else { r_odd };
            let a = std::f64::consts::TAU * k as f64 / n as f64;
            DVec3::new(r * a.cos(), r * a.sin(), 0.0)
        })
        .collect()
}

fn triangle_area(mesh: &TriangleMesh, t: usize) -> DVec3 {
    let [a, b, c] = mesh.corners(t);
    (b - a).cross(c - a) / 2.0
}

#[test]
fn thousand_vertex_face_triangulates_to_n_minus_2_triangles_with_its_area() {
    let dir = scratch("big-face");
    let n = 1000;
    // A star (concave: every other corner reflex) and a regular polygon (convex). The
    // area of a polygon of corners at radii r_k, angle 2 pi / n apart, is the sum of
    // its n triangles with the centre: n/2 r_even r_odd sin(2 pi / n).
    for (r_even, r_odd) in [(1.0, 0.5), (1.0, 1.0)] {
        let corners = star(n, r_even, r_odd);
        let area = n as f64 / 2.0 * r_even * r_odd * (std::f64::consts::TAU / n as f64).sin();
        let mut obj = String::new();
        for c in &corners {
            obj += &format!("v {:?} {:?} 0\n", c.x, c.y);
        }
        obj += &format!("f {}\n", (1..=n).map(|i| i.to_string()).collect::<Vec<_>>().join(" "));
        let (mesh, warnings) = read_mesh_and_warnings(write(&dir, "big.obj", obj.as_bytes())).unwrap();
        assert!(warnings.is_empty(), "{warnings:?}");
        assert_eq!(mesh.triangles.len(), n - 2);
        // Every triangle faces +z as the polygon does, so the areas add up to the
        // polygon's without cancelling (a fan of the star would overlap itself).
        let areas: Vec<DVec3> = (0..mesh.triangles.len()).map(|t| triangle_area(&mesh, t)).collect();
        assert!(areas.iter().all(|a| a.z >= 0.0 && a.x == 0.0 && a.y == 0.0));
        let total: f64 = areas.iter().map(|a| a.z).sum();
        assert!((total - area).abs() < 1e-12 * n as f64, "{r_odd}: {total} vs {area}");
        // No fan of slivers: a fan's triangles are all about as long as the polygon
        // (n diameters in all); ear clipping shortest diagonal first halves the corners
        // level by level (about perimeter x log2 n).
        let longest: f64 = (0..mesh.triangles.len())
            .map(|t| {
                let [a, b, c] = mesh.corners(t);
                a.distance(b).max(b.distance(c)).max(c.distance(a))
            })
            .sum();
        let perimeter: f64 = (0..n).map(|k| corners[k].distance(corners[(k + 1) % n])).sum();
        assert!(longest < perimeter * (n as f64).log2(), "{r_odd}: {longest} vs {perimeter}");
        // The same face from a PLY file.
        let mut ply = format!(
            "ply\nformat ascii 1.0\nelement vertex {n}\nproperty double x\nproperty double y\nproperty double z\n\
             element face 1\nproperty list ushort int vertex_indices\nend_header\n"
        );
        for c in &corners {
            ply += &format!("{:?} {:?} 0\n", c.x, c.y);
        }
        ply += &format!("{n} {}\n", (0..n).map(|i| i.to_string()).collect::<Vec<_>>().join(" "));
        let from_ply = read_mesh(write(&dir, "big.ply", ply.as_bytes())).unwrap();
        assert_eq!(from_ply.triangles.len(), n - 2);
        let total: f64 = (0..n - 2).map(|t| triangle_area(&from_ply, t).z).sum();
        assert!((total - area).abs() < 1e-12 * n as f64, "ply {r_odd}: {total} vs {area}");
    }
}

/// Whether `s` holds a character a terminal would act on.
fn has_control(s: &str) -> bool {
    s.chars().any(|c| c.is_control())
}

#[test]
fn error_messages_escape_control_characters() {
    let dir = scratch("escape");
    let esc = "\x1b[2J\x1b]0;pwned\x07";
    let cases: Vec<(&str, String)> = vec![
        ("v.obj", format!("v 0 0 0\nv 1 {esc} 0\n")),
        ("f.obj", format!("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 {esc}\n")),
        ("s.stl", format!("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 {esc} 0\n")),
        ("k.stl", format!("solid x\n{esc}\n")),
        ("h.ply", format!("ply\nformat ascii 1.0\nelement vertex {esc}\nend_header\n")),
        ("t.ply", format!("ply\nformat ascii 1.0\nelement vertex 1\nproperty {esc} x\nend_header\n")),
        (
            "b.ply",
            format!(
                "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\nend_header\n0 {esc} 0\n"
            ),
        ),
        ("m.ply", format!("ply\nformat {esc} 1.0\nend_header\n")),
        ("p.patches", format!("1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n16\n0,{esc},0\n")),
        ("n.patches", format!("{esc}\n")),
    ];
    for (name, text) in cases {
        let path = write(&dir, name, text.as_bytes());
        let e = match name.ends_with(".patches") {
            true => read_patches(&path).unwrap_err().to_string(),
            false => read_mesh(&path).unwrap_err().to_string(),
        };
        assert!(!has_control(&e) && e.contains("\\x1b[2J\\x1b]0;pwned\\x07"), "{name}: {e:?}");
    }
    // Warnings too: an unknown PLY header line, a material library's name.
    let ply = tetra_ply(&format!("{esc} made this\n"));
    let (_, warnings) = read_mesh_and_warnings(write(&dir, "w.ply", ply.as_bytes())).unwrap();
    let obj = format!("mtllib {esc}.mtl\n{}", cube_obj(DVec3::ZERO, 1.0));
    let (_, more) = read_mesh_and_warnings(write(&dir, "w.obj", obj.as_bytes())).unwrap();
    assert_eq!((warnings.len(), more.len()), (1, 1));
    for w in warnings.iter().chain(&more) {
        assert!(!has_control(&w.to_string()) && w.message.contains("\\x1b[2J"), "{w:?}");
    }
}

/// `.vdb` grid, type and transform names, a scene's solid names and the values its
/// TOML reader quotes reach messages escaped, as the mesh formats' do.
#[test]
fn solid_file_and_scene_errors_escape_control_characters() {
    use octsolid::io::{ColouredSolid, ReadOptions, Solids, WriteOptions};
    use octsolid::octree::{Domain, LinearOctree};
    use octsolid::{NoProgress, SolidFile, write_solid_file};
    let dir = scratch("escape-solids");
    let esc = "\x1b[2J\x1b]0;pwned\x07";
    let domain = Domain::new(DVec3::ZERO, 1.0, 2).unwrap();
    let solids =
        Solids { domain, solids: vec![ColouredSolid::new(format!("part{esc}"), None, LinearOctree::full(domain))] };
    let vdb = dir.join("named.vdb");
    write_solid_file(&vdb, &solids.borrowed(), &WriteOptions::default(), &NoProgress).unwrap();
    let expect_escaped = |what: &str, e: String| {
        assert!(!has_control(&e) && e.contains("\\x1b[2J\\x1b]0;pwned\\x07"), "{what}: {e:?}");
    };
    // The grid's name, listed when the asked grid is missing.
    let e = SolidFile::read(&vdb, &ReadOptions { grid: Some("other".into()), ..ReadOptions::default() }).unwrap_err();
    expect_escaped("grid name", e.to_string());
    // The transform's and the grid type's names, put there byte for byte.
    let bytes = std::fs::read(&vdb).unwrap();
    let transform = format!("Uniform{esc}Map");
    let kind = format!("{esc}xx");
    for (field, hostile) in [(&b"UniformScaleTranslateMap"[..], transform), (&b"Tree_float_5_4_3"[..], kind)] {
        assert_eq!(field.len(), hostile.len());
        let at = bytes.windows(field.len()).position(|w| w == field).expect("the writer's name is in the file");
        let mut patched = bytes.clone();
        patched[at..at + field.len()].copy_from_slice(hostile.as_bytes());
        let path = dir.join("patched.vdb");
        std::fs::write(&path, &patched).unwrap();
        let options = ReadOptions { grid: Some(format!("part{esc}")), ..ReadOptions::default() };
        expect_escaped(&hostile, SolidFile::read(&path, &options).unwrap_err().to_string());
    }
    // A scene: a solid's name in front of its error, and a value the TOML reader quotes.
    let toml_escaped: String = esc.chars().map(|c| format!("\\u{:04x}", c as u32)).collect();
    let named = format!("[[solid]]\nname = \"{toml_escaped}\"\nshape = {{ sphere = {{ radius = -1 }} }}\n");
    let unknown = format!("[[solid]]\nshape = {{ \"{toml_escaped}\" = {{ radius = 1 }} }}\n");
    for (name, text) in [("named.toml", named), ("unknown.toml", unknown)] {
        let path = write(&dir, name, text.as_bytes());
        let Err(e) = octsolid::scene_file::read_scene(&path, octsolid::MemoryBudget::default()) else {
            panic!("{name} loaded")
        };
        expect_escaped(name, e.to_string());
    }
}

#[test]
fn import_and_scene_files_pass_the_warnings_on() {
    let dir = scratch("pass-on");
    write(&dir, "cube.obj", format!("mtllib gone.mtl\n{}", cube_obj(DVec3::ZERO, 1.0)).as_bytes());
    let (input, warnings) = octsolid::import::Input::read_and_warnings(dir.join("cube.obj")).unwrap();
    assert!(matches!(input, octsolid::import::Input::Mesh(ref m) if m.triangles.len() == 12));
    assert_eq!(warnings.len(), 1);
    let scene = write(&dir, "s.toml", b"[[solid]]\nmesh = \"cube.obj\"\ndepth = 4\n");
    let file = octsolid::scene_file::read_scene(&scene, octsolid::MemoryBudget::default()).unwrap();
    assert_eq!(file.warnings, warnings);
}
