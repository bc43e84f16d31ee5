//! The `.oct` format: round trips, determinism, and a clear error (never a panic or a
//! silently different solid) for every corruption.

mod common;

use std::path::Path;

use common::Rng;
use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::io::{oct, write_atomic};
use octsolid::octree::{Domain, LinearOctree, Node, VoxelizeOptions, voxelize};
use octsolid::{Error, samples};

fn decode(bytes: &[u8]) -> octsolid::Result<LinearOctree> {
    oct::decode(bytes, Path::new("t.oct"), MemoryBudget::unlimited())
}

fn solids() -> Vec<LinearOctree> {
    let d = |depth| Domain::new(DVec3::new(-2.0, 0.5, 1.0), 4.0, depth).unwrap();
    let mut rng = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        rng
    };
    let random: Vec<[u32; 3]> = (0..300).map(|_| [0; 3].map(|_| (next() % 16) as u32)).collect();
    vec![
        LinearOctree::empty(d(3)),
        LinearOctree::full(d(1)),
        LinearOctree::full(d(21)),
        LinearOctree::from_voxels(d(4), random).unwrap(),
        LinearOctree::from_voxels(d(21), [[0, 0, 0], [2_097_151; 3]]).unwrap(),
        voxelize(&samples::showcase(), samples::showcase_domain(6).unwrap(), &VoxelizeOptions::default()).unwrap(),
    ]
}

#[test]
fn round_trip_is_exact_and_bytes_are_deterministic() {
    for tree in solids() {
        let bytes = oct::encode(&tree);
        let back = decode(&bytes).unwrap();
        back.validate().unwrap();
        assert_eq!(back, tree);
        assert_eq!(oct::encode(&back), bytes);
    }
    // The same solid built two ways gives the same bytes.
    let d = Domain::new(DVec3::ZERO, 1.0, 3).unwrap();
    let a = LinearOctree::from_nodes(d, [Node { level: 1, min: [4, 0, 0], size: 4 }]).unwrap();
    let voxels = (4..8).flat_map(|x| (0..4).flat_map(move |y| (0..4).map(move |z| [x, y, z])));
    let b = LinearOctree::from_voxels(d, voxels).unwrap();
    assert_eq!(oct::encode(&a), oct::encode(&b));
    // Nodes outside the domain are refused, even where their Morton code would wrap.
    for min in [[8, 0, 0], [0, 4, 8], [1 << 21, 0, 0]] {
        assert!(LinearOctree::from_nodes(d, [Node { level: 3, min, size: 1 }]).is_err(), "{min:?}");
    }
}

#[test]
fn payload_matches_the_documented_example() {
    // docs/FORMAT.md: voxel 0, the node 8..16 and voxel 20 at depth 2.
    let d = Domain::new(DVec3::ZERO, 1.0, 2).unwrap();
    let nodes = [
        Node { level: 2, min: [0, 0, 0], size: 1 },
        Node { level: 1, min: [2, 0, 0], size: 2 },
        Node { level: 2, min: [0, 2, 1], size: 1 },
    ];
    let tree = LinearOctree::from_nodes(d, nodes).unwrap();
    let starts: Vec<u64> = tree.keys().iter().map(|k| k.start()).collect();
    assert_eq!(starts, [0, 8, 20]);
    let bytes = oct::encode(&tree);
    assert_eq!(bytes.len(), oct::HEADER_BYTES + 5);
    assert_eq!(&bytes[oct::HEADER_BYTES..], &[0x00, 0xe1, 0x01, 0x80, 0x01]);
    assert_eq!(&bytes[..8], b"OCTSOLID");
}

#[test]
fn surfaces_take_about_two_bytes_a_node() {
    let tree =
        voxelize(&samples::showcase(), samples::showcase_domain(8).unwrap(), &VoxelizeOptions::default()).unwrap();
    let per_node = (oct::encode(&tree).len() - oct::HEADER_BYTES) as f64 / tree.node_count() as f64;
    assert!(per_node < 2.0, "{per_node} bytes a node");
}

