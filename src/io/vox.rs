//! MagicaVoxel `.vox`: read through the `dot_vox` crate (models, palette, materials,
//! scene graph), written here. Format: the MagicaVoxel file format and its scene-graph
//! extension (`MagicaVoxel-file-format-vox.txt`, `...-vox-extension.txt` in ephtracy's
//! `voxel-model` repository); mapping in `docs/FORMAT.md`, section ".vox".
//!
//! **Reading.** A structure walk of our own first checks every chunk the models and the
//! scene depend on (`SIZE`, `XYZI`, `RGBA`, `MATL`, `nTRN`, `nGRP`, `nSHP`, `LAYR`,
//! `IMAP`) and records node ids and byte offsets, because `dot_vox` drops a malformed
//! chunk silently and numbers scene nodes by position; only then are the bytes handed
//! to `dot_vox`. Every error names the file, the chunk and its byte offset. Then:
//!
//! 1. **Placement.** The scene graph is walked from node 0 (transform, group, shape;
//!    frame 0 of each transform, the first model of each shape; hidden nodes and
//!    nodes on hidden layers are skipped). A model voxel `v` of a model of size `s`
//!    under the accumulated rotation `R` (one of the 24 rotations or their 24 mirror
//!    images, `_r`) and translation `t` (`_t`) lands on world voxel
//!    `floor(R (v + 1/2 - floor(s/2)) + t)` (MagicaVoxel's pivot: the model's centre
//!    voxel), computed exactly as `(R (2v + 1 - 2 floor(s/2)) + 2t - 1) / 2`. A file
//!    without a scene graph places each model at its own coordinates.
//! 2. **Domain.** The cube of the smallest depth (at least 1, at most 21) holding every
//!    placed voxel, its lowest corner at the lowest placed voxel, a voxel
//!    [`ReadOptions::voxel_size`] world units a side (1 by default: world unit =
//!    MagicaVoxel unit). A file octsolid wrote carries its exact domain in the root
//!    transform's `_octsolid_domain` attribute and reads back with it
//!    ([`ReadOptions::stored_domain`]), so `.oct -> .vox -> .oct` is exact.
//! 3. **Solids.** One solid a palette index in use, in ascending order; where placed
//!    models overlap the one placed last wins. Colour: the palette entry, sRGB decoded
//!    to linear ([`crate::render::from_srgb8`]); material: the `MATL` chunk whose id is
//!    the palette index. `IMAP` only reorders the editor's palette display and does
//!    not change colours.
//!
//! **Writing.** One palette index a solid (its own [`ColouredSolid::palette_index`]
//! when it has a free one, else the lowest free index; colour quantized to sRGB8, a
//! solid without one is light grey), at most [`MAX_COLOURS`] solids (more are refused).
//! The voxels' bounding box is cut into models of at most [`MAX_MODEL_SIDE`]^3 (the
//! format's limit: coordinates are bytes), each placed by a transform under one group,
//! so world voxel = the solid's lattice voxel. Each node is put in the models it meets
//! (one piece a model, sorted by model, then by solid), so only models holding voxels
//! are visited and work follows the nodes and the voxels, not the box (two voxels in
//! opposite corners of a depth-12 domain are two models, not 4,096 of which 4,094
//! empty). A model whose pieces fill at least 1/16 of its box is painted piece by piece
//! into a byte grid of the model (at most 16 MiB, reused), solid after solid, so where
//! solids overlap the later one wins, and read out in the order `XYZI` lists them (x,
//! then y, then z); a sparser one lists its voxels packed with their solid's place and
//! sorts them, the last entry of a voxel (the latest solid's) winning: the same bytes.
//! The bytes are a function of the solids alone (no map iteration order leaks out).
//!
//! Limits: `.vox` stores every voxel (4 bytes each), so reading and writing cost
//! memory proportional to the voxels, checked against the budget first.

use std::collections::BTreeMap;
use std::ops::Range;
use std::path::Path;

use glam::DVec3;
use rayon::slice::ParallelSliceMut;

use super::solid_set::{ColouredSolid, ReadOptions, SolidRef, Solids, SolidsRef};
use crate::atomic::write_atomic;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::morton;
use crate::octree::{Domain, LinearOctree, MAX_DEPTH, Node};
use crate::render::{from_srgb8, to_srgb8};

/// Largest model side the format can address (voxel coordinates are bytes).
pub const MAX_MODEL_SIDE: u32 = 256;
/// Palette indices a file can use (index 0 is empty).
pub const MAX_COLOURS: usize = 255;
/// Root transform attribute holding the exact domain: `"min_x min_y min_z edge depth"`.
pub const DOMAIN_KEY: &str = "_octsolid_domain";
/// The file version written (MagicaVoxel 0.99's).
const VERSION: u32 = 200;
/// Peak bytes a placed voxel takes while reading: position and index, its sort
/// record, the key.
const BYTES_PER_VOXEL: u64 = 48;
/// Colour written for a solid without one (sRGB 204, 204, 204).
const DEFAULT_GREY: f64 = 0.6;

/// A chunk found by the structure walk: id, offset of its 12-byte header, content bytes.
struct Chunk {
    id: [u8; 4],
    at: usize,
    content: Range<usize>,
}

impl Chunk {
    fn name(&self) -> String {
        crate::error::printable(&String::from_utf8_lossy(&self.id)).into_owned()
    }
}

/// A scene node as the walk found it: its id and chunk offset (the kind and links come
/// from `dot_vox`, whose nodes are in the same file order).
struct NodeInfo {
    id: u32,
    at: usize,
}

