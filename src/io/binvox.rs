//! binvox `.binvox` (Patrick Min's voxelizer; format by Michael Kazhdan, specified at
//! `patrickmin.com/binvox/binvox.html`): read and write. Mapping in `docs/FORMAT.md`,
//! section ".binvox".
//!
//! The file is an ASCII header, `#binvox 1` (or `2`), `dim d w h`, `translate tx ty
//! tz`, `scale s`, `data`, one a line, then run-length pairs of bytes `(value, count)`,
//! `count` in `1..=255` (a count of 0, which some writers emit after a run of exactly
//! 255, is read as no voxels), over the voxels in the spec's order: index
//! `x * (w h) + z * w + y` (x slowest, then z, y fastest), so `dim` lists the sizes
//! along x, z and y. Voxel `(i, j, k)` has its centre at
//! `translate + scale * ((i, j, k) + 1/2) / d`.
//!
//! **Header lines** besides those: blank lines and `#` comments are read past (trimesh
//! writes `# generated in \`trimesh\`` on the second line; the reference reader skips
//! what it does not know), keys in any case. A file with trimesh's comment is read in
//! trimesh's own convention, which its reader and writer share and the spec does not:
//! `translate` the first voxel's centre and `scale` the distance from the first centre
//! to the last, `pitch (n - 1)`; so a grid goes from trimesh to octsolid where trimesh
//! has it.
//!
//! **Domain.** `translate` is the domain's lowest corner, `scale / n` the voxel edge,
//! with `n` the largest of the three dims; the depth is the smallest with
//! `2^depth >= n` (at most 21). A cubic power-of-two grid is the domain exactly
//! (`scale` = domain edge); any other grid sits at the cube's low corner, padded with
//! empty voxels up to `2^depth` along each axis. (The spec asks for equal dims; for
//! unequal ones this follows the reference reader's `depth, height, width` order and a
//! uniform voxel, the only reading a single `scale` allows.)
//!
//! **Reading** checks the header line by line (errors name the byte offset of the
//! line), sums the runs before anything is allocated (their total must be exactly the
//! dims' product), checks the bit grid's memory against the budget, then fills the
//! bits and builds the octree (`io/bitgrid.rs`). Version 2 files (any non-zero
//! value is a set voxel) are read too; version 1 values must be 0 or 1.
//!
//! **Writing** gives a cubic grid of `2^depth` (`translate` = domain min, `scale` =
//! domain edge, both printed with the shortest decimal that reads back to the same
//! `f64`, so `.oct -> .binvox -> .oct` is exact) and streams the runs slab by slab
//! (x), row by row (z), from the octree's nodes, without a dense grid: work and
//! memory follow the nodes and the output, which is at least two bytes a 255 voxels
//! of the cube. A grid our reader would refuse under the same budget is refused
//! before a byte is written (a full depth-14 domain is a file of 34 GB at least).

use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::bitgrid::BitGrid;
use crate::atomic::write_atomic;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::octree::{Domain, LinearOctree, MAX_DEPTH, Node};

/// Longest header accepted, in bytes (real headers are under 100).
const MAX_HEADER: usize = 4096;

fn fail(path: &Path, offset: usize, reason: impl Into<String>) -> Error {
    Error::Format { path: path.to_path_buf(), offset: offset as u64, reason: reason.into() }
}

/// Reads the `.binvox` file at `path`.
pub fn read(path: impl AsRef<Path>, budget: MemoryBudget) -> Result<LinearOctree> {
    let path = path.as_ref();
    let bytes = crate::input_file::read(path)?;
    decode(&bytes, path, budget)
}

/// The header's fields.
struct Header {
    version: u8,
    /// Sizes along x, z, y (the file's order).
    dims: [u64; 3],
    translate: DVec3,
    scale: f64,
    /// Written by trimesh (its comment line `# generated in \`trimesh\``): `translate`
    /// is the first voxel's centre and `scale` the span of the centres, `pitch (n - 1)`.
    trimesh: bool,
    /// Offset of the first data byte.
    data: usize,
}

