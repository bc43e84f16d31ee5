//! OpenVDB `.vdb`: a reader and a writer of our own for the documented file format
//! (OpenVDB's `io/Archive`, `io/Compression`, `tree/RootNode`, `InternalNode`,
//! `LeafNode` read and write routines, file format version 224 of OpenVDB 6 to 12).
//! Mapping in `docs/FORMAT.md`, section ".vdb".
//!
//! File: magic `0x56444220` (i64), file version, library version, a has-offsets byte,
//! a 36-character UUID, file metadata, the grid count, then for each grid its
//! descriptor (name, type, instance parent, three stream offsets), the grid's
//! compression flags, metadata, transform, topology (root: background, tiles and
//! children; internal nodes: child mask, value mask, tile values; leaves: value mask)
//! and buffers (each leaf: value mask and its 512 values). The tree is OpenVDB's
//! default `5-4-3`: root tiles of `4096^3` voxels, upper internal nodes of `32^3`
//! tiles of `128^3`, lower ones of `16^3` tiles of `8^3`, leaves of `8^3` voxels.
//!
//! **Writing: a fog volume.** One `Tree_float_5_4_3` grid a solid, class `fog
//! volume`, value 1 inside (active) and 0 outside (background, inactive). A fog volume
//! holds the solid exactly, voxel for voxel, and a full octree node becomes tiles as
//! large as the tree allows: a node of `4096` voxels or more a side is root tiles, of
//! `128` or more tiles of an upper node, of `8` or more tiles of a lower node, so only
//! leaves on the boundary store voxels. A narrow-band level set would need signed
//! distances (a pass over the boundary the octree does not have), store a band of
//! voxels on both sides of the surface whatever the solid, and give back the solid
//! only up to the band's sampling. Blender reads the grid as a volume's `density`.
//! Transform: `UniformScaleTranslateMap`, voxel size `h` = the domain's and translation
//! `min + h/2` (OpenVDB puts voxel centres on integer index coordinates), so lattice
//! voxel `(i, j, k)` is index `(i, j, k)`. The exact domain is stored in the grid's
//! `octsolid_domain` metadata (`"min_x min_y min_z edge depth"`) so `.oct -> .vdb ->
//! .oct` is exact. Values are written with OpenVDB's active-mask compression and, by
//! default, zlib (`Compression::Zip`); the UUID is derived from the content, so the
//! same solids give the same bytes.
//! Before anything is built, one pass over the nodes counts the tree's root tiles,
//! internal nodes, tiles, leaves and leaf voxels (`TreeCounts`), and the memory they
//! take (each one's map entry and three times its bytes in the file) is checked
//! against the budget; a refusal names the output and the counts.
//! Limit: a full node of side `2^k >= 4096` becomes `(2^k / 4096)^3` root tiles, about
//! 180 bytes each while written (a full depth-20 domain is 2^24 of them, about 3 GiB,
//! a full depth-21 domain 2^27).
//!
//! **Reading**: float, half-float, double and bool grids (`Tree_{float,double,bool}_
//! 5_4_3`, `_HalfFloat`); the grid named by [`ReadOptions::grid`] or else the first of
//! those. Inside: a level set's negative values, a fog volume's (or any other class's)
//! values above [`ReadOptions::fog_threshold`], a bool grid's true values; the value
//! decides, active or not, so a level set's inactive interior tiles are inside. Value
//! buffers may be uncompressed, zlib, or Blosc with LZ4 or zlib blocks
//! (`io/blosc.rs`), with or without active-mask compression. Transforms: uniform
//! scale, translation, scale and translation, or an affine map that is one of these.
//! Refused by name: other grid types (vec3s, int32, points, masks), other tree
//! configurations, instanced grids, file versions before 222, frustum and non-uniform
//! transforms, Blosc codecs other than LZ4 and zlib, a background that is inside
//! (an unbounded solid). The domain is the stored one when the file has it and it
//! matches the transform, else the cube of smallest depth holding every inside voxel,
//! its corner on the lowest inside index rounded down to the largest inside tile's
//! size (so tiles stay aligned octree nodes).

use std::collections::BTreeMap;
use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::blosc;
use super::solid_set::{ColouredSolid, ReadOptions, SolidRef, Solids, SolidsRef};
use super::vdb_level_set::LevelSetValues;
use crate::atomic::write_atomic;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result, printable, quoted};
use crate::fields::Fields;
use crate::octree::{Domain, LinearOctree, MAX_DEPTH, Node};
use crate::surface::HermiteData;

/// The first 8 bytes: `0x56444220` as a little-endian i64.
pub const MAGIC: u64 = 0x5644_4220;
/// The file format version written (OpenVDB 6 and later).
pub const FILE_VERSION: u32 = 224;
/// Oldest file format version read (node-mask compression, OpenVDB 3).
const OLDEST_VERSION: u32 = 222;
/// The grid metadata key of the exact domain.
pub const DOMAIN_KEY: &str = "octsolid_domain";

const COMPRESS_ZIP: u32 = 0x1;
const COMPRESS_ACTIVE_MASK: u32 = 0x2;
const COMPRESS_BLOSC: u32 = 0x4;

/// log2 of the children a side: upper internal node, lower internal node, leaf.
const UPPER_LOG2: u32 = 5;
const LOWER_LOG2: u32 = 4;
const LEAF_LOG2: u32 = 3;
/// Voxels a side of a leaf, a lower node and an upper node (= a root tile).
const LEAF_SIDE: i64 = 1 << LEAF_LOG2;
const LOWER_SIDE: i64 = 1 << (LEAF_LOG2 + LOWER_LOG2);
const UPPER_SIDE: i64 = 1 << (LEAF_LOG2 + LOWER_LOG2 + UPPER_LOG2);

/// How value buffers are compressed when writing.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Compression {
    /// Raw values (with active-mask compression: only active values are stored).
    None,
    /// zlib, as OpenVDB's `COMPRESS_ZIP`.
    Zip,
}

// ------------------------------------------------------------------------------------
// The tree as written: maps from origins to nodes, children in OpenVDB's order.

/// A bit mask of `n` bits, OpenVDB's `NodeMask` (u64 words, bit `i` of word `i / 64`).
#[derive(Clone, Debug, PartialEq)]
struct Mask(Vec<u64>);

impl Mask {
    fn new(bits: usize) -> Self {
        Mask(vec![0; bits / 64])
    }
    fn on(&self, i: usize) -> bool {
        self.0[i / 64] >> (i % 64) & 1 == 1
    }
    fn set(&mut self, i: usize) {
        self.0[i / 64] |= 1 << (i % 64);
    }
    fn count(&self) -> usize {
        self.0.iter().map(|w| w.count_ones() as usize).sum()
    }
    fn bytes(&self) -> Vec<u8> {
        self.0.iter().flat_map(|w| w.to_le_bytes()).collect()
    }
}