/// Reads a content field by field, naming the chunk and the byte in errors.
struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    end: usize,
    chunk: &'a Chunk,
    path: &'a Path,
}

impl<'a> Cursor<'a> {
    fn new(bytes: &'a [u8], chunk: &'a Chunk, path: &'a Path) -> Self {
        Cursor { bytes, pos: chunk.content.start, end: chunk.content.end, chunk, path }
    }

    fn err(&self, reason: impl std::fmt::Display) -> Error {
        chunk_error(self.path, self.chunk, self.pos, reason)
    }

    fn u32(&mut self, what: &str) -> Result<u32> {
        if self.end - self.pos < 4 {
            return Err(self.err(format!("truncated: {what} needs 4 bytes, {} left", self.end - self.pos)));
        }
        let v = u32::from_le_bytes(self.bytes[self.pos..self.pos + 4].try_into().expect("4 bytes"));
        self.pos += 4;
        Ok(v)
    }

    fn string(&mut self, what: &str) -> Result<String> {
        let n = self.u32(what)? as usize;
        if n > self.end - self.pos {
            return Err(self.err(format!("{what} of {n} bytes overruns the chunk ({} left)", self.end - self.pos)));
        }
        let s = std::str::from_utf8(&self.bytes[self.pos..self.pos + n])
            .map_err(|_| self.err(format!("{what} is not UTF-8")))?
            .to_owned();
        self.pos += n;
        Ok(s)
    }

    fn dict(&mut self, what: &str) -> Result<Vec<(String, String)>> {
        let n = self.u32(what)?;
        // Every pair takes at least 8 bytes: refuse a count the chunk cannot hold.
        if u64::from(n) * 8 > (self.end - self.pos) as u64 {
            return Err(self.err(format!("{what} claims {n} entries, more than the chunk holds")));
        }
        (0..n).map(|_| Ok((self.string("dictionary key")?, self.string("dictionary value")?))).collect()
    }
}

fn fail(path: &Path, offset: usize, reason: impl Into<String>) -> Error {
    Error::Format { path: path.to_path_buf(), offset: offset as u64, reason: reason.into() }
}

fn chunk_error(path: &Path, chunk: &Chunk, offset: usize, reason: impl std::fmt::Display) -> Error {
    fail(path, offset, format!("{} chunk at byte {}: {reason}", chunk.name(), chunk.at))
}

