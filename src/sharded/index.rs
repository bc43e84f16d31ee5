//! The shard index (`index` in a sharded solid's folder) and the part files a task
//! leaves for the join (`part-FIRST-END` beside the shards while a job runs): one
//! binary layout for both, described in `docs/FORMAT.md`.
//!
//! Both start with a 96-byte header (magic, version, depth, up axis and unit, cell
//! level, domain, two counts that differ: the index's node and voxel totals, a part's
//! range of cells; how many full entries and shard entries follow; the job's identity,
//! [`JobId`]), then the full entries, the shard entries, and a CRC-32 of everything
//! before it. The file's length is checked against the counts before anything is
//! allocated (and read: [`ShardIndex::read`] reads the header first), and every entry
//! against the domain, the level and its neighbours. Version 1 (an 80-byte header
//! without the job) is still read for indexes, as of job [`JobId::NONE`]; a part of
//! version 1 is refused (its tasks are run again).

use std::path::Path;

use glam::DVec3;

use super::job::JobId;
use super::layout::Layout;
use super::staging;
use crate::error::{Error, Result};
use crate::io::oct::{self, Metadata};
use crate::octree::{Cells, Domain, LinearOctree, MAX_DEPTH, NodeKey};

/// The first eight bytes of a shard index.
pub const INDEX_MAGIC: [u8; 8] = *b"OCTSHARD";
/// The first eight bytes of a part file.
pub(crate) const PART_MAGIC: [u8; 8] = *b"OCTSPART";
/// The index and part format version this build writes (it reads version 1 indexes
/// too).
pub const INDEX_VERSION: u16 = 2;
/// Header bytes of version 2.
const HEADER_BYTES: usize = 96;
/// Header bytes of version 1 (no job).
const HEADER_V1_BYTES: usize = 80;
/// Bytes of a full entry in the index (start `u64`, `k` `u32`).
const FULL_BYTES: usize = 12;
/// Bytes of a full cell in a part (the cell's number).
const FULL_CELL_BYTES: usize = 8;
/// Bytes of a shard entry.
const SHARD_BYTES: usize = 60;

/// One shard: a cell holding some voxels but not all, stored in its own `.oct` file.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ShardEntry {
    /// The cell's number at the solid's cell level (Morton order).
    pub cell: u64,
    /// Nodes in the shard.
    pub nodes: u64,
    /// Voxels in the shard.
    pub voxels: u64,
    /// The shard file's length in bytes.
    pub bytes: u64,
    /// CRC-32 of the whole shard file.
    pub crc32: u32,
    /// The lowest voxel coordinates of the shard's voxels.
    pub min: [u32; 3],
    /// The highest voxel coordinates of the shard's voxels.
    pub max: [u32; 3],
}

/// What a sharded solid's index says: the domain, what the solid was made from, the
/// cell level, the full nodes of at least a cell (kept in the index, never in a
/// shard) and the shards, both in Morton order.
#[derive(Clone, Debug, PartialEq)]
pub struct ShardIndex {
    /// The job that made the solid ([`JobId::NONE`] for a version 1 index).
    pub job: JobId,
    /// The domain every shard shares.
    pub domain: Domain,
    /// The up axis and unit recorded with the solid.
    pub meta: Metadata,
    /// The cell level: shards are cells `level` levels below the root.
    pub level: u8,
    /// Nodes of the whole solid (full entries and every shard's).
    pub nodes: u64,
    /// Voxels of the whole solid.
    pub voxels: u64,
    /// The solid's nodes of a cell or larger, canonical.
    pub full: Vec<NodeKey>,
    /// The shards by cell.
    pub shards: Vec<ShardEntry>,
}

impl ShardIndex {
    /// The cells' geometry.
    #[must_use]
    pub fn layout(&self) -> Layout {
        Layout { depth: self.domain.depth(), level: self.level }
    }