/// Offset of voxel `c` in a node whose children are `2^child_log2` voxels a side and
/// which has `2^log2` children a side: x slowest, z fastest.
fn offset(c: [i64; 3], log2: u32, child_log2: u32) -> usize {
    let mask = (1i64 << (log2 + child_log2)) - 1;
    let [x, y, z] = c.map(|v| ((v & mask) >> child_log2) as usize);
    (x << (2 * log2)) | (y << log2) | z
}

#[derive(Default)]
struct Lower {
    tiles: BTreeMap<usize, ()>,
    leaves: BTreeMap<usize, Mask>,
}

#[derive(Default)]
struct Upper {
    tiles: BTreeMap<usize, ()>,
    lowers: BTreeMap<usize, Lower>,
}

/// Root entries by origin: a tile (`None`) or an upper node.
type Root = BTreeMap<[i64; 3], Option<Upper>>;

/// What the fog-volume tree of a solid holds, counted from its nodes before it is built.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct TreeCounts {
    root_tiles: u64,
    uppers: u64,
    upper_tiles: u64,
    lowers: u64,
    lower_tiles: u64,
    leaves: u64,
    /// Active voxels of the leaves.
    leaf_voxels: u64,
}

/// Estimated peak bytes of each part while a grid is written: its map entry in the
/// tree being built (`BTreeMap`s about half full) and three times its bytes in the
/// file (the grid's buffer as it grows, then the file's beside it), values apart
/// ([`value_bytes`]).
const ROOT_TILE_BYTES: u64 = 130 + 3 * 17;
const UPPER_BYTES: u64 = 130 + 3 * (12 + 2 * 4096 + 1);
const LOWER_BYTES: u64 = 100 + 3 * (2 * 512 + 1);
const INNER_TILE_BYTES: u64 = 20;
const LEAF_BYTES: u64 = 150 + 3 * (3 * 64 + 1);
/// Beside them: zlib's state and the raw values of one node (at most 128 KiB).
const FIXED_BYTES: u64 = 1 << 20;

/// Bytes in the file of `n` values of 1 written by [`write_ones`] (three times, as
/// above), at most: raw, or zlib's (at least 64 to 1 on a run of one value, plus its
/// header and size).
fn value_bytes(n: u64, compression: Compression) -> u64 {
    3 * match compression {
        Compression::None => 4 * n,
        Compression::Zip => 8 + 32 + 4 * n / 64,
    }
}

impl TreeCounts {
    /// The counts of [`build_tree`]'s tree, in one pass over the nodes: a node is
    /// tiles of the largest size that fits it, or voxels of a leaf; the nodes inside
    /// one aligned block (an upper or lower node, a leaf) are consecutive in Morton
    /// order, so a block is new when it differs from the last one seen.
    fn of(tree: &LinearOctree) -> TreeCounts {
        let mut c = TreeCounts::default();
        let (mut upper, mut lower, mut leaf) = (None, None, None);
        for node in tree.nodes() {
            let s = i64::from(node.size);
            let tiles = |side: i64| ((s / side) as u64).pow(3);
            let block = |side: i64| node.min.map(|v| i64::from(v) & !(side - 1));
            let new =
                |last: &mut Option<[i64; 3]>, side: i64| u64::from(last.replace(block(side)) != Some(block(side)));
            if s >= UPPER_SIDE {
                c.root_tiles += tiles(UPPER_SIDE);
                continue;
            }
            c.uppers += new(&mut upper, UPPER_SIDE);
            if s >= LOWER_SIDE {
                c.upper_tiles += tiles(LOWER_SIDE);
                continue;
            }
            c.lowers += new(&mut lower, LOWER_SIDE);
            if s >= LEAF_SIDE {
                c.lower_tiles += tiles(LEAF_SIDE);
                continue;
            }
            c.leaves += new(&mut leaf, LEAF_SIDE);
            c.leaf_voxels += tiles(1);
        }
        c
    }

    fn add(self, o: TreeCounts) -> TreeCounts {
        TreeCounts {
            root_tiles: self.root_tiles + o.root_tiles,
            uppers: self.uppers + o.uppers,
            upper_tiles: self.upper_tiles + o.upper_tiles,
            lowers: self.lowers + o.lowers,
            lower_tiles: self.lower_tiles + o.lower_tiles,
            leaves: self.leaves + o.leaves,
            leaf_voxels: self.leaf_voxels + o.leaf_voxels,
        }
    }

    /// Estimated peak bytes of writing these (the constants above).
    fn bytes(&self, compression: Compression) -> u64 {
        let blocks = self.uppers + self.lowers + self.leaves;
        let values = value_bytes(self.upper_tiles + self.lower_tiles, compression)
            .saturating_add(value_bytes(self.leaf_voxels, compression))
            .saturating_add(blocks.saturating_mul(value_bytes(0, compression)));
        [
            (self.root_tiles, ROOT_TILE_BYTES),
            (self.uppers, UPPER_BYTES),
            (self.upper_tiles + self.lower_tiles, INNER_TILE_BYTES),
            (self.lowers, LOWER_BYTES),
            (self.leaves, LEAF_BYTES),
        ]
        .iter()
        .fold(values.saturating_add(FIXED_BYTES), |sum, &(n, each)| sum.saturating_add(n.saturating_mul(each)))
    }
}

/// The fog-volume tree of `tree` (module doc, "Writing").
fn build_tree(tree: &LinearOctree) -> Root {
    let mut root: Root = BTreeMap::new();
    for node in tree.nodes() {
        let s = i64::from(node.size);
        let m = node.min.map(i64::from);
        // Step 1: the node's blocks of the largest tile size that fits it.
        let block = if s >= UPPER_SIDE {
            UPPER_SIDE
        } else if s >= LOWER_SIDE {
            LOWER_SIDE
        } else if s >= LEAF_SIDE {
            LEAF_SIDE
        } else {
            1
        };
        let n = s / block;
        for i in 0..n * n * n {
            let c = [m[0] + (i % n) * block, m[1] + (i / n % n) * block, m[2] + (i / (n * n)) * block];
            let root_origin = c.map(|v| v & !(UPPER_SIDE - 1));
            // Step 2: a root tile, or a tile or voxel below an upper node.
            if block == UPPER_SIDE {
                root.insert(root_origin, None);
                continue;
            }
            let upper = root.entry(root_origin).or_insert_with(|| Some(Upper::default())).as_mut().expect("no tile");
            let u = offset(c, UPPER_LOG2, LEAF_LOG2 + LOWER_LOG2);
            if block == LOWER_SIDE {
                upper.tiles.insert(u, ());
                continue;
            }
            let lower = upper.lowers.entry(u).or_default();
            let l = offset(c, LOWER_LOG2, LEAF_LOG2);
            if block == LEAF_SIDE {
                lower.tiles.insert(l, ());
                continue;
            }
            lower.leaves.entry(l).or_insert_with(|| Mask::new(512)).set(offset(c, LEAF_LOG2, 0));
        }
    }
    root
}

