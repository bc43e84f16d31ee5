//! The `.oct` surface section: a solid's Hermite data ([`HermiteData`]: a crossing
//! and a normal a boundary face) appended after the payload, optional, versioned and
//! checked on its own (full description in `docs/FORMAT.md`).
//!
//! Layout: a 24-byte section header (magic `SURF`, section version, reserved, face
//! count, body length), the body, and a CRC-32 of the section's bytes before it. The
//! body is one record a face, faces strictly increasing in ([`FaceKey`]) order:
//!
//! - a LEB128 varint `(voxel - previous voxel) << 3 | direction` (the first face's
//!   previous voxel is 0), so the six faces of a voxel and the voxels along a surface,
//!   close in Morton order, take one or two bytes;
//! - `t` as a `u16`, `round(t * 65535)`: within `0.5 / 65535` of a voxel, and every
//!   code is a `t` in `0..=1`;
//! - the normal as two `u16`, its octahedral projection (Cigolle, Donow, Evangelakos,
//!   Mara, McGuire and Meyer, *A Survey of Efficient Representations for Independent
//!   Unit Vectors*, JCGT 3(2), 2014, §3.3 "oct"): `n / |n|_1` on the octahedron, the
//!   lower half folded over the upper, `x` and `y` in `[-1, 1]` mapped to `0..=65535`
//!   by rounding. Every code decodes to a finite unit vector; the round trip is within
//!   within 0.004 degrees (measured over 20,000 directions; we round, not search the four
//!   neighbouring codes, so the bound is its rounding one, not its precise one).
//!
//! A record takes at least 7 bytes, so the face count is checked against the body's
//! length before anything is allocated, and its memory against the budget. Every face
//! must be a boundary face of the file's own solid: a full voxel whose neighbour in
//! the face's direction is empty or outside the domain. A shard of a sharded solid is
//! checked against its own nodes, in which a neighbour in another cell is empty: the
//! check is the same and holds for the whole solid's faces too.

use std::path::Path;

use glam::{DVec2, DVec3, Vec3};
use rayon::prelude::*;

use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::octree::{Domain, LinearOctree};
use crate::surface::{Crossing, FaceKey, HermiteData};

use super::boundary_walk::first_not_on_boundary;
use super::varint;

/// The first four bytes of the section.
pub(crate) const SECTION_MAGIC: [u8; 4] = *b"SURF";
/// The section version this build writes and the only one it reads.
pub(crate) const SECTION_VERSION: u16 = 1;
/// Section header size in bytes; the body starts here.
pub(crate) const SECTION_HEADER_BYTES: usize = 24;
/// The fewest bytes a face's record takes: a one-byte varint, `t` and the normal.
const MIN_RECORD_BYTES: u64 = 7;
/// The most bytes a record's varint takes: a voxel gap of 63 bits and a direction.
const RECORD_VARINT_BYTES: usize = 10;
/// Faces a task of the writer encodes.
const ENCODE_CHUNK: usize = 1 << 15;
/// Largest code of a `u16` field, as a float.
const CODE_MAX: f64 = 65535.0;

/// `t` in `0..=1` as its `u16` code.
pub(crate) fn encode_t(t: f32) -> u16 {
    round_code(f64::from(t).clamp(0.0, 1.0) * CODE_MAX)
}

/// `x.round() as u16` for `x` in `0..=65535` or NaN (which gives 0): the nearest
/// integer, halves away from zero. Without SSE4.1 (the baseline x86-64 target) Rust's
/// `f64::round` is a call into a software routine, some fifty instructions, three a
/// face; here a truncation and one comparison of the remainder, which is exact (`x`
/// minus its integer part has fewer significant bits than `x`).
#[inline]
fn round_code(x: f64) -> u16 {
    let whole = x as u16;
    whole + u16::from(x - f64::from(whole) >= 0.5)
}

/// The `t` a code stands for.
pub(crate) fn decode_t(code: u16) -> f32 {
    (f64::from(code) / CODE_MAX) as f32
}

/// Sign of `x` with zero taken as positive (the fold needs a side for every point).
fn sign_not_zero(x: f64) -> f64 {
    if x < 0.0 { -1.0 } else { 1.0 }
}

