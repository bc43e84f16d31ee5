//! Voxel interchange formats (.vox, .binvox, .vdb, .glb): files written by other tools
//! (MagicaVoxel's samples from the dot_vox crate, OpenVDB 10 through python3-openvdb,
//! the PyPI binvox package; see tests/data/make_reference_files.sh) against the
//! analytic shapes that made them, octsolid's output read by independent readers
//! (dot_vox, OpenVDB), exact round trips, and errors, never panics, for damaged files.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{Rng, random_octree};
use glam::DVec3;
use octsolid::io::{ColouredSolid, ReadOptions, Solids, SolidsRef, WriteOptions, binvox, gltf, vdb, vox};
use octsolid::octree::{Domain, LinearOctree, Node};
use octsolid::render::{from_srgb8, to_srgb8};
use octsolid::shape::Axis;
use octsolid::{MemoryBudget, NoProgress, SolidFile, write_solid_file};
use serde_json::Value;

fn data(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data").join(path)
}

/// A folder of its own for each test (tests run in parallel).
fn scratch(test: &str) -> PathBuf {
    common::scratch_dir("formats", test)
}

/// The solids of a solid file, read through the door ([`SolidFile::read`]).
fn read_solids(path: impl AsRef<Path>, options: &ReadOptions) -> octsolid::Result<Solids> {
    SolidFile::read(path, options).map(|file| file.solids)
}

/// Writes `solids`, borrowed, through the door ([`write_solid_file`]).
fn write_solids(path: impl AsRef<Path>, solids: &Solids, options: &WriteOptions) -> octsolid::Result<u64> {
    write_solid_file(path, &solids.borrowed(), options, &NoProgress)
}

/// Writes one solid with a colour, named by the file's stem, through the door.
fn write_solid(
    path: impl AsRef<Path>,
    tree: &LinearOctree,
    color: Option<DVec3>,
    options: &WriteOptions,
) -> octsolid::Result<u64> {
    let path = path.as_ref();
    let mut solids = SolidsRef::of_file(path, tree);
    solids.solids[0].color = color;
    write_solid_file(path, &solids, options, &NoProgress)
}

fn options() -> ReadOptions {
    ReadOptions { budget: MemoryBudget::unlimited(), ..ReadOptions::default() }
}