/// Writes the values of a node whose active values are all 1 and inactive ones 0
/// (the background): metadata byte 0 (no inactive values stored), then the active
/// values, compressed.
fn write_ones(out: &mut Vec<u8>, active: usize, compression: Compression) {
    out.push(0);
    let raw: Vec<u8> = std::iter::repeat_n(1.0f32.to_le_bytes(), active).flatten().collect();
    write_data(out, &raw, compression);
}

/// OpenVDB's `writeData`: raw bytes, or zlib's with an i64 size before them (the
/// negated raw size when zlib does not make the data smaller).
fn write_data(out: &mut Vec<u8>, raw: &[u8], compression: Compression) {
    match compression {
        Compression::None => out.extend_from_slice(raw),
        Compression::Zip => {
            let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
            z.write_all(raw).expect("writing to memory");
            let zipped = z.finish().expect("writing to memory");
            if zipped.len() < raw.len() {
                out.extend((zipped.len() as i64).to_le_bytes());
                out.extend(zipped);
            } else {
                out.extend((-(raw.len() as i64)).to_le_bytes());
                out.extend_from_slice(raw);
            }
        }
    }
}

fn write_string(out: &mut Vec<u8>, s: &str) {
    out.extend((s.len() as u32).to_le_bytes());
    out.extend_from_slice(s.as_bytes());
}

/// One metadata entry: name, type name, size, value.
fn write_meta(out: &mut Vec<u8>, name: &str, kind: &str, value: &[u8]) {
    write_string(out, name);
    write_string(out, kind);
    out.extend((value.len() as u32).to_le_bytes());
    out.extend_from_slice(value);
}

/// The grid from its compression flags to its last buffer; `base` is its file offset.
fn encode_grid(solid: &SolidRef<'_>, compression: Compression) -> (Vec<u8>, usize) {
    let tree = solid.tree;
    let mut out = Vec::new();
    let flags = COMPRESS_ACTIVE_MASK | if compression == Compression::Zip { COMPRESS_ZIP } else { 0 };
    out.extend(flags.to_le_bytes());
    write_grid_metadata(&mut out, solid);
    write_transform(&mut out, tree.domain());
    let root = build_tree(tree);
    write_topology(&mut out, &root, compression);
    let block = out.len();
    write_leaf_buffers(&mut out, &root, compression);
    (out, block)
}

/// The grid's metadata: its count, then the entries sorted by name as OpenVDB's map is.
fn write_grid_metadata(out: &mut Vec<u8>, solid: &SolidRef<'_>) {
    let tree = solid.tree;
    let d = tree.domain();
    let mut meta = Vec::new();
    let mut count = 0u32;
    let mut add = |name: &str, kind: &str, value: &[u8]| {
        write_meta(&mut meta, name, kind, value);
        count += 1;
    };
    add("class", "string", b"fog volume");
    add("creator", "string", b"octsolid");
    if let Some((lo, hi)) = tree.voxel_bounds() {
        let vec3i = |v: [u32; 3]| -> Vec<u8> { v.iter().flat_map(|&c| (c as i32).to_le_bytes()).collect() };
        add("file_bbox_max", "vec3i", &vec3i(hi.map(|c| c - 1)));
        add("file_bbox_min", "vec3i", &vec3i(lo));
    }
    add("file_voxel_count", "int64", &(tree.voxel_count() as i64).to_le_bytes());
    add("name", "string", solid.name.as_bytes());
    let domain = format!("{} {} {} {} {}", d.min().x, d.min().y, d.min().z, d.edge(), d.depth());
    add(DOMAIN_KEY, "string", domain.as_bytes());
    out.extend(count.to_le_bytes());
    out.extend(meta);
}

/// The transform: a uniform scale and translation that puts voxel centres of `d` on
/// integer indices.
fn write_transform(out: &mut Vec<u8>, d: &Domain) {
    let h = d.voxel_size();
    write_string(out, "UniformScaleTranslateMap");
    let t = d.min() + DVec3::splat(0.5 * h);
    for v in
        [t, DVec3::splat(h), DVec3::splat(h), DVec3::splat(1.0 / h), DVec3::splat(1.0 / (h * h)), DVec3::splat(0.5 / h)]
    {
        for c in v.to_array() {
            out.extend(c.to_le_bytes());
        }
    }
}

/// The topology: one buffer; the root's background 0, its tiles, then its children in
/// origin order, each upper and lower node with its masks and tile values and each leaf
/// with its mask.
fn write_topology(out: &mut Vec<u8>, root: &Root, compression: Compression) {
    out.extend(1i32.to_le_bytes());
    out.extend(0f32.to_le_bytes());
    let tiles = root.values().filter(|e| e.is_none()).count() as u32;
    out.extend(tiles.to_le_bytes());
    out.extend((root.len() as u32 - tiles).to_le_bytes());
    let origin_bytes = |o: &[i64; 3]| -> Vec<u8> { o.iter().flat_map(|&c| (c as i32).to_le_bytes()).collect() };
    for (o, _) in root.iter().filter(|(_, e)| e.is_none()) {
        out.extend(origin_bytes(o));
        out.extend(1f32.to_le_bytes());
        out.push(1);
    }
    for (o, upper) in root.iter().filter_map(|(o, e)| e.as_ref().map(|u| (o, u))) {
        out.extend(origin_bytes(o));
        let (mut child, mut value) = (Mask::new(1 << (3 * UPPER_LOG2)), Mask::new(1 << (3 * UPPER_LOG2)));
        upper.lowers.keys().for_each(|&i| child.set(i));
        upper.tiles.keys().for_each(|&i| value.set(i));
        out.extend(child.bytes());
        out.extend(value.bytes());
        write_ones(out, upper.tiles.len(), compression);
        for lower in upper.lowers.values() {
            let (mut child, mut value) = (Mask::new(1 << (3 * LOWER_LOG2)), Mask::new(1 << (3 * LOWER_LOG2)));
            lower.leaves.keys().for_each(|&i| child.set(i));
            lower.tiles.keys().for_each(|&i| value.set(i));
            out.extend(child.bytes());
            out.extend(value.bytes());
            write_ones(out, lower.tiles.len(), compression);
            for leaf in lower.leaves.values() {
                out.extend(leaf.bytes());
            }
        }
    }
}

/// The buffers: every leaf again, its mask and its active values.
fn write_leaf_buffers(out: &mut Vec<u8>, root: &Root, compression: Compression) {
    for upper in root.values().flatten() {
        for lower in upper.lowers.values() {
            for leaf in lower.leaves.values() {
                out.extend(leaf.bytes());
                write_ones(out, leaf.count(), compression);
            }
        }
    }
}