    /// Integer bounds `[min, max)` of the solid's voxels (as
    /// [`LinearOctree::voxel_bounds`]), from the index alone; `None` when it is empty.
    #[must_use]
    pub fn voxel_bounds(&self) -> Option<([u32; 3], [u32; 3])> {
        let depth = self.domain.depth();
        let boxes = self.full.iter().map(|k| {
            let n = k.node(depth);
            (n.min, n.min.map(|c| c + n.size - 1))
        });
        let boxes = boxes.chain(self.shards.iter().map(|s| (s.min, s.max)));
        let (min, max) = boxes.reduce(|(a, b), (c, d)| {
            (std::array::from_fn(|i| a[i].min(c[i])), std::array::from_fn(|i| b[i].max(d[i])))
        })?;
        Some((min, max.map(|c| c + 1)))
    }

    /// The whole index file.
    #[must_use]
    pub fn encode(&self) -> Vec<u8> {
        let head = Head {
            job: self.job,
            header: HEADER_BYTES,
            domain: self.domain,
            meta: self.meta,
            level: self.level,
            counts: [self.nodes, self.voxels],
            full: self.full.len(),
            shards: self.shards.len(),
        };
        let mut out = head.encode(&INDEX_MAGIC);
        for key in &self.full {
            out.extend_from_slice(&key.start().to_le_bytes());
            out.extend_from_slice(&key.k().to_le_bytes());
        }
        encode_shards(&mut out, &self.shards);
        finish(out)
    }

    /// Parses and checks an index file; `path` names it in errors.
    pub fn decode(bytes: &[u8], path: &Path) -> Result<ShardIndex> {
        let fail = failure(path);
        let head = Head::decode(bytes, &INDEX_MAGIC, FULL_BYTES, path)?;
        let (domain, level) = (head.domain, head.level);
        let layout = Layout { depth: domain.depth(), level };
        let mut at = head.header;
        let mut full = Vec::with_capacity(head.full);
        for i in 0..head.full {
            let start = u64_at(bytes, at);
            let k = u32::from_le_bytes(bytes[at + 8..at + 12].try_into().expect("4 bytes"));
            let cell_k = u32::from(layout.cell_k());
            if k < cell_k || k > u32::from(domain.depth()) {
                return Err(fail(
                    at,
                    format!("full node {i}: level {k} above the voxels is not {cell_k}..={}", domain.depth()),
                ));
            }
            if !start.is_multiple_of(1u64 << (3 * k)) || start >= domain.voxel_total() {
                return Err(fail(at, format!("full node {i}: start {start} is not an aligned node of the domain")));
            }
            let key = NodeKey::new(start, k);
            if full.last().is_some_and(|last: &NodeKey| last.end() > start) {
                return Err(fail(at, format!("full node {i} overlaps or precedes the one before it")));
            }
            full.push(key);
            at += FULL_BYTES;
        }
        // No eight full siblings: the full nodes alone are canonical.
        LinearOctree::from_keys(domain, full.clone())
            .map_err(|e| fail(head.header, format!("the full nodes are not canonical: {e}")))?;
        let shards = decode_shards(bytes, &mut at, head.shards, &layout, path)?;
        check_disjoint(&full, &shards, &layout).map_err(|reason| fail(head.header, reason))?;
        let nodes = shards.iter().try_fold(full.len() as u64, |n, s| n.checked_add(s.nodes));
        let voxels =
            full.iter().map(|k| k.len()).chain(shards.iter().map(|s| s.voxels)).try_fold(0u64, u64::checked_add);
        let [want_nodes, want_voxels] = head.counts;
        if nodes != Some(want_nodes) || voxels != Some(want_voxels) {
            return Err(fail(
                48,
                format!(
                    "the entries hold {nodes:?} nodes and {voxels:?} voxels, the header says {want_nodes} and {want_voxels}"
                ),
            ));
        }
        Ok(ShardIndex {
            job: head.job,
            domain,
            meta: head.meta,
            level,
            nodes: want_nodes,
            voxels: want_voxels,
            full,
            shards,
        })
    }

    /// Reads and checks the index of the sharded solid in folder `dir`: a regular
    /// file (never a FIFO or device), whose length its header gives before the rest
    /// is read.
    pub fn read(dir: &Path) -> Result<ShardIndex> {
        let path = dir.join(super::INDEX_FILE);
        let bytes = read_file(&path, &INDEX_MAGIC, FULL_BYTES)?;
        ShardIndex::decode(&bytes, &path)
    }
}

