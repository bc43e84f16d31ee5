//! `.3mf` output against an independent reader: Python's own `zipfile` (which checks
//! every entry's CRC-32) and `xml.etree` read the package octsolid writes, and the
//! volume the model's triangles enclose (the divergence theorem over the triangles as
//! read) must be the solid's voxel volume, the boundary mesh enclosing exactly the
//! voxels. Also: the package's parts are the ones the 3MF core specification names.

mod common;

use std::process::Command;

use glam::DVec3;
use octsolid::io::{SolidsRef, WriteOptions};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::samples::classic_csg;
use octsolid::shape::{Axis, Torus};
use octsolid::{MemoryBudget, NoProgress, write_solid_file};

/// What Python reads from the package at `path`: its entry names, then the vertex and
/// triangle counts, the unit and the enclosed volume, one a line.
const READER: &str = r#"
import sys, zipfile, xml.etree.ElementTree as ET
z = zipfile.ZipFile(sys.argv[1])
assert z.testzip() is None, "a CRC-32 does not match"
print(",".join(z.namelist()))
root = ET.fromstring(z.read("3D/3dmodel.model"))
ns = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
V = [tuple(float(v.get(k)) for k in "xyz") for v in root.iterfind(".//m:vertex", ns)]
T = [tuple(int(t.get(k)) for k in ("v1", "v2", "v3")) for t in root.iterfind(".//m:triangle", ns)]
def det(a, b, c):
    return a[0]*(b[1]*c[2]-b[2]*c[1]) - a[1]*(b[0]*c[2]-b[2]*c[0]) + a[2]*(b[0]*c[1]-b[1]*c[0])
print(len(V)); print(len(T)); print(root.get("unit"))
print(repr(sum(det(V[i], V[j], V[k]) for i, j, k in T) / 6))
"#;

fn read_back(path: &std::path::Path) -> (String, usize, usize, String, f64) {
    let out = Command::new("python3").arg("-c").arg(READER).arg(path).output().expect("python3 runs");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    (
        lines[0].to_owned(),
        lines[1].parse().unwrap(),
        lines[2].parse().unwrap(),
        lines[3].to_owned(),
        lines[4].parse().unwrap(),
    )
}

fn written(tree: &LinearOctree, name: &str) -> std::path::PathBuf {
    let path = common::scratch_dir("three_mf", name).join(format!("{name}.3mf"));
    write_solid_file(&path, &SolidsRef::one(name, None, tree), &WriteOptions::default(), &NoProgress).unwrap();
    path
}

#[test]
fn a_3mf_package_reads_back_in_another_reader_with_the_voxel_volume() {
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 7).unwrap();
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
    let part = voxelize(&classic_csg(), domain, &options).unwrap();
    let torus = voxelize(&Torus::new(DVec3::ZERO, Axis::Z, 0.7, 0.25).unwrap(), domain, &options).unwrap();
    for (tree, name) in [(&part, "classic"), (&torus, "torus")] {
        let (entries, vertices, triangles, unit, volume) = read_back(&written(tree, name));
        assert_eq!(entries, "[Content_Types].xml,_rels/.rels,3D/3dmodel.model");
        assert_eq!(unit, "millimeter");
        assert!(vertices > 0 && triangles > vertices, "{vertices} vertices, {triangles} triangles");
        let exact = tree.volume();
        assert!((volume - exact).abs() < 1e-9 * exact, "{name}: {volume} enclosed, {exact} in voxels");
    }
}
