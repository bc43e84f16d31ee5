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

use std::path::{Path, PathBuf};
use std::process::Command;

use common::Rng;
use glam::DVec3;
use octsolid::mesh::{BoundaryOptions, PolygonTables, TriangleMesh, boundary_mesh, load_mesh, save_mesh};
use octsolid::octree::{Domain, LinearOctree, Node};

const MODES: [(&str, BoundaryOptions); 2] =
    [("merged", BoundaryOptions { unit_faces: false }), ("unit", BoundaryOptions { unit_faces: true })];

/// A folder of its own for each test (tests run in parallel).
fn scratch(test: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("octsolid-stl-export-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
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
    let mut rng = Rng(0x57_1e_c0de);
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
                save_mesh(&mesh, &path).unwrap();
                let want = std::fs::read(reference(&name)).unwrap();
                assert!(std::fs::read(&path).unwrap() == want, "{name} differs from tests/data/boundary/{name}");
            }
        }
    }
}
