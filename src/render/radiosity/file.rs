//! The `.rad` file: a radiosity solution, versioned, checksummed and tied to its
//! scene (docs/FORMAT.md).
//!
//! Little-endian, in order: the magic `OCTSRAD\0` (8 bytes), the version `u32` (1, or
//! 2 for a subdivided solution), the scene fingerprint `u64` ([`super::fingerprint`]),
//! the patch size `f64` and the elements a patch side `u32` it was solved with, the
//! patch and element counts (`u64` each; elements split by subdivision included), the
//! shots `u64`, the unshot fraction `f64`, the ambient term (3 `f64`); version 2 only:
//! the count of elements split `u64` and each split element's index `u32`, in the
//! order they were split; then each element's radiosity (3 `f64`, radiance units,
//! element order), and last the CRC-32 of every byte before it. A solution without
//! subdivision is written as version 1, the same bytes as before version 2 existed.
//!
//! Reading: the header is checked field by field (magic, version, fingerprint against
//! the scene's, a shot count no run reaches, an unshot fraction that is not finite and
//! non-negative), the patches are rebuilt from the scene with the file's settings (the
//! memory budget applies there, and to the elements the splits add), their counts must
//! equal the file's (the splits' count included), and only then is
//! the file's length checked against the size they give and the body read: no
//! allocation is ever sized by the header. Values are stored as their bits, so a
//! solution reloads bit for bit.

use std::io::Write;
use std::path::Path;

use glam::DVec3;

use super::patches::{self, Patches};
use super::{Radiosity, RadiosityStats, fingerprint};
use crate::atomic::write_atomic;
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::fields::Fields;
use crate::render::scene::Scene;

/// The magic bytes.
pub(crate) const MAGIC: &[u8; 8] = b"OCTSRAD\0";
/// The newest format version, which this build writes for a subdivided solution (and
/// version 1 otherwise); it reads both.
pub(crate) const VERSION: u32 = 2;
/// The most shots a file may claim: about a year of shooting at ten million shots a
/// second, far beyond any solver run; a larger count is damage, not a solution.
const MAX_SHOTS: u64 = 1 << 48;
/// Bytes before the element values.
const HEADER: usize = 8 + 4 + 8 + 8 + 4 + 8 + 8 + 8 + 8 + 24;