#[test]
fn every_byte_flip_and_truncation_is_an_error() {
    for tree in solids().into_iter().filter(|t| t.node_count() < 2000) {
        let bytes = oct::encode(&tree);
        for i in 0..bytes.len() {
            for bit in [0x01, 0x80] {
                let mut bad = bytes.clone();
                bad[i] ^= bit;
                let err = decode(&bad).expect_err("a flipped byte must be caught");
                assert!(matches!(err, Error::Format { .. }), "byte {i}: {err}");
            }
        }
        for len in 0..bytes.len() {
            assert!(decode(&bytes[..len]).is_err(), "truncated to {len}");
        }
    }
}

#[test]
fn random_garbage_is_an_error() {
    let mut rng = Rng(12345);
    for len in [0, 1, 7, 8, 79, 80, 81, 200, 5000] {
        let mut garbage: Vec<u8> = (0..len).map(|_| (rng.next() >> 33) as u8).collect();
        assert!(decode(&garbage).is_err());
        if len >= 8 {
            garbage[..8].copy_from_slice(b"OCTSOLID");
            assert!(decode(&garbage).is_err());
        }
    }
}

/// Rewrites the header's CRC so a deliberate edit reaches the deeper checks.
fn reseal(bytes: &mut [u8]) {
    let mut h = crc32fast::Hasher::new();
    h.update(&bytes[..72]);
    h.update(&bytes[oct::HEADER_BYTES..]);
    let crc = h.finalize();
    bytes[72..76].copy_from_slice(&crc.to_le_bytes());
}

fn error_text(bytes: &[u8]) -> String {
    decode(bytes).unwrap_err().to_string()
}

#[test]
fn errors_say_what_and_where() {
    let tree = LinearOctree::from_voxels(Domain::new(DVec3::ZERO, 1.0, 2).unwrap(), [[0, 0, 0], [1, 1, 1]]).unwrap();
    let good = oct::encode(&tree);

    assert!(error_text(&good[..10]).contains("shorter than the 80-byte header"));
    let mut bad = good.clone();
    bad[0] = b'X';
    assert!(error_text(&bad).contains("bad magic"));
    let mut bad = good.clone();
    bad[8] = 9;
    let text = error_text(&bad);
    assert!(text.contains("version 9") && text.contains("byte 8"), "{text}");
    let mut bad = good.clone();
    bad[12] = 30;
    assert!(error_text(&bad).contains("depth 30"));
    let mut bad = good.clone();
    bad[oct::HEADER_BYTES] ^= 0x04;
    assert!(error_text(&bad).contains("checksum mismatch"));
    let mut bad = good.clone();
    bad.push(0);
    assert!(error_text(&bad).contains("payload bytes"));

    // A header claiming 2^60 nodes is refused before allocating.
    let mut bad = good.clone();
    bad[48..56].copy_from_slice(&(1u64 << 60).to_le_bytes());
    reseal(&mut bad);
    assert!(error_text(&bad).contains("cannot fit"));
    // The budget is checked before the nodes are read.
    let err = oct::decode(&good, Path::new("t.oct"), MemoryBudget(4)).unwrap_err();
    assert!(matches!(err, Error::OverBudget { .. }), "{err}");

    // Deeper checks, each with the node index and byte offset.
    let mut bad = good.clone();
    bad[oct::HEADER_BYTES] = 5; // k = 5 > depth 2
    reseal(&mut bad);
    let text = error_text(&bad);
    assert!(text.contains("node 0") && text.contains("byte 80") && text.contains("exceeds depth"), "{text}");
    let mut bad = good.clone();
    bad[oct::HEADER_BYTES] = (3 << 5) | 1; // start 3, size 8: misaligned
    reseal(&mut bad);
    assert!(error_text(&bad).contains("not aligned"));
    let mut bad = good.clone();
    bad[56] ^= 1;
    reseal(&mut bad);
    assert!(error_text(&bad).contains("voxels, the header says"));

    // Eight full siblings written as eight voxels: not canonical.
    let d = Domain::new(DVec3::ZERO, 1.0, 1).unwrap();
    let mut bytes = oct::encode(&LinearOctree::full(d));
    bytes.truncate(oct::HEADER_BYTES);
    bytes[48..56].copy_from_slice(&8u64.to_le_bytes());
    bytes[56..64].copy_from_slice(&8u64.to_le_bytes());
    bytes[64..72].copy_from_slice(&8u64.to_le_bytes());
    bytes.extend_from_slice(&[0; 8]);
    reseal(&mut bytes);
    let text = error_text(&bytes);
    assert!(text.contains("node 7") && text.contains("eight full siblings"), "{text}");
}

