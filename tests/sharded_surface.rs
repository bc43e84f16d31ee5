//! A sharded solid's surface exported cell by cell (`sharded::export_surface`) against
//! the analytic sphere and against the same solid meshed whole (`surface::extract`):
//! closed, oriented, 2-manifold across the cells' seams, the same triangles; and
//! shards whose surface section is damaged refused by name.

mod common;

use common::mesh_checks::{assert_closed_manifold, stl_triangles};
use std::path::{Path, PathBuf};

use octsolid::NoProgress;
use octsolid::glam::DVec3;
use octsolid::io::oct::Metadata;
use octsolid::mesh::{TriangleMesh, separate_sheets};
use octsolid::octree::{Domain, LinearOctree, SetOp, voxelize};
use octsolid::shape::{Axis, Cuboid, Cylinder, Sphere};
use octsolid::sharded::{self, ShardIndex, ShardedSolid, StreamOptions, SurfaceExport, SurfaceExportOptions};
use octsolid::surface::{ExtractOptions, HermiteData, Style, extract};
use octsolid::{Error, MemoryBudget};

fn scratch(name: &str) -> PathBuf {
    common::scratch_dir("sharded-surface", name)
}

fn at_level(level: u8) -> StreamOptions<'static> {
    StreamOptions { level: Some(level), budget: MemoryBudget::unlimited(), ..StreamOptions::default() }
}

fn export(dir: &Path, out: &str, style: Style) -> octsolid::Result<SurfaceExport> {
    let solid = ShardedSolid::open(dir)?;
    let options = SurfaceExportOptions { style, budget: MemoryBudget::unlimited(), progress: &NoProgress };
    sharded::export_surface(&solid, &dir.with_file_name(out), &options)
}

/// An OBJ file's vertices and triangles, parsed here (not through the library).
fn read_obj(path: &Path) -> TriangleMesh {
    let text = std::fs::read_to_string(path).unwrap();
    let (mut vertices, mut triangles) = (Vec::new(), Vec::new());
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let c: Vec<f64> = words.map(|w| w.parse().unwrap()).collect();
                vertices.push(DVec3::new(c[0], c[1], c[2]));
            }
            Some("f") => {
                let i: Vec<u32> = words.map(|w| w.parse::<u32>().unwrap() - 1).collect();
                assert!(i.iter().all(|&i| (i as usize) < vertices.len()), "a face before its vertices: {line}");
                triangles.push([i[0], i[1], i[2]]);
            }
            _ => {}
        }
    }
    TriangleMesh { vertices, triangles, groups: Vec::new() }
}

/// The whole solid's surface, as `export` writes a `.oct` file's.
fn whole_surface(tree: &LinearOctree, hermite: &HermiteData, style: Style) -> TriangleMesh {
    let options = ExtractOptions { style, unit_faces: true, ..ExtractOptions::default() };
    extract(tree, hermite, &options, &NoProgress).unwrap().mesh
}

/// The mesh written as STL by the whole solid's path (sheets moved apart).
fn write_whole_stl(mesh: &TriangleMesh, path: &Path) {
    octsolid::mesh::write_mesh(&separate_sheets(mesh).unwrap(), path).unwrap();
}

fn assert_same_surface(cells: &TriangleMesh, whole: &TriangleMesh, what: &str) {
    assert_eq!(cells.triangles.len(), whole.triangles.len(), "{what}: triangles");
    assert_eq!(cells.vertices.len(), whole.vertices.len(), "{what}: vertices (seams welded once)");
    let (v, w) = (cells.volume(), whole.volume());
    assert!((v - w).abs() <= 1e-9 * w.abs(), "{what}: volume {v} cell by cell, {w} whole");
    let (a, b) = (cells.area(), whole.area());
    assert!((a - b).abs() <= 1e-9 * b, "{what}: area {a} cell by cell, {b} whole");
}