/// A unit vector as its two octahedral codes (a zero or non-finite vector as +z).
pub(crate) fn encode_normal(n: Vec3) -> [u16; 2] {
    let n = n.as_dvec3();
    let l1 = n.x.abs() + n.y.abs() + n.z.abs();
    let n = if l1.is_finite() && l1 > 0.0 { n / l1 } else { DVec3::Z };
    let p = if n.z >= 0.0 {
        DVec2::new(n.x, n.y)
    } else {
        DVec2::new((1.0 - n.y.abs()) * sign_not_zero(n.x), (1.0 - n.x.abs()) * sign_not_zero(n.y))
    };
    let code = |c: f64| round_code((c.clamp(-1.0, 1.0) * 0.5 + 0.5) * CODE_MAX);
    [code(p.x), code(p.y)]
}

/// The unit vector two octahedral codes stand for.
pub(crate) fn decode_normal(codes: [u16; 2]) -> Vec3 {
    let p = DVec2::new(f64::from(codes[0]), f64::from(codes[1])) / CODE_MAX * 2.0 - 1.0;
    let z = 1.0 - p.x.abs() - p.y.abs();
    let (x, y) = if z >= 0.0 {
        (p.x, p.y)
    } else {
        ((1.0 - p.y.abs()) * sign_not_zero(p.x), (1.0 - p.x.abs()) * sign_not_zero(p.y))
    };
    // |x| + |y| + |z| = 1 on the octahedron, so the length is at least 1/sqrt(3).
    DVec3::new(x, y, z).normalize().as_vec3()
}

impl HermiteData {
    /// The data as an `.oct` file stores it and reads it back: each `t` and normal
    /// through its `u16` codes (see the module doc), so what is drawn or meshed from
    /// it is what the file gives (the Python package keeps a solid's data so).
    #[must_use]
    pub fn as_stored(&self) -> HermiteData {
        let faces = self
            .faces()
            .iter()
            .map(|&(key, c)| {
                (key, Crossing { t: decode_t(encode_t(c.t)), normal: decode_normal(encode_normal(c.normal)) })
            })
            .collect();
        HermiteData::from_faces(faces)
    }
}

/// Appends the section of `surface` to `out`.
///
/// The records are encoded in chunks in parallel: a record depends only on its face
/// and the face before it, which every chunk can read, so the bytes are those of one
/// pass in order whatever the threads.
pub(crate) fn encode(surface: &HermiteData, out: &mut Vec<u8>) {
    let faces = surface.faces();
    let chunks: Vec<Vec<u8>> = faces
        .par_chunks(ENCODE_CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let previous = c.checked_sub(1).map_or(0, |p| faces[(p + 1) * ENCODE_CHUNK - 1].0.voxel);
            encode_records(chunk, previous)
        })
        .collect();
    let body_len: usize = chunks.iter().map(Vec::len).sum();
    out.reserve(SECTION_HEADER_BYTES + body_len + 4);
    let start = out.len();
    out.extend_from_slice(&SECTION_MAGIC);
    out.extend_from_slice(&SECTION_VERSION.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    out.extend_from_slice(&(surface.len() as u64).to_le_bytes());
    out.extend_from_slice(&(body_len as u64).to_le_bytes());
    for chunk in &chunks {
        out.extend_from_slice(chunk);
    }
    let crc = crc32fast::hash(&out[start..]);
    out.extend_from_slice(&crc.to_le_bytes());
}

/// The records of `faces`, the face before the first at voxel `previous`.
fn encode_records(faces: &[(FaceKey, Crossing)], mut previous: u64) -> Vec<u8> {
    let mut body = Vec::with_capacity(faces.len() * 8);
    for (key, crossing) in faces {
        // A varint of at most ten bytes, then `t` and the normal's codes.
        let mut record = [0u8; 16];
        let mut len = varint::put(&mut record, (u128::from(key.voxel - previous) << 3) | u128::from(key.direction));
        previous = key.voxel;
        let [x, y] = encode_normal(crossing.normal);
        for code in [encode_t(crossing.t), x, y] {
            record[len..len + 2].copy_from_slice(&code.to_le_bytes());
            len += 2;
        }
        body.extend_from_slice(&record[..len]);
    }
    body
}

