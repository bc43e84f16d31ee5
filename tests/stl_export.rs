//! Boundary meshes written as STL reload closed and manifold, even where voxels touch
//! only along an edge or at a corner; OBJ and PLY are written as before.
//!
//! Oracles: our loader's polygon-table report of the reloaded file (no boundary,
//! non-manifold or misoriented edge), its vertex and triangle counts against the
//! boundary mesh's (welding by position gives back the same vertices), its volume
//! against the octree's voxel volume, reference files written before STL moved its
//! shared vertices apart (OBJ and PLY must stay byte for byte), and, when the peers'
//! Python venv is there (`benches/peers/setup.sh`), trimesh's own reading of the file.

mod common;

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::Rng;
use glam::DVec3;
use octsolid::mesh::{
    BoundaryOptions, PolygonTables, SEPARATION_STEP, TriangleMesh, boundary_mesh, read_mesh, separate_sheets,
    write_mesh, write_stl,
};
use octsolid::octree::{Domain, LinearOctree, Node};
use rayon::prelude::*;

const MODES: [(&str, BoundaryOptions); 2] =
    [("merged", BoundaryOptions { unit_faces: false }), ("unit", BoundaryOptions { unit_faces: true })];

/// A folder of its own for each test (tests run in parallel).
fn scratch(test: &str) -> PathBuf {
    common::scratch_dir("stl-export", test)
}

fn reference(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/boundary").join(name)
}

/// A domain whose lattice points are exact binary fractions (exact in `f32` too), away
/// from the origin.
fn domain(depth: u8) -> Domain {
    Domain::new(DVec3::new(-1.5, 0.25, 3.0), f64::from(1u32 << depth) * 0.375, depth).unwrap()
}

fn voxels(depth: u8, v: impl IntoIterator<Item = [u32; 3]>) -> LinearOctree {
    LinearOctree::from_voxels(domain(depth), v).unwrap()
}

/// Solids with voxels touching along edges and at corners, and one without.
fn cases() -> Vec<(&'static str, LinearOctree)> {
    let cube = |n: u32, at: u32| {
        (0..n).flat_map(move |x| (0..n).flat_map(move |y| (0..n).map(move |z| [x + at, y + at, z + at])))
    };
    let mut rng = Rng(0x571e_c0de);
    vec![
        ("edge", voxels(4, [[4, 4, 4], [5, 5, 4]])),
        ("corner", voxels(4, [[4, 4, 4], [5, 5, 5]])),
        ("checker", voxels(4, cube(4, 2).filter(|v| (v[0] + v[1] + v[2]) % 2 == 0))),
        ("sparse", voxels(4, cube(6, 4).filter(|_| rng.unit() < 0.25))),
        ("nodes", {
            let nodes = [
                Node { level: 2, min: [0, 0, 0], size: 4 },
                Node { level: 2, min: [4, 4, 0], size: 4 },
                Node { level: 3, min: [8, 8, 2], size: 2 },
                Node { level: 4, min: [10, 10, 4], size: 1 },
            ];
            LinearOctree::from_nodes(domain(4), nodes).unwrap()
        }),
        ("block", LinearOctree::from_nodes(domain(4), [Node { level: 3, min: [0, 8, 0], size: 2 }]).unwrap()),
    ]
}

/// OBJ and PLY of every case, in both modes, are the reference files' bytes (written
/// by the code before this test existed; `OCTSOLID_BLESS=1` rewrites them). STL too
/// for the solid without contacts, which has no shared positions to move apart.
#[test]
fn obj_and_ply_bytes_are_unchanged() {
    let dir = scratch("reference");
    let bless = std::env::var_os("OCTSOLID_BLESS").is_some();
    if bless {
        std::fs::create_dir_all(reference("")).unwrap();
    }
    for (what, tree) in cases() {
        for (mode, options) in MODES {
            let mesh = boundary_mesh(&tree, &options);
            let formats: &[&str] = if what == "block" { &["obj", "ply", "stl"] } else { &["obj", "ply"] };
            for ext in formats {
                let name = format!("{what}-{mode}.{ext}");
                let path = if bless { reference(&name) } else { dir.join(&name) };
                write_mesh(&mesh, &path).unwrap();
                let want = std::fs::read(reference(&name)).unwrap();
                assert!(std::fs::read(&path).unwrap() == want, "{name} differs from tests/data/boundary/{name}");
            }
        }
    }
}