/// The comment trimesh's writer puts on the second line.
const TRIMESH_COMMENT: &str = "# generated in `trimesh`";

/// The header, line by line up to its `data` line: the version line first, then `dim`,
/// `translate`, `scale` and comments in any order.
fn parse_header(bytes: &[u8], path: &Path) -> Result<Header> {
    let mut pos = 0;
    let mut line_no = 0;
    let mut header = Header { version: 0, dims: [0; 3], translate: DVec3::ZERO, scale: 1.0, trimesh: false, data: 0 };
    let mut have_dims = false;
    loop {
        let at = pos;
        let line = next_header_line(bytes, &mut pos, path)?;
        if line_no > 0 && line.starts_with('#') {
            // A comment line (trimesh writes one; the reference reader skips what it
            // does not know).
            header.trimesh |= line == TRIMESH_COMMENT;
            continue;
        }
        // A comment after the values, as trimesh's reader allows.
        let line = if line_no > 0 { line.split('#').next().unwrap_or("").trim() } else { line };
        if line.is_empty() {
            continue;
        }
        let mut words = line.split_whitespace();
        let key = words.next().unwrap_or("");
        let lower = key.to_ascii_lowercase();
        let values: Vec<&str> = words.collect();
        if line_no == 0 {
            header.version = parse_version(key, &values, line, at, path)?;
            line_no += 1;
            continue;
        }
        match lower.as_str() {
            "dim" => {
                header.dims = parse_dims(&values, line, at, path)?;
                have_dims = true;
            }
            "translate" => {
                let t = parse_numbers(key, &values, 3, line, at, path)?;
                header.translate = DVec3::new(t[0], t[1], t[2]);
            }
            "scale" => {
                header.scale = parse_numbers(key, &values, 1, line, at, path)?[0];
                if header.scale <= 0.0 {
                    return Err(fail(path, at, format!("scale {} must be positive", header.scale)));
                }
            }
            "data" => {
                if !have_dims {
                    return Err(fail(path, at, "the header ends without a dim line"));
                }
                header.data = pos;
                return Ok(header);
            }
            _ => {
                return Err(fail(
                    path,
                    at,
                    format!("unknown header line {line:?} (dim, translate, scale, data or a # comment)"),
                ));
            }
        }
        line_no += 1;
    }
}

/// The header line at `pos`, trimmed, with `pos` moved past its newline; refused when
/// no newline comes within the first [`MAX_HEADER`] bytes or the line is not text.
fn next_header_line<'a>(bytes: &'a [u8], pos: &mut usize, path: &Path) -> Result<&'a str> {
    let at = *pos;
    let Some(len) = bytes[at..bytes.len().min(MAX_HEADER)].iter().position(|&b| b == b'\n') else {
        return Err(fail(path, at, format!("no \"data\" line within the first {MAX_HEADER} bytes")));
    };
    let line =
        std::str::from_utf8(&bytes[at..at + len]).map_err(|_| fail(path, at, "header line is not ASCII"))?.trim();
    *pos += len + 1;
    Ok(line)
}

/// The version the first line (`line` at `at`, its first word `key`) names: 1 or 2.
fn parse_version(key: &str, values: &[&str], line: &str, at: usize, path: &Path) -> Result<u8> {
    match (key, values) {
        ("#binvox", ["1"]) => Ok(1),
        ("#binvox", ["2"]) => Ok(2),
        ("#binvox", _) => Err(fail(path, at, format!("binvox version {line:?} is not supported (1 or 2)"))),
        _ => Err(fail(path, 0, "not a binvox file (the first line is not \"#binvox 1\")")),
    }
}

/// The sizes a `dim` line (`line` at `at`) gives: three integers in `1..=2^MAX_DEPTH`.
fn parse_dims(values: &[&str], line: &str, at: usize, path: &Path) -> Result<[u64; 3]> {
    let dims: Vec<u64> = values.iter().filter_map(|v| v.parse().ok()).collect();
    let limit = 1u64 << MAX_DEPTH;
    let [a, b, c] = dims.as_slice() else {
        return Err(fail(path, at, format!("dim needs three integers, got {line:?}")));
    };
    let dims = [*a, *b, *c];
    if values.len() != 3 || dims.iter().any(|&d| d == 0 || d > limit) {
        return Err(fail(path, at, format!("dims {line:?} must be three integers in 1..={limit}")));
    }
    Ok(dims)
}