/// Reads the `.vox` file at `path`.
pub fn read(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Solids> {
    let path = path.as_ref();
    let bytes = crate::input_file::read(path)?;
    decode(&bytes, path, options)
}

/// Parses a whole `.vox` file; `path` names it in errors. See the module doc.
pub fn decode(bytes: &[u8], path: &Path, options: &ReadOptions) -> Result<Solids> {
    if !(options.voxel_size.is_finite() && options.voxel_size > 0.0) {
        return Err(Error::invalid("voxel size", format!("{} must be finite and positive", options.voxel_size)));
    }
    // Step 1: structure, then every chunk the solids depend on.
    let chunks = walk(bytes, path)?;
    let checked = check_chunks(bytes, &chunks, path, options.budget)?;
    // Step 2: contents through dot_vox (it parses exactly what the walk checked).
    let data = dot_vox::load_bytes(bytes).map_err(|e| fail(path, 0, format!("dot_vox: {e}")))?;
    if data.models.len() != checked.models.len() || data.scenes.len() != checked.nodes.len() {
        return Err(fail(path, 8, "dot_vox read a different number of models or scene nodes than the file holds"));
    }
    // Step 3: place every shape's model in the world.
    let instances = scene_instances(&data, &checked, path)?;
    let total: u64 = instances.iter().map(|i| data.models[i.model].voxels.len() as u64).sum();
    budget_check(options.budget, path, total)?;
    let mut placed: Vec<([i64; 3], u8)> = Vec::with_capacity(total as usize);
    for inst in &instances {
        let model = &data.models[inst.model];
        let size = [model.size.x, model.size.y, model.size.z];
        for v in &model.voxels {
            // dot_vox's index is the file's minus one; the walk refused file index 0.
            placed.push((inst.place([v.x, v.y, v.z], size), v.i + 1));
        }
    }
    // Step 4: the domain, stored or fitted.
    let stored = if options.stored_domain { checked.stored_domain } else { None };
    let (domain, origin) = fit_domain(&placed, stored, options.voxel_size, path)?;
    // Step 5: one solid a palette index; the voxel placed last wins.
    let mut records: Vec<(u64, u32, u8)> = placed
        .iter()
        .enumerate()
        .map(|(seq, (w, index))| {
            let c = [0, 1, 2].map(|a| (w[a] - origin[a]) as u32);
            (morton::encode(c[0], c[1], c[2]), seq as u32, *index)
        })
        .collect();
    drop(placed);
    // A total order (every sequence number is distinct): the same on any thread count.
    records.par_sort_unstable();
    let mut codes: Vec<Vec<u64>> = vec![Vec::new(); 256];
    for (i, r) in records.iter().enumerate() {
        if records.get(i + 1).is_none_or(|next| next.0 != r.0) {
            codes[usize::from(r.2)].push(r.0);
        }
    }
    drop(records);
    let mut solids = Vec::new();
    for (index, list) in codes.into_iter().enumerate().filter(|(_, l)| !l.is_empty()) {
        let tree = LinearOctree::from_sorted_runs(domain, list.into_iter().map(|c| (c, c + 1)));
        tree.validate()?;
        let color = data.palette.get(index - 1).map(|c| DVec3::new(from_srgb8(c.r), from_srgb8(c.g), from_srgb8(c.b)));
        let material = data
            .materials
            .iter()
            .find(|m| m.id as usize == index)
            .map(|m| m.properties.iter().map(|(k, v)| (k.clone(), v.clone())).collect())
            .unwrap_or_default();
        solids.push(ColouredSolid {
            name: format!("colour {index}"),
            color,
            palette_index: Some(index as u8),
            material,
            tree,
        });
    }
    Ok(Solids { domain, solids })
}

fn budget_check(budget: MemoryBudget, path: &Path, voxels: u64) -> Result<()> {
    budget.check(format!("reading {} ({voxels} placed voxels)", path.display()), voxels.saturating_mul(BYTES_PER_VOXEL))
}

/// The file's chunks below `MAIN`, checked to nest and fit.
fn walk(bytes: &[u8], path: &Path) -> Result<Vec<Chunk>> {
    if bytes.len() < 20 {
        return Err(fail(
            path,
            bytes.len(),
            format!("file of {} bytes is shorter than a header and MAIN", bytes.len()),
        ));
    }
    if &bytes[..4] != b"VOX " {
        return Err(fail(path, 0, "not a MagicaVoxel file (bad magic; expected \"VOX \")"));
    }
    let u32_at = |o: usize| u64::from(u32::from_le_bytes(bytes[o..o + 4].try_into().expect("4 bytes")));
    if &bytes[8..12] != b"MAIN" {
        return Err(fail(path, 8, "the first chunk is not MAIN"));
    }
    let (n, m) = (u32_at(12), u32_at(16));
    let end = 20 + n + m;
    if end != bytes.len() as u64 {
        return Err(fail(
            path,
            12,
            format!("MAIN chunk at byte 8 claims {} bytes but the file holds {}", end, bytes.len()),
        ));
    }
    let mut chunks = Vec::new();
    let mut pos = 20 + n;
    while pos < end {
        let at = pos as usize;
        if end - pos < 12 {
            return Err(fail(path, at, format!("truncated chunk header at byte {at} ({} bytes left)", end - pos)));
        }
        let id: [u8; 4] = bytes[at..at + 4].try_into().expect("4 bytes");
        if !id.iter().all(|b| b.is_ascii_graphic() || *b == b' ') {
            return Err(fail(path, at, format!("chunk at byte {at} has no ASCII id ({id:02x?})")));
        }
        let (n, m) = (u32_at(at + 4), u32_at(at + 8));
        if pos + 12 + n + m > end {
            return Err(fail(
                path,
                at,
                format!(
                    "{} chunk at byte {at}: {} content and {} child bytes overrun MAIN",
                    String::from_utf8_lossy(&id),
                    n,
                    m
                ),
            ));
        }
        let start = at + 12;
        chunks.push(Chunk { id, at, content: start..start + n as usize });
        pos += 12 + n + m;
    }
    Ok(chunks)
}

/// What the checks learnt: model sizes, scene node ids in file order, the stored domain.
struct Checked {
    models: Vec<[u32; 3]>,
    nodes: Vec<NodeInfo>,
    stored_domain: Option<Domain>,
}

/// Checks every chunk `dot_vox` reads, so that none is dropped silently, and that the
/// voxels fit their models and use palette indices 1..=255.
fn check_chunks(bytes: &[u8], chunks: &[Chunk], path: &Path, budget: MemoryBudget) -> Result<Checked> {
    let mut checked = Checked { models: Vec::new(), nodes: Vec::new(), stored_domain: None };
    let mut size: Option<[u32; 3]> = None;
    let mut voxels = 0u64;
    for chunk in chunks {
        let mut c = Cursor::new(bytes, chunk, path);
        match &chunk.id {
            b"SIZE" => {
                let s = [c.u32("size x")?, c.u32("size y")?, c.u32("size z")?];
                if s.iter().any(|&v| v == 0 || v > MAX_MODEL_SIDE) {
                    return Err(c.err(format!("model size {s:?} is outside 1..={MAX_MODEL_SIDE}")));
                }
                size = Some(s);
            }
            b"XYZI" => {
                let Some(s) = size.take() else {
                    return Err(c.err("voxels without a SIZE chunk before them"));
                };
                let n = c.u32("voxel count")?;
                if u64::from(n) * 4 > (c.end - c.pos) as u64 {
                    return Err(c.err(format!("{n} voxels need {} bytes, {} left", u64::from(n) * 4, c.end - c.pos)));
                }
                voxels += u64::from(n);
                budget_check(budget, path, voxels)?;
                for _ in 0..n {
                    let v = &bytes[c.pos..c.pos + 4];
                    if (0..3).any(|a| u32::from(v[a]) >= s[a]) || v[3] == 0 {
                        return Err(c.err(format!(
                            "voxel ({}, {}, {}) colour {} is outside the {s:?} model or has colour 0",
                            v[0], v[1], v[2], v[3]
                        )));
                    }
                    c.pos += 4;
                }
                if c.pos != c.end {
                    // A count short of the chunk's size would drop the voxels after it.
                    return Err(c.err(format!(
                        "{} bytes after the {n} voxels the count gives: the count and the chunk's size disagree",
                        c.end - c.pos
                    )));
                }
                checked.models.push(s);
            }
            b"RGBA" if chunk.content.len() != 1024 => {
                return Err(c.err(format!("palette of {} bytes, expected 1024", chunk.content.len())));
            }
            b"IMAP" if chunk.content.len() != 256 => {
                return Err(c.err(format!("index map of {} bytes, expected 256", chunk.content.len())));
            }
            b"MATL" => {
                c.u32("material id")?;
                c.dict("material properties")?;
            }
            b"LAYR" => {
                c.u32("layer id")?;
                c.dict("layer attributes")?;
                c.u32("reserved")?;
            }
            b"nTRN" | b"nGRP" | b"nSHP" => {
                let id = c.u32("node id")?;
                let attributes = c.dict("node attributes")?;
                check_node(&mut c, chunk, id)?;
                if id == 0 && &chunk.id == b"nTRN" {
                    checked.stored_domain = stored_domain(&attributes);
                }
                checked.nodes.push(NodeInfo { id, at: chunk.at });
            }
            _ => {}
        }
    }
    Ok(checked)
}

/// The rest of a scene node after its id and attributes.
fn check_node(c: &mut Cursor<'_>, chunk: &Chunk, id: u32) -> Result<()> {
    match &chunk.id {
        b"nTRN" => {
            c.u32("child id")?;
            c.u32("reserved id")?;
            c.u32("layer id")?;
            let frames = c.u32("frame count")?;
            if frames == 0 {
                return Err(c.err(format!("transform node {id} has no frame")));
            }
            if u64::from(frames) * 4 > (c.end - c.pos) as u64 {
                return Err(c.err(format!("{frames} frames cannot fit in the chunk")));
            }
            for f in 0..frames {
                let frame = c.dict("frame")?;
                if f == 0 {
                    frame_transform(&frame).map_err(|reason| c.err(format!("transform node {id}: {reason}")))?;
                }
            }
        }
        b"nGRP" => {
            let n = c.u32("child count")?;
            if u64::from(n) * 4 > (c.end - c.pos) as u64 {
                return Err(c.err(format!("{n} children cannot fit in the chunk")));
            }
            for _ in 0..n {
                c.u32("child id")?;
            }
        }
        _ => {
            let n = c.u32("model count")?;
            if n == 0 || u64::from(n) * 8 > (c.end - c.pos) as u64 {
                return Err(c.err(format!("shape node {id}: {n} models (at least one, each 8 bytes or more)")));
            }
            for _ in 0..n {
                c.u32("model id")?;
                c.dict("model attributes")?;
            }
        }
    }
    Ok(())
}

/// The domain a file octsolid wrote stores in its root transform, if well formed.
fn stored_domain(attributes: &[(String, String)]) -> Option<Domain> {
    let value = &attributes.iter().find(|(k, _)| k == DOMAIN_KEY)?.1;
    let parts: Vec<&str> = value.split_whitespace().collect();
    let [x, y, z, edge, depth] = parts.as_slice() else { return None };
    let f = |s: &str| s.parse::<f64>().ok();
    Domain::new(DVec3::new(f(x)?, f(y)?, f(z)?), f(edge)?, depth.parse().ok()?).ok()
}

/// A rigid placement in the voxel lattice: a signed permutation and a translation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Placement {
    /// Rows of the matrix: row `i` is `sign[i]` at column `col[i]`.
    col: [usize; 3],
    sign: [i64; 3],
    t: [i64; 3],
}