#[test]
fn a_sphere_exported_cell_by_cell_is_closed_manifold_and_the_surface_of_the_whole() {
    let dir = scratch("sphere");
    let (centre, radius) = (DVec3::new(0.013, -0.021, 0.007), 0.77);
    let sphere = Sphere::new(centre, radius).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let tree = voxelize(&sphere, domain, &Default::default()).unwrap();
    // The crossings as a `.oct` file stores them (16-bit places, octahedral normals),
    // as the shards do.
    let hermite = HermiteData::from_shape(&sphere, &tree);
    let file = octsolid::io::oct::encode_with_surface(&tree, &Metadata::default(), Some(&hermite));
    let (_, _, stored) =
        octsolid::io::oct::decode_and_surface(&file, Path::new("whole.oct"), MemoryBudget::unlimited()).unwrap();
    let whole = whole_surface(&tree, &stored.unwrap(), Style::Smooth);
    write_whole_stl(&whole, &dir.join("whole.stl"));
    let h = domain.voxel_size();
    let mut equal_levels = Vec::new();
    for level in [1u8, 2, 3] {
        let octs = dir.join(format!("sphere-{level}.octs"));
        let index =
            sharded::voxelize_shape(&sphere, domain, Metadata::default(), &octs, &at_level(level)).unwrap().unwrap();
        assert!(index.shards.len() >= 8, "level {level}: the surface crosses several cells");
        let report = export(&octs, &format!("sphere-{level}.obj"), Style::Smooth).unwrap();
        let what = format!("sphere at level {level}");
        assert_eq!(report.estimated, 0, "{what}: every vertex from the shards' crossings");
        assert!(report.seam_vertices > 0, "{what}: cells share vertices");
        let mesh = read_obj(&dir.join(format!("sphere-{level}.obj")));
        assert_eq!(report.triangles as usize, mesh.triangles.len());
        assert_closed_manifold(&mesh, &what);
        // The analytic sphere: vertices within 0.03 voxel of it (as the whole mesh's
        // are), triangles chords of at most 2 sqrt(3) voxels, so the enclosed volume is
        // within the area times the vertices' distance and the chords' sagitta.
        let exact = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
        let bound = 4.0 * std::f64::consts::PI * radius * radius * (0.03 * h + 12.0 * h * h / (8.0 * radius));
        assert!(
            (mesh.volume() - exact).abs() < bound,
            "{what}: volume {} against {exact} (bound {bound})",
            mesh.volume()
        );
        if report.full_cell_faces > 0 {
            // Faces of full cells carry no crossings (the index holds those cells as
            // nodes): the surface differs from the whole near them, closed all the same.
            equal_levels.push((level, false));
            continue;
        }
        equal_levels.push((level, true));
        assert_same_surface(&mesh, &whole, &what);
        // STL: the whole solid's triangles, corner for corner in f32, in another order.
        export(&octs, &format!("sphere-{level}.stl"), Style::Smooth).unwrap();
        assert!(
            stl_triangles(&dir.join(format!("sphere-{level}.stl"))) == stl_triangles(&dir.join("whole.stl")),
            "{what}: STL differs from the whole solid's"
        );
    }
    // Cells of 32 and 16 voxels have no full cell beside an empty voxel here.
    assert_eq!(&equal_levels[..2], &[(1, true), (2, true)]);
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_part_reaching_out_of_its_domain_goes_to_stl_cell_by_cell_as_whole() {
    // The classic part's body and bores together, the bores cut by the domain's
    // faces: vertices on the domain's edge, creases, and windows whose cut edge comes
    // within f32's reach of real vertices (STL's sheets are moved apart near the cell
    // only).
    let dir = scratch("part");
    let body = Cuboid::new(DVec3::ZERO, DVec3::splat(2.0)).unwrap() & Sphere::new(DVec3::ZERO, 1.3).unwrap();
    let bores = Cylinder::new(DVec3::ZERO, Axis::X, 0.6, 3.0).unwrap()
        | Cylinder::new(DVec3::ZERO, Axis::Y, 0.6, 3.0).unwrap()
        | Cylinder::new(DVec3::ZERO, Axis::Z, 0.6, 3.0).unwrap();
    let part = body | bores;
    let domain = Domain::new(DVec3::splat(-1.35), 2.7, 7).unwrap();
    let tree = voxelize(&part, domain, &Default::default()).unwrap();
    let hermite = HermiteData::from_shape(&part, &tree);
    let file = octsolid::io::oct::encode_with_surface(&tree, &Metadata::default(), Some(&hermite));
    let (_, _, stored) =
        octsolid::io::oct::decode_and_surface(&file, Path::new("part.oct"), MemoryBudget::unlimited()).unwrap();
    write_whole_stl(&whole_surface(&tree, &stored.unwrap(), Style::Smooth), &dir.join("whole.stl"));
    let octs = dir.join("part.octs");
    sharded::voxelize_shape(&part, domain, Metadata::default(), &octs, &at_level(2)).unwrap();
    let report = export(&octs, "part.stl", Style::Smooth).unwrap();
    assert!(report.creases > 0 && report.full_cell_faces == 0, "{report:?}");
    assert!(stl_triangles(&dir.join("part.stl")) == stl_triangles(&dir.join("whole.stl")));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn the_staircase_cell_by_cell_is_the_whole_solids_in_unit_faces() {
    let dir = scratch("staircase");
    let shape = Sphere::new(DVec3::new(0.1, 0.0, -0.05), 0.7).unwrap()
        - Cuboid::new(DVec3::splat(0.35), DVec3::splat(0.6)).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 5).unwrap();
    let tree = voxelize(&shape, domain, &Default::default()).unwrap();
    let whole = whole_surface(&tree, &HermiteData::none(), Style::Voxels);
    write_whole_stl(&whole, &dir.join("whole.stl"));
    let octs = dir.join("part.octs");
    sharded::voxelize_shape(&shape, domain, Metadata::default(), &octs, &at_level(2)).unwrap();
    export(&octs, "part.obj", Style::Voxels).unwrap();
    let mesh = read_obj(&dir.join("part.obj"));
    assert_closed_manifold(&mesh, "staircase");
    // The voxels' own volume, exactly as the octree counts it.
    assert!((mesh.volume() - tree.volume()).abs() < 1e-12 * tree.volume());
    assert_same_surface(&mesh, &whole, "staircase");
    export(&octs, "part.stl", Style::Voxels).unwrap();
    assert!(stl_triangles(&dir.join("part.stl")) == stl_triangles(&dir.join("whole.stl")));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_solid_without_crossings_is_estimated_alike_cell_by_cell_and_whole() {
    // A set operation of sharded solids carries no crossings: every vertex is
    // estimated, relaxed along the quads eight rounds, the farthest reach of a window.
    let dir = scratch("estimated");
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
    let a = Sphere::new(DVec3::new(-0.2, 0.05, 0.0), 0.6).unwrap();
    let b = Sphere::new(DVec3::new(0.3, -0.1, 0.1), 0.5).unwrap();
    let mut operands = Vec::new();
    for (name, shape) in [("a.octs", &a), ("b.octs", &b)] {
        sharded::voxelize_shape(shape, domain, Metadata::default(), &dir.join(name), &at_level(2)).unwrap();
        operands.push(ShardedSolid::open(dir.join(name)).unwrap());
    }
    let octs = dir.join("union.octs");
    sharded::combine(&operands, SetOp::Union, &octs, &at_level(2)).unwrap();
    let tree = ShardedSolid::open(&octs).unwrap().read(MemoryBudget::unlimited()).unwrap();
    let whole = whole_surface(&tree, &HermiteData::none(), Style::Smooth);
    let report = export(&octs, "union.obj", Style::Smooth).unwrap();
    assert!(report.is_estimate() && report.estimated == report.vertices, "{report:?}");
    let mesh = read_obj(&dir.join("union.obj"));
    assert_closed_manifold(&mesh, "estimated union");
    assert_same_surface(&mesh, &whole, "estimated union");
    assert_eq!(report.seam_gap, 0.0, "both sides of every seam placed its vertices alike");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The first shard of `octs` that carries a surface section, its path and bytes.
fn a_shard_with_surface(octs: &Path) -> (usize, PathBuf, Vec<u8>) {
    let solid = ShardedSolid::open(octs).unwrap();
    let i = (0..solid.index().shards.len())
        .find(|&i| solid.read_shard_and_surface(i, MemoryBudget::unlimited()).unwrap().1.is_some_and(|s| s.len() > 4))
        .unwrap();
    let path = solid.shard_path(i);
    let bytes = std::fs::read(&path).unwrap();
    (i, path, bytes)
}

#[test]
fn a_shard_whose_surface_section_is_damaged_is_refused_naming_the_file() {
    let dir = scratch("corrupt");
    let sphere = Sphere::new(DVec3::ZERO, 0.7).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 5).unwrap();
    let octs = dir.join("s.octs");
    sharded::voxelize_shape(&sphere, domain, Metadata::default(), &octs, &at_level(1)).unwrap();
    let (i, path, bytes) = a_shard_with_surface(&octs);
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    // A byte of the section's body flipped: the index's checksum of the shard fails.
    let mut damaged = bytes.clone();
    let at = damaged.len() - 10;
    damaged[at] ^= 0x5a;
    std::fs::write(&path, &damaged).unwrap();
    let e = export(&octs, "s.stl", Style::Smooth).unwrap_err().to_string();
    assert!(e.contains(&name) && e.contains("checksum mismatch with the index"), "{e}");
    // The index made to agree with the damaged shard: the section's own checksum fails.
    let mut index = ShardIndex::read(&octs).unwrap();
    index.shards[i].crc32 = crc32fast::hash(&damaged);
    std::fs::write(octs.join(sharded::INDEX_FILE), index.encode()).unwrap();
    let e = export(&octs, "s.stl", Style::Smooth).unwrap_err();
    assert!(matches!(e, Error::Format { .. }), "{e:?}");
    let e = e.to_string();
    assert!(e.contains(&name) && e.contains("surface section: checksum mismatch"), "{e}");
    assert!(!dir.join("s.stl").exists(), "no output left behind");
    // A section whose face is not a boundary face of the shard, its checksums right.
    let solid = ShardedSolid::open(&octs).unwrap();
    let entry = &solid.index().shards[i];
    let cell = solid.index().layout().cell_key(entry.cell);
    std::fs::write(&path, &bytes).unwrap();
    let (keys, _) = {
        let mut index = ShardIndex::read(&octs).unwrap();
        index.shards[i].crc32 = crc32fast::hash(&bytes);
        std::fs::write(octs.join(sharded::INDEX_FILE), index.encode()).unwrap();
        ShardedSolid::open(&octs).unwrap().read_shard_and_surface(i, MemoryBudget::unlimited()).unwrap()
    };
    let tree = LinearOctree::from_keys(domain, keys).unwrap();
    let inner = tree.keys().iter().find(|k| k.k() >= 1).expect("a node of eight voxels");
    let voxel = octsolid::morton::decode(inner.start());
    let key = octsolid::surface::FaceKey::new(voxel, 1);
    let bad = HermiteData::from_faces(vec![(key, octsolid::surface::Crossing::face(key))]);
    let forged = octsolid::io::oct::encode_with_surface(&tree, &Metadata::default(), Some(&bad));
    assert!(cell.start() <= inner.start() && inner.end() <= cell.end());
    std::fs::write(&path, &forged).unwrap();
    let mut index = ShardIndex::read(&octs).unwrap();
    index.shards[i].crc32 = crc32fast::hash(&forged);
    index.shards[i].bytes = forged.len() as u64;
    std::fs::write(octs.join(sharded::INDEX_FILE), index.encode()).unwrap();
    let e = export(&octs, "s.stl", Style::Smooth).unwrap_err().to_string();
    assert!(e.contains(&name) && e.contains("is not a boundary face"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn only_stl_and_obj_are_streamed() {
    let dir = scratch("formats");
    let sphere = Sphere::new(DVec3::ZERO, 0.5).unwrap();
    let domain = Domain::new(DVec3::splat(-1.0), 2.0, 3).unwrap();
    let octs = dir.join("s.octs");
    sharded::voxelize_shape(&sphere, domain, Metadata::default(), &octs, &at_level(1)).unwrap();
    let e = export(&octs, "s.ply", Style::Smooth).unwrap_err().to_string();
    assert!(e.contains("s.ply") && e.contains(".stl or .obj"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