fn json(path: &str) -> Value {
    serde_json::from_str(&std::fs::read_to_string(data(path)).unwrap()).unwrap()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn ijk(v: &Value) -> [i64; 3] {
    [0, 1, 2].map(|a| v[a].as_i64().unwrap())
}

/// Solids of a few depths and kinds: random nodes and voxels, full, empty, one voxel
/// in a far corner.
fn solids(depths: &[u8], seed: u64) -> Vec<LinearOctree> {
    let mut rng = Rng(seed);
    let mut out = Vec::new();
    for &depth in depths {
        let d = Domain::new(DVec3::new(-1.25, 0.5, 3.0), 0.75 * f64::from(depth), depth).unwrap();
        out.push(random_octree(&mut rng, d));
        let far = [d.resolution() - 1; 3];
        out.push(LinearOctree::from_voxels(d, [far, [0, 0, 0]]).unwrap());
    }
    let d = Domain::new(DVec3::ZERO, 1.0, depths[0]).unwrap();
    out.push(LinearOctree::empty(d));
    out.push(LinearOctree::full(d));
    out
}

// ---------------------------------------------------------------------------------
// MagicaVoxel .vox

/// The RGBA chunk of a .vox file, read by hand: entry `i - 1` is palette index `i`.
fn raw_palette(bytes: &[u8]) -> Vec<[u8; 4]> {
    let at = bytes.windows(4).position(|w| w == b"RGBA").unwrap() + 12;
    bytes[at..at + 1024].chunks(4).map(|c| [c[0], c[1], c[2], c[3]]).collect()
}

#[test]
fn vox_sample_places_its_voxels_by_the_pivot_convention() {
    // dot_vox's own documentation of placeholder.vox: a 2^3 model with voxels
    // (0,0,0) 225, (0,1,1) 215, (1,0,1) 235, (1,1,0) 5 (zero-based indices), placed by
    // a transform of _t = (0, 0, 1): world = v - floor(2/2) + t.
    let path = data("vox/placeholder.vox");
    let solids = read_solids(&path, &options()).unwrap();
    solids.validate().unwrap();
    assert_eq!(solids.domain.min(), DVec3::new(-1.0, -1.0, 0.0));
    assert_eq!((solids.domain.depth(), solids.domain.edge()), (1, 2.0));
    let palette = raw_palette(&std::fs::read(&path).unwrap());
    let expected = [(6u8, [1u32, 1, 0]), (216, [0, 1, 1]), (226, [0, 0, 0]), (236, [1, 0, 1])];
    assert_eq!(solids.solids.len(), 4);
    for (solid, (index, voxel)) in solids.solids.iter().zip(expected) {
        assert_eq!(solid.palette_index, Some(index));
        assert_eq!(solid.tree.voxel_count(), 1);
        assert!(solid.tree.contains_voxel(voxel), "index {index} at {voxel:?}");
        let c = palette[usize::from(index) - 1];
        assert_eq!(solid.color, Some(DVec3::new(from_srgb8(c[0]), from_srgb8(c[1]), from_srgb8(c[2]))));
    }
    // A voxel edge of 0.5 world units scales the domain, not the voxels.
    let half = read_solids(&path, &ReadOptions { voxel_size: 0.5, ..options() }).unwrap();
    assert_eq!((half.domain.min(), half.domain.edge()), (DVec3::new(-0.5, -0.5, 0.0), 1.0));
    assert_eq!(half.solids[0].tree.keys(), solids.solids[0].tree.keys());
}

/// Translation-only placements of a scene graph, walked independently of octsolid
/// through dot_vox's nodes (MagicaVoxel numbers nodes in file order).
fn translated_instances(data: &dot_vox::DotVoxData) -> Vec<(usize, [i64; 3])> {
    let mut out = Vec::new();
    let mut stack = vec![(0u32, [0i64; 3])];
    while let Some((id, t)) = stack.pop() {
        match &data.scenes[id as usize] {
            dot_vox::SceneNode::Transform { frames, child, .. } => {
                let p = frames[0].position().map_or([0; 3], |p| [p.x, p.y, p.z].map(i64::from));
                assert!(frames[0].attributes.get("_r").is_none(), "translations only");
                stack.push((*child, [0, 1, 2].map(|a| t[a] + p[a])));
            }
            dot_vox::SceneNode::Group { children, .. } => children.iter().for_each(|&c| stack.push((c, t))),
            dot_vox::SceneNode::Shape { models, .. } => out.push((models[0].model_id as usize, t)),
        }
    }
    out
}

#[test]
fn vox_scene_graph_of_several_models_matches_an_independent_walk() {
    let path = data("vox/axes.vox");
    let solids = read_solids(&path, &options()).unwrap();
    solids.validate().unwrap();
    let file = dot_vox::load(path.to_str().unwrap()).unwrap();
    let instances = translated_instances(&file);
    assert_eq!(instances.len(), 10, "axes.vox places ten shapes of four models");
    // Every world voxel of every instance: v - floor(s/2) + t.
    let mut expected = std::collections::BTreeMap::new();
    for (m, t) in &instances {
        let model = &file.models[*m];
        let s = [model.size.x, model.size.y, model.size.z].map(|v| i64::from(v / 2));
        for v in &model.voxels {
            let w = [0, 1, 2].map(|a| i64::from([v.x, v.y, v.z][a]) - s[a] + t[a]);
            expected.insert(w, v.i + 1);
        }
    }
    let lo = [0, 1, 2].map(|a| expected.keys().map(|w| w[a]).min().unwrap());
    assert_eq!(solids.domain.min(), DVec3::new(lo[0] as f64, lo[1] as f64, lo[2] as f64));
    let total: u64 = solids.solids.iter().map(|s| s.tree.voxel_count()).sum();
    assert_eq!(total, expected.len() as u64);
    for (w, index) in &expected {
        let c = [0, 1, 2].map(|a| (w[a] - lo[a]) as u32);
        let solid = solids.solids.iter().find(|s| s.palette_index == Some(*index)).unwrap();
        assert!(solid.tree.contains_voxel(c), "index {index} at world {w:?}");
        let colour = file.palette[usize::from(*index) - 1];
        assert_eq!(solid.color.unwrap().x, from_srgb8(colour.r));
    }
}

#[test]
fn vox_materials_come_with_their_palette_index() {
    for name in ["single-voxel-with-material.vox", "metal-material.vox", "placeholder-with-materials.vox"] {
        let path = data(&format!("vox/{name}"));
        let solids = read_solids(&path, &options()).unwrap();
        let file = dot_vox::load(path.to_str().unwrap()).unwrap();
        let voxels: usize = file.models.iter().map(|m| m.voxels.len()).sum();
        assert_eq!(solids.solids.iter().map(|s| s.tree.voxel_count()).sum::<u64>(), voxels as u64, "{name}");
        for solid in &solids.solids {
            let index = u32::from(solid.palette_index.unwrap());
            let matl = file.materials.iter().find(|m| m.id == index).unwrap();
            assert_eq!(solid.material.len(), matl.properties.len(), "{name}");
            for (k, v) in &matl.properties {
                assert_eq!(solid.material.get(k), Some(v), "{name} {k}");
            }
        }
    }
    let metal = read_solids(data("vox/metal-material.vox"), &options()).unwrap();
    assert!(metal.solids.iter().any(|s| s.material.get("_type").is_some_and(|t| t == "_metal")));
}

/// MagicaVoxel materials reach the renderer: the files MagicaVoxel wrote (dot_vox's
/// samples) give their metals' reflectance; glass and emitters written through
/// octsolid's own `.vox` writer come back as Whitted's refraction and as emission, and
/// a scene with an emitter is lit by its emitters alone.
#[test]
fn vox_materials_become_mirrors_glass_and_lights() {
    use octsolid::render::Material;
    let bounds = |s: &Solids| s.union().bounds().unwrap();
    for (name, palette, reflectance) in [
        ("metal-material.vox", 85, 0.526316),
        ("placeholder-with-materials.vox", 216, 0.694737),
        ("single-voxel-with-material.vox", 249, 1.0),
    ] {
        let solids = read_solids(data(&format!("vox/{name}")), &options()).unwrap();
        let b = bounds(&solids);
        let index = solids.solids.iter().position(|s| s.palette_index == Some(palette)).unwrap();
        let scene = solids.scene(name, &b);
        let m = &scene.solids[index].material;
        assert_eq!((m.reflectance, m.transmittance), (reflectance, 0.0), "{name}");
        m.validate().unwrap();
    }
    // Glass and an emitter through octsolid's writer and reader.
    let d = Domain::new(DVec3::ZERO, 8.0, 3).unwrap();
    let cube = |lo: u32| LinearOctree::from_voxels(d, (lo..lo + 2).flat_map(|x| [[x, 0, 0], [x, 1, 0]])).unwrap();
    let with = |name: &str, tree, props: &[(&str, &str)]| ColouredSolid {
        material: props.iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
        ..ColouredSolid::new(name, Some(DVec3::new(0.5, 0.6, 0.7)), tree)
    };
    let written = Solids {
        domain: d,
        solids: vec![
            with("glass", cube(0), &[("_type", "_glass"), ("_weight", "0.8"), ("_ior", "0.5"), ("_rough", "0.1")]),
            with("lamp", cube(4), &[("_type", "_emit"), ("_weight", "0.5"), ("_flux", "2")]),
        ],
    };
    let dir = scratch("vox-materials");
    let path = dir.join("m.vox");
    write_solids(&path, &written, &WriteOptions::default()).unwrap();
    let back = read_solids(&path, &options()).unwrap();
    let (b, colour) = (bounds(&back), back.solids[1].color.unwrap());
    let scene = back.scene("m", &b);
    let [glass, lamp] = [0, 1].map(|i| &scene.solids[i].material);
    assert_eq!((glass.transmittance, glass.ior), (0.8, 1.5));
    assert!((glass.reflectance - 0.04).abs() < 1e-12, "{glass:?}");
    assert!((lamp.emission - colour * 2.0).length() < 1e-12, "{lamp:?}");
    assert!(scene.lights.is_empty(), "an emitter lights the scene alone");
    // Diffuse and unreadable values keep the default material.
    let plain = Material::from_magicavoxel(
        DVec3::ONE,
        &[("_type", "_diffuse"), ("_weight", "x")].iter().map(|(k, v)| (k.to_string(), v.to_string())).collect(),
    );
    assert_eq!(plain, Material { color: DVec3::ONE, ..Material::default() });
}

/// A .vox written by dot_vox's own writer: one 3 x 2 x 1 model (an L of three colours)
/// under the given transform frames (outermost first), each with a group between.
fn dot_vox_scene(frames: &[&[(&str, String)]]) -> Vec<u8> {
    let dict = |entries: &[(&str, String)]| -> dot_vox::Dict {
        entries.iter().map(|(k, v)| (k.to_string(), v.clone())).collect()
    };
    let voxels = vec![
        dot_vox::Voxel { x: 0, y: 0, z: 0, i: 0 },
        dot_vox::Voxel { x: 1, y: 0, z: 0, i: 1 },
        dot_vox::Voxel { x: 2, y: 0, z: 0, i: 1 },
        dot_vox::Voxel { x: 0, y: 1, z: 0, i: 2 },
    ];
    let mut scenes = Vec::new();
    for (k, frame) in frames.iter().enumerate() {
        let id = scenes.len() as u32;
        let last = k + 1 == frames.len();
        scenes.push(dot_vox::SceneNode::Transform {
            attributes: dict(&[]),
            frames: vec![dot_vox::Frame::new(dict(frame))],
            child: id + 1,
            layer_id: 0,
        });
        if last {
            scenes.push(dot_vox::SceneNode::Shape {
                attributes: dict(&[]),
                models: vec![dot_vox::ShapeModel { model_id: 0, attributes: dict(&[]) }],
            });
        } else {
            scenes.push(dot_vox::SceneNode::Group { attributes: dict(&[]), children: vec![id + 2] });
        }
    }
    let file = dot_vox::DotVoxData {
        version: 200,
        index_map: Vec::new(),
        models: vec![dot_vox::Model { size: dot_vox::Size { x: 3, y: 2, z: 1 }, voxels }],
        palette: dot_vox::DEFAULT_PALETTE.to_vec(),
        materials: Vec::new(),
        scenes,
        layers: Vec::new(),
    };
    let mut bytes = Vec::new();
    file.write_vox(&mut bytes).unwrap();
    bytes
}

/// World voxels (lattice + domain corner) of every solid, with palette indices.
fn world_voxels(solids: &Solids) -> std::collections::BTreeSet<([i64; 3], u8)> {
    let mut out = std::collections::BTreeSet::new();
    let lo = solids.domain.min();
    for s in &solids.solids {
        for n in s.tree.nodes() {
            assert_eq!(n.size, 1);
            let w = [0, 1, 2].map(|a| n.min[a] as i64 + lo[a] as i64);
            out.insert((w, s.palette_index.unwrap()));
        }
    }
    out
}

#[test]
fn vox_rotations_are_the_48_signed_permutations_and_compose() {
    let read = |bytes: &[u8]| vox::decode(bytes, Path::new("r.vox"), &options()).unwrap();
    // No rotation: world = v - floor((3, 2, 1) / 2) + t.
    let plain = world_voxels(&read(&dot_vox_scene(&[&[("_t", "10 20 30".into())]])));
    let expect: std::collections::BTreeSet<_> =
        [([9, 19, 30], 1), ([10, 19, 30], 2), ([11, 19, 30], 2), ([9, 20, 30], 3)].into_iter().collect();
    assert_eq!(plain, expect);
    // 90 degrees about z (x' = -y, y' = x: _r = 1 | 0 << 2 | 1 << 4) turns the model
    // about the pivot point (1, 1, 0): the bar along x now runs along y.
    let turned = world_voxels(&read(&dot_vox_scene(&[&[("_r", "17".into()), ("_t", "10 20 30".into())]])));
    let expect: std::collections::BTreeSet<_> =
        [([10, 19, 30], 1), ([10, 20, 30], 2), ([10, 21, 30], 2), ([9, 19, 30], 3)].into_iter().collect();
    assert_eq!(turned, expect);
    // All 48 valid bytes: distinct placements of the asymmetric L, each congruent to it
    // (same pairwise squared distances); each undone by its inverse in a child transform.
    let shape = |s: &std::collections::BTreeSet<([i64; 3], u8)>| {
        let v: Vec<_> = s.iter().collect();
        let mut d: Vec<(u8, u8, i64)> = Vec::new();
        for a in &v {
            for b in &v {
                d.push((a.1, b.1, (0..3).map(|i| (a.0[i] - b.0[i]).pow(2)).sum()));
            }
        }
        d.sort();
        d
    };
    let mut seen = std::collections::BTreeSet::new();
    let mut valid = 0;
    for r in 0u8..128 {
        let (c0, c1) = (r & 3, r >> 2 & 3);
        if c0 > 2 || c1 > 2 || c0 == c1 {
            let bytes = dot_vox_scene(&[&[("_r", r.to_string())]]);
            assert!(vox::decode(&bytes, Path::new("r.vox"), &options()).is_err(), "_r = {r}");
            continue;
        }
        valid += 1;
        let placed = world_voxels(&read(&dot_vox_scene(&[&[("_r", r.to_string())]])));
        assert_eq!(shape(&placed), shape(&plain), "_r = {r} is not rigid");
        let key: Vec<_> = placed.iter().map(|(w, i)| (*i, *w)).collect();
        assert!(seen.insert(key), "_r = {r} repeats a placement");
        // The inverse of a signed permutation is its transpose: column c0 -> row 0, ...
        let c2 = 3 - c0 - c1;
        let cols = [c0, c1, c2];
        let signs = [r >> 4 & 1, r >> 5 & 1, r >> 6 & 1];
        let mut inv_row = [0u8; 3];
        let mut inv_sign = [0u8; 3];
        for (row, &c) in cols.iter().enumerate() {
            inv_row[usize::from(c)] = row as u8;
            inv_sign[usize::from(c)] = signs[row];
        }
        let inv = inv_row[0] | inv_row[1] << 2 | inv_sign[0] << 4 | inv_sign[1] << 5 | inv_sign[2] << 6;
        let undone = world_voxels(&read(&dot_vox_scene(&[
            &[("_r", r.to_string()), ("_t", "10 20 30".into())],
            &[("_r", inv.to_string()), ("_t", "0 0 0".into())],
        ])));
        let shifted: std::collections::BTreeSet<_> = plain.iter().map(|(w, i)| ([w[0], w[1], w[2]], *i)).collect();
        assert_eq!(undone, shifted, "_r = {r} then its inverse {inv}");
    }
    assert_eq!(valid, 48);
}

#[test]
fn vox_round_trips_exactly_and_dot_vox_reads_what_we_write() {
    let dir = scratch("vox-round");
    for tree in solids(&[1, 3, 5, 7], 0x51ed_2701) {
        let path = dir.join("t.vox");
        write_solid(&path, &tree, Some(DVec3::new(0.2, 0.5, 0.9)), &WriteOptions::default()).unwrap();
        let back = read_solids(&path, &options()).unwrap();
        back.validate().unwrap();
        assert_eq!(back.domain, *tree.domain());
        assert_eq!(back.union(), tree);
        assert!(back.solids.len() <= 1);
        // dot_vox, independently: every voxel once, in models of at most 256 a side.
        let file = dot_vox::load(path.to_str().unwrap()).unwrap();
        let voxels: usize = file.models.iter().map(|m| m.voxels.len()).sum();
        assert_eq!(voxels as u64, tree.voxel_count());
        assert!(file.models.iter().all(|m| m.size.x.max(m.size.y).max(m.size.z) <= 256));
    }
    // Several solids: palette indices, quantized colours and materials survive.
    let d = Domain::new(DVec3::new(4.0, -2.0, 0.5), 16.0, 4).unwrap();
    let mut rng = Rng(77);
    let mut list = Vec::new();
    for k in 0..3u8 {
        let tree = &random_octree(&mut rng, d)
            - &list.iter().fold(LinearOctree::empty(d), |a, s: &ColouredSolid| &a | &s.tree);
        let mut s = ColouredSolid::new(format!("s{k}"), Some(DVec3::new(0.1 * f64::from(k), 0.7, 0.33)), tree);
        s.palette_index = Some(40 + k);
        s.material.insert("_type".into(), "_metal".into());
        s.material.insert("_rough".into(), format!("0.{k}"));
        list.push(s);
    }
    let solids = Solids { domain: d, solids: list.clone() };
    let bytes = vox::encode(&solids, MemoryBudget::unlimited()).unwrap();
    assert_eq!(bytes, vox::encode(&solids, MemoryBudget::unlimited()).unwrap(), "deterministic");
    let back = vox::decode(&bytes, Path::new("s.vox"), &options()).unwrap();
    let kept: Vec<_> = list.iter().filter(|s| !s.tree.is_empty()).collect();
    assert_eq!(back.solids.len(), kept.len());
    for (a, b) in back.solids.iter().zip(kept) {
        assert_eq!((a.palette_index, &a.material, &a.tree), (b.palette_index, &b.material, &b.tree));
        let q = b.color.unwrap().to_array().map(|c| from_srgb8(to_srgb8(c)));
        assert_eq!(a.color.unwrap().to_array(), q);
    }
}

#[test]
fn vox_voxel_count_disagreeing_with_its_chunk_is_refused_not_cut_short() {
    // A solid of more than five voxels, then its XYZI chunk's count set to 5: the
    // voxels after the fifth would be dropped without a word.
    let tree = solids(&[4], 0x0c07).into_iter().find(|t| t.voxel_count() > 5).unwrap();
    let one = Solids { domain: *tree.domain(), solids: vec![ColouredSolid::new("s", None, tree)] };
    let mut bytes = vox::encode(&one, MemoryBudget::unlimited()).unwrap();
    let at = bytes.windows(4).position(|w| w == b"XYZI").unwrap() + 12;
    let count = u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap());
    assert!(count > 5);
    bytes[at..at + 4].copy_from_slice(&5u32.to_le_bytes());
    let message = vox::decode(&bytes, Path::new("short.vox"), &options()).unwrap_err().to_string();
    assert!(message.contains("short.vox") && message.contains("count and the chunk's size disagree"), "{message}");
    // The count as written reads.
    bytes[at..at + 4].copy_from_slice(&count.to_le_bytes());
    assert!(vox::decode(&bytes, Path::new("whole.vox"), &options()).is_ok());
}