/// Writes `solids` to `path`, one fog-volume grid each, atomically; returns the bytes
/// written. Refused before anything is built when its estimated memory exceeds `budget`.
pub fn write(
    path: impl AsRef<Path>,
    solids: &SolidsRef<'_>,
    compression: Compression,
    budget: MemoryBudget,
) -> Result<u64> {
    let path = path.as_ref();
    let bytes = encode_named(solids, compression, budget, &path.display().to_string())?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// The whole `.vdb` file for `solids` (module doc, "Writing"), refused before anything
/// is built when its estimated memory exceeds `budget`.
pub fn encode(solids: &Solids, compression: Compression, budget: MemoryBudget) -> Result<Vec<u8>> {
    encode_named(&solids.borrowed(), compression, budget, "a .vdb file")
}

/// [`encode`], the output called `output` in a refusal.
fn encode_named(
    solids: &SolidsRef<'_>,
    compression: Compression,
    budget: MemoryBudget,
    output: &str,
) -> Result<Vec<u8>> {
    let c = solids.solids.iter().map(|s| TreeCounts::of(s.tree)).fold(TreeCounts::default(), TreeCounts::add);
    let job = format!(
        "{output}: {} grid(s) of {} root tiles, {} upper and {} lower internal nodes, {} leaves",
        solids.solids.len(),
        c.root_tiles,
        c.uppers,
        c.lowers,
        c.leaves
    );
    budget.check(job, c.bytes(compression))?;
    // Grids first, so the UUID can be derived from them.
    let mut names: BTreeMap<&str, usize> = BTreeMap::new();
    let mut grids = Vec::new();
    for solid in &solids.solids {
        let seen = names.entry(&solid.name).or_insert(0);
        // Repeated names get OpenVDB's own suffix: a record separator and a number.
        let unique = if *seen == 0 { solid.name.to_string() } else { format!("{}\u{1e}{seen}", solid.name) };
        *seen += 1;
        grids.push((unique, encode_grid(solid, compression)));
    }
    let uuid = {
        let mut h = [0u8; 16];
        for (k, chunk) in h.chunks_mut(4).enumerate() {
            let mut crc = crc32fast::Hasher::new_with_initial(k as u32);
            grids.iter().for_each(|(n, (g, _))| {
                crc.update(n.as_bytes());
                crc.update(g);
            });
            chunk.copy_from_slice(&crc.finalize().to_le_bytes());
        }
        let x: String = h.iter().map(|b| format!("{b:02x}")).collect();
        format!("{}-{}-{}-{}-{}", &x[..8], &x[8..12], &x[12..16], &x[16..20], &x[20..])
    };
    let names: usize = grids.iter().map(|(n, _)| n.len() + 64).sum();
    let mut out = Vec::with_capacity(256 + names + grids.iter().map(|(_, (g, _))| g.len()).sum::<usize>());
    out.extend(MAGIC.to_le_bytes());
    out.extend(FILE_VERSION.to_le_bytes());
    out.extend([10u32, 0].map(u32::to_le_bytes).concat());
    out.push(1);
    out.extend_from_slice(uuid.as_bytes());
    out.extend(0u32.to_le_bytes());
    out.extend((grids.len() as u32).to_le_bytes());
    for (name, (grid, block)) in grids {
        write_string(&mut out, &name);
        write_string(&mut out, "Tree_float_5_4_3");
        write_string(&mut out, "");
        let grid_pos = out.len() + 24;
        for p in [grid_pos, grid_pos + block, grid_pos + grid.len()] {
            out.extend((p as i64).to_le_bytes());
        }
        out.extend(grid);
    }
    Ok(out)
}

// ------------------------------------------------------------------------------------
// Reading.

/// A grid's value type as stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ValueType {
    F32,
    F64,
    Bool,
}

impl<'a> Fields<'a> {
    fn coord(&mut self, what: &str) -> Result<[i64; 3]> {
        let b: [u8; 12] = self.array(what)?;
        Ok([0, 4, 8].map(|o| i64::from(i32::from_le_bytes(b[o..o + 4].try_into().expect("4 bytes")))))
    }

    fn mask(&mut self, bits: usize, what: &str) -> Result<Mask> {
        let b = self.take(bits / 8, what)?;
        Ok(Mask(b.chunks_exact(8).map(|w| u64::from_le_bytes(w.try_into().expect("8 bytes"))).collect()))
    }

    /// A metadata map: name, type and value of each entry (values as raw bytes).
    fn meta_map(&mut self, what: &str) -> Result<Vec<(String, String, &'a [u8])>> {
        let at = self.pos;
        let n = self.u32(what)?;
        // Each entry takes at least 12 bytes.
        if u64::from(n) * 12 > self.left() as u64 {
            return Err(self.err(at, format!("{what}: {n} entries cannot fit in the file")));
        }
        (0..n)
            .map(|_| {
                let name = self.string("metadata name")?;
                let kind = self.string("metadata type")?;
                let size = self.u32("metadata size")? as usize;
                Ok((name, kind, self.take(size, "metadata value")?))
            })
            .collect()
    }
}

/// What a chosen grid's header says and the stream state its nodes need.
struct Grid {
    name: String,
    value: ValueType,
    half: bool,
    compression: u32,
    class: String,
    stored_domain: Option<Domain>,
    /// Voxel size and the world position of index (0, 0, 0).
    h: f64,
    t: DVec3,
    background: f64,
    /// Inside test on a value.
    level_set: bool,
    threshold: f64,
}

impl Grid {
    fn inside(&self, v: f64) -> bool {
        match self.value {
            ValueType::Bool => v != 0.0,
            _ if self.level_set => v < 0.0,
            _ => v > self.threshold,
        }
    }

    /// Bytes of a stored value in a node's value buffer.
    fn buffer_size(&self) -> usize {
        match (self.value, self.half) {
            (ValueType::Bool, _) => 1,
            (ValueType::F64, false) => 8,
            (_, true) => 2,
            (ValueType::F32, false) => 4,
        }
    }

    /// Bytes of a full-precision value (root values, inactive values).
    fn value_size(&self) -> usize {
        match self.value {
            ValueType::Bool => 1,
            ValueType::F32 => 4,
            ValueType::F64 => 8,
        }
    }

    fn decode_value(&self, b: &[u8]) -> f64 {
        match b.len() {
            1 => f64::from(b[0] != 0),
            2 => f64::from(half_to_f32(u16::from_le_bytes([b[0], b[1]]))),
            4 => f64::from(f32::from_le_bytes(b.try_into().expect("4 bytes"))),
            _ => f64::from_le_bytes(b.try_into().expect("8 bytes")),
        }
    }