/// The vertices of `mesh` whose position another vertex has, with the shortest edge at
/// each and the sum of its triangles' area vectors.
fn shared_copies(mesh: &TriangleMesh) -> Vec<(usize, f64, DVec3)> {
    let mut at: HashMap<[u64; 3], Vec<usize>> = HashMap::new();
    for (i, v) in mesh.vertices.iter().enumerate() {
        at.entry(v.to_array().map(f64::to_bits)).or_default().push(i);
    }
    let mut out = Vec::new();
    for copies in at.values().filter(|c| c.len() > 1) {
        for &v in copies {
            let (mut shortest, mut area) = (f64::INFINITY, DVec3::ZERO);
            for t in 0..mesh.triangles.len() {
                let ids = mesh.triangles[t];
                if let Some(k) = ids.iter().position(|&i| i as usize == v) {
                    let c = mesh.corners(t);
                    let (a, b) = (c[(k + 1) % 3] - c[k], c[(k + 2) % 3] - c[k]);
                    shortest = shortest.min(a.length()).min(b.length());
                    area += a.cross(b) / 2.0;
                }
            }
            out.push((v, shortest, area));
        }
    }
    out.sort_by_key(|c| c.0);
    out
}

/// The generalized winding number of `mesh` at `p`: the sum of its triangles' signed
/// solid angles (Van Oosterom and Strackee) over `4 pi`.
fn winding_number(mesh: &TriangleMesh, p: DVec3) -> f64 {
    let total: f64 = (0..mesh.triangles.len())
        .map(|t| {
            let [a, b, c] = mesh.corners(t).map(|v| v - p);
            let (la, lb, lc) = (a.length(), b.length(), c.length());
            let det = a.dot(b.cross(c));
            let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
            2.0 * det.atan2(den)
        })
        .sum();
    total / (4.0 * std::f64::consts::PI)
}