/// Reads an index or part file: its header, then the rest once the length the header
/// gives matches the file's.
pub(crate) fn read_file(path: &Path, magic: &[u8; 8], full_bytes: usize) -> Result<Vec<u8>> {
    staging::read_checked_len(path, HEADER_BYTES + 4, |head| Head::file_len(head, magic, full_bytes, path))
}

/// Reads a part file.
pub(crate) fn read_part(path: &Path) -> Result<Part> {
    let bytes = read_file(path, &PART_MAGIC, FULL_CELL_BYTES)?;
    Part::decode(&bytes, path)
}

/// What one task made: its range of cells, the full cells and the shards in it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Part {
    pub(crate) job: JobId,
    pub(crate) domain: Domain,
    pub(crate) meta: Metadata,
    pub(crate) cells: Cells,
    /// Full cells, by number.
    pub(crate) full: Vec<u64>,
    pub(crate) shards: Vec<ShardEntry>,
}

impl Part {
    pub(crate) fn encode(&self) -> Vec<u8> {
        let head = Head {
            job: self.job,
            header: HEADER_BYTES,
            domain: self.domain,
            meta: self.meta,
            level: self.cells.level,
            counts: [self.cells.range.start, self.cells.range.end],
            full: self.full.len(),
            shards: self.shards.len(),
        };
        let mut out = head.encode(&PART_MAGIC);
        for cell in &self.full {
            out.extend_from_slice(&cell.to_le_bytes());
        }
        encode_shards(&mut out, &self.shards);
        finish(out)
    }

    pub(crate) fn decode(bytes: &[u8], path: &Path) -> Result<Part> {
        let fail = failure(path);
        let head = Head::decode(bytes, &PART_MAGIC, FULL_CELL_BYTES, path)?;
        if head.header != HEADER_BYTES {
            return Err(fail(8, "a part of version 1 (made by an older octsolid): run its task again".into()));
        }
        let layout = Layout { depth: head.domain.depth(), level: head.level };
        let [first, end] = head.counts;
        if first > end || end > layout.cell_count() {
            return Err(fail(48, format!("cells {first}..{end} are not a range of the {} cells", layout.cell_count())));
        }
        let cells = Cells { level: head.level, range: first..end };
        let mut at = head.header;
        let mut full = Vec::with_capacity(head.full);
        for i in 0..head.full {
            let cell = u64_at(bytes, at);
            if !cells.range.contains(&cell) || full.last().is_some_and(|&last| last >= cell) {
                return Err(fail(at, format!("full cell {i} ({cell}) is out of order or outside {first}..{end}")));
            }
            full.push(cell);
            at += FULL_CELL_BYTES;
        }
        let shards = decode_shards(bytes, &mut at, head.shards, &layout, path)?;
        if let Some(s) = shards.iter().find(|s| !cells.range.contains(&s.cell) || full.binary_search(&s.cell).is_ok()) {
            return Err(fail(head.header, format!("shard of cell {} is outside {first}..{end} or also full", s.cell)));
        }
        Ok(Part { job: head.job, domain: head.domain, meta: head.meta, cells, full, shards })
    }
}

/// The header fields.
struct Head {
    job: JobId,
    /// The header's length: [`HEADER_BYTES`], or [`HEADER_V1_BYTES`] for version 1.
    header: usize,
    domain: Domain,
    meta: Metadata,
    level: u8,
    /// Bytes 48..64: the index's node and voxel totals, or a part's cell range.
    counts: [u64; 2],
    full: usize,
    shards: usize,
}