/// A section's faces as parsed, each record checked on its own and against the one
/// before, not yet against the solid ([`ParsedSection::check_against`]).
pub(crate) struct ParsedSection<'a> {
    faces: Vec<(FaceKey, Crossing)>,
    /// The records, for the offset of a face refused.
    body: &'a [u8],
    /// The section's offset in the file, and the file.
    base: usize,
    path: &'a Path,
}

/// The error at byte `offset` of the section that starts at byte `base` of `path`.
fn section_error(path: &Path, base: usize, offset: usize, reason: String) -> Error {
    Error::Format {
        path: path.to_path_buf(),
        offset: (base + offset) as u64,
        reason: format!("surface section: {reason}"),
    }
}

/// Parses and checks the section `bytes` (from its magic to the file's end), which
/// starts at byte `base` of the file `path`, against the file's solid `tree`.
#[cfg(test)]
fn decode(bytes: &[u8], base: usize, tree: &LinearOctree, path: &Path, budget: MemoryBudget) -> Result<HermiteData> {
    parse(bytes, base, tree.domain(), path, budget)?.check_against(tree)
}

/// Parses the section `bytes` (from its magic to the file's end), which starts at byte
/// `base` of the file `path` of a solid in `domain`: everything but its faces' check
/// against the solid, which needs only the domain.
pub(crate) fn parse<'a>(
    bytes: &'a [u8],
    base: usize,
    domain: &Domain,
    path: &'a Path,
    budget: MemoryBudget,
) -> Result<ParsedSection<'a>> {
    let fail = |offset: usize, reason: String| section_error(path, base, offset, reason);
    if bytes.len() < SECTION_HEADER_BYTES + 4 {
        return Err(fail(
            bytes.len(),
            format!(
                "{} bytes are shorter than its {SECTION_HEADER_BYTES}-byte header and 4-byte checksum",
                bytes.len()
            ),
        ));
    }
    if bytes[..4] != SECTION_MAGIC {
        return Err(fail(0, "bad magic (expected \"SURF\")".into()));
    }
    let u64_at = |o: usize| u64::from_le_bytes(bytes[o..o + 8].try_into().expect("8 bytes"));
    let version = u16::from_le_bytes([bytes[4], bytes[5]]);
    if version != SECTION_VERSION {
        return Err(fail(4, format!("version {version} is not supported (this build reads {SECTION_VERSION})")));
    }
    if bytes[6..8] != [0, 0] {
        return Err(fail(6, "reserved field is not zero".into()));
    }
    let (count, body_len) = (u64_at(8), u64_at(16));
    let held = (bytes.len() - SECTION_HEADER_BYTES - 4) as u64;
    if body_len != held {
        return Err(fail(16, format!("says {body_len} body bytes but the file holds {held} before the checksum")));
    }
    if count.saturating_mul(MIN_RECORD_BYTES) > body_len {
        return Err(fail(
            8,
            format!("{count} faces cannot fit in {body_len} bytes ({MIN_RECORD_BYTES} bytes a face at least)"),
        ));
    }
    let crc_at = bytes.len() - 4;
    let stored = u32::from_le_bytes(bytes[crc_at..].try_into().expect("4 bytes"));
    let computed = crc32fast::hash(&bytes[..crc_at]);
    if stored != computed {
        return Err(fail(crc_at, format!("checksum mismatch: stored {stored:08x}, computed {computed:08x}")));
    }
    let face_bytes = std::mem::size_of::<(FaceKey, Crossing)>() as u64;
    budget.check(format!("loading the surface of {}", path.display()), count.saturating_mul(face_bytes))?;
    let body = &bytes[SECTION_HEADER_BYTES..crc_at];
    let total = domain.voxel_total();
    let mut faces = Vec::with_capacity(count as usize);
    let mut pos = 0usize;
    let mut previous: Option<FaceKey> = None;
    while pos < body.len() {
        let at = SECTION_HEADER_BYTES + pos;
        let index = faces.len();
        if index as u64 == count {
            return Err(fail(at, format!("more faces than the {count} its header says")));
        }
        let value = varint::read(body, &mut pos, RECORD_VARINT_BYTES)
            .ok_or_else(|| fail(at, format!("face {index}: truncated or overlong varint")))?;
        let direction = (value & 7) as u8;
        if direction > 5 {
            return Err(fail(at, format!("face {index}: direction {direction} is not 0..=5")));
        }
        let voxel = u64::try_from(value >> 3)
            .ok()
            .and_then(|gap| gap.checked_add(previous.map_or(0, |p| p.voxel)))
            .filter(|v| *v < total)
            .ok_or_else(|| fail(at, format!("face {index}: voxel beyond the domain's {total} voxels")))?;
        let key = FaceKey { voxel, direction };
        if previous.is_some_and(|p| p >= key) {
            return Err(fail(
                at,
                format!("face {index}: not after the face before it (faces must be strictly sorted)"),
            ));
        }
        let Some(record) = body.get(pos..pos + 6) else {
            return Err(fail(SECTION_HEADER_BYTES + pos, format!("face {index}: truncated (t and normal missing)")));
        };
        let code = |i: usize| u16::from_le_bytes([record[2 * i], record[2 * i + 1]]);
        let normal = decode_normal([code(1), code(2)]);
        if !normal.is_finite() {
            return Err(fail(
                SECTION_HEADER_BYTES + pos + 2,
                format!("face {index}: normal does not decode to a unit vector"),
            ));
        }
        faces.push((key, Crossing { t: decode_t(code(0)), normal }));
        pos += 6;
        previous = Some(key);
    }
    if faces.len() as u64 != count {
        return Err(fail(crc_at, format!("{} faces found, its header says {count}", faces.len())));
    }
    Ok(ParsedSection { faces, body, base, path })
}