    /// `math::negative` of OpenVDB: `-v`, and `!v` for bools.
    fn negative(&self, v: f64) -> f64 {
        if self.value == ValueType::Bool { f64::from(v == 0.0) } else { -v }
    }
}

/// IEEE 754 binary16 to binary32 (exact).
fn half_to_f32(h: u16) -> f32 {
    let sign = if h >> 15 == 1 { -1.0 } else { 1.0 };
    let exp = i32::from(h >> 10 & 0x1f);
    let frac = f32::from(h & 0x3ff);
    sign * match exp {
        0 => frac * 2f32.powi(-24),
        31 if frac == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + frac / 1024.0) * 2f32.powi(e - 15),
    }
}

impl Fields<'_> {
    /// OpenVDB's `readData`: `count` values of `size` bytes, raw, zlib or Blosc.
    fn data(&mut self, grid: &Grid, count: usize, size: usize) -> Result<Vec<u8>> {
        let len = count * size;
        if grid.compression & (COMPRESS_BLOSC | COMPRESS_ZIP) == 0 {
            return Ok(self.take(len, "values")?.to_vec());
        }
        let at = self.pos;
        let n = self.i64("compressed size")?;
        if n <= 0 {
            if n.unsigned_abs() != len as u64 {
                return Err(self.err(at, format!("{} raw bytes stored, {len} expected", n.unsigned_abs())));
            }
            return Ok(self.take(len, "values")?.to_vec());
        }
        let src = self.take(usize::try_from(n).unwrap_or(usize::MAX), "compressed values")?;
        let out =
            if grid.compression & COMPRESS_BLOSC != 0 { blosc::decompress(src, len) } else { blosc::inflate(src, len) };
        out.map_err(|e| self.err(at, e))
    }

    /// OpenVDB's `readCompressedValues` for a node of `count` values (module doc of
    /// `io/Compression.h`: a metadata byte says which inactive values and selection
    /// mask precede the stored values).
    fn values(&mut self, grid: &Grid, count: usize, active: &Mask) -> Result<Vec<f64>> {
        let at = self.pos;
        let meta = self.array::<1>("value metadata")?[0];
        if meta > 6 {
            return Err(self.err(at, format!("value metadata {meta} is not one of 0..=6")));
        }
        let bg = grid.background;
        let mut inactive = [if meta == 0 { bg } else { grid.negative(bg) }, bg];
        if matches!(meta, 2 | 4 | 5) {
            inactive[0] = grid.decode_value(self.take(grid.value_size(), "inactive value")?);
            if meta == 5 {
                inactive[1] = grid.decode_value(self.take(grid.value_size(), "inactive value")?);
            }
        }
        let selection = if matches!(meta, 3..=5) { Some(self.mask(count, "selection mask")?) } else { None };
        let masked = grid.compression & COMPRESS_ACTIVE_MASK != 0 && meta != 6;
        let stored = if masked { active.count() } else { count };
        let size = grid.buffer_size();
        // OpenVDB's half writer writes nothing at all, not even a size, for no values.
        let raw = if grid.half && stored == 0 { Vec::new() } else { self.data(grid, stored, size)? };
        let decoded: Vec<f64> = raw.chunks_exact(size).map(|b| grid.decode_value(b)).collect();
        if stored == count {
            return Ok(decoded);
        }
        let mut next = decoded.into_iter();
        Ok((0..count)
            .map(|i| {
                if active.on(i) {
                    next.next().unwrap_or(bg)
                } else {
                    inactive[usize::from(selection.as_ref().is_some_and(|s| s.on(i)))]
                }
            })
            .collect())
    }
}

/// A node of the tree read: its origin and, for each slot, child, inside tile or nothing.
struct ReadLower {
    origin: [i64; 3],
    inside_tiles: Vec<usize>,
    leaves: Vec<usize>,
}

struct ReadUpper {
    origin: [i64; 3],
    inside_tiles: Vec<usize>,
    lowers: Vec<ReadLower>,
}

/// The root's children read, by origin.
type ReadRoot = BTreeMap<[i64; 3], ReadUpper>;

/// A cube of inside voxels: its origin and side, in index space.
type Block = ([i64; 3], i64);