#[test]
fn save_and_load_through_files_atomically() {
    let dir = common::scratch_dir("oct", "atomic");
    let path = dir.join("solid.oct");
    let tree = solids().pop().unwrap();
    let bytes = oct::write(&tree, &path).unwrap();
    assert_eq!(bytes, std::fs::metadata(&path).unwrap().len());
    assert_eq!(oct::read(&path, MemoryBudget::default()).unwrap(), tree);

    // A write that fails halfway leaves the old file whole and no temporary behind.
    let err = write_atomic(&path, |w| {
        w.write_all(b"half")?;
        Err(std::io::Error::other("disk full"))
    })
    .unwrap_err();
    assert!(err.to_string().contains("solid.oct") && err.to_string().contains("disk full"), "{err}");
    assert_eq!(oct::read(&path, MemoryBudget::default()).unwrap(), tree);
    let names: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().file_name()).collect();
    assert_eq!(names.len(), 1, "{names:?}");

    let missing = oct::read(dir.join("nope.oct"), MemoryBudget::default()).unwrap_err();
    assert!(missing.to_string().contains("nope.oct"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn version_2_keeps_the_up_axis_and_units_and_version_1_still_reads() {
    use octsolid::shape::Axis;
    let tree = solids().swap_remove(3);
    // No metadata: version 1, byte-identical to the plain encoder, read back as empty.
    let plain = oct::encode_with(&tree, &oct::Metadata::default());
    assert_eq!(plain, oct::encode(&tree));
    assert_eq!(u16::from_le_bytes([plain[8], plain[9]]), 1);
    let (back, meta) = oct::decode_and_metadata(&plain, Path::new("t.oct"), MemoryBudget::unlimited()).unwrap();
    assert_eq!((back, meta), (tree.clone(), oct::Metadata::default()));
    for up in [None, Some(Axis::X), Some(Axis::Y), Some(Axis::Z)] {
        for units in [None, Some(oct::Units::Millimetre), Some(oct::Units::Inch)] {
            let meta = oct::Metadata { up, units };
            let bytes = oct::encode_with(&tree, &meta);
            let version = u16::from_le_bytes([bytes[8], bytes[9]]);
            assert_eq!(version, if up.is_none() && units.is_none() { 1 } else { 2 });
            // The documented codes, at the documented offsets.
            assert_eq!(bytes[13], up.map_or(0, |a| a.index() as u8 + 1));
            assert_eq!(bytes[14], units.map_or(0, |u| if u == oct::Units::Millimetre { 2 } else { 5 }));
            let (back, got) = oct::decode_and_metadata(&bytes, Path::new("t.oct"), MemoryBudget::unlimited()).unwrap();
            assert_eq!((back, got), (tree.clone(), meta));
        }
    }
    // Unknown codes are refused with their offset; version 1 keeps bytes 13..16 zero.
    let mut bad = oct::encode_with(&tree, &oct::Metadata { up: Some(Axis::Y), units: None });
    bad[13] = 4;
    reseal(&mut bad);
    assert!(error_text(&bad).contains("byte 13"), "{}", error_text(&bad));
    bad[13] = 2;
    bad[14] = 9;
    reseal(&mut bad);
    assert!(error_text(&bad).contains("byte 14"), "{}", error_text(&bad));
    let mut v1 = oct::encode(&tree);
    v1[13] = 2;
    reseal(&mut v1);
    assert!(error_text(&v1).contains("reserved"), "{}", error_text(&v1));
    let mut v3 = oct::encode(&tree);
    v3[8] = 3;
    reseal(&mut v3);
    assert!(error_text(&v3).contains("version 3"), "{}", error_text(&v3));
    assert_eq!("MM".parse::<oct::Units>(), Ok(oct::Units::Millimetre));
    assert!("furlong".parse::<oct::Units>().unwrap_err().contains("um, mm, cm, m, in, ft"));
}