impl Placement {
    const IDENTITY: Placement = Placement { col: [0, 1, 2], sign: [1, 1, 1], t: [0, 0, 0] };

    /// `R v`.
    fn rotate(&self, v: [i64; 3]) -> [i64; 3] {
        [0, 1, 2].map(|i| self.sign[i] * v[self.col[i]])
    }

    /// `self ∘ child`: `R_p (R_c v + t_c) + t_p`.
    fn then(&self, child: &Placement) -> Placement {
        let col = [0, 1, 2].map(|i| child.col[self.col[i]]);
        let sign = [0, 1, 2].map(|i| self.sign[i] * child.sign[self.col[i]]);
        let rt = self.rotate(child.t);
        Placement { col, sign, t: [0, 1, 2].map(|i| rt[i] + self.t[i]) }
    }
}

/// A model placed in the world; `centred` is false for files without a scene graph.
struct Instance {
    model: usize,
    placement: Placement,
    centred: bool,
}

impl Instance {
    /// World voxel of model voxel `v` (module doc, step 1), exact in integers.
    fn place(&self, v: [u8; 3], size: [u32; 3]) -> [i64; 3] {
        if !self.centred {
            return self.placement.rotate(v.map(i64::from));
        }
        let d = [0, 1, 2].map(|a| 2 * i64::from(v[a]) + 1 - 2 * i64::from(size[a] / 2));
        let r = self.placement.rotate(d);
        // r is odd, so r + 2t - 1 is even and the halving exact.
        [0, 1, 2].map(|a| (r[a] + 2 * self.placement.t[a] - 1).div_euclid(2))
    }
}

/// Frame 0's rotation `_r` and translation `_t`.
fn frame_transform(frame: &[(String, String)]) -> std::result::Result<Placement, String> {
    let mut p = Placement::IDENTITY;
    for (key, value) in frame {
        match key.as_str() {
            "_r" => {
                let r: u8 = value.trim().parse().map_err(|_| format!("rotation _r = {value:?} is not a byte"))?;
                let (c0, c1) = (usize::from(r & 3), usize::from((r >> 2) & 3));
                if c0 > 2 || c1 > 2 || c0 == c1 || r >> 7 != 0 {
                    return Err(format!("rotation _r = {r} is no signed permutation"));
                }
                p.col = [c0, c1, 3 - c0 - c1];
                p.sign = [4, 5, 6].map(|bit| if r >> bit & 1 == 1 { -1 } else { 1 });
            }
            "_t" => {
                let parts: Vec<i64> = value
                    .split_whitespace()
                    .map(|s| s.parse::<i32>().map(i64::from))
                    .collect::<std::result::Result<_, _>>()
                    .map_err(|_| format!("translation _t = {value:?} is not three integers"))?;
                let [x, y, z] = parts.as_slice() else {
                    return Err(format!("translation _t = {value:?} is not three integers"));
                };
                p.t = [*x, *y, *z];
            }
            _ => {}
        }
    }
    Ok(p)
}