/// The `n` finite numbers the `key` line (`line` at `at`) gives.
fn parse_numbers(key: &str, values: &[&str], n: usize, line: &str, at: usize, path: &Path) -> Result<Vec<f64>> {
    let parsed: Vec<f64> = values.iter().filter_map(|v| v.parse::<f64>().ok()).filter(|v| v.is_finite()).collect();
    if values.len() != n || parsed.len() != n {
        return Err(fail(path, at, format!("{key} needs {n} finite numbers, got {line:?}")));
    }
    Ok(parsed)
}

/// Parses and checks a whole `.binvox` file; `path` names it in errors.
pub fn decode(bytes: &[u8], path: &Path, budget: MemoryBudget) -> Result<LinearOctree> {
    // Step 1: header and domain.
    let header = parse_header(bytes, path)?;
    let [nx, nz, ny] = header.dims;
    let n = nx.max(ny).max(nz);
    let depth = n.next_power_of_two().trailing_zeros().max(1) as u8;
    let (min, voxel) = if header.trimesh {
        // trimesh's grid: voxel i's centre at translate + i scale / (n - 1).
        if n < 2 {
            return Err(fail(path, 0, "a one-voxel grid written by trimesh does not record its voxel size"));
        }
        let pitch = header.scale / (n - 1) as f64;
        (header.translate - DVec3::splat(0.5 * pitch), pitch)
    } else {
        (header.translate, header.scale / n as f64)
    };
    let edge = voxel * f64::from(1u32 << depth);
    let domain = Domain::new(min, edge, depth).map_err(|e| fail(path, 0, e.to_string()))?;
    // Step 2: the runs must cover the dims exactly; nothing is allocated yet.
    let data = &bytes[header.data..];
    if !data.len().is_multiple_of(2) {
        return Err(fail(path, bytes.len() - 1, "voxel data ends in the middle of a (value, count) pair"));
    }
    let total = nx * ny * nz;
    let mut sum = 0u64;
    let mut set = 0u64;
    for (p, pair) in data.chunks_exact(2).enumerate() {
        let at = header.data + 2 * p;
        let (value, count) = (pair[0], u64::from(pair[1]));
        if header.version == 1 && value > 1 {
            return Err(fail(path, at, format!("value {value} in a version-1 file (0 or 1)")));
        }
        sum += count;
        if sum > total {
            return Err(fail(path, at, format!("runs cover more than the {total} voxels of the dims")));
        }
        if value != 0 {
            set += count;
        }
    }
    if sum != total {
        return Err(fail(path, bytes.len(), format!("runs cover {sum} voxels, the dims hold {total}")));
    }
    let estimate = read_estimate([nx, ny, nz], set);
    budget.check(format!("reading {} ({nx} x {nz} x {ny} voxels)", path.display()), estimate)?;
    // Step 3: the bits (file order x, z, y = the grid's), then the octree.
    let mut grid = BitGrid::new([nx, ny, nz]);
    let mut index = 0u64;
    for pair in data.chunks_exact(2) {
        let count = u64::from(pair[1]);
        if pair[0] != 0 {
            grid.set_run(index, count);
        }
        index += count;
    }
    grid.to_octree(domain)
}

/// Writes `tree` to `path` as a cubic binvox grid, atomically; returns the bytes
/// written. Refused before anything is written when reading the file back would
/// exceed `budget` (the bits and a node a set voxel).
pub fn write(path: impl AsRef<Path>, tree: &LinearOctree, budget: MemoryBudget) -> Result<u64> {
    let path = path.as_ref();
    check_write(tree, budget, &path.display().to_string())?;
    write_atomic(path, |w| stream(tree, w))
}