/// Reads the `.vdb` file at `path` (one grid; see the module doc).
pub fn read(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Solids> {
    read_and_surface(path, options).map(|(solids, _)| solids)
}

/// [`read`], with the solid's surface data when the grid is a level set: each boundary
/// face's crossing from the distances at its two voxel centres and the normal from
/// their gradient (`vdb_level_set.rs`); `None` for fog volumes and bool grids.
pub fn read_and_surface(path: impl AsRef<Path>, options: &ReadOptions) -> Result<(Solids, Option<HermiteData>)> {
    let path = path.as_ref();
    let bytes = crate::input_file::read(path)?;
    decode_and_surface(&bytes, path, options)
}

/// Parses a whole `.vdb` file; `path` names it in errors.
pub fn decode(bytes: &[u8], path: &Path, options: &ReadOptions) -> Result<Solids> {
    decode_and_surface(bytes, path, options).map(|(solids, _)| solids)
}

/// [`decode`], with the surface data of a level set ([`read_and_surface`]).
pub fn decode_and_surface(bytes: &[u8], path: &Path, options: &ReadOptions) -> Result<(Solids, Option<HermiteData>)> {
    let mut r = Fields::new(path, bytes, 0);
    read_file_header(&mut r)?;
    let at = r.pos;
    let count = r.u32("grid count")?;
    // Step 2: grid descriptors; the chosen grid is read, the others skipped.
    let mut found = Vec::new();
    for _ in 0..count {
        let grid = read_descriptor(&mut r, bytes.len())?;
        let (value, half) = value_type_of(&grid.kind);
        let wanted = options.grid.as_ref().is_none_or(|g| *g == grid.name);
        if wanted && (value.is_some() || options.grid.is_some()) {
            let value = check_readable(&r, &grid, value)?;
            return read_grid(&mut r, grid.name, value, half, options);
        }
        found.push(format!("{} ({})", printable(&grid.name), printable(&grid.kind)));
        r.pos = grid.end_pos as usize;
    }
    Err(no_grid_to_read(&r, at, options, &found))
}

/// Step 1: the file's header (magic, versions, the grid offsets flag, UUID) and its
/// metadata, which is skipped.
fn read_file_header(r: &mut Fields<'_>) -> Result<()> {
    let magic = r.i64("magic")?;
    if magic as u64 != MAGIC {
        return Err(r.err(0, "not an OpenVDB file (bad magic; expected 0x56444220)"));
    }
    let version = r.u32("file version")?;
    if version < OLDEST_VERSION {
        return Err(r.err(
            8,
            format!("file format version {version} is older than {OLDEST_VERSION}; re-save it with OpenVDB 3 or later"),
        ));
    }
    r.take(8, "library version")?;
    if r.array::<1>("grid offsets flag")?[0] == 0 {
        return Err(r.err(20, "files without grid offsets (written to a stream) are not supported"));
    }
    r.take(36, "UUID")?;
    r.meta_map("file metadata")?;
    Ok(())
}

/// A grid descriptor read: where it starts, the grid's name (without the suffix that
/// makes it unique), type name, instance parent and where the grid ends.
struct Descriptor {
    /// The descriptor's file offset.
    at: usize,
    /// The grid's name.
    name: String,
    /// The grid's tree type name, e.g. `Tree_float_5_4_3`.
    kind: String,
    /// The grid this one instances; empty for none.
    parent: String,
    /// The file offset just past the grid.
    end_pos: i64,
}

/// One grid descriptor, its offsets checked to follow it in order within the
/// `file_len` bytes of the file.
fn read_descriptor(r: &mut Fields<'_>, file_len: usize) -> Result<Descriptor> {
    let at = r.pos;
    let unique = r.string("grid name")?;
    let kind = r.string("grid type")?;
    let parent = r.string("instance parent")?;
    let (grid_pos, block_pos, end_pos) = (r.i64("grid offset")?, r.i64("block offset")?, r.i64("end offset")?);
    let name = unique.split('\u{1e}').next().unwrap_or_default().to_owned();
    let ok =
        grid_pos == r.pos as i64 && grid_pos <= block_pos && block_pos <= end_pos && end_pos as u64 <= file_len as u64;
    if !ok {
        return Err(r.err(
            at,
            format!("grid {}: offsets {grid_pos}, {block_pos}, {end_pos} do not fit the file", quoted(name.as_bytes())),
        ));
    }
    Ok(Descriptor { at, name, kind, parent, end_pos })
}

/// The value type of a tree type name and whether it is stored as half floats; `None`
/// for a type not read.
fn value_type_of(kind: &str) -> (Option<ValueType>, bool) {
    match kind {
        "Tree_float_5_4_3" => (Some(ValueType::F32), false),
        "Tree_float_5_4_3_HalfFloat" => (Some(ValueType::F32), true),
        "Tree_double_5_4_3" => (Some(ValueType::F64), false),
        "Tree_bool_5_4_3" => (Some(ValueType::Bool), false),
        _ => (None, false),
    }
}

/// The chosen grid's value type, or the reason it cannot be read: a type not read, or
/// an instanced grid.
fn check_readable(r: &Fields<'_>, grid: &Descriptor, value: Option<ValueType>) -> Result<ValueType> {
    let Some(value) = value else {
        return Err(r.err(
            grid.at,
            format!(
                "grid {} is of type {}; float, double and bool grids are read",
                quoted(grid.name.as_bytes()),
                quoted(grid.kind.as_bytes())
            ),
        ));
    };
    if !grid.parent.is_empty() {
        return Err(r.err(
            grid.at,
            format!(
                "grid {} is an instance of {}; instanced grids are not supported",
                quoted(grid.name.as_bytes()),
                quoted(grid.parent.as_bytes())
            ),
        ));
    }
    Ok(value)
}

/// The refusal when no grid was chosen, at the grid count (`at`), listing the grids
/// `found`.
fn no_grid_to_read(r: &Fields<'_>, at: usize, options: &ReadOptions, found: &[String]) -> Error {
    let what = options
        .grid
        .as_ref()
        .map_or("no float, double or bool grid".to_string(), |g| format!("no grid named {}", quoted(g.as_bytes())));
    r.err(at, format!("{what}; the file has {}", if found.is_empty() { "no grids".into() } else { found.join(", ") }))
}

/// Reads the chosen grid from its compression flags on, into solids, with a level
/// set's surface data.
fn read_grid(
    r: &mut Fields<'_>,
    name: String,
    value: ValueType,
    half: bool,
    options: &ReadOptions,
) -> Result<(Solids, Option<HermiteData>)> {
    let mut grid = read_grid_header(r, name, value, half, options)?;
    read_background(r, &mut grid)?;
    let (mut blocks, uppers) = read_root_children(r, &grid)?;
    check_read_budget(r, &grid, &uppers, blocks.len(), options)?;
    push_inside_tiles(&uppers, &mut blocks);
    let mut distances = (grid.level_set && grid.value != ValueType::Bool).then(LevelSetValues::default);
    read_leaf_buffers(r, &grid, &uppers, &mut blocks, distances.as_mut())?;
    let (solids, origin) = build_solids(grid, blocks, options, r)?;
    let surface = distances.map(|d| d.crossings(&solids.solids[0].tree, origin));
    Ok((solids, surface))
}

/// Step 3: the grid's compression flags, metadata (its class and the domain octsolid
/// stored) and transform.
fn read_grid_header(
    r: &mut Fields<'_>,
    name: String,
    value: ValueType,
    half: bool,
    options: &ReadOptions,
) -> Result<Grid> {
    let at = r.pos;
    let compression = r.u32("compression flags")?;
    if compression & !(COMPRESS_ZIP | COMPRESS_ACTIVE_MASK | COMPRESS_BLOSC) != 0 {
        return Err(r.err(at, format!("unknown compression flags {compression:#x}")));
    }
    let mut grid = Grid {
        name,
        value,
        half,
        compression,
        class: String::new(),
        stored_domain: None,
        h: 1.0,
        t: DVec3::ZERO,
        background: 0.0,
        level_set: false,
        threshold: options.fog_threshold,
    };
    for (key, kind, v) in r.meta_map("grid metadata")? {
        match (key.as_str(), kind.as_str()) {
            ("class", "string") => grid.class = String::from_utf8_lossy(v).into_owned(),
            (DOMAIN_KEY, "string") => grid.stored_domain = parse_domain(&String::from_utf8_lossy(v)),
            _ => {}
        }
    }
    grid.level_set = grid.class == "level set";
    read_transform(r, &mut grid)?;
    Ok(grid)
}

/// Step 4, the topology's start: one buffer a node, and the root's background, which
/// must be outside.
fn read_background(r: &mut Fields<'_>, grid: &mut Grid) -> Result<()> {
    let at = r.pos;
    let buffers = r.u32("buffer count")?;
    if buffers != 1 {
        return Err(r.err(at, format!("{buffers} buffers a node; only 1 is supported")));
    }
    let vs = grid.value_size();
    grid.background = grid.decode_value(r.take(vs, "background")?);
    if grid.inside(grid.background) {
        return Err(
            r.err(at + 4, format!("the background {} is inside: the solid would be unbounded", grid.background))
        );
    }
    Ok(())
}

/// Step 4, the root's tiles and children: the blocks of its inside tiles, and its
/// upper nodes by origin (each checked aligned and alone at its origin).
fn read_root_children(r: &mut Fields<'_>, grid: &Grid) -> Result<(Vec<Block>, ReadRoot)> {
    let vs = grid.value_size();
    let at = r.pos;
    let (tiles, children) = (r.u32("tile count")? as u64, r.u32("child count")? as u64);
    let left = r.left() as u64;
    if tiles * (13 + vs as u64) + children * (12 + 8192) > left {
        return Err(r.err(at, format!("{tiles} tiles and {children} children cannot fit in the {left} bytes left")));
    }
    let mut blocks: Vec<Block> = Vec::new();
    for _ in 0..tiles {
        let o = r.coord("tile origin")?;
        let v = grid.decode_value(r.take(vs, "tile value")?);
        r.take(1, "tile state")?;
        if grid.inside(v) {
            blocks.push((o, UPPER_SIDE));
        }
    }
    let mut uppers = BTreeMap::new();
    for _ in 0..children {
        let at = r.pos;
        let o = r.coord("child origin")?;
        if o.iter().any(|c| c % UPPER_SIDE != 0) {
            return Err(r.err(at, format!("root child at {o:?} is not aligned to {UPPER_SIDE}")));
        }
        let upper = read_upper(r, grid, o)?;
        if uppers.insert(o, upper).is_some() {
            return Err(r.err(at, format!("two root children at {o:?}")));
        }
    }
    Ok((blocks, uppers))
}

/// The budget: a node a tile (`root_blocks` of the root's, and every upper and lower
/// node's inside tiles) and a voxel of every leaf at most, 40 bytes each.
fn check_read_budget(
    r: &Fields<'_>,
    grid: &Grid,
    uppers: &ReadRoot,
    root_blocks: usize,
    options: &ReadOptions,
) -> Result<()> {
    let leaves: usize = uppers.values().flat_map(|u: &ReadUpper| &u.lowers).map(|l| l.leaves.len()).sum();
    let tile_count: usize = uppers
        .values()
        .map(|u| u.inside_tiles.len() + u.lowers.iter().map(|l| l.inside_tiles.len()).sum::<usize>())
        .sum();
    let estimate = (leaves as u64 * 512 + tile_count as u64 + root_blocks as u64) * 40;
    options.budget.check(format!("reading grid {} of {}", quoted(grid.name.as_bytes()), r.path.display()), estimate)
}

/// Step 5, first: the blocks of the upper and lower nodes' inside tiles.
fn push_inside_tiles(uppers: &ReadRoot, blocks: &mut Vec<Block>) {
    for u in uppers.values() {
        for &i in &u.inside_tiles {
            blocks.push((child_origin(u.origin, i, UPPER_LOG2, LEAF_LOG2 + LOWER_LOG2), LOWER_SIDE));
        }
        for l in &u.lowers {
            for &i in &l.inside_tiles {
                blocks.push((child_origin(l.origin, i, LOWER_LOG2, LEAF_LOG2), LEAF_SIDE));
            }
        }
    }
}

/// Step 5, then: the buffers of every leaf in the root's origin order, their inside
/// voxels as blocks (and a level set's values kept in `distances`).
fn read_leaf_buffers(
    r: &mut Fields<'_>,
    grid: &Grid,
    uppers: &ReadRoot,
    blocks: &mut Vec<Block>,
    mut distances: Option<&mut LevelSetValues>,
) -> Result<()> {
    for u in uppers.values() {
        for l in &u.lowers {
            for &i in &l.leaves {
                let origin = child_origin(l.origin, i, LOWER_LOG2, LEAF_LOG2);
                read_leaf_buffer(r, grid, origin, blocks, distances.as_deref_mut())?;
            }
        }
    }
    Ok(())
}

/// The origin of child `i` of a node at `origin`.
fn child_origin(origin: [i64; 3], i: usize, log2: u32, child_log2: u32) -> [i64; 3] {
    let n = 1usize << log2;
    let c = [i >> (2 * log2), (i >> log2) & (n - 1), i & (n - 1)];
    [0, 1, 2].map(|a| origin[a] + ((c[a] as i64) << child_log2))
}

fn read_upper(r: &mut Fields<'_>, grid: &Grid, origin: [i64; 3]) -> Result<ReadUpper> {
    let n = 1 << (3 * UPPER_LOG2);
    let child = r.mask(n, "upper child mask")?;
    let value = r.mask(n, "upper value mask")?;
    let values = r.values(grid, n, &value)?;
    let inside_tiles = (0..n).filter(|&i| !child.on(i) && grid.inside(values[i])).collect();
    let mut lowers = Vec::new();
    for i in (0..n).filter(|&i| child.on(i)) {
        let o = child_origin(origin, i, UPPER_LOG2, LEAF_LOG2 + LOWER_LOG2);
        let m = 1 << (3 * LOWER_LOG2);
        let child = r.mask(m, "lower child mask")?;
        let value = r.mask(m, "lower value mask")?;
        let values = r.values(grid, m, &value)?;
        let inside_tiles = (0..m).filter(|&i| !child.on(i) && grid.inside(values[i])).collect();
        let leaves: Vec<usize> = (0..m).filter(|&i| child.on(i)).collect();
        // Leaf topology: a value mask each (the buffers repeat it).
        r.take(leaves.len() * 64, "leaf value masks")?;
        lowers.push(ReadLower { origin: o, inside_tiles, leaves });
    }
    Ok(ReadUpper { origin, inside_tiles, lowers })
}

/// A leaf's buffer: its value mask and values (bools: its origin and a value mask);
/// the values kept in `distances` when given.
fn read_leaf_buffer(
    r: &mut Fields<'_>,
    grid: &Grid,
    origin: [i64; 3],
    blocks: &mut Vec<([i64; 3], i64)>,
    distances: Option<&mut LevelSetValues>,
) -> Result<()> {
    let active = r.mask(512, "leaf value mask")?;
    let inside: Vec<bool> = if grid.value == ValueType::Bool {
        let at = r.pos;
        let o = r.coord("leaf origin")?;
        if o != origin {
            return Err(r.err(at, format!("bool leaf says origin {o:?}, the tree puts it at {origin:?}")));
        }
        let values = r.mask(512, "leaf values")?;
        (0..512).map(|i| values.on(i)).collect()
    } else {
        let values = r.values(grid, 512, &active)?;
        if let Some(distances) = distances {
            distances.insert(origin, &values);
        }
        values.into_iter().map(|v| grid.inside(v)).collect()
    };
    if inside.iter().all(|&b| b) {
        blocks.push((origin, LEAF_SIDE));
    } else {
        for i in (0..512).filter(|&i| inside[i]) {
            blocks.push((child_origin(origin, i, LEAF_LOG2, 0), 1));
        }
    }
    Ok(())
}

fn read_transform(r: &mut Fields<'_>, grid: &mut Grid) -> Result<()> {
    let at = r.pos;
    let kind = r.string("transform type")?;
    let (scale, t) = match kind.as_str() {
        "UniformScaleMap" | "ScaleMap" => {
            let s = r.vec3("scale")?;
            (0..4).try_for_each(|_| r.vec3("scale terms").map(drop))?;
            (s, DVec3::ZERO)
        }
        "UniformScaleTranslateMap" | "ScaleTranslateMap" => {
            let t = r.vec3("translation")?;
            let s = r.vec3("scale")?;
            (0..4).try_for_each(|_| r.vec3("scale terms").map(drop))?;
            (s, t)
        }
        "TranslationMap" => (DVec3::ONE, r.vec3("translation")?),
        "AffineMap" | "UnitaryMap" => {
            let m: Vec<f64> = (0..16).map(|_| r.f64("matrix")).collect::<Result<_>>()?;
            let off_diagonal = [1, 2, 4, 6, 8, 9, 3, 7, 11].iter().any(|&i| m[i] != 0.0);
            if off_diagonal || m[15] != 1.0 {
                return Err(r.err(
                    at,
                    format!("{} with rotation, shear or projection is not supported", quoted(kind.as_bytes())),
                ));
            }
            (DVec3::new(m[0], m[5], m[10]), DVec3::new(m[12], m[13], m[14]))
        }
        _ => {
            return Err(r.err(
                at,
                format!("{} transforms are not supported (uniform scale and translation are)", quoted(kind.as_bytes())),
            ));
        }
    };
    if !(scale.x == scale.y && scale.y == scale.z && scale.x > 0.0 && scale.x.is_finite() && t.is_finite()) {
        return Err(r.err(at, format!("voxels of {scale} are not uniform positive cubes")));
    }
    grid.h = scale.x;
    grid.t = t;
    Ok(())
}

fn parse_domain(value: &str) -> Option<Domain> {
    let parts: Vec<&str> = value.split_whitespace().collect();
    let [x, y, z, edge, depth] = parts.as_slice() else { return None };
    let f = |s: &str| s.parse::<f64>().ok();
    Domain::new(DVec3::new(f(x)?, f(y)?, f(z)?), f(edge)?, depth.parse().ok()?).ok()
}

/// The domain and the solid from the inside blocks (module doc, "Reading"), and the
/// index of lattice voxel 0.
fn build_solids(
    grid: Grid,
    blocks: Vec<([i64; 3], i64)>,
    options: &ReadOptions,
    r: &Fields<'_>,
) -> Result<(Solids, [i64; 3])> {
    let (mut lo, mut hi) = ([i64::MAX; 3], [i64::MIN; 3]);
    let mut align = 1;
    for (o, s) in &blocks {
        for a in 0..3 {
            lo[a] = lo[a].min(o[a]);
            hi[a] = hi[a].max(o[a] + s);
        }
        align = align.max(*s);
    }
    // The stored domain, when it matches the transform and holds every block.
    let stored = grid.stored_domain.filter(|d| {
        let h = d.voxel_size();
        let t = d.min() + DVec3::splat(0.5 * h);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * h.max(1e-300);
        let n = i64::from(d.resolution());
        options.stored_domain
            && close(h, grid.h)
            && (0..3).all(|a| close(t[a], grid.t[a]))
            && (blocks.is_empty() || (lo.iter().all(|&c| c >= 0) && hi.iter().all(|&c| c <= n)))
    });
    let (domain, origin) = if let Some(d) = stored {
        (d, [0; 3])
    } else if blocks.is_empty() {
        let min = grid.t - DVec3::splat(0.5 * grid.h);
        (Domain::new(min, 2.0 * grid.h, 1)?, [0; 3])
    } else {
        let origin = lo.map(|c| c.div_euclid(align) * align);
        let extent = (0..3).map(|a| hi[a] - origin[a]).max().unwrap_or(1) as u64;
        let depth = extent.next_power_of_two().trailing_zeros().max(1);
        if depth > u32::from(MAX_DEPTH) {
            return Err(r.err(
                0,
                format!("grid {} spans {extent} voxels a side, more than 2^{MAX_DEPTH}", quoted(grid.name.as_bytes())),
            ));
        }
        let min =
            grid.t + (DVec3::new(origin[0] as f64, origin[1] as f64, origin[2] as f64) - DVec3::splat(0.5)) * grid.h;
        (Domain::new(min, grid.h * f64::from(1u32 << depth), depth as u8)?, origin)
    };
    let depth = domain.depth();
    let nodes = blocks.into_iter().map(|(o, s)| Node {
        level: depth - s.trailing_zeros() as u8,
        min: [0, 1, 2].map(|a| (o[a] - origin[a]) as u32),
        size: s as u32,
    });
    let tree = LinearOctree::from_nodes(domain, nodes)?;
    tree.validate()?;
    Ok((Solids { domain, solids: vec![ColouredSolid::new(grid.name, None, tree)] }, origin))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    /// The counts the estimate is made of, from the nodes alone, are those of the tree
    /// [`build_tree`] builds: random nodes of every size, from voxels to several root
    /// tiles, scattered over a depth-14 domain.
    #[test]
    fn counts_from_the_nodes_are_the_built_trees() {
        let mut rng = Rng(0x0dbc_0075);
        for round in 0..20 {
            let depth = 14u8;
            let domain = Domain::new(DVec3::ZERO, 1.0, depth).unwrap();
            let nodes: Vec<Node> = (0..1 + rng.below(60))
                .map(|_| {
                    // Mostly small nodes, now and then one of 128 to 8192 voxels a side.
                    let k = if rng.below(8) == 0 { 7 + rng.below(7) as u32 } else { rng.below(5) as u32 };
                    let cells = domain.resolution() >> k;
                    let min = [0; 3].map(|_| (rng.below(u64::from(cells)) as u32) << k);
                    Node { level: depth - k as u8, min, size: 1 << k }
                })
                .collect();
            let tree = LinearOctree::from_nodes(domain, nodes).unwrap();
            let root = build_tree(&tree);
            let uppers = || root.values().flatten();
            let lowers = || uppers().flat_map(|u| u.lowers.values());
            let built = TreeCounts {
                root_tiles: root.values().filter(|e| e.is_none()).count() as u64,
                uppers: uppers().count() as u64,
                upper_tiles: uppers().map(|u| u.tiles.len() as u64).sum(),
                lowers: lowers().count() as u64,
                lower_tiles: lowers().map(|l| l.tiles.len() as u64).sum(),
                leaves: lowers().map(|l| l.leaves.len() as u64).sum(),
                leaf_voxels: lowers().flat_map(|l| l.leaves.values()).map(|m| m.count() as u64).sum(),
            };
            assert_eq!(TreeCounts::of(&tree), built, "round {round}");
        }
    }
}