/// Writes `r` to `path` (see the module doc).
pub(super) fn write(r: &Radiosity, path: &Path) -> Result<u64> {
    let splits = &r.mesh.splits;
    let version: u32 = if splits.is_empty() { 1 } else { 2 };
    let mut bytes = Vec::with_capacity(HEADER + 8 + splits.len() * 4 + r.radiosity.len() * 24 + 4);
    bytes.extend_from_slice(MAGIC);
    bytes.extend_from_slice(&version.to_le_bytes());
    bytes.extend_from_slice(&r.fingerprint.to_le_bytes());
    bytes.extend_from_slice(&r.patch_size.to_le_bytes());
    bytes.extend_from_slice(&r.elements.to_le_bytes());
    bytes.extend_from_slice(&(r.mesh.patches.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&(r.mesh.elements.len() as u64).to_le_bytes());
    bytes.extend_from_slice(&r.stats.shots.to_le_bytes());
    bytes.extend_from_slice(&r.stats.unshot_fraction.to_le_bytes());
    for c in r.ambient.to_array() {
        bytes.extend_from_slice(&c.to_le_bytes());
    }
    if version == 2 {
        bytes.extend_from_slice(&(splits.len() as u64).to_le_bytes());
        for e in splits {
            bytes.extend_from_slice(&e.to_le_bytes());
        }
    }
    for v in &r.radiosity {
        for c in v.to_array() {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    let crc = crc32fast::hash(&bytes);
    bytes.extend_from_slice(&crc.to_le_bytes());
    write_atomic(path, |out: &mut dyn Write| out.write_all(&bytes))
}

/// Reads the header (at most `HEADER` bytes, and the split count of version 2) of the
/// file.
fn read_head(path: &Path) -> Result<(Vec<u8>, u64)> {
    use std::io::Read;
    let io = |source| Error::Io { path: path.to_path_buf(), source };
    let (file, len) = crate::input_file::open_regular(path)?;
    let mut head = Vec::with_capacity(HEADER + 8);
    file.take(HEADER as u64 + 8).read_to_end(&mut head).map_err(io)?;
    Ok((head, len))
}

/// Reads `path` for `scene` (see the module doc).
pub(super) fn read(path: &Path, scene: &Scene, budget: MemoryBudget) -> Result<Radiosity> {
    let (head, len) = read_head(path)?;
    let mut r = Fields::new(path, &head, 0);
    let header = read_header(&mut r, scene)?;
    let mut mesh = rebuild_patches(&r, scene, &header, budget)?;
    let (bytes, splits_at) = read_checked_file(path, &r, &header, len)?;
    let mut r = Fields::new(path, &bytes, splits_at);
    replay_splits(&mut r, scene, &mut mesh, header.split_count)?;
    let radiosity = read_radiosities(&mut r, &mesh)?;
    let stats = RadiosityStats {
        patches: mesh.patches.len(),
        elements: mesh.leaf_count(),
        splits: mesh.splits.len(),
        shots: header.shots,
        unshot_fraction: header.unshot_fraction,
        rays: 0,
        emitted: 0.0,
        absorbed: 0.0,
        escaped: 0.0,
        history: Vec::new(),
        iterations: 0,
        residual: 0.0,
    };
    Ok(Radiosity {
        mesh,
        radiosity,
        ambient: header.ambient,
        fingerprint: header.fingerprint,
        patch_size: header.patch_size,
        elements: header.elements,
        stats,
        timeline: Vec::new(),
        show_elements: false,
    })
}

/// The header's fields, each checked on its own as it is read.
struct Header {
    /// The format version, 1 or 2.
    version: u32,
    /// The scene fingerprint, equal to the scene's.
    fingerprint: u64,
    /// The patch size the solution was solved with.
    patch_size: f64,
    /// The elements a patch side it was solved with.
    elements: u32,
    /// The patch count.
    patches: u64,
    /// The element count, elements split by subdivision included.
    element_count: u64,
    /// The shots.
    shots: u64,
    /// The unshot fraction.
    unshot_fraction: f64,
    /// The ambient term.
    ambient: DVec3,
    /// The count of elements split (0 in version 1).
    split_count: u64,
}

/// The header, field by field (module doc): the file's identity first, then the
/// settings, counts and solver state.
fn read_header(r: &mut Fields<'_>, scene: &Scene) -> Result<Header> {
    let (version, fingerprint) = read_identity(r, scene)?;
    let patch_size = r.f64("patch size")?;
    let elements = r.u32("elements a side")?;
    if !(patch_size.is_finite() && patch_size > 0.0 && (1..=64).contains(&elements)) {
        return Err(r.err(20, format!("invalid settings: patch size {patch_size}, {elements} elements a side")));
    }
    let patches = r.u64("patch count")?;
    let element_count = r.u64("element count")?;
    let shots = r.u64("shot count")?;
    if shots > MAX_SHOTS {
        return Err(r.err(r.pos - 8, format!("{shots} shots, more than any solver run makes ({MAX_SHOTS})")));
    }
    let unshot_fraction = r.f64("unshot fraction")?;
    if !(unshot_fraction.is_finite() && unshot_fraction >= 0.0) {
        return Err(r.err(r.pos - 8, format!("unshot fraction {unshot_fraction} is not finite and non-negative")));
    }
    let ambient = r.vec3("ambient term")?;
    if !(ambient.is_finite() && ambient.min_element() >= 0.0) {
        return Err(r.err(r.pos - 24, format!("ambient term {ambient} is not finite and non-negative")));
    }
    let split_count = if version == 2 { r.u64("split count")? } else { 0 };
    Ok(Header {
        version,
        fingerprint,
        patch_size,
        elements,
        patches,
        element_count,
        shots,
        unshot_fraction,
        ambient,
        split_count,
    })
}

/// The magic, a version this build reads and the scene fingerprint, which must be
/// `scene`'s; returns the version and the fingerprint.
fn read_identity(r: &mut Fields<'_>, scene: &Scene) -> Result<(u32, u64)> {
    if r.array::<8>("magic").ok().as_ref() != Some(MAGIC) {
        return Err(r.err(0, "not a radiosity solution (.rad): the magic bytes differ"));
    }
    let version = r.u32("version")?;
    if !(1..=VERSION).contains(&version) {
        return Err(r.err(8, format!("format version {version}, this build reads versions 1 to {VERSION}")));
    }
    let stored = r.u64("scene fingerprint")?;
    let own = fingerprint(scene);
    if stored != own {
        return Err(r.err(
            12,
            format!(
                "the solution belongs to another scene (fingerprint {stored:016x}, this scene's is {own:016x}: \
                 its solids, materials or lights differ); solve this scene with `octsolid radiosity`"
            ),
        ));
    }
    Ok((version, own))
}

/// The patches rebuilt from `scene` with the file's settings; their counts (the splits'
/// elements added) must equal the file's, and the file's elements fit `budget`.
fn rebuild_patches(r: &Fields<'_>, scene: &Scene, header: &Header, budget: MemoryBudget) -> Result<Patches> {
    let Header { patches, element_count, split_count, .. } = *header;
    let mesh = Patches::build(scene, header.patch_size, header.elements, budget, &crate::NoProgress)?;
    let counts =
        (mesh.patches.len() as u64, (mesh.elements.len() as u64).saturating_add(split_count.saturating_mul(4)));
    if (patches, element_count) != counts {
        return Err(r.err(
            32,
            format!(
                "{patches} patches of {element_count} elements ({split_count} split), but the scene has {} of {} \
                 with {split_count} split",
                counts.0, counts.1
            ),
        ));
    }
    if element_count > mesh.elements_within(budget) as u64 {
        return Err(Error::OverBudget {
            job: format!("a radiosity solution of {element_count} elements"),
            estimate: element_count.saturating_mul(patches::BYTES_PER_ELEMENT),
            budget: budget.0,
        });
    }
    Ok(mesh)
}

/// The whole file, once its length `len` is the size the header gives, read and
/// checked against its checksum; returns it and the offset of its splits.
fn read_checked_file(path: &Path, r: &Fields<'_>, header: &Header, len: u64) -> Result<(Vec<u8>, usize)> {
    let element_count = header.element_count;
    let splits_at = if header.version == 2 { HEADER + 8 } else { HEADER };
    let values_at = splits_at + header.split_count as usize * 4;
    let want = (values_at + element_count as usize * 24 + 4) as u64;
    if len != want {
        return Err(r.err(
            len.min(want) as usize,
            format!("the file has {len} bytes, {want} expected for {element_count} elements (truncated or damaged)"),
        ));
    }
    let bytes = crate::input_file::read(path)?;
    if bytes.len() as u64 != want {
        return Err(r.err(0, "the file changed while it was read"));
    }
    let body = bytes.len() - 4;
    let stored_crc = u32::from_le_bytes(bytes[body..].try_into().expect("4 bytes"));
    let crc = crc32fast::hash(&bytes[..body]);
    if crc != stored_crc {
        return Err(r.err(body, format!("checksum mismatch (stored {stored_crc:08x}, computed {crc:08x}): damaged")));
    }
    Ok((bytes, splits_at))
}

/// The file's `split_count` splits applied to `mesh` in their order, each checked to
/// name an element that can be split.
fn replay_splits(r: &mut Fields<'_>, scene: &Scene, mesh: &mut Patches, split_count: u64) -> Result<()> {
    for _ in 0..split_count {
        let at = r.pos;
        let e = r.u32("splits")? as usize;
        if e >= mesh.elements.len() || !mesh.can_split(e) {
            return Err(r.err(at, format!("element {e} cannot be split here (no such leaf, or too small)")));
        }
        mesh.split(scene, e);
    }
    Ok(())
}

/// Each element's radiosity, checked finite and non-negative.
fn read_radiosities(r: &mut Fields<'_>, mesh: &Patches) -> Result<Vec<DVec3>> {
    let mut radiosity = Vec::with_capacity(mesh.elements.len());
    for _ in 0..mesh.elements.len() {
        let at = r.pos;
        let v = r.vec3("radiosities")?;
        if !(v.is_finite() && v.min_element() >= 0.0) {
            return Err(r.err(at, format!("radiosity {v} is not finite and non-negative")));
        }
        radiosity.push(v);
    }
    Ok(radiosity)
}