#[test]
fn vox_splits_large_solids_into_models_and_refuses_too_many_colours() {
    // Voxels 1000 apart along x: the file needs several models of at most 256^3.
    let d = Domain::new(DVec3::ZERO, 1024.0, 10).unwrap();
    let tree = LinearOctree::from_nodes(
        d,
        [
            Node { level: 7, min: [0, 0, 0], size: 8 },
            Node { level: 10, min: [1000, 600, 300], size: 1 },
            Node { level: 8, min: [256, 256, 252], size: 4 },
        ],
    )
    .unwrap();
    let solids = Solids { domain: d, solids: vec![ColouredSolid::new("big", None, tree.clone())] };
    let bytes = vox::encode(&solids, MemoryBudget::unlimited()).unwrap();
    let file = dot_vox::load_bytes(&bytes).unwrap();
    assert!(file.models.len() >= 3, "{} models", file.models.len());
    assert!(file.models.iter().all(|m| m.size.x.max(m.size.y).max(m.size.z) <= 256));
    let back = vox::decode(&bytes, Path::new("b.vox"), &options()).unwrap();
    assert_eq!(back.union(), tree);
    // Without the stored domain the domain fits the voxels, placement kept.
    let fitted = vox::decode(&bytes, Path::new("b.vox"), &ReadOptions { stored_domain: false, ..options() }).unwrap();
    assert_eq!(fitted.domain.min(), DVec3::ZERO);
    assert_eq!(fitted.domain.depth(), 10);
    assert_eq!(fitted.union().keys(), tree.keys());
    // 256 solids cannot get a colour each.
    let many: Vec<_> = (0..256).map(|i| ColouredSolid::new(format!("{i}"), None, LinearOctree::empty(d))).collect();
    let err = vox::encode(&Solids { domain: d, solids: many }, MemoryBudget::unlimited()).unwrap_err();
    assert!(err.to_string().contains("255 colours"), "{err}");
}

