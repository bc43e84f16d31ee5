//! The native `.oct` format, version 1 (full description in `docs/FORMAT.md`).
//!
//! An 80-byte little-endian header (magic, version, depth, domain, counts, payload
//! length, CRC-32) and a payload of one LEB128 varint a node, in Morton order:
//! `(gap << 5) | k`, where `gap` is the number of empty voxels between the previous
//! node's end and this node's start and `k` the node's levels above the voxels.
//! Surface-dominated solids take one to two bytes a node. The encoding is a function
//! of the solid alone, so the same solid always gives the same bytes.

use std::path::Path;

use glam::DVec3;

use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::io::write_atomic;
use crate::octree::{Domain, LinearOctree, MAX_DEPTH, NodeKey};

/// The first eight bytes of every `.oct` file.
pub const MAGIC: [u8; 8] = *b"OCTSOLID";
/// The format version this build writes and reads.
pub const VERSION: u16 = 1;
/// Header size in bytes; the payload starts here.
pub const HEADER_BYTES: usize = 80;
/// Byte offset of the CRC-32 field; the checksum covers the bytes before it and the payload.
const CRC_OFFSET: usize = 72;

/// The whole file for `tree`.
#[must_use]
pub fn encode(tree: &LinearOctree) -> Vec<u8> {
    let d = tree.domain();
    let mut payload = Vec::with_capacity(tree.node_count() * 2);
    let mut end = 0u64;
    for key in tree.keys() {
        let value = (u128::from(key.start() - end) << 5) | u128::from(key.k());
        write_varint(&mut payload, value);
        end = key.end();
    }
    let mut out = Vec::with_capacity(HEADER_BYTES + payload.len());
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    out.extend_from_slice(&[d.depth(), 0, 0, 0]);
    for v in [d.min().x, d.min().y, d.min().z, d.edge()] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for v in [tree.node_count() as u64, tree.voxel_count(), payload.len() as u64] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    let crc = checksum(&out, &payload);
    out.extend_from_slice(&crc.to_le_bytes());
    out.extend_from_slice(&[0; 4]);
    out.extend_from_slice(&payload);
    out
}

/// Writes `tree` to `path` atomically; returns the file size in bytes.
pub fn save(tree: &LinearOctree, path: impl AsRef<Path>) -> Result<u64> {
    let path = path.as_ref();
    let bytes = encode(tree);
    write_atomic(path, |w| w.write_all(&bytes))
}

/// Reads and checks the `.oct` file at `path`.
pub fn load(path: impl AsRef<Path>, budget: MemoryBudget) -> Result<LinearOctree> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    decode(&bytes, path, budget)
}

/// CRC-32 of the header before the checksum field, then the payload.
fn checksum(header: &[u8], payload: &[u8]) -> u32 {
    let mut h = crc32fast::Hasher::new();
    h.update(&header[..CRC_OFFSET]);
    h.update(payload);
    h.finalize()
}

fn write_varint(out: &mut Vec<u8>, mut v: u128) {
    while v >= 0x80 {
        out.push((v as u8) | 0x80);
        v >>= 7;
    }
    out.push(v as u8);
}

/// Reads a varint at `*pos`; `None` when truncated or longer than 19 bytes.
fn read_varint(bytes: &[u8], pos: &mut usize) -> Option<u128> {
    let mut v = 0u128;
    for shift in (0..128).step_by(7).take(19) {
        let b = *bytes.get(*pos)?;
        *pos += 1;
        v |= u128::from(b & 0x7f) << shift;
        if b & 0x80 == 0 {
            return Some(v);
        }
    }
    None
}

/// Parses and checks a whole `.oct` file; `path` names it in errors.
pub fn decode(bytes: &[u8], path: &Path, budget: MemoryBudget) -> Result<LinearOctree> {
    let fail =
        |offset: usize, reason: String| Error::Format { path: path.to_path_buf(), offset: offset as u64, reason };
    // Step 1: header.
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
    if version != VERSION {
        return Err(fail(8, format!("format version {version} is not supported (this build reads version {VERSION})")));
    }
    if u16_at(10) != 0 || bytes[13..16] != [0, 0, 0] || bytes[76..80] != [0; 4] {
        return Err(fail(10, "reserved header fields are not zero".into()));
    }
    let depth = bytes[12];
    if !(1..=MAX_DEPTH).contains(&depth) {
        return Err(fail(12, format!("depth {depth} is outside 1..={MAX_DEPTH}")));
    }
    let domain = Domain::new(DVec3::new(f64_at(16), f64_at(24), f64_at(32)), f64_at(40), depth)
        .map_err(|e| fail(16, e.to_string()))?;
    let (nodes, voxels, payload_len) = (u64_at(48), u64_at(56), u64_at(64));
    let payload = &bytes[HEADER_BYTES..];
    if payload_len != payload.len() as u64 {
        return Err(fail(
            64,
            format!("header says {payload_len} payload bytes but the file holds {} after the header", payload.len()),
        ));
    }
    let stored = u32::from_le_bytes(bytes[CRC_OFFSET..CRC_OFFSET + 4].try_into().expect("4 bytes"));
    let computed = checksum(bytes, payload);
    if stored != computed {
        return Err(fail(CRC_OFFSET, format!("checksum mismatch: stored {stored:08x}, computed {computed:08x}")));
    }
    // Step 2: refuse absurd counts before allocating (every node takes at least a byte).
    if nodes > payload_len {
        return Err(fail(48, format!("{nodes} nodes cannot fit in {payload_len} payload bytes")));
    }
    budget.check(format!("loading {}", path.display()), nodes.saturating_mul(8))?;

    // Step 3: nodes, each in range, aligned, sorted and disjoint by construction.
    let total = domain.voxel_total();
    let mut keys = Vec::with_capacity(nodes as usize);
    let mut pos = 0usize;
    let mut end = 0u64;
    let mut count = 0u64;
    while pos < payload.len() {
        let at = HEADER_BYTES + pos;
        let index = keys.len();
        let value = read_varint(payload, &mut pos)
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
        if start % len != 0 {
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
        return Err(fail(bytes.len(), format!("{} nodes found, the header says {nodes}", keys.len())));
    }
    if count != voxels {
        return Err(fail(56, format!("nodes hold {count} voxels, the header says {voxels}")));
    }
    // Step 4: canonical form (no eight full siblings), named by the node's offset.
    LinearOctree::from_keys(domain, keys).map_err(|e| match e {
        Error::InvalidOctree { index, reason } => {
            let mut pos = 0;
            for _ in 0..index {
                read_varint(payload, &mut pos);
            }
            fail(HEADER_BYTES + pos, format!("node {index}: {reason}"))
        }
        other => other,
    })
}
