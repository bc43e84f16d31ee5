//! Surface data (Hermite data) through files, set operations and exact moves: the
//! `.oct` surface section read back within its quantization, corrupt sections refused
//! naming the file and the place, the CSG of saved solids against the exact data of
//! the whole CSG tree, and exact transforms against the moved shape's exact data.

mod common;

use std::path::Path;

use glam::{DAffine3, DMat3, DQuat, DVec3};
use octsolid::io::oct::{self, Metadata, Units};
use octsolid::io::{ReadOptions, SolidsRef, WriteOptions};
use octsolid::octree::{Domain, Fit, LinearOctree, SetOp, VoxelizeOptions, voxelize};
use octsolid::shape::{Axis, Csg, Cylinder, Shape, Sphere, Transformed};
use octsolid::surface::{FaceKey, HermiteData};
use octsolid::{MemoryBudget, NoProgress, SolidFile, write_solid_file};

/// Half a step of the 16-bit `t` code, and a margin for f32.
const T_QUANTUM: f32 = 0.5 / 65535.0 + 1e-6;
/// The octahedral normal code's worst round trip (0.0036 degrees) with a margin.
const NORMAL_QUANTUM: f32 = 0.004 * std::f32::consts::PI / 180.0;

fn domain(depth: u8) -> Domain {
    Domain::new(DVec3::splat(-1.0), 2.0, depth).unwrap()
}

fn ball() -> Sphere {
    Sphere::new(DVec3::new(0.05, -0.1, 0.02), 0.7).unwrap()
}

fn bore() -> Cylinder {
    Cylinder::new(DVec3::new(0.2, 0.1, 0.0), Axis::X, 0.3, 3.0).unwrap()
}

fn solid(shape: &dyn Shape, d: Domain) -> LinearOctree {
    voxelize(shape, d, &VoxelizeOptions::default()).unwrap()
}

fn decode(bytes: &[u8]) -> octsolid::Result<(LinearOctree, Metadata, Option<HermiteData>)> {
    oct::decode_and_surface(bytes, Path::new("t.oct"), MemoryBudget::unlimited())
}

/// How `got` and `want` agree: the faces must be the same; returns the share of faces
/// whose `t` and normal agree within `t_tol` and `angle_tol`, and the worst of each.
fn agreement(got: &HermiteData, want: &HermiteData, t_tol: f32, angle_tol: f32) -> (f64, f32, f32) {
    let keys = |h: &HermiteData| h.faces().iter().map(|(k, _)| *k).collect::<Vec<_>>();
    assert_eq!(keys(got), keys(want), "the faces differ");
    let (mut close, mut worst_t, mut worst_angle) = (0usize, 0f32, 0f32);
    for ((_, a), (_, b)) in got.faces().iter().zip(want.faces()) {
        let (dt, angle) = ((a.t - b.t).abs(), a.normal.as_dvec3().angle_between(b.normal.as_dvec3()) as f32);
        worst_t = worst_t.max(dt);
        worst_angle = worst_angle.max(angle);
        close += usize::from(dt <= t_tol && angle <= angle_tol);
    }
    (close as f64 / got.len().max(1) as f64, worst_t, worst_angle)
}

#[test]
fn a_surface_section_reads_back_within_its_quantization_and_files_without_one_are_unchanged() {
    let d = domain(6);
    let tree = solid(&ball(), d);
    let surface = HermiteData::from_shape(&ball(), &tree);
    assert!(surface.len() > 1000);
    for meta in [Metadata::default(), Metadata { up: Some(Axis::Y), units: Some(Units::Millimetre) }] {
        let plain = oct::encode_with(&tree, &meta);
        // No section: the bytes of before, read as no surface.
        assert_eq!(oct::encode_with_surface(&tree, &meta, None), plain);
        assert_eq!(decode(&plain).unwrap(), (tree.clone(), meta, None));
        let bytes = oct::encode_with_surface(&tree, &meta, Some(&surface));
        // The same header but the flag, the same payload, then the section.
        assert_eq!(
            (&bytes[..10], &bytes[12..72], &bytes[80..plain.len()]),
            (&plain[..10], &plain[12..72], &plain[80..])
        );
        assert_eq!(u16::from_le_bytes([bytes[10], bytes[11]]), 1);
        let (back, back_meta, back_surface) = decode(&bytes).unwrap();
        assert_eq!((back, back_meta), (tree.clone(), meta));
        let back_surface = back_surface.expect("a surface section");
        let (share, worst_t, worst_angle) = agreement(&back_surface, &surface, T_QUANTUM, NORMAL_QUANTUM);
        assert_eq!(share, 1.0, "worst t {worst_t}, worst angle {worst_angle}");
        // Quantized data is a fixed point: written again, the same bytes.
        assert_eq!(oct::encode_with_surface(&tree, &meta, Some(&back_surface)), bytes);
        // The plain readers take the file too and give the solid.
        assert_eq!(oct::decode_and_metadata(&bytes, Path::new("t.oct"), MemoryBudget::unlimited()).unwrap().0, tree);
    }
    // Through the door for solid files.
    let dir = common::scratch_dir("surface-file", "door");
    let path = dir.join("ball.oct");
    let options = WriteOptions { surface: Some(surface.clone().into()), ..WriteOptions::default() };
    write_solid_file(&path, &SolidsRef::of_file(&path, &tree), &options, &NoProgress).unwrap();
    let file = SolidFile::read(&path, &ReadOptions::default()).unwrap();
    assert_eq!(file.solids.solids[0].tree, tree);
    assert_eq!(agreement(file.surface.as_ref().unwrap(), &surface, T_QUANTUM, NORMAL_QUANTUM).0, 1.0);
    // Other formats leave it out.
    let vox = dir.join("ball.binvox");
    write_solid_file(&vox, &SolidsRef::of_file(&vox, &tree), &options, &NoProgress).unwrap();
    assert_eq!(SolidFile::read(&vox, &ReadOptions::default()).unwrap().surface, None);
}