/// The shapes reached from the root with their accumulated placements.
fn scene_instances(data: &dot_vox::DotVoxData, checked: &Checked, path: &Path) -> Result<Vec<Instance>> {
    if checked.nodes.is_empty() {
        let placement = Placement::IDENTITY;
        return Ok((0..data.models.len()).map(|model| Instance { model, placement, centred: false }).collect());
    }
    let mut by_id = BTreeMap::new();
    for (i, node) in checked.nodes.iter().enumerate() {
        if by_id.insert(node.id, i).is_some() {
            return Err(fail(path, node.at, format!("scene node id {} is used twice", node.id)));
        }
    }
    let hidden = |attributes: &dot_vox::Dict| attributes.get("_hidden").is_some_and(|v| v == "1");
    let layer_hidden = |layer: u32| data.layers.get(layer as usize).is_some_and(|l| l.hidden());
    let Some(&root) = by_id.get(&0) else {
        return Err(fail(path, checked.nodes[0].at, "the scene graph has no root node 0"));
    };
    let mut visited = vec![false; checked.nodes.len()];
    let mut out = Vec::new();
    let mut stack = vec![(root, Placement::IDENTITY)];
    while let Some((index, placement)) = stack.pop() {
        let at = checked.nodes[index].at;
        if std::mem::replace(&mut visited[index], true) {
            return Err(fail(
                path,
                at,
                format!("scene node {} is reached twice (a cycle or a shared node)", checked.nodes[index].id),
            ));
        }
        let child = |id: u32| {
            by_id.get(&id).copied().ok_or_else(|| {
                fail(path, at, format!("scene node {} links to missing node {id}", checked.nodes[index].id))
            })
        };
        match &data.scenes[index] {
            dot_vox::SceneNode::Transform { attributes, frames, child: c, layer_id } => {
                if hidden(attributes) || layer_hidden(*layer_id) {
                    continue;
                }
                let frame: Vec<(String, String)> =
                    frames[0].attributes.iter().map(|(k, v)| (k.clone(), v.clone())).collect();
                let local = frame_transform(&frame).map_err(|r| fail(path, at, r))?;
                stack.push((child(*c)?, placement.then(&local)));
            }
            dot_vox::SceneNode::Group { attributes, children } => {
                if hidden(attributes) {
                    continue;
                }
                // Reversed so that children are placed in file order.
                for &c in children.iter().rev() {
                    stack.push((child(c)?, placement));
                }
            }
            dot_vox::SceneNode::Shape { models, .. } => {
                let model = models[0].model_id as usize;
                if model >= data.models.len() {
                    return Err(fail(
                        path,
                        at,
                        format!("shape node uses model {model}; the file has {}", data.models.len()),
                    ));
                }
                out.push(Instance { model, placement, centred: true });
            }
        }
    }
    Ok(out)
}

/// The domain and the world voxel at its lattice origin (module doc, step 2).
fn fit_domain(
    placed: &[([i64; 3], u8)],
    stored: Option<Domain>,
    voxel_size: f64,
    path: &Path,
) -> Result<(Domain, [i64; 3])> {
    let Some(first) = placed.first() else {
        return Ok((stored.unwrap_or(Domain::new(DVec3::ZERO, 2.0 * voxel_size, 1)?), [0; 3]));
    };
    let (mut lo, mut hi) = (first.0, first.0);
    for (w, _) in placed {
        for a in 0..3 {
            lo[a] = lo[a].min(w[a]);
            hi[a] = hi[a].max(w[a]);
        }
    }
    if let Some(d) = stored {
        let n = i64::from(d.resolution());
        if lo.iter().all(|&c| c >= 0) && hi.iter().all(|&c| c < n) {
            return Ok((d, [0; 3]));
        }
    }
    let extent = (0..3).map(|a| hi[a] - lo[a] + 1).max().unwrap_or(1) as u64;
    let depth = extent.next_power_of_two().trailing_zeros().max(1);
    if depth > u32::from(MAX_DEPTH) {
        return Err(fail(path, 8, format!("placed voxels span {extent} a side, more than 2^{MAX_DEPTH}")));
    }
    let min = DVec3::new(lo[0] as f64, lo[1] as f64, lo[2] as f64) * voxel_size;
    let domain = Domain::new(min, voxel_size * f64::from(1u32 << depth), depth as u8)?;
    Ok((domain, lo))
}