/// The models a `.vox` file of `solids` must hold, worked out voxel by voxel: every
/// voxel of every solid in order (a later solid's colour wins), cut into cubes of 256
/// from the voxels' lowest corner, each cube's voxels in x, y, z order, its size their
/// extent and its translation its corner plus half its size. Models by their cube's
/// (x, y, z), as the file lists them; `(size, voxels as XYZI has them, translation)`.
type VoxModel = ([u32; 3], Vec<[u8; 4]>, [i64; 3]);
fn vox_models_voxel_by_voxel(solids: &Solids, indices: &[u8]) -> Vec<VoxModel> {
    let mut colour = std::collections::BTreeMap::new();
    for (solid, &index) in solids.solids.iter().zip(indices) {
        for n in solid.tree.nodes() {
            for i in 0..u64::from(n.size).pow(3) {
                let s = u64::from(n.size);
                let v = [i % s, i / s % s, i / (s * s)].map(|c| c as u32);
                colour.insert([0, 1, 2].map(|a| n.min[a] + v[a]), index);
            }
        }
    }
    let lo = [0, 1, 2].map(|a| colour.keys().map(|v| v[a]).min().unwrap_or(0));
    let mut models: std::collections::BTreeMap<[u32; 3], Vec<[u8; 4]>> = std::collections::BTreeMap::new();
    for (v, &index) in &colour {
        let local = [0, 1, 2].map(|a| v[a] - lo[a]);
        models.entry(local.map(|c| c / 256)).or_default().push([local[0] as u8, local[1] as u8, local[2] as u8, index]);
    }
    models
        .into_iter()
        .map(|(m, mut voxels)| {
            voxels.sort_by_key(|v| [v[0], v[1], v[2]]);
            let size = [0, 1, 2].map(|a| voxels.iter().map(|v| u32::from(v[a]) + 1).max().unwrap());
            let t = [0, 1, 2].map(|a| i64::from(lo[a] + 256 * m[a]) + i64::from(size[a] / 2));
            (size, voxels, t)
        })
        .collect()
}

/// The writer visits only the models its nodes meet, listing a sparse one from its
/// voxels and painting a dense one into a byte grid: both give the models an
/// independent voxel-by-voxel walk gives, with overlapping solids (the later wins on
/// either path) and nodes across model borders (the voxels' corner is not a multiple
/// of 256).
#[test]
fn vox_models_match_a_voxel_by_voxel_walk() {
    let d = Domain::new(DVec3::ZERO, 1.0, 10).unwrap();
    let node = |size: u32, min: [u32; 3]| Node { level: 10 - size.trailing_zeros() as u8, min, size };
    let mut rng = Rng(0x00f0_0d5e);
    let mut scattered = |n: usize, lo: u32, span: u32| -> Vec<Node> {
        (0..n).map(|_| node(1, [0; 3].map(|_| lo + rng.below(u64::from(span)) as u32))).collect()
    };
    // A dense block across four models, sparse voxels in far models, a lone corner.
    let mut a = vec![node(128, [256, 128, 256]), node(1, [3, 5, 7]), node(64, [448, 448, 448])];
    a.extend(scattered(300, 600, 400));
    let mut b = vec![node(32, [352, 224, 352]), node(8, [0, 512, 8])];
    b.extend(scattered(300, 600, 400));
    // The first solid's own scattered voxels again (overlap on the sparse path).
    b.extend(a[3..200].iter().copied());
    let trees = [a, b].map(|nodes| LinearOctree::from_nodes(d, nodes).unwrap());
    let solids = Solids {
        domain: d,
        solids: vec![
            ColouredSolid::new("a", Some(DVec3::new(1.0, 0.0, 0.0)), trees[0].clone()),
            ColouredSolid::new("b", Some(DVec3::new(0.0, 0.0, 1.0)), trees[1].clone()),
        ],
    };
    let bytes = vox::encode(&solids, MemoryBudget::unlimited()).unwrap();
    let file = dot_vox::load_bytes(&bytes).unwrap();
    let places = translated_instances(&file);
    let got: Vec<VoxModel> = (0..file.models.len())
        .map(|m| {
            let model = &file.models[m];
            let voxels = model.voxels.iter().map(|v| [v.x, v.y, v.z, v.i + 1]).collect();
            let t = places.iter().find(|(k, _)| *k == m).expect("placed").1;
            ([model.size.x, model.size.y, model.size.z], voxels, t)
        })
        .collect();
    let expected = vox_models_voxel_by_voxel(&solids, &[1, 2]);
    assert!(expected.len() >= 8, "{} models", expected.len());
    assert_eq!(got.len(), expected.len());
    for (k, (g, e)) in got.iter().zip(&expected).enumerate() {
        assert_eq!(g, e, "model {k}");
    }
}

/// Two voxels in opposite corners of a depth-12 domain: two models of one voxel
/// (the box holds 4,096 models' room), read back as they were.
#[test]
fn vox_of_two_far_corners_reads_back() {
    let d = Domain::new(DVec3::ZERO, 1.0, 12).unwrap();
    let node = |min: [u32; 3]| Node { level: 12, min, size: 1 };
    let tree = LinearOctree::from_nodes(d, [node([0; 3]), node([4095; 3])]).unwrap();
    let solids = Solids { domain: d, solids: vec![ColouredSolid::new("corners", None, tree.clone())] };
    let bytes = vox::encode(&solids, MemoryBudget::unlimited()).unwrap();
    assert_eq!(dot_vox::load_bytes(&bytes).unwrap().models.len(), 2);
    let back = vox::decode(&bytes, Path::new("c.vox"), &options()).unwrap();
    assert_eq!(back.domain, d);
    assert_eq!(back.union(), tree);
}

// ---------------------------------------------------------------------------------
// binvox

