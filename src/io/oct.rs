//! The native `.oct` format, versions 1 and 2 (full description in `docs/FORMAT.md`).
//!
//! An 80-byte little-endian header (magic, version, depth, domain, counts, payload
//! length, CRC-32; version 2 adds the up axis and the length unit of what the solid
//! was made from, in bytes that version 1 reserved) and a payload of one LEB128 varint a node, in Morton order:
//! `(gap << 5) | k`, where `gap` is the number of empty voxels between the previous
//! node's end and this node's start and `k` the node's levels above the voxels.
//! Surface-dominated solids take one to two bytes a node. The encoding is a function
//! of the solid alone, so the same solid always gives the same bytes.
//!
//! Optionally the solid's surface data (its [`HermiteData`]) follows the payload in a
//! section of its own, flagged by bit 0 of the header's flags field (reserved zero
//! before, so older builds refuse such a file cleanly rather than misread it) and
//! checked on its own (`io/oct_surface.rs`). A file without it is byte for byte what
//! earlier builds wrote.

use std::path::Path;

use glam::DVec3;

use crate::atomic::write_atomic;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::octree::{Domain, LinearOctree, MAX_DEPTH, NodeKey};
use crate::shape::Axis;
use crate::surface::HermiteData;

use super::{oct_surface, varint};

/// The first eight bytes of every `.oct` file.
pub const MAGIC: [u8; 8] = *b"OCTSOLID";
/// The newest format version, which this build writes when there is [`Metadata`] to
/// record; it reads every version up to this one.
pub const VERSION: u16 = 2;
/// The version written for a solid without metadata: version 1 readers open it.
const PLAIN_VERSION: u16 = 1;
/// The most bytes a node's varint (its gap from the node before and its level) takes.
const NODE_VARINT_BYTES: usize = 19;
/// Header size in bytes; the payload starts here.
pub const HEADER_BYTES: usize = 80;
/// Byte offset of the CRC-32 field; the checksum covers the bytes before it and the payload.
const CRC_OFFSET: usize = 72;
/// Byte offset of the flags field.
const FLAGS_OFFSET: usize = 10;
/// Flag: a surface section follows the payload.
const SURFACE_FLAG: u16 = 1;
/// Byte offsets of the version 2 fields.
const UP_OFFSET: usize = 13;
const UNITS_OFFSET: usize = 14;

/// What a solid was made from, beyond its voxels: version 2's header fields.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Metadata {
    /// The world's up axis (+x, +y or +z) of the source: y for a y-up OBJ. `None`:
    /// not recorded (octsolid's own convention, z, applies).
    pub up: Option<Axis>,
    /// The length unit of the coordinates, when the source said or the user gave it.
    pub units: Option<Units>,
}

/// Length units a file may record.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Units {
    /// Micrometres.
    Micrometre,
    /// Millimetres.
    Millimetre,
    /// Centimetres.
    Centimetre,
    /// Metres.
    Metre,
    /// Inches.
    Inch,
    /// Feet.
    Foot,
}

impl Units {
    const ALL: [(Units, &'static str, u8); 6] = [
        (Units::Micrometre, "um", 1),
        (Units::Millimetre, "mm", 2),
        (Units::Centimetre, "cm", 3),
        (Units::Metre, "m", 4),
        (Units::Inch, "in", 5),
        (Units::Foot, "ft", 6),
    ];

    /// The short name: `um`, `mm`, `cm`, `m`, `in` or `ft`.
    #[must_use]
    pub fn name(self) -> &'static str {
        Units::ALL.iter().find(|u| u.0 == self).expect("every unit listed").1
    }

    fn code(self) -> u8 {
        Units::ALL.iter().find(|u| u.0 == self).expect("every unit listed").2
    }

    fn from_code(code: u8) -> Option<Units> {
        Units::ALL.iter().find(|u| u.2 == code).map(|u| u.0)
    }
}

impl std::str::FromStr for Units {
    type Err = String;