impl Head {
    fn encode(&self, magic: &[u8; 8]) -> Vec<u8> {
        let d = self.domain;
        let mut out = Vec::with_capacity(HEADER_BYTES + 12 * self.full + SHARD_BYTES * self.shards + 4);
        out.extend_from_slice(magic);
        out.extend_from_slice(&INDEX_VERSION.to_le_bytes());
        out.extend_from_slice(&0u16.to_le_bytes());
        let [up, units] = self.meta.codes();
        out.extend_from_slice(&[d.depth(), up, units, self.level]);
        for v in [d.min().x, d.min().y, d.min().z, d.edge()] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        for v in [self.counts[0], self.counts[1], self.full as u64, self.shards as u64] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&self.job.0);
        out
    }

    /// The magic and version of `bytes`, and the header's length.
    fn version(bytes: &[u8], magic: &[u8; 8], path: &Path) -> Result<usize> {
        let fail = failure(path);
        let what = if magic == &INDEX_MAGIC { "shard index" } else { "shard part file" };
        if bytes.len() < HEADER_V1_BYTES + 4 {
            return Err(fail(bytes.len(), format!("{} bytes is shorter than a {what}", bytes.len())));
        }
        if &bytes[..8] != magic {
            let name = String::from_utf8_lossy(magic).into_owned();
            return Err(fail(0, format!("not a {what} (bad magic; expected {name:?})")));
        }
        match u16::from_le_bytes([bytes[8], bytes[9]]) {
            1 => Ok(HEADER_V1_BYTES),
            2 if bytes.len() >= HEADER_BYTES + 4 => Ok(HEADER_BYTES),
            2 => Err(fail(bytes.len(), format!("{} bytes is shorter than a {what}", bytes.len()))),
            version => Err(fail(
                8,
                format!("{what} version {version} is not supported (this build reads 1 and {INDEX_VERSION})"),
            )),
        }
    }

    /// The file's length its header gives (the first [`HEADER_BYTES`] + 4 bytes or all
    /// of a shorter file), with entries of `full_bytes` each.
    fn file_len(head: &[u8], magic: &[u8; 8], full_bytes: usize, path: &Path) -> Result<u64> {
        // A file shorter than a header is refused by its length: as long as it is.
        if head.len() < HEADER_V1_BYTES + 4 {
            return Ok(head.len() as u64);
        }
        let header = Head::version(head, magic, path)?;
        let (full, shards) = (u64_at(head, 64), u64_at(head, 72));
        full.checked_mul(full_bytes as u64)
            .and_then(|f| shards.checked_mul(SHARD_BYTES as u64).and_then(|s| s.checked_add(f)))
            .and_then(|n| n.checked_add(header as u64 + 4))
            .ok_or_else(|| {
                failure(path)(64, format!("{full} full entries and {shards} shards cannot be the counts of a file"))
            })
    }

    /// Checks the header and the file's length against its counts (full entries of
    /// `full_bytes` each) and its checksum.
    fn decode(bytes: &[u8], magic: &[u8; 8], full_bytes: usize, path: &Path) -> Result<Head> {
        let fail = failure(path);
        let header = Head::version(bytes, magic, path)?;
        if bytes[10..12] != [0, 0] {
            return Err(fail(10, "reserved flags are not zero".into()));
        }
        let (depth, level) = (bytes[12], bytes[15]);
        if !(1..=MAX_DEPTH).contains(&depth) {
            return Err(fail(12, format!("depth {depth} is outside 1..={MAX_DEPTH}")));
        }
        if level > depth {
            return Err(fail(15, format!("cell level {level} is below the voxels of depth {depth}")));
        }
        let meta = Metadata::from_codes([bytes[13], bytes[14]]).map_err(|(byte, reason)| fail(13 + byte, reason))?;
        let f64_at = |o: usize| f64::from_bits(u64_at(bytes, o));
        let domain = Domain::new(DVec3::new(f64_at(16), f64_at(24), f64_at(32)), f64_at(40), depth)
            .map_err(|e| fail(16, e.to_string()))?;
        let counts = [u64_at(bytes, 48), u64_at(bytes, 56)];
        let (full, shards) = (u64_at(bytes, 64), u64_at(bytes, 72));
        // The length first: no count is trusted before it matches the file.
        let want = full
            .checked_mul(full_bytes as u64)
            .and_then(|f| shards.checked_mul(SHARD_BYTES as u64).and_then(|s| s.checked_add(f)))
            .and_then(|n| n.checked_add(header as u64 + 4));
        if want != Some(bytes.len() as u64) {
            return Err(fail(
                64,
                format!("{full} full entries and {shards} shards do not make the file's {} bytes", bytes.len()),
            ));
        }
        let body = bytes.len() - 4;
        let stored = u32::from_le_bytes(bytes[body..].try_into().expect("4 bytes"));
        let computed = crc32fast::hash(&bytes[..body]);
        if stored != computed {
            return Err(fail(body, format!("checksum mismatch: stored {stored:08x}, computed {computed:08x}")));
        }
        let job = if header == HEADER_BYTES { JobId(bytes[80..96].try_into().expect("16 bytes")) } else { JobId::NONE };
        Ok(Head { job, header, domain, meta, level, counts, full: full as usize, shards: shards as usize })
    }
}