/// A surface section written as docs/FORMAT.md says, independently of the library:
/// records `(voxel gap << 3 | direction)` varint, `t` u16, normal 2 x u16.
fn section(count: u64, records: &[(u64, u8, u16, [u16; 2])]) -> Vec<u8> {
    let mut body = Vec::new();
    let mut previous = 0u64;
    for &(voxel, direction, t, normal) in records {
        let mut v = (u128::from(voxel.wrapping_sub(previous)) << 3) | u128::from(direction);
        previous = voxel;
        while v >= 0x80 {
            body.push((v as u8) | 0x80);
            v >>= 7;
        }
        body.push(v as u8);
        body.extend_from_slice(&t.to_le_bytes());
        body.extend_from_slice(&normal[0].to_le_bytes());
        body.extend_from_slice(&normal[1].to_le_bytes());
    }
    let mut out = b"SURF".to_vec();
    out.extend_from_slice(&1u16.to_le_bytes());
    out.extend_from_slice(&[0, 0]);
    out.extend_from_slice(&count.to_le_bytes());
    out.extend_from_slice(&(body.len() as u64).to_le_bytes());
    out.extend_from_slice(&body);
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// The file of `tree` with `section` after its payload and the surface flag set.
fn with_section(tree: &LinearOctree, section: &[u8]) -> Vec<u8> {
    let mut bytes = oct::encode(tree);
    bytes[10] = 1;
    // The header's CRC-32 covers bytes 0..72 (the flags with them) and the payload.
    let mut h = crc32fast::Hasher::new();
    h.update(&bytes[..72]);
    h.update(&bytes[oct::HEADER_BYTES..]);
    bytes[72..76].copy_from_slice(&h.finalize().to_le_bytes());
    bytes.extend_from_slice(section);
    bytes
}

fn refusal(bytes: &[u8]) -> String {
    match decode(bytes) {
        Ok(_) => panic!("a corrupt file was read"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn corrupt_surface_sections_are_refused_naming_the_file_and_the_place() {
    // Two voxels side by side along x: (1,1,1) and (2,1,1), at depth 2.
    let d = Domain::new(DVec3::ZERO, 4.0, 2).unwrap();
    let tree = LinearOctree::from_voxels(d, [[1, 1, 1], [2, 1, 1]]).unwrap();
    let morton = |v: [u32; 3]| FaceKey::new(v, 0).voxel;
    let (a, b) = (morton([1, 1, 1]), morton([2, 1, 1]));
    let good = [(a, 0, 100, [30000, 31000]), (a, 2, 200, [40000, 20000]), (b, 1, 300, [50000, 33000])];
    let payload_end = oct::encode(&tree).len();
    // The library writes what this test writes.
    let faces = good
        .iter()
        .map(|&(v, dir, t, n)| {
            let key = FaceKey { voxel: v, direction: dir };
            let back = decode(&with_section(&tree, &section(1, &[(v, dir, t, n)]))).unwrap().2.unwrap();
            (key, back.get(key).unwrap())
        })
        .collect();
    let surface = HermiteData::from_faces(faces);
    assert_eq!(
        oct::encode_with_surface(&tree, &Metadata::default(), Some(&surface)),
        with_section(&tree, &section(3, &good))
    );
    assert_eq!(decode(&with_section(&tree, &section(3, &good))).unwrap().2.unwrap(), surface);

    let at = |offset: usize| format!("t.oct: byte {}: surface section: ", payload_end + offset);
    // Truncated: the body is shorter than the header says.
    let whole = with_section(&tree, &section(3, &good));
    let e = refusal(&whole[..whole.len() - 5]);
    assert!(e.starts_with(&at(16)) && e.contains("body bytes"), "{e}");
    // A section shorter than its own header.
    let e = refusal(&whole[..payload_end + 10]);
    assert!(e.contains("t.oct") && e.contains("shorter than its 24-byte header"), "{e}");
    // A count that cannot fit (refused before anything is allocated).
    let e = refusal(&with_section(&tree, &section(u64::MAX / 2, &good)));
    assert!(e.starts_with(&at(8)) && e.contains("cannot fit"), "{e}");
    // Fewer faces said than held, and more.
    let e = refusal(&with_section(&tree, &section(2, &good)));
    assert!(e.starts_with(&at(24 + 14)) && e.contains("more faces than the 2"), "{e}");
    let e = refusal(&with_section(&tree, &section(3, &good[..2])));
    assert!(e.starts_with(&at(8)) && e.contains("3 faces cannot fit in 14 bytes"), "{e}");
    // Unsorted: the second face before the first.
    let e = refusal(&with_section(&tree, &section(3, &[good[1], good[0], good[2]])));
    assert!(e.starts_with(&at(24 + 7)) && e.contains("face 1") && e.contains("strictly sorted"), "{e}");
    // A face given twice.
    let e = refusal(&with_section(&tree, &section(3, &[good[0], good[0], good[2]])));
    assert!(e.contains("face 1") && e.contains("strictly sorted"), "{e}");
    // A direction that is no face.
    let e = refusal(&with_section(&tree, &section(1, &[(a, 6, 0, [0, 0])])));
    assert!(e.starts_with(&at(24)) && e.contains("direction 6"), "{e}");
    // A face inside the solid (voxel a towards +x is voxel b), and a face of an empty voxel.
    let e = refusal(&with_section(&tree, &section(2, &[good[0], (a, 1, 0, [0, 0])])));
    assert!(e.starts_with(&at(24 + 7)) && e.contains("face 1") && e.contains("not a boundary face"), "{e}");
    let e = refusal(&with_section(&tree, &section(1, &[(0, 0, 0, [0, 0])])));
    assert!(e.contains("face 0") && e.contains("not a boundary face"), "{e}");
    // A voxel beyond the domain.
    let e = refusal(&with_section(&tree, &section(1, &[(64, 0, 0, [0, 0])])));
    assert!(e.contains("beyond the domain"), "{e}");
    // A flipped bit in the body: the checksum.
    let mut flipped = whole.clone();
    flipped[payload_end + 24 + 2] ^= 0x10;
    let e = refusal(&flipped);
    assert!(e.starts_with(&at(24 + 21)) && e.contains("checksum mismatch"), "{e}");
    // A section version or magic this build does not know.
    let mut other = section(3, &good);
    other[4] = 2;
    let e = refusal(&with_section(&tree, &other));
    assert!(e.starts_with(&at(4)) && e.contains("version 2"), "{e}");
    let mut other = section(3, &good);
    other[0] = b'X';
    assert!(refusal(&with_section(&tree, &other)).contains("bad magic"));
    // The flag without a section, and a flag this build does not know.
    let e = refusal(&with_section(&tree, &[]));
    assert!(e.starts_with(&at(0)) && e.contains("shorter"), "{e}");
    let mut unknown = with_section(&tree, &section(3, &good));
    unknown[10] = 3;
    let e = refusal(&unknown);
    assert!(e.starts_with("t.oct: byte 10:") && e.contains("flags"), "{e}");
    // Bytes after the payload without the flag are refused as before.
    let mut extra = oct::encode(&tree);
    extra.extend_from_slice(&section(3, &good));
    assert!(refusal(&extra).contains("payload bytes"));
}

/// The operands' shapes, each voxelized and with its exact data, written to `.oct`
/// files and read back; their CSG by `op` with the data combined, against the whole
/// CSG tree voxelized with its exact data.
fn csg_of_files_against_the_whole_tree(op: SetOp, whole: &Csg, d: Domain) -> (f64, f32, f32) {
    let dir = common::scratch_dir("surface-file", op.name());
    let shapes: [&dyn Shape; 2] = [&ball(), &bore()];
    let mut read = Vec::new();
    for (i, shape) in shapes.iter().enumerate() {
        let tree = solid(*shape, d);
        let surface = HermiteData::from_shape(*shape, &tree);
        let path = dir.join(format!("{i}.oct"));
        oct::write_with_surface(&tree, &Metadata::default(), Some(&surface), &path).unwrap();
        let (tree, _, surface) = oct::read_and_surface(&path, MemoryBudget::unlimited()).unwrap();
        read.push((tree, surface.unwrap()));
    }
    let trees: Vec<&LinearOctree> = read.iter().map(|(t, _)| t).collect();
    let result = LinearOctree::combine_all(&trees, op).unwrap();
    let operands: Vec<(&LinearOctree, &HermiteData)> = read.iter().map(|(t, s)| (t, s)).collect();
    let combined = HermiteData::combine(op, &operands, &result).unwrap();
    // The oracle: the whole tree voxelized in the same domain, its data from the tree.
    let direct = solid(whole, d);
    assert_eq!(result, direct, "voxels decided at the same centres agree");
    let exact = HermiteData::from_shape(whole, &direct);
    agreement(&combined, &exact, T_QUANTUM + 1e-4, NORMAL_QUANTUM + 1e-4)
}

#[test]
fn csg_of_saved_solids_carries_their_surface_as_the_whole_tree_gives_it() {
    let d = domain(6);
    let cases = [
        (SetOp::Union, ball() | bore()),
        (SetOp::Intersection, ball() & bore()),
        (SetOp::Difference, ball() - bore()),
        (SetOp::SymmetricDifference, ball() ^ bore()),
    ];
    for (op, whole) in cases {
        let (share, worst_t, worst_angle) = csg_of_files_against_the_whole_tree(op, &whole, d);
        // Every face agrees (a surface crossing a segment twice, a feature thinner
        // than a voxel, would not: there is none here).
        assert!(
            share == 1.0,
            "{op}: {:.3}% of faces agree; worst t {worst_t}, worst angle {worst_angle}",
            100.0 * share
        );
    }
}

/// A solid off the domain's centre, its exact data, and the same under `map` exactly.
fn moved_against_the_moved_shape(map: DAffine3, target: impl FnOnce(Domain) -> octsolid::Result<Domain>) -> Fit {
    let d = domain(6);
    let shape = ball() - bore();
    let tree = solid(&shape, d);
    let surface = HermiteData::from_shape(&shape, &tree);
    let (moved, fit) = tree.transformed(map, target, &VoxelizeOptions::default()).unwrap();
    let carried = surface.transformed(tree.domain(), map, &moved, fit).expect("an exact move carries the data");
    let moved_shape = Transformed::new(shape, map).unwrap();
    let exact = HermiteData::from_shape(&moved_shape, &moved);
    let (share, worst_t, worst_angle) = agreement(&carried, &exact, 2e-5, 2e-5);
    assert!(share >= 0.999, "{fit}: {share}; worst t {worst_t}, worst angle {worst_angle}");
    fit
}

#[test]
fn exact_moves_carry_the_surface_as_the_moved_shape_gives_it() {
    let quarter = DQuat::from_axis_angle(DVec3::Z, 90f64.to_radians());
    let turn = DAffine3::from_mat3_translation(DMat3::from_quat(quarter), DVec3::new(0.3, 0.0, -0.1));
    assert!(matches!(moved_against_the_moved_shape(turn, Ok), Fit::Exact { refined: 0, .. }));
    let mirror = DAffine3::from_mat3(DMat3::from_diagonal(DVec3::new(1.0, -1.0, 1.0)));
    moved_against_the_moved_shape(mirror, Ok);
    let about_x = DAffine3::from_mat3(DMat3::from_quat(DQuat::from_axis_angle(DVec3::X, -90f64.to_radians())) * 2.0);
    moved_against_the_moved_shape(about_x, Ok);
    // Into a domain whose lattice nests at the same voxel size: whole voxels moved, and
    // faces moved out of it dropped.
    let shifted = |d: Domain| Domain::new(d.min() + DVec3::new(3.0, -5.0, 1.0) * d.voxel_size(), d.edge(), d.depth());
    let fit = moved_against_the_moved_shape(DAffine3::IDENTITY, shifted);
    assert_eq!(fit, Fit::Exact { refined: 0, offset: [-3, 5, -1] });
    // A resampling or a refinement carries nothing.
    let d = domain(5);
    let tree = solid(&ball(), d);
    let surface = HermiteData::from_shape(&ball(), &tree);
    let eighth = DAffine3::from_quat(DQuat::from_axis_angle(DVec3::Z, 45f64.to_radians()));
    let (moved, fit) = tree.transformed(eighth, Ok, &VoxelizeOptions::default()).unwrap();
    assert_eq!((fit, surface.transformed(tree.domain(), eighth, &moved, fit)), (Fit::Resampled, None));
    let finer = |d: Domain| Domain::new(d.min(), d.edge(), d.depth() + 1);
    let (moved, fit) = tree.transformed(DAffine3::IDENTITY, finer, &VoxelizeOptions::default()).unwrap();
    assert!(matches!(fit, Fit::Exact { refined: 1, .. }));
    assert_eq!(surface.transformed(tree.domain(), DAffine3::IDENTITY, &moved, fit), None);
}