/// Writes `solids` to `path` as `.vox`, atomically; returns the bytes written.
pub fn write(path: impl AsRef<Path>, solids: &SolidsRef<'_>, budget: MemoryBudget) -> Result<u64> {
    let path = path.as_ref();
    let bytes = encode_borrowed(solids, budget)?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// The whole `.vox` file for `solids` (module doc, "Writing").
pub fn encode(solids: &Solids, budget: MemoryBudget) -> Result<Vec<u8>> {
    encode_borrowed(&solids.borrowed(), budget)
}

/// [`encode`] of borrowed solids.
pub(crate) fn encode_borrowed(solids: &SolidsRef<'_>, budget: MemoryBudget) -> Result<Vec<u8>> {
    // Step 1: a palette index a solid.
    let indices = palette_indices(&solids.solids)?;
    let models = models_of(solids);
    let pieces = pieces_within_budget(solids, &models, budget)?;
    // Step 3: chunks. Models first (those some node meets, in the file's order), then
    // the scene graph, layer, palette, materials.
    let mut main = Vec::new();
    let placements = write_models(&mut main, solids, &models, pieces, &indices);
    write_scene_graph(&mut main, &solids.domain, &placements);
    write_layer(&mut main);
    write_palette(&mut main, solids, &indices);
    write_materials(&mut main, solids, &indices);
    Ok(vox_file(main))
}

/// Step 2: the voxels' bounding box cut into models of at most 256^3 from its low
/// corner.
fn models_of(solids: &SolidsRef<'_>) -> Models {
    let bounds = solids
        .solids
        .iter()
        .filter_map(|s| s.tree.voxel_bounds())
        .reduce(|a, b| (std::array::from_fn(|i| a.0[i].min(b.0[i])), std::array::from_fn(|i| a.1[i].max(b.1[i]))));
    let (lo, hi) = bounds.unwrap_or(([0; 3], [0; 3]));
    Models { lo, hi, count: [0, 1, 2].map(|a| (hi[a] - lo[a]).div_ceil(MAX_MODEL_SIDE)) }
}

/// The number of pieces (nodes' parts in models), once the file is known to fit the
/// budget. Memory: 4 bytes a voxel in the file, three times (the chunks' buffer as it
/// grows, then the file beside it); the largest model's voxels listed, sorted and
/// copied into its chunk (16 bytes each at most); the byte grid of one model; each
/// node's pieces.
fn pieces_within_budget(solids: &SolidsRef<'_>, models: &Models, budget: MemoryBudget) -> Result<u64> {
    let (lo, hi) = (models.lo, models.hi);
    let voxels: u64 = solids.solids.iter().map(|s| s.tree.voxel_count()).sum();
    let grid: u64 = (0..3).map(|a| u64::from((hi[a] - lo[a]).min(MAX_MODEL_SIDE))).product();
    let pieces: u64 = solids.solids.iter().flat_map(|s| s.tree.nodes()).map(|n| models.met_by(n).count() as u64).sum();
    let estimate = voxels
        .saturating_mul(12)
        .saturating_add(voxels.min(grid).saturating_mul(16))
        .saturating_add(grid)
        .saturating_add(pieces.saturating_mul(PIECE_BYTES));
    budget.check(format!("a .vox file of {voxels} voxels"), estimate)?;
    Ok(pieces)
}

/// A `SIZE` and an `XYZI` chunk for each model some node meets (of `pieces` in all), in
/// the file's order; a model with no voxel is left out. Returns each model's
/// translation.
fn write_models(
    main: &mut Vec<u8>,
    solids: &SolidsRef<'_>,
    models: &Models,
    pieces: u64,
    indices: &[u8],
) -> Vec<[i64; 3]> {
    let mut placements = Vec::new();
    let mut grid = Vec::new();
    let pieces = models.pieces(solids, pieces as usize);
    for pieces in pieces.chunk_by(|a, b| a.model == b.model) {
        let (start, end) = models.span(pieces[0].model);
        let kept = model_voxels(pieces, indices, start, end, &mut grid);
        let size = [0, 1, 2].map(|a| kept.iter().map(|v| u32::from(v[a]) + 1).max().unwrap_or(1));
        chunk(main, b"SIZE", &[size[0], size[1], size[2]].map(u32::to_le_bytes).concat());
        let mut xyzi = Vec::with_capacity(4 + 4 * kept.len());
        xyzi.extend((kept.len() as u32).to_le_bytes());
        xyzi.extend(kept.iter().flatten());
        chunk(main, b"XYZI", &xyzi);
        // World voxel = lattice voxel: v - floor(s/2) + t with v local, so t = corner + floor(s/2).
        let t = [0, 1, 2].map(|a| i64::from(start[a]) + i64::from(size[a] / 2));
        placements.push(t);
    }
    placements
}

/// The scene graph: the root transform (carrying the domain `d`), a group, and a
/// transform (to its `placements` entry) and shape a model.
fn write_scene_graph(main: &mut Vec<u8>, d: &Domain, placements: &[[i64; 3]]) {
    let domain_value = format!("{} {} {} {} {}", d.min().x, d.min().y, d.min().z, d.edge(), d.depth());
    let mut root = node_header(0, &[(DOMAIN_KEY, &domain_value)]);
    root.extend([1u32, u32::MAX, u32::MAX, 1, 0].map(u32::to_le_bytes).concat());
    chunk(main, b"nTRN", &root);
    let mut group = node_header(1, &[]);
    group.extend((placements.len() as u32).to_le_bytes());
    for k in 0..placements.len() as u32 {
        group.extend((2 + 2 * k).to_le_bytes());
    }
    chunk(main, b"nGRP", &group);
    for (k, t) in placements.iter().enumerate() {
        let id = 2 + 2 * k as u32;
        let mut trn = node_header(id, &[]);
        trn.extend([id + 1, u32::MAX, 0, 1].map(u32::to_le_bytes).concat());
        write_dict(&mut trn, &[("_t", &format!("{} {} {}", t[0], t[1], t[2]))]);
        chunk(main, b"nTRN", &trn);
        let mut shp = node_header(id + 1, &[]);
        shp.extend([1, k as u32].map(u32::to_le_bytes).concat());
        write_dict(&mut shp, &[]);
        chunk(main, b"nSHP", &shp);
    }
}

/// The one layer.
fn write_layer(main: &mut Vec<u8>) {
    let mut layer = node_header(0, &[]);
    layer.extend(u32::MAX.to_le_bytes());
    chunk(main, b"LAYR", &layer);
}

/// The palette: MagicaVoxel's default, each solid's colour (grey without one) at its
/// index.
fn write_palette(main: &mut Vec<u8>, solids: &SolidsRef<'_>, indices: &[u8]) {
    let mut palette: Vec<[u8; 4]> = dot_vox::DEFAULT_PALETTE.iter().map(<[u8; 4]>::from).collect();
    palette.resize(256, [0, 0, 0, 255]);
    for (solid, &index) in solids.solids.iter().zip(indices) {
        let c = solid.color.unwrap_or(DVec3::splat(DEFAULT_GREY));
        palette[usize::from(index) - 1] = [to_srgb8(c.x), to_srgb8(c.y), to_srgb8(c.z), 255];
    }
    chunk(main, b"RGBA", &palette.concat());
}

/// A `MATL` chunk for each solid with material properties, at its palette index.
fn write_materials(main: &mut Vec<u8>, solids: &SolidsRef<'_>, indices: &[u8]) {
    for (solid, &index) in solids.solids.iter().zip(indices) {
        if !solid.material.is_empty() {
            let entries: Vec<(&str, &str)> = solid.material.iter().map(|(k, v)| (k.as_str(), v.as_str())).collect();
            let mut matl = u32::from(index).to_le_bytes().to_vec();
            write_dict(&mut matl, &entries);
            chunk(main, b"MATL", &matl);
        }
    }
}

/// The file: its header, then the `MAIN` chunk holding `main` as its children.
fn vox_file(main: Vec<u8>) -> Vec<u8> {
    let mut out = Vec::with_capacity(20 + main.len());
    out.extend_from_slice(b"VOX ");
    out.extend(VERSION.to_le_bytes());
    out.extend_from_slice(b"MAIN");
    out.extend([0, main.len() as u32].map(u32::to_le_bytes).concat());
    out.extend(main);
    out
}

/// Bytes a piece (a node's part in one model) takes while the models are listed.
const PIECE_BYTES: u64 = 32;
/// A model is listed from its voxels, sorted, instead of from a byte grid of its box when
/// its pieces hold fewer voxels than its box over this.
const SPARSE_FRACTION: u64 = 16;

/// The models the voxels' bounding box `lo..hi` is cut into: `count` a side, each
/// [`MAX_MODEL_SIDE`] a side from `lo` (the last ones cut at `hi`). Model `(x, y, z)`
/// is number `(x count_y + y) count_z + z`, its place in the file.
struct Models {
    lo: [u32; 3],
    hi: [u32; 3],
    count: [u32; 3],
}

/// A node's part in one model: the model's number, the solid's place among the solids.
struct Piece {
    model: u64,
    solid: u8,
    node: Node,
}

impl Models {
    /// The numbers of the models `node` meets.
    fn met_by(&self, node: Node) -> impl Iterator<Item = u64> + use<> {
        let first = [0, 1, 2].map(|a| (node.min[a] - self.lo[a]) / MAX_MODEL_SIDE);
        let last = [0, 1, 2].map(|a| (node.min[a] + node.size - 1 - self.lo[a]) / MAX_MODEL_SIDE);
        let [_, cy, cz] = self.count.map(u64::from);
        (first[0]..=last[0]).flat_map(move |x| {
            (first[1]..=last[1]).flat_map(move |y| {
                (first[2]..=last[2]).map(move |z| (u64::from(x) * cy + u64::from(y)) * cz + u64::from(z))
            })
        })
    }

    /// The lattice voxels `start..end` of model `model`.
    fn span(&self, model: u64) -> ([u32; 3], [u32; 3]) {
        let [_, cy, cz] = self.count.map(u64::from);
        let m = [model / (cy * cz), model / cz % cy, model % cz];
        let start = [0, 1, 2].map(|a| self.lo[a] + m[a] as u32 * MAX_MODEL_SIDE);
        (start, [0, 1, 2].map(|a| (start[a] + MAX_MODEL_SIDE).min(self.hi[a])))
    }

    /// Every node's pieces (`total` of them), by model, then by solid.
    fn pieces(&self, solids: &SolidsRef<'_>, total: usize) -> Vec<Piece> {
        let mut pieces = Vec::with_capacity(total);
        for (solid, s) in solids.solids.iter().enumerate() {
            for node in s.tree.nodes() {
                pieces.extend(self.met_by(node).map(|model| Piece { model, solid: solid as u8, node }));
            }
        }
        // Nodes of one solid are disjoint, so their order within a model changes nothing.
        pieces.par_sort_unstable_by_key(|p| (p.model, p.solid));
        pieces
    }
}

/// The voxels of the model covering lattice voxels `start..end` as XYZI lists them:
/// `[x, y, z, palette index]` in the model, in x, then y, then z order; `pieces` are
/// the nodes meeting it, by solid. Where solids overlap the later one wins. A model
/// whose pieces hold few voxels for its box lists them and sorts them; any other is
/// painted piece by piece into `grid` (a byte a voxel of the model, reused from model
/// to model), which is then read out in that order.
fn model_voxels(pieces: &[Piece], indices: &[u8], start: [u32; 3], end: [u32; 3], grid: &mut Vec<u8>) -> Vec<[u8; 4]> {
    let ext = [0, 1, 2].map(|a| (end[a] - start[a]) as usize);
    let clip = |p: &Piece| {
        let from = [0, 1, 2].map(|a| p.node.min[a].max(start[a]) - start[a]);
        let to = [0, 1, 2].map(|a| (p.node.min[a] + p.node.size).min(end[a]) - start[a]);
        (from, to)
    };
    let voxels: u64 = pieces
        .iter()
        .map(|p| {
            let (from, to) = clip(p);
            (0..3).map(|a| u64::from(to[a] - from[a])).product::<u64>()
        })
        .sum();
    let volume = ext.iter().map(|&e| e as u64).product::<u64>();
    if voxels.saturating_mul(SPARSE_FRACTION) < volume {
        // x, y, z and the solid's place in one u32 each, so that sorting orders them
        // as XYZI does and the last of a voxel's entries is the latest solid's.
        let mut packed = Vec::with_capacity(voxels as usize);
        for p in pieces {
            let (from, to) = clip(p);
            for x in from[0]..to[0] {
                for y in from[1]..to[1] {
                    packed.extend((from[2]..to[2]).map(|z| x << 24 | y << 16 | z << 8 | u32::from(p.solid)));
                }
            }
        }
        packed.sort_unstable();
        return packed
            .chunk_by(|a, b| a >> 8 == b >> 8)
            .map(|same| {
                let v = same[same.len() - 1];
                [(v >> 24) as u8, (v >> 16) as u8, (v >> 8) as u8, indices[(v & 0xff) as usize]]
            })
            .collect();
    }
    grid.clear();
    grid.resize(ext[0] * ext[1] * ext[2], 0);
    for p in pieces {
        let (from, to) = clip(p);
        let index = indices[usize::from(p.solid)];
        for x in from[0]..to[0] {
            for y in from[1]..to[1] {
                let row = (x as usize * ext[1] + y as usize) * ext[2];
                grid[row + from[2] as usize..row + to[2] as usize].fill(index);
            }
        }
    }
    let mut kept = Vec::new();
    for (i, &index) in grid.iter().enumerate() {
        if index != 0 {
            let (x, y, z) = (i / (ext[1] * ext[2]), i / ext[2] % ext[1], i % ext[2]);
            kept.push([x as u8, y as u8, z as u8, index]);
        }
    }
    kept
}

/// A palette index for each solid: its own when free, else the lowest free one.
fn palette_indices(solids: &[SolidRef<'_>]) -> Result<Vec<u8>> {
    if solids.len() > MAX_COLOURS {
        return Err(Error::invalid(
            "solids",
            format!(
                "a .vox palette holds {MAX_COLOURS} colours and {} solids were given (one colour a solid)",
                solids.len()
            ),
        ));
    }
    let mut taken = [false; 256];
    taken[0] = true;
    let mut out: Vec<Option<u8>> = solids
        .iter()
        .map(|s| s.palette_index.filter(|&i| i != 0 && !std::mem::replace(&mut taken[usize::from(i)], true)))
        .collect();
    for slot in out.iter_mut().filter(|s| s.is_none()) {
        let free = taken.iter().position(|t| !t).expect("at most 255 solids");
        taken[free] = true;
        *slot = Some(free as u8);
    }
    Ok(out.into_iter().map(|s| s.expect("assigned")).collect())
}

/// Appends a childless chunk.
fn chunk(out: &mut Vec<u8>, id: &[u8; 4], content: &[u8]) {
    out.extend_from_slice(id);
    out.extend((content.len() as u32).to_le_bytes());
    out.extend(0u32.to_le_bytes());
    out.extend_from_slice(content);
}

/// A node's id and attributes.
fn node_header(id: u32, attributes: &[(&str, &str)]) -> Vec<u8> {
    let mut out = id.to_le_bytes().to_vec();
    write_dict(&mut out, attributes);
    out
}

fn write_dict(out: &mut Vec<u8>, entries: &[(&str, &str)]) {
    out.extend((entries.len() as u32).to_le_bytes());
    for s in entries.iter().flat_map(|(k, v)| [k, v]) {
        out.extend((s.len() as u32).to_le_bytes());
        out.extend_from_slice(s.as_bytes());
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn placements_compose_like_matrices() {
        // Every valid _r against a sample of others: composition is the matrix product.
        let rows = |p: &Placement| -> [[i64; 3]; 3] {
            std::array::from_fn(|i| std::array::from_fn(|j| if p.col[i] == j { p.sign[i] } else { 0 }))
        };
        let all: Vec<Placement> = (0u8..128)
            .filter_map(|r| frame_transform(&[("_r".into(), r.to_string())]).ok())
            .map(|p| Placement { t: [1, -2, 3], ..p })
            .collect();
        assert_eq!(all.len(), 48, "24 rotations and 24 mirror images");
        for a in &all {
            for b in all.iter().step_by(5) {
                let ab = a.then(b);
                let (ma, mb, mab) = (rows(a), rows(b), rows(&ab));
                for i in 0..3 {
                    for j in 0..3 {
                        assert_eq!(mab[i][j], (0..3).map(|k| ma[i][k] * mb[k][j]).sum::<i64>());
                    }
                }
                let v = [5, -7, 11];
                let direct = a.rotate(b.rotate(v));
                let bt = a.rotate(b.t);
                let expect: [i64; 3] = std::array::from_fn(|i| direct[i] + bt[i] + a.t[i]);
                let got = ab.rotate(v);
                assert_eq!(std::array::from_fn::<i64, 3, _>(|i| got[i] + ab.t[i]), expect);
            }
        }
    }
}