fn encode_shards(out: &mut Vec<u8>, shards: &[ShardEntry]) {
    for s in shards {
        for v in [s.cell, s.nodes, s.voxels, s.bytes] {
            out.extend_from_slice(&v.to_le_bytes());
        }
        out.extend_from_slice(&s.crc32.to_le_bytes());
        for v in s.min.iter().chain(&s.max) {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
}

/// Reads `count` shard entries at `*at`, each checked against the layout and the one
/// before it.
fn decode_shards(bytes: &[u8], at: &mut usize, count: usize, layout: &Layout, path: &Path) -> Result<Vec<ShardEntry>> {
    let fail = failure(path);
    let mut shards: Vec<ShardEntry> = Vec::with_capacity(count);
    let cell_voxels = 1u64 << (3 * u32::from(layout.cell_k()));
    let cell_edge = 1u32 << layout.cell_k();
    for i in 0..count {
        let o = *at;
        let u32_at = |o: usize| u32::from_le_bytes(bytes[o..o + 4].try_into().expect("4 bytes"));
        let s = ShardEntry {
            cell: u64_at(bytes, o),
            nodes: u64_at(bytes, o + 8),
            voxels: u64_at(bytes, o + 16),
            bytes: u64_at(bytes, o + 24),
            crc32: u32_at(o + 32),
            min: std::array::from_fn(|a| u32_at(o + 36 + 4 * a)),
            max: std::array::from_fn(|a| u32_at(o + 48 + 4 * a)),
        };
        if s.cell >= layout.cell_count() || shards.last().is_some_and(|last| last.cell >= s.cell) {
            return Err(fail(
                o,
                format!("shard {i}: cell {} is out of order or beyond the {} cells", s.cell, layout.cell_count()),
            ));
        }
        if s.bytes <= oct::HEADER_BYTES as u64 {
            return Err(fail(
                o + 24,
                format!(
                    "shard {i}: a shard file of {} bytes is impossible (an .oct header alone is {})",
                    s.bytes,
                    oct::HEADER_BYTES
                ),
            ));
        }
        if s.nodes == 0 || s.voxels < s.nodes || s.voxels >= cell_voxels {
            return Err(fail(
                o + 8,
                format!(
                    "shard {i}: {} nodes of {} voxels cannot be part of a cell of {cell_voxels}",
                    s.nodes, s.voxels
                ),
            ));
        }
        let cell_min = layout.cell_min(s.cell);
        let inside =
            (0..3).all(|a| cell_min[a] <= s.min[a] && s.min[a] <= s.max[a] && s.max[a] < cell_min[a] + cell_edge);
        if !inside {
            return Err(fail(o + 36, format!("shard {i}: voxel bounds {:?}..{:?} are not in its cell", s.min, s.max)));
        }
        shards.push(s);
        *at += SHARD_BYTES;
    }
    Ok(shards)
}

/// Refuses a shard inside a full node.
fn check_disjoint(full: &[NodeKey], shards: &[ShardEntry], layout: &Layout) -> std::result::Result<(), String> {
    for s in shards {
        let start = layout.cell_key(s.cell).start();
        let i = full.partition_point(|k| k.end() <= start);
        if full.get(i).is_some_and(|k| k.start() <= start) {
            return Err(format!("the shard of cell {} lies in the full node starting at {}", s.cell, full[i].start()));
        }
    }
    Ok(())
}

fn finish(mut out: Vec<u8>) -> Vec<u8> {
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

fn u64_at(bytes: &[u8], o: usize) -> u64 {
    u64::from_le_bytes(bytes[o..o + 8].try_into().expect("8 bytes"))
}

fn failure(path: &Path) -> impl Fn(usize, String) -> Error + '_ {
    move |offset, reason| Error::Format { path: path.to_path_buf(), offset: offset as u64, reason }
}
