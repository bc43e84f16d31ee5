//! `.3mf` output against an independent reader: Python's own `zipfile` (which checks
//! every entry's CRC-32) and `xml.etree` read the package octsolid writes, and the
//! volume the model's triangles enclose (the divergence theorem over the triangles as
//! read) must be the solid's voxel volume, the boundary mesh enclosing exactly the
//! voxels (the staircase) or within a tenth of a percent of it (the true surface, the
//! default). Also: the package's parts are the ones the 3MF core specification names,
//! the model's unit is the solid's, and a y-up solid's build item turns it upright.

mod common;

use std::process::Command;
use std::sync::Arc;

use glam::DVec3;

use octsolid::io::oct::{Metadata, Units};
use octsolid::io::{SolidsRef, WriteOptions};
use octsolid::octree::{Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::samples::classic_csg;
use octsolid::shape::{Axis, Torus};
use octsolid::surface::{HermiteData, Style};
use octsolid::{MemoryBudget, NoProgress, write_solid_file};

/// What Python reads from the package at `path` (every entry deflated and smaller for
/// it): its entry names, then the vertex and
/// triangle counts, the unit and the enclosed volume, one a line, then the build
/// item's transform applied to the unit y vector (`x,y,z`; `1 0 0 ...` when none).
const READER: &str = r#"
import sys, zipfile, xml.etree.ElementTree as ET
z = zipfile.ZipFile(sys.argv[1])
assert z.testzip() is None, "a CRC-32 does not match"
for info in z.infolist():
    assert info.compress_type == zipfile.ZIP_DEFLATED, f"{info.filename} is not deflated"
    assert info.compress_size < info.file_size, f"{info.filename}: {info.compress_size} of {info.file_size} bytes"
print(",".join(z.namelist()))
root = ET.fromstring(z.read("3D/3dmodel.model"))
ns = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}
V = [tuple(float(v.get(k)) for k in "xyz") for v in root.iterfind(".//m:vertex", ns)]
T = [tuple(int(t.get(k)) for k in ("v1", "v2", "v3")) for t in root.iterfind(".//m:triangle", ns)]
def det(a, b, c):
    return a[0]*(b[1]*c[2]-b[2]*c[1]) - a[1]*(b[0]*c[2]-b[2]*c[0]) + a[2]*(b[0]*c[1]-b[1]*c[0])
print(len(V)); print(len(T)); print(root.get("unit"))
print(repr(sum(det(V[i], V[j], V[k]) for i, j, k in T) / 6))
m = [float(x) for x in (root.find(".//m:item", ns).get("transform") or "1 0 0 0 1 0 0 0 1 0 0 0").split()]
print(",".join(repr(c) for c in m[3:6]))
"#;

fn read_back(path: &std::path::Path) -> (String, usize, usize, String, f64, String) {
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
        lines[5].to_owned(),
    )
}

fn written(tree: &LinearOctree, name: &str, options: &WriteOptions) -> std::path::PathBuf {
    let path = common::scratch_dir("three_mf", name).join(format!("{name}.3mf"));
    write_solid_file(&path, &SolidsRef::one(name, None, tree), options, &NoProgress).unwrap();
    path
}

#[test]
fn a_3mf_package_reads_back_in_another_reader_with_the_voxel_volume() {
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 7).unwrap();
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
    let part = voxelize(&classic_csg(), domain, &options).unwrap();
    let torus = voxelize(&Torus::new(DVec3::ZERO, Axis::Z, 0.7, 0.25).unwrap(), domain, &options).unwrap();
    let staircase = WriteOptions { mesh_style: Style::Voxels, ..WriteOptions::default() };
    for (tree, name) in [(&part, "classic"), (&torus, "torus")] {
        let (entries, vertices, triangles, unit, volume, up) = read_back(&written(tree, name, &staircase));
        assert_eq!(entries, "[Content_Types].xml,_rels/.rels,3D/3dmodel.model");
        assert_eq!(unit, "millimeter");
        assert_eq!(up, "0.0,1.0,0.0", "a z-up solid is not turned");
        assert!(vertices > 0 && triangles > vertices, "{vertices} vertices, {triangles} triangles");
        let exact = tree.volume();
        assert!((volume - exact).abs() < 1e-9 * exact, "{name}: {volume} enclosed, {exact} in voxels");
    }
}

#[test]
fn a_3mf_model_is_the_true_surface_in_the_solids_unit_standing_upright() {
    let domain = Domain::new(DVec3::splat(-1.1), 2.2, 7).unwrap();
    let options = VoxelizeOptions { budget: MemoryBudget::unlimited(), ..Default::default() };
    let torus = Torus::new(DVec3::ZERO, Axis::Z, 0.7, 0.25).unwrap();
    let tree = voxelize(&torus, domain, &options).unwrap();
    let surface = Arc::new(HermiteData::from_shape(&torus, &tree));
    // A y-up solid in inches (as `voxelize spot.obj --units in` records it).
    let meta = Metadata { up: Some(Axis::Y), units: Some(Units::Inch) };
    let options = WriteOptions { meta, surface: Some(surface), ..WriteOptions::default() };
    let (_, vertices, _, unit, volume, up) = read_back(&written(&tree, "torus-inches", &options));
    assert_eq!(unit, "inch");
    // The build item takes the world's up (+y) to 3MF's +z.
    assert_eq!(up, "0.0,0.0,1.0");
    // The true surface (not the staircase's volume): the exact torus volume 2 pi^2 R r^2
    // within 0.1%, a vertex a boundary voxel corner's sheet.
    let exact = 2.0 * std::f64::consts::PI.powi(2) * 0.7 * 0.25f64.powi(2);
    assert!((volume / exact - 1.0).abs() < 1e-3, "{volume} enclosed, {exact} exact");
    assert!((volume / tree.volume() - 1.0).abs() > 1e-6, "{volume}: the staircase's volume");
    assert!(vertices > 1000);
}