/// Writes the boundary mesh of `tree` as STL, reloads it and checks it against the
/// oracles of the module doc; returns how many vertices were moved apart.
fn check_round_trip(tree: &LinearOctree, options: &BoundaryOptions, path: &Path, what: &str) -> usize {
    let mesh = boundary_mesh(tree, options);
    write_mesh(&mesh, path).unwrap_or_else(|e| panic!("{what}: {e}"));
    let loaded = read_mesh(path).unwrap();
    let report = PolygonTables::new(&loaded).report();
    assert_eq!(
        (report.boundary_edges, report.non_manifold_edges, report.misoriented_edges, report.degenerate_faces),
        (0, 0, 0, 0),
        "{what}: {report:?}"
    );
    assert!(report.watertight && loaded.is_watertight(), "{what}: {report:?}");
    // Welding by position gave back one vertex for each of the mesh's.
    assert_eq!((loaded.vertices.len(), loaded.triangles.len()), (mesh.vertices.len(), mesh.triangles.len()), "{what}");

    // Each moved copy by at most the documented step, into the solid (onto a full
    // voxel's closed box), and the volume by at most the steps times the areas.
    let domain = tree.domain();
    let h = domain.voxel_size();
    let copies = shared_copies(&mesh);
    let bound: f64 = copies.iter().map(|&(_, l, area)| l * SEPARATION_STEP * area.length() / 3.0).sum();
    let volume = tree.volume();
    assert!(
        (report.volume - volume).abs() <= bound * 1.01 + 1e-12 * volume,
        "{what}: volume {} vs the octree's {volume}, bound {bound}",
        report.volume
    );
    let longest = copies.iter().map(|c| c.1).fold(0.0, f64::max);
    let mut points: Vec<DVec3> = Vec::new();
    for v in &loaded.vertices {
        let p = domain.min() + ((*v - domain.min()) / h).round() * h;
        let moved = *v - p;
        assert!(moved.length() <= longest * SEPARATION_STEP * 1.001, "{what}: vertex {v} is {moved} from {p}");
        if moved != DVec3::ZERO && !points.contains(&p) {
            points.push(p);
        }
    }
    // The sheets moved apart do not cross: around each shared point, at and near it
    // (within a few steps) the winding number of the file's mesh is between 0 and 1
    // (2 or -1 where sheets overlap), and a quarter voxel into each of the eight
    // voxels around it, 1 in a full one, 0 in an empty one.
    let step = longest * SEPARATION_STEP;
    points.par_iter().for_each(|&p| {
        let lattice = ((p - domain.min()) / h).round();
        let mut near = vec![p];
        for s in [0.5, 3.0] {
            for d in [DVec3::new(1.0, 1.1, 1.2), DVec3::new(1.0, 0.13, 0.07)] {
                for signs in 0..8 {
                    let sign = DVec3::new([1.0, -1.0][signs & 1], [1.0, -1.0][signs >> 1 & 1], [1.0, -1.0][signs >> 2]);
                    near.push(p + s * step * (d * sign).normalize());
                }
            }
        }
        for q in near {
            let w = winding_number(&loaded, q);
            assert!((-1e-9..=1.0 + 1e-9).contains(&w), "{what}: winding number {w} at {q}, near {p}");
        }
        for o in 0..8 {
            let o = [o & 1, (o >> 1) & 1, o >> 2].map(|b| i64::from(b) * 2 - 1);
            let voxel = [0, 1, 2].map(|a| lattice[a] as i64 + (o[a] - 1) / 2);
            let full = voxel.iter().all(|&c| (0..i64::from(domain.resolution())).contains(&c))
                && tree.contains_voxel(voxel.map(|c| c as u32));
            let q = p + DVec3::new(o[0] as f64, o[1] as f64, o[2] as f64) * (h / 4.0);
            let w = winding_number(&loaded, q);
            assert!((w - f64::from(u8::from(full))).abs() < 1e-6, "{what}: winding number {w} at {q} (full: {full})");
        }
    });
    copies.len()
}

#[test]
fn stl_reloads_closed_with_edge_and_corner_contacts() {
    let dir = scratch("contacts");
    for (what, tree) in cases() {
        for (mode, options) in MODES {
            let what = format!("{what} ({mode})");
            let moved = check_round_trip(&tree, &options, &dir.join("m.stl"), &what);
            assert_eq!(moved == 0, what.starts_with("block"), "{what}: {moved} moved");
        }
    }
}

/// Every set of the eight voxels around a lattice point, and random dense sets of
/// 3^3 and 4^3 voxels (where touches meet and the mesher chooses pairings).
#[test]
fn stl_reloads_closed_for_every_configuration_around_a_point() {
    let dir = scratch("configurations");
    let path = dir.join("c.stl");
    for mask in 1..256u32 {
        let tree =
            voxels(3, (0..8).filter(|b| mask >> b & 1 == 1).map(|b| [3 + (b & 1), 3 + (b >> 1 & 1), 3 + (b >> 2)]));
        for (mode, options) in MODES {
            check_round_trip(&tree, &options, &path, &format!("configuration {mask:08b} ({mode})"));
        }
    }
    let mut rng = Rng(0xc0ff_ee11);
    for round in 0..150 {
        let n = 3 + round % 2;
        let fill = rng.range(0.3, 0.7);
        let cells: Vec<[u32; 3]> =
            (0..n).flat_map(|x| (0..n).flat_map(move |y| (0..n).map(move |z| [x + 2, y + 2, z + 2]))).collect();
        let tree = voxels(3, cells.into_iter().filter(|_| rng.unit() < fill));
        for (mode, options) in MODES {
            check_round_trip(&tree, &options, &path, &format!("random {round} ({mode})"));
        }
    }
}