    fn from_str(s: &str) -> std::result::Result<Self, String> {
        Units::ALL.iter().find(|u| u.1.eq_ignore_ascii_case(s)).map(|u| u.0).ok_or_else(|| {
            let names: Vec<_> = Units::ALL.iter().map(|u| u.1).collect();
            format!("unknown unit {s:?}; expected one of {}", names.join(", "))
        })
    }
}

impl std::fmt::Display for Units {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl Metadata {
    /// The header bytes of the up axis and the unit (0 where not recorded).
    pub(crate) fn codes(&self) -> [u8; 2] {
        [axis_code(self.up), self.units.map_or(0, Units::code)]
    }

    /// The metadata the header bytes `codes` record; the error names which byte (0 the
    /// up axis, 1 the unit) is refused and why.
    pub(crate) fn from_codes(codes: [u8; 2]) -> std::result::Result<Metadata, (usize, String)> {
        let up = axis_from_code(codes[0])
            .ok_or_else(|| (0, format!("up axis code {} is not 0 (none), 1 (x), 2 (y) or 3 (z)", codes[0])))?;
        let units = match codes[1] {
            0 => None,
            code => Some(Units::from_code(code).ok_or_else(|| (1, format!("unit code {code} is unknown")))?),
        };
        Ok(Metadata { up, units })
    }
}

fn axis_code(up: Option<Axis>) -> u8 {
    up.map_or(0, |a| a.index() as u8 + 1)
}

fn axis_from_code(code: u8) -> Option<Option<Axis>> {
    match code {
        0 => Some(None),
        1 => Some(Some(Axis::X)),
        2 => Some(Some(Axis::Y)),
        3 => Some(Some(Axis::Z)),
        _ => None,
    }
}

/// The whole file for `tree`, without metadata (version 1).
#[must_use]
pub fn encode(tree: &LinearOctree) -> Vec<u8> {
    encode_with(tree, &Metadata::default())
}

/// The whole file for `tree` with `meta`: version 2 when `meta` records anything,
/// else version 1, so files without metadata stay readable by older builds.
#[must_use]
pub fn encode_with(tree: &LinearOctree, meta: &Metadata) -> Vec<u8> {
    encode_with_surface(tree, meta, None)
}

/// The whole file for `tree` with `meta` and, when given, its surface data in a
/// surface section after the payload (each of `surface`'s faces must be a boundary
/// face of `tree`, as [`HermiteData::from_shape`] gives; a reader refuses others).
/// Without `surface`, the bytes of [`encode_with`].
#[must_use]
pub fn encode_with_surface(tree: &LinearOctree, meta: &Metadata, surface: Option<&HermiteData>) -> Vec<u8> {
    let d = tree.domain();
    let version = if *meta == Metadata::default() { PLAIN_VERSION } else { VERSION };
    // The payload is written in place after room for the header, which follows it.
    let mut out = vec![0u8; HEADER_BYTES];
    out.reserve(tree.node_count() * 2);
    let mut end = 0u64;
    for key in tree.keys() {
        let gap = key.start() - end;
        varint::write(&mut out, (u128::from(gap) << 5) | u128::from(key.k()));
        end = key.end();
    }
    let payload_len = out.len() - HEADER_BYTES;
    let mut header = Vec::with_capacity(HEADER_BYTES);
    header.extend_from_slice(&MAGIC);
    header.extend_from_slice(&version.to_le_bytes());
    let flags = if surface.is_some() { SURFACE_FLAG } else { 0 };
    header.extend_from_slice(&flags.to_le_bytes());
    let [up, units] = meta.codes();
    header.extend_from_slice(&[d.depth(), up, units, 0]);
    for v in [d.min().x, d.min().y, d.min().z, d.edge()] {
        header.extend_from_slice(&v.to_le_bytes());
    }
    for v in [tree.node_count() as u64, tree.voxel_count(), payload_len as u64] {
        header.extend_from_slice(&v.to_le_bytes());
    }
    let crc = checksum(&header, &out[HEADER_BYTES..]);
    header.extend_from_slice(&crc.to_le_bytes());
    header.extend_from_slice(&[0; 4]);
    out[..HEADER_BYTES].copy_from_slice(&header);
    if let Some(surface) = surface {
        oct_surface::encode(surface, &mut out);
    }
    out
}

/// Writes `tree` to `path` atomically, without metadata; returns the file size in bytes.
pub fn write(tree: &LinearOctree, path: impl AsRef<Path>) -> Result<u64> {
    write_with(tree, &Metadata::default(), path)
}

/// Writes `tree` with `meta` to `path` atomically; returns the file size in bytes.
pub fn write_with(tree: &LinearOctree, meta: &Metadata, path: impl AsRef<Path>) -> Result<u64> {
    write_with_surface(tree, meta, None, path)
}

/// Writes `tree` with `meta` and, when given, its surface data to `path` atomically
/// ([`encode_with_surface`]); returns the file size in bytes.
pub fn write_with_surface(
    tree: &LinearOctree,
    meta: &Metadata,
    surface: Option<&HermiteData>,
    path: impl AsRef<Path>,
) -> Result<u64> {
    let bytes = encode_with_surface(tree, meta, surface);
    write_atomic(path.as_ref(), |w| w.write_all(&bytes))
}

/// Reads and checks the `.oct` file at `path`.
pub fn read(path: impl AsRef<Path>, budget: MemoryBudget) -> Result<LinearOctree> {
    Ok(read_and_metadata(path, budget)?.0)
}

/// Reads and checks the `.oct` file at `path`, with its metadata (empty for version 1).
/// A surface section is checked and left out ([`read_and_surface`] keeps it).
pub fn read_and_metadata(path: impl AsRef<Path>, budget: MemoryBudget) -> Result<(LinearOctree, Metadata)> {
    let (tree, meta, _) = read_and_surface(path, budget)?;
    Ok((tree, meta))
}

/// Reads and checks the `.oct` file at `path`, with its metadata and its surface data
/// (`None` for a file without a surface section).
pub fn read_and_surface(
    path: impl AsRef<Path>,
    budget: MemoryBudget,
) -> Result<(LinearOctree, Metadata, Option<HermiteData>)> {
    let path = path.as_ref();
    let bytes = crate::input_file::read(path)?;
    decode_and_surface(&bytes, path, budget)
}

/// CRC-32 of the header before the checksum field, then the payload.
fn checksum(header: &[u8], payload: &[u8]) -> u32 {
    let mut h = crc32fast::Hasher::new();
    h.update(&header[..CRC_OFFSET]);
    h.update(payload);
    h.finalize()
}

/// Parses and checks a whole `.oct` file; `path` names it in errors.
pub fn decode(bytes: &[u8], path: &Path, budget: MemoryBudget) -> Result<LinearOctree> {
    Ok(decode_and_metadata(bytes, path, budget)?.0)
}

/// The header fields the payload is read against.
struct Header {
    domain: Domain,
    nodes: u64,
    voxels: u64,
    meta: Metadata,
    /// The payload's length: the nodes' bytes.
    payload_len: usize,
    /// Whether a surface section follows the payload.
    surface: bool,
}

/// Parses and checks a whole `.oct` file with its metadata; `path` names it in errors.
/// A surface section is checked and left out ([`decode_and_surface`] keeps it).
pub fn decode_and_metadata(bytes: &[u8], path: &Path, budget: MemoryBudget) -> Result<(LinearOctree, Metadata)> {
    let (tree, meta, _) = decode_and_surface(bytes, path, budget)?;
    Ok((tree, meta))
}

/// Parses and checks a whole `.oct` file with its metadata and its surface data
/// (`None` without a surface section); `path` names it in errors.
pub fn decode_and_surface(
    bytes: &[u8],
    path: &Path,
    budget: MemoryBudget,
) -> Result<(LinearOctree, Metadata, Option<HermiteData>)> {
    let fail =
        |offset: usize, reason: String| Error::Format { path: path.to_path_buf(), offset: offset as u64, reason };
    let header = decode_header(bytes, path)?;
    // Refuse absurd counts before allocating (every node takes at least a byte).
    let payload_end = HEADER_BYTES + header.payload_len;
    let payload = &bytes[HEADER_BYTES..payload_end];
    if header.nodes > payload.len() as u64 {
        return Err(fail(48, format!("{} nodes cannot fit in {} payload bytes", header.nodes, payload.len())));
    }
    budget.check(format!("loading {}", path.display()), header.nodes.saturating_mul(8))?;
    let decode_tree = || {
        let keys = decode_nodes(payload, &header, path)?;
        // Canonical form (no eight full siblings), named by the node's offset.
        LinearOctree::from_ordered_keys(header.domain, keys).map_err(|e| match e {
            Error::InvalidOctree { index, reason } => {
                let mut pos = 0;
                for _ in 0..index {
                    varint::read(payload, &mut pos, NODE_VARINT_BYTES);
                }
                fail(HEADER_BYTES + pos, format!("node {index}: {reason}"))
            }
            other => other,
        })
    };
    if !header.surface {
        return Ok((decode_tree()?, header.meta, None));
    }
    // The section is parsed while the nodes are decoded (it needs only the domain
    // until its faces are checked against them); the nodes' errors come first, as
    // from a reader in file order. Its budget is what the tree leaves: the tree holds
    // its struct and exactly the header's count of keys.
    let tree_bytes = (std::mem::size_of::<LinearOctree>() as u64)
        .saturating_add(header.nodes.saturating_mul(std::mem::size_of::<NodeKey>() as u64));
    let section_budget = MemoryBudget(budget.0.saturating_sub(tree_bytes));
    let section = || oct_surface::parse(&bytes[payload_end..], payload_end, &header.domain, path, section_budget);
    let (tree, section) = rayon::join(decode_tree, section);
    let tree = tree?;
    debug_assert_eq!(tree.bytes() as u64, tree_bytes);
    let surface = section?.check_against(&tree)?;
    Ok((tree, header.meta, Some(surface)))
}

/// Checks the header: magic, version, reserved bytes, depth, domain, metadata codes,
/// payload length and checksum.
fn decode_header(bytes: &[u8], path: &Path) -> Result<Header> {
    let fail =
        |offset: usize, reason: String| Error::Format { path: path.to_path_buf(), offset: offset as u64, reason };
    if bytes.len() < HEADER_BYTES {
        return Err(fail(
            bytes.len(),
            format!("file of {} bytes is shorter than the {HEADER_BYTES}-byte header", bytes.len()),
        ));
    }
    if bytes[..8] != MAGIC {
        return Err(fail(0, "not an .oct file (bad magic; expected \"OCTSOLID\")".into()));
    }
    let u16_at = |o: usize| u16::from_le_bytes([bytes[o], bytes[o + 1]]);
    let u64_at = |o: usize| u64::from_le_bytes(bytes[o..o + 8].try_into().expect("8 bytes"));
    let f64_at = |o: usize| f64::from_bits(u64_at(o));
    let version = u16_at(8);
    if !(1..=VERSION).contains(&version) {
        return Err(fail(8, format!("format version {version} is not supported (this build reads 1..={VERSION})")));
    }
    let flags = u16_at(FLAGS_OFFSET);
    if flags & !SURFACE_FLAG != 0 {
        return Err(fail(
            FLAGS_OFFSET,
            format!("flags {flags:#06x} hold bits this build does not know (it knows bit 0, the surface section)"),
        ));
    }
    let surface = flags & SURFACE_FLAG != 0;
    let reserved = if version == 1 { 13..16 } else { 15..16 };
    if let Some(at) = reserved.chain(76..80).find(|&i| bytes[i] != 0) {
        return Err(fail(at, "reserved header fields are not zero".into()));
    }
    let Metadata { up, units } = Metadata::from_codes([bytes[UP_OFFSET], bytes[UNITS_OFFSET]])
        .map_err(|(byte, reason)| fail(UP_OFFSET + byte, reason))?;
    let depth = bytes[12];
    if !(1..=MAX_DEPTH).contains(&depth) {
        return Err(fail(12, format!("depth {depth} is outside 1..={MAX_DEPTH}")));
    }
    let domain = Domain::new(DVec3::new(f64_at(16), f64_at(24), f64_at(32)), f64_at(40), depth)
        .map_err(|e| fail(16, e.to_string()))?;
    let (nodes, voxels, payload_len) = (u64_at(48), u64_at(56), u64_at(64));
    let after_header = (bytes.len() - HEADER_BYTES) as u64;
    if (!surface && payload_len != after_header) || payload_len > after_header {
        return Err(fail(
            64,
            format!("header says {payload_len} payload bytes but the file holds {after_header} after the header"),
        ));
    }
    let payload = &bytes[HEADER_BYTES..HEADER_BYTES + payload_len as usize];
    let stored = u32::from_le_bytes(bytes[CRC_OFFSET..CRC_OFFSET + 4].try_into().expect("4 bytes"));
    let computed = checksum(bytes, payload);
    if stored != computed {
        return Err(fail(CRC_OFFSET, format!("checksum mismatch: stored {stored:08x}, computed {computed:08x}")));
    }
    Ok(Header { domain, nodes, voxels, meta: Metadata { up, units }, payload_len: payload.len(), surface })
}

/// The payload's nodes, each in range, aligned, sorted and disjoint by construction,
/// as many as the header says, holding its voxel count.
fn decode_nodes(payload: &[u8], header: &Header, path: &Path) -> Result<Vec<NodeKey>> {
    let fail =
        |offset: usize, reason: String| Error::Format { path: path.to_path_buf(), offset: offset as u64, reason };
    let (domain, nodes, voxels) = (header.domain, header.nodes, header.voxels);
    let depth = domain.depth();
    let total = domain.voxel_total();
    let mut keys = Vec::with_capacity(nodes as usize);
    let mut pos = 0usize;
    let mut end = 0u64;
    let mut count = 0u64;
    while pos < payload.len() {
        let at = HEADER_BYTES + pos;
        let index = keys.len();
        let value = varint::read(payload, &mut pos, NODE_VARINT_BYTES)
            .ok_or_else(|| fail(at, format!("node {index}: truncated or overlong varint")))?;
        let k = (value & 31) as u32;
        if k > u32::from(depth) {
            return Err(fail(at, format!("node {index}: level {k} above the voxels exceeds depth {depth}")));
        }
        let gap = u64::try_from(value >> 5).ok().filter(|g| *g < total);
        let start = gap.and_then(|g| end.checked_add(g)).filter(|s| *s < total);
        let Some(start) = start else {
            return Err(fail(at, format!("node {index}: starts beyond the domain's {total} voxels")));
        };
        let len = 1u64 << (3 * k);
        if start & (len - 1) != 0 {
            return Err(fail(at, format!("node {index}: start {start} is not aligned to its size {len}")));
        }
        if start + len > total {
            return Err(fail(at, format!("node {index}: ends beyond the domain's {total} voxels")));
        }
        if keys.len() as u64 == nodes {
            return Err(fail(at, format!("more nodes than the {nodes} the header says")));
        }
        keys.push(NodeKey::new(start, k));
        end = start + len;
        count += len;
    }
    if keys.len() as u64 != nodes {
        return Err(fail(HEADER_BYTES + payload.len(), format!("{} nodes found, the header says {nodes}", keys.len())));
    }
    if count != voxels {
        return Err(fail(56, format!("nodes hold {count} voxels, the header says {voxels}")));
    }
    Ok(keys)
}