impl ParsedSection<'_> {
    /// The section's data once every face is found a boundary face of `tree`, the
    /// file's solid (a full voxel beside an empty one or the domain's side).
    pub(crate) fn check_against(self, tree: &LinearOctree) -> Result<HermiteData> {
        let faces = self.faces;
        if let Some(index) = first_not_on_boundary(tree, &faces, |(key, _)| *key) {
            let (key, _) = faces[index];
            return Err(section_error(
                self.path,
                self.base,
                record_offset(self.body, index),
                format!(
                    "face {index} (voxel {:?}, direction {}) is not a boundary face of the solid (a full voxel beside an empty one)",
                    key.voxel(),
                    key.direction
                ),
            ));
        }
        // Strictly increasing, as checked record by record: no sort.
        Ok(HermiteData::from_sorted(faces))
    }
}

/// The offset in the section of face `index`'s record (the body is known to parse).
fn record_offset(body: &[u8], index: usize) -> usize {
    let mut pos = 0;
    for _ in 0..index {
        varint::read(body, &mut pos, RECORD_VARINT_BYTES);
        pos += 6;
    }
    SECTION_HEADER_BYTES + pos
}

#[cfg(test)]
mod tests {
    use super::*;

    fn key(v: [u32; 3], direction: u8) -> FaceKey {
        FaceKey::new(v, direction)
    }

    /// A deterministic spread of unit vectors: a Fibonacci sphere plus the axes and
    /// the octahedron's fold lines, where the encoding changes branch.
    fn directions() -> Vec<Vec3> {
        let mut out: Vec<Vec3> = (0..20_000)
            .map(|i| {
                let z = 1.0 - 2.0 * (f64::from(i) + 0.5) / 20_000.0;
                let phi = f64::from(i) * std::f64::consts::PI * (3.0 - 5f64.sqrt());
                let r = (1.0 - z * z).sqrt();
                DVec3::new(r * phi.cos(), r * phi.sin(), z).as_vec3()
            })
            .collect();
        for s in [1.0f32, -1.0] {
            out.extend([Vec3::X * s, Vec3::Y * s, Vec3::Z * s]);
            out.push(Vec3::new(s, 1.0, 0.0).normalize());
            out.push(Vec3::new(0.0, s, -1.0).normalize());
            out.push(Vec3::new(s, -1.0, 0.0).normalize());
        }
        out
    }