/// The whole file for `tree` (module doc, "Writing"), refused as [`write()`] refuses it.
pub fn encode(tree: &LinearOctree, budget: MemoryBudget) -> Result<Vec<u8>> {
    check_write(tree, budget, "a .binvox file")?;
    let mut out = Vec::new();
    stream(tree, &mut out).expect("writing to memory");
    Ok(out)
}

/// Bytes our reader needs for a grid of `dims` with `set` voxels set: the bits, and a
/// node a set voxel at most, 8 bytes each.
fn read_estimate(dims: [u64; 3], set: u64) -> u64 {
    BitGrid::estimate_bytes(dims).saturating_add(set.saturating_mul(8))
}

/// Refuses to write a file `output` of `tree` that [`decode`] would refuse under the
/// same budget: a cube of `2^depth` voxels a side is at least two bytes a 255 voxels
/// on disk, so the budget bounds the file too.
fn check_write(tree: &LinearOctree, budget: MemoryBudget, output: &str) -> Result<()> {
    let n = u64::from(tree.domain().resolution());
    let job = format!("writing {output} ({n}^3 voxels, as much as reading it back needs)");
    budget.check(job, read_estimate([n; 3], tree.voxel_count()))
}

/// Streams the file for `tree` into `w` (module doc, "Writing").
fn stream(tree: &LinearOctree, w: &mut dyn Write) -> std::io::Result<()> {
    let d = tree.domain();
    let n = d.resolution();
    write!(
        w,
        "#binvox 1\ndim {n} {n} {n}\ntranslate {} {} {}\nscale {}\ndata\n",
        d.min().x,
        d.min().y,
        d.min().z,
        d.edge()
    )?;
    // Nodes by their first slab; a node is active in slabs [x0, x0 + size).
    let mut nodes: Vec<Node> = tree.nodes().collect();
    nodes.sort_by_key(|n| n.min[0]);
    let mut next = 0;
    let mut active: Vec<Node> = Vec::new();
    let mut rows: Vec<Vec<(u32, u32)>> = vec![Vec::new(); n as usize];
    let mut rle = Rle { w, value: 0, count: 0, buf: Vec::with_capacity(1 << 16) };
    for x in 0..n {
        active.retain(|node| node.min[0] + node.size > x);
        while next < nodes.len() && nodes[next].min[0] == x {
            active.push(nodes[next]);
            next += 1;
        }
        if active.is_empty() {
            rle.feed(0, u64::from(n) * u64::from(n))?;
            continue;
        }
        // Each active node covers rows z0..z0+s with the y interval [y0, y0 + s).
        for node in &active {
            for z in node.min[2]..node.min[2] + node.size {
                rows[z as usize].push((node.min[1], node.min[1] + node.size));
            }
        }
        for row in &mut rows {
            row.sort_unstable();
            let mut y = 0;
            for &(a, b) in row.iter() {
                // Nodes are disjoint, so sorted intervals do not overlap.
                rle.feed(0, u64::from(a - y))?;
                rle.feed(1, u64::from(b - a))?;
                y = b;
            }
            rle.feed(0, u64::from(n - y))?;
            row.clear();
        }
    }
    rle.finish()
}

/// Run-length encoder into `(value, count)` byte pairs.
struct Rle<'a> {
    w: &'a mut dyn Write,
    value: u8,
    count: u64,
    buf: Vec<u8>,
}

impl Rle<'_> {
    fn feed(&mut self, value: u8, count: u64) -> std::io::Result<()> {
        if count == 0 {
            return Ok(());
        }
        if value != self.value {
            self.flush_run()?;
            self.value = value;
        }
        self.count += count;
        Ok(())
    }

    fn flush_run(&mut self) -> std::io::Result<()> {
        while self.count > 0 {
            let c = self.count.min(255);
            self.buf.extend_from_slice(&[self.value, c as u8]);
            self.count -= c;
            if self.buf.len() >= 1 << 16 {
                self.w.write_all(&self.buf)?;
                self.buf.clear();
            }
        }
        Ok(())
    }

    fn finish(mut self) -> std::io::Result<()> {
        self.flush_run()?;
        self.w.write_all(&self.buf)
    }
}