#[test]
fn binvox_reference_files_hold_their_analytic_shapes() {
    let shapes = json("binvox/shapes.json");
    for (name, inside) in [
        (
            "torus64.binvox",
            Box::new(|p: [f64; 3], s: &Value| {
                (p[0].hypot(p[1]) - f(&s["major"])).powi(2) + p[2].powi(2) - f(&s["minor"]).powi(2)
            }) as Box<dyn Fn([f64; 3], &Value) -> f64>,
        ),
        (
            "ellipsoid50.binvox",
            Box::new(|p: [f64; 3], s: &Value| {
                (0..3).map(|a| (p[a] / f(&s["semi_axes"][a])).powi(2)).sum::<f64>() - 1.0
            }),
        ),
    ] {
        let s = &shapes[name];
        let tree = binvox::read(data(&format!("binvox/{name}")), MemoryBudget::unlimited()).unwrap();
        tree.validate().unwrap();
        let dim = s["dim"].as_u64().unwrap() as u32;
        let t = [0, 1, 2].map(|a| f(&s["translate"][a]));
        let scale = f(&s["scale"]);
        let d = tree.domain();
        assert_eq!(d.min(), DVec3::from_array(t), "{name}");
        assert_eq!(d.depth(), 6, "{name}");
        assert!((d.voxel_size() - scale / f64::from(dim)).abs() < 1e-15, "{name}");
        assert_eq!(tree.voxel_count(), s["voxels"].as_u64().unwrap(), "{name}");
        let mut checked = 0;
        for i in 0..64u32 {
            for j in 0..64u32 {
                for k in 0..64u32 {
                    let full = tree.contains_voxel([i, j, k]);
                    if i >= dim || j >= dim || k >= dim {
                        assert!(!full, "{name}: padding voxel {i} {j} {k}");
                        continue;
                    }
                    let p = [0, 1, 2]
                        .map(|a| t[a] + scale * (f64::from([i, j, k][a]) + 0.5) / f64::from(dim) - f(&s["center"][a]));
                    let v = inside(p, s);
                    if v.abs() > 1e-9 {
                        assert_eq!(full, v < 0.0, "{name}: voxel {i} {j} {k}");
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked as u32 >= dim.pow(3) - 10, "{name}: {checked} voxels decided");
    }
}

#[test]
fn binvox_round_trips_exactly() {
    let dir = scratch("binvox-round");
    for tree in solids(&[1, 2, 5, 8], 0x00b1_d0c5) {
        let path = dir.join("t.binvox");
        write_solid(&path, &tree, None, &WriteOptions::default()).unwrap();
        let back = binvox::read(&path, MemoryBudget::unlimited()).unwrap();
        assert_eq!(back.domain(), tree.domain());
        assert_eq!(back, tree);
    }
}

#[test]
fn binvox_reads_non_cubic_grids_padded_into_the_cube() {
    // dim lists x, z, y sizes: 3 along x, 2 along z, 5 along y, voxel edge 0.5 / 5.
    let mut file = b"#binvox 1\ndim 3 2 5\ntranslate 1 2 3\nscale 0.5\ndata\n".to_vec();
    // Index x * 10 + z * 5 + y: set (x=1, z=0, y=4) and (x=2, z=1, y=0), nothing else.
    let set = [14usize, 25];
    let mut bits = vec![0u8; 30];
    set.iter().for_each(|&i| bits[i] = 1);
    for b in bits {
        file.extend([b, 1]);
    }
    let tree = binvox::decode(&file, Path::new("n.binvox"), MemoryBudget::unlimited()).unwrap();
    assert_eq!(tree.domain().depth(), 3);
    assert!((tree.domain().voxel_size() - 0.1).abs() < 1e-15);
    assert_eq!(tree.voxel_count(), 2);
    assert!(tree.contains_voxel([1, 4, 0]) && tree.contains_voxel([2, 0, 1]));
}

/// A ball written by trimesh's own binvox writer (tests/data/make_reference_files.py):
/// its comment line is read past, and its grid is where trimesh has it (trimesh's
/// `translate` is the first voxel's centre, its `scale` the centres' span), every voxel
/// decided as the analytic ball decides its centre.
#[test]
fn binvox_files_written_by_trimesh_are_read_where_trimesh_has_them() {
    let s = &json("binvox/shapes.json")["ball40-trimesh.binvox"];
    let tree = binvox::read(data("binvox/ball40-trimesh.binvox"), MemoryBudget::unlimited()).unwrap();
    tree.validate().unwrap();
    let (pitch, dim) = (f(&s["pitch"]), s["dim"].as_u64().unwrap() as u32);
    let first = DVec3::new(f(&s["first_centre"][0]), f(&s["first_centre"][1]), f(&s["first_centre"][2]));
    let center = DVec3::new(f(&s["center"][0]), f(&s["center"][1]), f(&s["center"][2]));
    let d = tree.domain();
    assert!((d.voxel_size() - pitch).abs() < 1e-12 && (d.voxel_center([0, 0, 0]) - first).length() < 1e-12, "{d:?}");
    assert_eq!(tree.voxel_count(), s["voxels"].as_u64().unwrap());
    let r = f(&s["radius"]);
    for i in 0..dim {
        for j in 0..dim {
            for k in 0..dim {
                let p = d.voxel_center([i, j, k]);
                assert_eq!(tree.contains_voxel([i, j, k]), (p - center).length() < r, "voxel {i} {j} {k}");
            }
        }
    }
}

#[test]
fn binvox_headers_may_hold_comments_blank_lines_and_crlf() {
    let file = |header: &str| {
        let mut bytes = header.as_bytes().to_vec();
        bytes.extend([1u8, 8]);
        binvox::decode(&bytes, Path::new("c.binvox"), MemoryBudget::unlimited())
    };
    let plain = file("#binvox 1\ndim 2 2 2\ntranslate 0 0 0\nscale 1\ndata\n").unwrap();
    for header in [
        "#binvox 1\n# a comment\n\ndim 2 2 2\ntranslate 0 0 0   # the corner\nscale 1\ndata\n",
        "#binvox 1\r\ndim 2 2 2\r\n\r\nTranslate 0 0 0\r\nSCALE 1\r\ndata\r\n",
    ] {
        assert_eq!(file(header).unwrap(), plain, "{header:?}");
    }
    let e = file("#binvox 1\ndim 2 2 2\ncolour red\ndata\n").unwrap_err().to_string();
    assert!(e.contains("c.binvox") && e.contains("byte 20") && e.contains("unknown header line"), "{e}");
}

// ---------------------------------------------------------------------------------
// OpenVDB

fn vdb_solid(path: &Path, options: &ReadOptions) -> LinearOctree {
    let s = vdb::read(path, options).unwrap();
    s.validate().unwrap();
    assert_eq!(s.solids.len(), 1);
    s.solids[0].tree.clone()
}

#[test]
fn vdb_level_set_spheres_are_inside_where_negative() {
    let shapes = json("vdb/shapes.json");
    let s = &shapes["sphere"];
    let (h, r) = (f(&s["voxel_size"]), f(&s["radius"]));
    let c = DVec3::new(f(&s["center"][0]), f(&s["center"][1]), f(&s["center"][2]));
    for (name, margin) in [("sphere.vdb", 1e-4), ("sphere_half.vdb", 2e-2)] {
        let tree = vdb_solid(&data(&format!("vdb/{name}")), &options());
        let n = (r / h).ceil() as i64 + 3;
        let (mut inside, mut decided) = (0u64, 0u64);
        let centre = (c / h).round().as_i64vec3();
        for i in -n..=n {
            for j in -n..=n {
                for k in -n..=n {
                    let idx = centre + glam::I64Vec3::new(i, j, k);
                    let p = idx.as_dvec3() * h;
                    let dist = (p - c).length() - r;
                    if dist.abs() > margin {
                        assert_eq!(tree.contains_point(p), dist < 0.0, "{name}: index {idx}");
                        decided += 1;
                    }
                    inside += u64::from(dist < 0.0);
                }
            }
        }
        assert!(decided > 0 && tree.voxel_count().abs_diff(inside) <= ((2 * n + 1).pow(3) as u64 - decided), "{name}");
    }
}

#[test]
fn vdb_fog_volume_and_bool_grid_by_name_and_threshold() {
    let shapes = json("vdb/shapes.json");
    let path = data("vdb/fog_and_mask.vdb");
    // The first grid, a fog volume: a box of 1s with changed voxels.
    let s = &shapes["density"];
    let (lo, hi) = (ijk(&s["box"]["min"]), ijk(&s["box"]["max"]));
    let h = f(&s["voxel_size"]);
    let t = DVec3::new(f(&s["translation"][0]), f(&s["translation"][1]), f(&s["translation"][2]));
    let world = |c: [i64; 3]| t + DVec3::new(c[0] as f64, c[1] as f64, c[2] as f64) * h;
    let in_box = |c: [i64; 3]| (0..3).all(|a| lo[a] <= c[a] && c[a] <= hi[a]);
    let box_voxels: u64 = (0..3).map(|a| (hi[a] - lo[a] + 1) as u64).product();
    for threshold in [0.5, 0.65, 0.3] {
        let tree = vdb_solid(&path, &ReadOptions { fog_threshold: threshold, ..options() });
        let mut expected = box_voxels;
        for v in s["voxels"].as_array().unwrap() {
            let (c, value) = (ijk(&v[0]), f(&v[1]));
            let inside = value > threshold;
            assert_eq!(tree.contains_point(world(c)), inside, "threshold {threshold}: voxel {c:?}");
            expected = expected - u64::from(in_box(c)) + u64::from(inside);
        }
        assert_eq!(tree.voxel_count(), expected, "threshold {threshold}");
        for c in [lo, hi, [lo[0], hi[1], lo[2]], [64, 64, 64]] {
            let changed = s["voxels"].as_array().unwrap().iter().any(|v| ijk(&v[0]) == c);
            assert!(changed || tree.contains_point(world(c)), "{c:?}");
        }
        assert!(!tree.contains_point(world([lo[0] - 1, lo[1], lo[2]])));
    }
    // The bool grid, by name: a block and a ball of voxels.
    let m = &shapes["mask"];
    let tree = vdb_solid(&path, &ReadOptions { grid: Some("mask".into()), ..options() });
    let (blo, bhi) = (ijk(&m["box"]["min"]), ijk(&m["box"]["max"]));
    let (bc, br) = (ijk(&m["ball"]["center"]), f(&m["ball"]["radius"]));
    let mut expected = (0..3).map(|a| (bhi[a] - blo[a] + 1) as u64).product::<u64>();
    let r = br.ceil() as i64;
    for x in -r..=r {
        for y in -r..=r {
            for z in -r..=r {
                let inside = ((x * x + y * y + z * z) as f64) < br * br;
                expected += u64::from(inside);
                let p = DVec3::new((bc[0] + x) as f64, (bc[1] + y) as f64, (bc[2] + z) as f64);
                assert_eq!(tree.contains_point(p), inside);
            }
        }
    }
    assert_eq!(tree.voxel_count(), expected);
    let err = vdb::read(&path, &ReadOptions { grid: Some("nope".into()), ..options() }).unwrap_err();
    assert!(err.to_string().contains("density (Tree_float_5_4_3)"), "{err}");
}

#[test]
fn vdb_round_trips_exactly_at_several_depths() {
    let mut list = solids(&[1, 4, 9, 14], 0x07d8_5eed);
    let d = Domain::new(DVec3::new(-3.0, 0.0, 7.5), 100.0, 13).unwrap();
    list.push(LinearOctree::full(d));
    for tree in list {
        for compression in [vdb::Compression::None, vdb::Compression::Zip] {
            let solids = Solids { domain: *tree.domain(), solids: vec![ColouredSolid::new("s", None, tree.clone())] };
            let bytes = vdb::encode(&solids, compression, MemoryBudget::unlimited()).unwrap();
            assert_eq!(bytes, vdb::encode(&solids, compression, MemoryBudget::unlimited()).unwrap(), "deterministic");
            let back = vdb::decode(&bytes, Path::new("t.vdb"), &options()).unwrap();
            assert_eq!(back.domain, *tree.domain());
            assert_eq!(back.solids[0].tree, tree);
        }
    }
}

/// An empty `.vox` (no voxels, so no solids) converts to a `.vdb` that reads back: one
/// empty grid, named by the file, over the `.vox`'s domain (it wrote a file of no grids,
/// which nothing can place in space).
#[test]
fn an_empty_vox_converts_to_a_vdb_that_reads_back() {
    let dir = scratch("empty-vox");
    let domain = Domain::new(DVec3::ZERO, 16.0, 4).unwrap();
    let empty = Solids { domain, solids: Vec::new() };
    let vox_path = dir.join("empty.vox");
    write_solids(&vox_path, &empty, &WriteOptions::default()).unwrap();
    let from_vox = read_solids(&vox_path, &options()).unwrap();
    assert!(from_vox.solids.is_empty());
    let vdb_path = dir.join("empty.vdb");
    write_solids(&vdb_path, &from_vox, &WriteOptions::default()).unwrap();
    let back = read_solids(&vdb_path, &options()).unwrap();
    assert_eq!(back.domain, from_vox.domain);
    assert_eq!(back.solids.len(), 1);
    assert_eq!((back.solids[0].name.as_str(), back.solids[0].tree.node_count()), ("empty", 0));
}

/// Runs the OpenVDB probe on `path` at index coordinates `points`.
fn probe(path: &Path, points: &[[u32; 3]]) -> Value {
    let mut cmd = Command::new("/usr/bin/python3");
    cmd.arg(data("vdb_probe.py")).arg(path);
    points.iter().flatten().for_each(|c| {
        cmd.arg(c.to_string());
    });
    let out = cmd.output().expect("python3 runs");
    assert!(
        out.status.success(),
        "OpenVDB's reader failed (install it with tests/data/install_reference_tools.sh): {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn openvdb_reads_the_fog_volumes_we_write() {
    let dir = scratch("vdb-probe");
    let mut rng = Rng(0xfade);
    let d = Domain::new(DVec3::new(-2.0, 1.0, 0.5), 8.0, 9).unwrap();
    let big = LinearOctree::from_nodes(d, [Node { level: 1, min: [256, 0, 0], size: 256 }]).unwrap();
    let tree = &random_octree(&mut rng, d) | &big;
    let other = random_octree(&mut rng, d);
    let solids = Solids {
        domain: d,
        solids: vec![
            ColouredSolid::new("density", None, tree.clone()),
            ColouredSolid::new("density", None, other.clone()),
        ],
    };
    let points: Vec<[u32; 3]> = (0..40).map(|_| [0; 3].map(|_| rng.below(512) as u32)).chain([[300, 10, 10]]).collect();
    for compression in [vdb::Compression::None, vdb::Compression::Zip] {
        let path = dir.join("p.vdb");
        let options = WriteOptions { vdb_compression: compression, ..WriteOptions::default() };
        write_solids(&path, &solids, &options).unwrap();
        let grids = probe(&path, &points);
        assert_eq!(grids.as_array().unwrap().len(), 2);
        for (g, t) in grids.as_array().unwrap().iter().zip([&tree, &other]) {
            assert_eq!(g["name"], "density");
            assert_eq!(g["type"], "float");
            assert_eq!(g["class"], "fog volume");
            assert_eq!(g["active"].as_u64().unwrap(), t.voxel_count());
            let (lo, hi) = t.voxel_bounds().unwrap();
            assert_eq!(ijk(&g["bbox"][0]), lo.map(i64::from));
            assert_eq!(ijk(&g["bbox"][1]), hi.map(|c| i64::from(c) - 1));
            let h = d.voxel_size();
            assert!((0..3).all(|a| (f(&g["voxel_size"][a]) - h).abs() < 1e-12));
            let o = d.min() + DVec3::splat(h / 2.0);
            assert!((0..3).all(|a| (f(&g["origin_world"][a]) - o[a]).abs() < 1e-12));
            for (p, v) in points.iter().zip(g["values"].as_array().unwrap()) {
                assert_eq!(f(v), if t.contains_voxel(*p) { 1.0 } else { 0.0 }, "{p:?}");
            }
        }
    }
}

// ---------------------------------------------------------------------------------
// glTF

#[test]
fn glb_structure_matches_the_boundary_mesh() {
    let mut rng = Rng(0x61b);
    let d = Domain::new(DVec3::new(-1.0, 2.0, 0.0), 3.0, 5).unwrap();
    let a = random_octree(&mut rng, d);
    let b = &random_octree(&mut rng, d) - &a;
    let solids = Solids {
        domain: d,
        solids: vec![
            ColouredSolid::new("a \"quoted\"", Some(DVec3::new(0.9, 0.1, 0.2)), a.clone()),
            ColouredSolid::new("empty", None, LinearOctree::empty(d)),
            ColouredSolid::new("b", None, b.clone()),
        ],
    };
    let bytes = gltf::encode(&solids, Axis::Z, MemoryBudget::unlimited()).unwrap();
    let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().unwrap()) as usize;
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!((u32_at(4), u32_at(8)), (2, bytes.len()));
    let json_len = u32_at(12);
    assert_eq!((json_len % 4, &bytes[16..20]), (0, &b"JSON"[..]));
    let doc: Value = serde_json::from_slice(&bytes[20..20 + json_len]).unwrap();
    let bin_at = 20 + json_len;
    let bin_len = u32_at(bin_at);
    assert_eq!((bin_len % 4, &bytes[bin_at + 4..bin_at + 8]), (0, &b"BIN\0"[..]));
    assert_eq!(bin_at + 8 + bin_len, bytes.len());
    let bin = &bytes[bin_at + 8..];
    assert_eq!(doc["asset"]["version"], "2.0");
    assert!(doc["buffers"][0]["byteLength"].as_u64().unwrap() as usize <= bin_len);
    assert_eq!(doc["meshes"].as_array().unwrap().len(), 2, "the empty solid has no mesh");
    assert_eq!(doc["materials"][0]["name"], "a \"quoted\"");
    let colour = &doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"];
    assert_eq!([0, 1, 2, 3].map(|i| f(&colour[i]) as f32), [0.9, 0.1, 0.2, 1.0]);
    for (m, tree) in [&a, &b].into_iter().enumerate() {
        let prim = &doc["meshes"][m]["primitives"][0];
        let acc = |k: &Value| &doc["accessors"][k.as_u64().unwrap() as usize];
        let view_of = |a: &Value| {
            let v = &doc["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
            let (o, l) = (v["byteOffset"].as_u64().unwrap() as usize, v["byteLength"].as_u64().unwrap() as usize);
            assert_eq!(o % 4, 0);
            &bin[o..o + l]
        };
        let floats = |s: &[u8]| s.chunks(4).map(|c| f32::from_le_bytes(c.try_into().unwrap())).collect::<Vec<_>>();
        let (pos, nrm, idx) =
            (acc(&prim["attributes"]["POSITION"]), acc(&prim["attributes"]["NORMAL"]), acc(&prim["indices"]));
        let n = pos["count"].as_u64().unwrap() as usize;
        let p = floats(view_of(pos));
        let normals = floats(view_of(nrm));
        let indices: Vec<u32> = view_of(idx).chunks(4).map(|c| u32::from_le_bytes(c.try_into().unwrap())).collect();
        assert_eq!((p.len(), normals.len(), nrm["count"].as_u64().unwrap() as usize), (3 * n, 3 * n, n));
        assert_eq!(indices.len(), idx["count"].as_u64().unwrap() as usize);
        assert!(indices.iter().all(|&i| (i as usize) < n));
        for a in 0..3 {
            let lo = p.iter().skip(a).step_by(3).cloned().fold(f32::MAX, f32::min);
            let hi = p.iter().skip(a).step_by(3).cloned().fold(f32::MIN, f32::max);
            assert_eq!((f(&pos["min"][a]) as f32, f(&pos["max"][a]) as f32), (lo, hi));
        }
        // Normals are unit axes and face the way the triangle winds.
        let v = |i: u32| {
            DVec3::new(f64::from(p[3 * i as usize]), f64::from(p[3 * i as usize + 1]), f64::from(p[3 * i as usize + 2]))
        };
        for t in indices.chunks(3) {
            let face = (v(t[1]) - v(t[0])).cross(v(t[2]) - v(t[0]));
            for &i in t {
                let nv = DVec3::new(
                    f64::from(normals[3 * i as usize]),
                    f64::from(normals[3 * i as usize + 1]),
                    f64::from(normals[3 * i as usize + 2]),
                );
                assert_eq!(nv.length(), 1.0);
                assert!(face.dot(nv) > 0.0);
            }
        }
        // Closed: by position, every directed edge is matched by its reverse (voxels
        // touching along an edge give four faces there, two each way); and the mesh
        // encloses the solid's volume.
        let mut edges = std::collections::BTreeMap::new();
        for t in indices.chunks(3) {
            for k in 0..3 {
                let (a, b) = (v(t[k]).to_array().map(f64::to_bits), v(t[(k + 1) % 3]).to_array().map(f64::to_bits));
                *edges.entry((a, b)).or_insert(0i64) += 1;
                *edges.entry((b, a)).or_insert(0i64) -= 1;
            }
        }
        assert!(edges.values().all(|&c| c == 0), "open edges");
        let mesh = octsolid::mesh::TriangleMesh::new(
            (0..n as u32).map(v).collect(),
            indices.chunks(3).map(|t| [t[0], t[1], t[2]]).collect(),
        )
        .unwrap();
        let boundary = octsolid::mesh::boundary_mesh(tree, &Default::default());
        assert_eq!(mesh.triangles.len(), boundary.triangles.len());
        assert!(
            (mesh.volume() - tree.volume()).abs() < 1e-4 * tree.volume().max(1.0),
            "{} vs {}",
            mesh.volume(),
            tree.volume()
        );
    }
}

// ---------------------------------------------------------------------------------
// Every format: the entry points, and damage.

#[test]
fn read_solids_and_write_solid_agree_for_every_format() {
    let dir = scratch("any");
    let mut rng = Rng(5);
    let d = Domain::new(DVec3::new(0.5, 0.25, -4.0), 2.0, 6).unwrap();
    let tree = random_octree(&mut rng, d);
    for ext in ["oct", "vox", "binvox", "vdb"] {
        let path = dir.join(format!("s.{ext}"));
        write_solid(&path, &tree, Some(DVec3::new(1.0, 0.0, 0.0)), &WriteOptions::default()).unwrap();
        let back = read_solids(&path, &options()).unwrap();
        assert_eq!((back.domain, back.union()), (d, tree.clone()), "{ext}");
    }
    let glb = dir.join("s.glb");
    assert!(write_solid(&glb, &tree, None, &WriteOptions::default()).unwrap() > 0);
    assert!(read_solids(&glb, &options()).is_err());
    assert!(read_solids(dir.join("s.xyz"), &options()).is_err());
    let two = Solids {
        domain: d,
        solids: vec![ColouredSolid::new("a", None, tree.clone()), ColouredSolid::new("b", None, tree)],
    };
    let err = write_solids(dir.join("two.binvox"), &two, &WriteOptions::default()).unwrap_err();
    assert!(err.to_string().contains("holds one solid"), "{err}");
}

#[test]
fn headers_claiming_more_than_the_budget_are_refused_before_allocating() {
    let small = ReadOptions { budget: MemoryBudget(4096), ..ReadOptions::default() };
    for path in ["vox/axes.vox", "vdb/sphere.vdb", "binvox/torus64.binvox"] {
        let err = read_solids(data(path), &small).unwrap_err();
        assert!(matches!(err, octsolid::Error::OverBudget { .. }), "{path}: {err}");
    }
    // A binvox grid of 2^21 a side whose runs do not cover it: refused, nothing allocated.
    let file = b"#binvox 1\ndim 2097152 2097152 2097152\ndata\n\x00\xff".to_vec();
    let err = binvox::decode(&file, Path::new("h.binvox"), MemoryBudget::unlimited()).unwrap_err();
    assert!(err.to_string().contains("runs cover 255 voxels"), "{err}");
}

/// Every truncation (or every `stride`-th), byte flips and random bytes: errors with
/// the file's name, or solids that validate; never a panic.
fn damage(name: &str, bytes: &[u8], stride: usize, decode: &dyn Fn(&[u8]) -> octsolid::Result<Solids>) {
    let check = |b: &[u8], what: &str| match decode(b) {
        Ok(s) => s.validate().unwrap(),
        Err(e) => {
            let text = e.to_string();
            assert!(text.contains(name) || !matches!(e, octsolid::Error::Format { .. }), "{what}: {text}");
        }
    };
    for len in (0..bytes.len()).step_by(stride) {
        check(&bytes[..len], &format!("{name} truncated to {len}"));
    }
    let mut rng = Rng(0xdead_beef ^ bytes.len() as u64);
    for i in 0..600 {
        let mut b = bytes.to_vec();
        for _ in 0..1 + i % 3 {
            let at = rng.below(b.len() as u64) as usize;
            b[at] ^= 1 << rng.below(8);
        }
        check(&b, &format!("{name} flip {i}"));
    }
    for i in 0..200 {
        let mut b: Vec<u8> = (0..rng.below(400)).map(|_| rng.next() as u8).collect();
        if i % 2 == 0 {
            // Keep the magic so that the parser gets past it.
            let keep = bytes.len().min(b.len()).min(16);
            b[..keep].copy_from_slice(&bytes[..keep]);
        }
        check(&b, &format!("{name} random {i}"));
    }
}

#[test]
fn damaged_files_give_errors_never_panics() {
    let o = options();
    let mut rng = Rng(99);
    let d = Domain::new(DVec3::ZERO, 1.0, 6).unwrap();
    let tree = random_octree(&mut rng, d);
    let one = Solids { domain: d, solids: vec![ColouredSolid::new("s", Some(DVec3::ONE), tree.clone())] };
    let vox_bytes = vox::encode(&one, MemoryBudget::unlimited()).unwrap();
    let vox_decode = |b: &[u8]| vox::decode(b, Path::new("d.vox"), &o);
    damage("d.vox", &vox_bytes, 1, &vox_decode);
    damage("d.vox", &std::fs::read(data("vox/axes.vox")).unwrap(), 7, &vox_decode);
    let binvox_bytes = binvox::encode(&tree, MemoryBudget::unlimited()).unwrap();
    let binvox_decode = |b: &[u8]| {
        binvox::decode(b, Path::new("d.binvox"), MemoryBudget(1 << 30))
            .map(|t| Solids { domain: *t.domain(), solids: vec![ColouredSolid::new("s", None, t)] })
    };
    damage("d.binvox", &binvox_bytes, 1, &binvox_decode);
    let vdb_decode =
        |b: &[u8]| vdb::decode(b, Path::new("d.vdb"), &ReadOptions { budget: MemoryBudget(1 << 30), ..o.clone() });
    let vdb = |c| vdb::encode(&one, c, MemoryBudget::unlimited()).unwrap();
    damage("d.vdb", &vdb(vdb::Compression::Zip), 3, &vdb_decode);
    damage("d.vdb", &vdb(vdb::Compression::None), 5, &vdb_decode);
    damage("d.vdb", &std::fs::read(data("vdb/sphere.vdb")).unwrap(), 211, &vdb_decode);
}

/// The door writes every solid output from a borrowed tree and reads every solid file
/// back with what it records: `.oct` and `.octs` keep their metadata, a mesh is the
/// boundary (refused for an empty solid, naming the file), formats of one solid refuse
/// two, and an output kind that holds no solid is refused listing those that do.
#[test]
fn the_door_writes_and_reads_every_solid_kind_with_its_metadata() {
    use octsolid::FileKind;
    use octsolid::io::oct::{Metadata, Units};
    let dir = scratch("door");
    let mut rng = Rng(11);
    let d = Domain::new(DVec3::new(-1.0, 0.5, 2.0), 4.0, 5).unwrap();
    let tree = random_octree(&mut rng, d);
    let meta = Metadata { up: Some(Axis::Y), units: Some(Units::Millimetre) };
    let write = WriteOptions { meta, ..WriteOptions::default() };
    for &kind in FileKind::SOLIDS {
        let path = dir.join(format!("door.{}", kind.extension()));
        let bytes = write_solid_file(&path, &SolidsRef::of_file(&path, &tree), &write, &NoProgress).unwrap();
        assert!(bytes > 0, "{kind:?}");
        let back = SolidFile::read(&path, &options()).unwrap();
        assert_eq!((back.kind, back.union(), back.coarsened_from), (kind, tree.clone(), None), "{kind:?}");
        // A file of one solid names it by its stem; .vox by its palette colour.
        let name = if kind == FileKind::Vox { "colour 1" } else { "door" };
        assert_eq!(back.solids.solids[0].name, name, "{kind:?}");
        let recorded = if matches!(kind, FileKind::Oct | FileKind::Octs) { meta } else { Metadata::default() };
        assert_eq!(back.meta, recorded, "{kind:?}");
        assert_eq!(SolidFile::read_to_draw(&path, &options()).unwrap(), back, "{kind:?}");
    }
    // The meshes: the staircase encloses the voxels; the true surface (the default,
    // here estimated from the voxels: the tree has no crossings) is closed too.
    let staircase = WriteOptions { mesh_style: octsolid::surface::Style::Voxels, ..write.clone() };
    for kind in [FileKind::Obj, FileKind::Stl, FileKind::Ply] {
        let path = dir.join(format!("door.{}", kind.extension()));
        write_solid_file(&path, &SolidsRef::of_file(&path, &tree), &staircase, &NoProgress).unwrap();
        let mesh = octsolid::mesh::read_mesh(&path).unwrap();
        // STL's f32 corners and its sheets moved apart (a thousandth of an edge) move
        // the enclosed volume a little; OBJ and PLY keep it exactly.
        let tolerance = if kind == FileKind::Stl { 1e-2 } else { 1e-9 };
        let (enclosed, volume) = (mesh.volume(), tree.volume());
        assert!((enclosed - volume).abs() <= tolerance * volume, "{kind:?}: {enclosed} vs {volume}");
        write_solid_file(&path, &SolidsRef::of_file(&path, &tree), &write, &NoProgress).unwrap();
        let smooth = octsolid::mesh::read_mesh(&path).unwrap();
        assert!(smooth.is_watertight() && smooth.vertices.len() > mesh.vertices.len(), "{kind:?}");
    }
    let empty = LinearOctree::empty(d);
    let path = dir.join("empty.stl");
    let e = write_solid_file(&path, &SolidsRef::of_file(&path, &empty), &write, &NoProgress).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!("{}: the solid is empty; there is no boundary to write as a mesh", path.display())
    );
    assert!(!path.exists());
    let two = Solids {
        domain: d,
        solids: vec![ColouredSolid::new("a", None, tree.clone()), ColouredSolid::new("b", None, tree.clone())],
    };
    for name in ["two.oct", "two.octs", "two.obj"] {
        let e = write_solid_file(dir.join(name), &two.borrowed(), &write, &NoProgress).unwrap_err();
        assert!(e.to_string().contains("holds one solid and 2 were given"), "{name}: {e}");
    }
    let e = write_solid_file(dir.join("s.png"), &SolidsRef::of_file("s.png", &tree), &write, &NoProgress).unwrap_err();
    assert!(e.to_string().ends_with("(use .oct, .octs, .vox, .binvox, .vdb, .glb, .obj, .stl, .ply or .3mf)"), "{e}");
    let e = SolidFile::read(dir.join("door.glb"), &options()).unwrap_err();
    assert!(e.to_string().ends_with("unexpected extension '.glb' (use .oct, .octs, .vox, .binvox or .vdb)"), "{e}");
    std::fs::remove_dir_all(&dir).ok();
}