    #[test]
    fn normals_survive_their_octahedral_codes_within_the_quantization_bound() {
        // Rounding to 16 bits a coordinate: 0.0036 degrees at worst over this set.
        let bound = 0.004f64.to_radians();
        let mut worst = 0.0f64;
        for n in directions() {
            let back = decode_normal(encode_normal(n));
            assert!((back.length() - 1.0).abs() < 1e-6, "{n} decoded to {back}, not unit");
            let angle = n.as_dvec3().angle_between(back.as_dvec3());
            worst = worst.max(angle);
        }
        assert!(worst < bound, "worst round trip {} degrees", worst.to_degrees());
        // A decoded normal is a fixed point: encoding it again gives the same
        // direction (the corners of the code square are all -z, so not always the code).
        for codes in [[0, 0], [65535, 65535], [32768, 1], [12345, 54321], [65535, 0], [32767, 32768]] {
            let n = decode_normal(codes);
            let again = decode_normal(encode_normal(n));
            assert!(n.angle_between(again) < 1e-5, "{codes:?} -> {n} -> {again}");
        }
    }

    #[test]
    fn every_normal_code_decodes_to_a_finite_unit_vector() {
        for x in (0..=65535u16).step_by(257) {
            for y in (0..=65535u16).step_by(257) {
                let n = decode_normal([x, y]);
                assert!(n.is_finite() && (n.length() - 1.0).abs() < 1e-6, "[{x}, {y}] -> {n}");
            }
        }
    }

    #[test]
    fn codes_round_as_the_library_rounds() {
        let mut rng = crate::test_util::Rng(11);
        let below_half = 0.5f64.next_down();
        let mut cases = vec![f64::NAN, 0.0, below_half, 0.5, 65534.5, 65535.0, 65534.5f64.next_down()];
        for i in 0..=65535u16 {
            let x = f64::from(i);
            cases.extend([x, x + 0.5, (x + 0.5).next_down(), (x + 0.5).next_up(), x.next_up()]);
        }
        cases.extend((0..100_000).map(|_| rng.range(0.0, 65535.0)));
        for x in cases.into_iter().filter(|x| x.is_nan() || *x <= 65535.0) {
            assert_eq!(round_code(x), x.round() as u16, "{x:e}");
        }
    }

    #[test]
    fn t_survives_its_code_within_half_a_step() {
        for i in 0..=10_000 {
            let t = i as f32 / 10_000.0;
            let back = decode_t(encode_t(t));
            assert!((back - t).abs() <= 0.5 / 65535.0 + 1e-7, "{t} -> {back}");
        }
        assert_eq!((decode_t(0), decode_t(65535)), (0.0, 1.0));
    }

    #[test]
    fn a_section_reads_back_as_written_and_a_face_off_the_boundary_is_refused() {
        use crate::octree::Domain;
        let domain = Domain::new(DVec3::ZERO, 4.0, 2).unwrap();
        // Voxels (1,1,1) and (2,1,1): the face between them is inside.
        let tree = LinearOctree::from_voxels(domain, [[1, 1, 1], [2, 1, 1]]).unwrap();
        let faces = vec![
            (key([1, 1, 1], 0), Crossing { t: 0.25, normal: Vec3::new(-0.6, 0.8, 0.0) }),
            (key([2, 1, 1], 5), Crossing { t: 0.75, normal: Vec3::Z }),
        ];
        let surface = HermiteData::from_faces(faces);
        let mut bytes = Vec::new();
        encode(&surface, &mut bytes);
        let back = decode(&bytes, 100, &tree, Path::new("s.oct"), MemoryBudget::unlimited()).unwrap();
        assert_eq!(back.len(), 2);
        for ((k, c), (k2, c2)) in surface.faces().iter().zip(back.faces()) {
            assert_eq!(k, k2);
            assert!((c.t - c2.t).abs() < 1e-5 && c.normal.angle_between(c2.normal) < 1e-4);
        }
        // What the section reads back is, to the bit, the data as stored.
        assert_eq!(back.faces(), surface.as_stored().faces());
        assert_ne!(surface.faces(), surface.as_stored().faces(), "0.25 and (-0.6, 0.8, 0) have no exact code");
        let inner = HermiteData::from_faces(vec![(key([1, 1, 1], 1), Crossing::face(key([1, 1, 1], 1)))]);
        let mut bytes = Vec::new();
        encode(&inner, &mut bytes);
        let e = decode(&bytes, 100, &tree, Path::new("s.oct"), MemoryBudget::unlimited()).unwrap_err().to_string();
        assert!(e.contains("s.oct: byte 124:") && e.contains("face 0") && e.contains("not a boundary face"), "{e}");
    }
}