/// `.glb` stores `f32` coordinates too: a solid past `f32`'s range (which wrote `inf`
/// into the JSON, invalid glTF) or so far out that neighbouring voxel corners round to
/// one `f32` is refused, naming the file, and nothing is written; the same solid nearer
/// the origin is written with its corners exact.
#[test]
fn glb_of_coordinates_single_precision_cannot_hold_is_refused() {
    use octsolid::io::{SolidsRef, WriteOptions};
    use octsolid::{NoProgress, write_solid_file};
    let write_solid = |path: &Path, tree: &LinearOctree| {
        write_solid_file(path, &SolidsRef::of_file(path, tree), &WriteOptions::default(), &NoProgress)
    };
    let dir = scratch("glb-far");
    let two = [[1, 1, 1], [2, 1, 1]];
    for (name, min, edge) in [("beyond.glb", 1e39, 1e38), ("collapsed.glb", 1e9, 16.0)] {
        let tree = LinearOctree::from_voxels(Domain::new(DVec3::splat(min), edge, 4).unwrap(), two).unwrap();
        let path = dir.join(name);
        let e = match write_solid(&path, &tree) {
            Ok(bytes) => panic!("{name}: written ({bytes} bytes)"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains(name) && e.contains("f32"), "{name}: {e}");
        assert!(!path.exists(), "{name}");
    }
    // Nearer, the staircase (the smooth surface, estimated, would round its corners)
    // keeps its corners exactly in f32.
    let near = LinearOctree::from_voxels(Domain::new(DVec3::splat(4096.0), 16.0, 4).unwrap(), two).unwrap();
    let path = dir.join("near.glb");
    let staircase = WriteOptions { mesh_style: octsolid::surface::Style::Voxels, ..WriteOptions::default() };
    write_solid_file(&path, &SolidsRef::of_file(&path, &near), &staircase, &NoProgress).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
    let json: serde_json::Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let position = &json["accessors"][0];
    assert_eq!(position["min"], serde_json::json!([4097.0, 4097.0, 4097.0]), "{position}");
    assert_eq!(position["max"], serde_json::json!([4099.0, 4098.0, 4098.0]), "{position}");
}

/// Far from the origin `f32` spacing grows past what a small step can bridge: the STL
/// of a contact is refused, naming the file, and nothing is written; where the voxels
/// do not touch, or the coordinates are smaller, it is written and reloads closed.
#[test]
fn coarse_f32_spacing_is_refused() {
    let dir = scratch("coarse");
    let at = |min: f64, edge: f64| Domain::new(DVec3::splat(min), edge, 4).unwrap();
    let contact = [[4, 4, 4], [5, 5, 4]];
    // f32 spacing at 10^6 is 1/16: four of it exceed a sixteenth of a unit voxel.
    let far = LinearOctree::from_voxels(at(1e6, 16.0), contact).unwrap();
    let path = dir.join("far.stl");
    let e = write_mesh(&boundary_mesh(&far, &BoundaryOptions::default()), &path).unwrap_err().to_string();
    assert!(e.contains("far.stl") && e.contains("f32") && e.contains(".obj or .ply"), "{e}");
    assert!(!path.exists());
    assert!(separate_sheets(&boundary_mesh(&far, &BoundaryOptions::default())).is_err());
    let alone = LinearOctree::from_voxels(at(1e6, 16.0), [[4, 4, 4], [9, 9, 9]]).unwrap();
    check_round_trip(&alone, &BoundaryOptions::default(), &path, "far, no contact");
    // Closer, 4 ulp take over from a thousandth of the voxel and still fit: voxels of
    // 1/4 at 4096 (f32 spacing 2^-11 there; a thousandth of the voxel is 2^-12).
    let near = LinearOctree::from_voxels(Domain::new(DVec3::splat(4096.0), 256.0, 10).unwrap(), contact).unwrap();
    let mesh = boundary_mesh(&near, &BoundaryOptions::default());
    write_mesh(&mesh, &path).unwrap();
    let loaded = read_mesh(&path).unwrap();
    assert!(loaded.is_watertight() && loaded.vertices.len() == mesh.vertices.len());
    let moved = loaded.vertices.iter().map(|v| (*v * 4.0 - (*v * 4.0).round()).length() / 4.0).fold(0.0, f64::max);
    assert!(moved > 1.5 * 0.25 * SEPARATION_STEP && moved < 0.25 / 16.0, "moved by {moved}");
    // At 10^8 (f32 spacing 8) unit voxels' corners themselves fall together.
    let huge = LinearOctree::from_voxels(at(1e8, 16.0), [[1, 1, 1]]).unwrap();
    let e = write_mesh(&boundary_mesh(&huge, &BoundaryOptions::default()), dir.join("huge.stl")).unwrap_err();
    assert!(e.to_string().contains("both"), "{e}");
    // The raw writer writes every corner as it is, and such a file welds the contact.
    let mut raw = Vec::new();
    write_stl(&boundary_mesh(&voxels(4, contact), &BoundaryOptions::default()), &mut raw).unwrap();
    std::fs::write(dir.join("raw.stl"), raw).unwrap();
    let report = PolygonTables::new(&read_mesh(dir.join("raw.stl")).unwrap()).report();
    assert!(report.non_manifold_edges > 0, "{report:?}");
}

/// trimesh (the peers' venv: `benches/peers/setup.sh`, or `PEERS_VENV`) reads the STL
/// files closed and consistently wound, with as many vertices as the boundary mesh and
/// the volume our loader reads. Skipped, saying so, without the venv.
#[test]
fn trimesh_reads_the_stl_closed() {
    let venv = std::env::var_os("PEERS_VENV")
        .map_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("target/peers-venv"), PathBuf::from);
    let python = venv.join("bin/python");
    let has_trimesh = Command::new(&python).args(["-c", "import trimesh"]).output().is_ok_and(|o| o.status.success());
    if !has_trimesh {
        eprintln!("skipped: no trimesh at {} (benches/peers/setup.sh installs it)", python.display());
        return;
    }
    let dir = scratch("trimesh");
    let script = "import sys, json, trimesh\n\
                  out = []\n\
                  for path in sys.argv[1:]:\n\
                  \x20   m = trimesh.load_mesh(path)\n\
                  \x20   out.append([m.is_watertight, m.is_winding_consistent, float(m.volume), len(m.vertices)])\n\
                  print(json.dumps(out))\n";
    let mut files = Vec::new();
    for (what, tree) in cases() {
        for (mode, options) in MODES {
            let path = dir.join(format!("{what}-{mode}.stl"));
            let mesh = boundary_mesh(&tree, &options);
            write_mesh(&mesh, &path).unwrap();
            let volume = PolygonTables::new(&read_mesh(&path).unwrap()).report().volume;
            files.push((path, volume, mesh.vertices.len()));
        }
    }
    let out = Command::new(&python).arg("-c").arg(script).args(files.iter().map(|f| &f.0)).output().unwrap();
    assert!(out.status.success(), "trimesh failed: {}", String::from_utf8_lossy(&out.stderr));
    let results: Vec<(bool, bool, f64, usize)> = serde_json::from_slice(&out.stdout).unwrap();
    for ((path, volume, vertices), (watertight, consistent, read, n)) in files.iter().zip(results) {
        assert!(watertight && consistent, "{}: trimesh reads it open or inconsistent", path.display());
        assert!((read - volume).abs() <= 1e-9 * volume, "{}: trimesh volume {read} vs {volume}", path.display());
        assert_eq!(n, *vertices, "{}", path.display());
    }
}
