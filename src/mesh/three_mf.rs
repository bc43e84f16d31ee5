//! Writing a mesh as a 3MF package (3D Manufacturing Format, the 3MF Consortium's core
//! specification 1.3): the printers' format, one ZIP archive holding the content types,
//! the package relationships and one model part.
//!
//! The model is one `object` of type `model` with the mesh's vertex table and its
//! triangles' indices (so a reader keeps vertices that share a position apart, as OBJ
//! and PLY do), and one build `item`; its unit is the specification's default,
//! millimetre, and its coordinates are written with Rust's shortest round-trip
//! formatting, so they read back exactly. 3MF is z-up, as octsolid is.
//!
//! The archive's entries are deflated (ZIP method 8, at the fast level: the model's
//! XML shrinks about fivefold, a printer's slicer reads a file that much smaller), each
//! followed by a data descriptor with its CRC-32 and sizes (APPNOTE 4.3.9), so the
//! model is compressed and written as it is made, in one pass, never held whole in
//! memory: every ZIP reader that reads the central directory (libzip under lib3mf,
//! Python's zipfile) opens it. No ZIP64: an archive whose model part passes 4 GiB
//! before compression (about 30 million triangles) is refused.

use std::io::{BufWriter, Write};

use flate2::Compression;
use flate2::write::DeflateEncoder;

use super::TriangleMesh;
use crate::shape::Axis;

/// The package's content types: what a `.rels` and a `.model` part are.
const CONTENT_TYPES: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/></Types>
"#;

/// The package's one relationship: its start part is the 3D model.
const RELATIONSHIPS: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Target="/3D/3dmodel.model" Id="rel0" Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>
"#;

/// The model part's path in the archive.
const MODEL_PATH: &str = "3D/3dmodel.model";

/// A 3MF model's unit of length (the specification's `ST_Unit`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ThreeMfUnit {
    /// Micrometres.
    Micron,
    /// Millimetres, the specification's default.
    #[default]
    Millimetre,
    /// Centimetres.
    Centimetre,
    /// Inches.
    Inch,
    /// Feet.
    Foot,
    /// Metres.
    Metre,
}

impl ThreeMfUnit {
    /// The `unit` attribute's value.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            ThreeMfUnit::Micron => "micron",
            ThreeMfUnit::Millimetre => "millimeter",
            ThreeMfUnit::Centimetre => "centimeter",
            ThreeMfUnit::Inch => "inch",
            ThreeMfUnit::Foot => "foot",
            ThreeMfUnit::Metre => "meter",
        }
    }
}

/// Where a 3MF model stands: its unit and the up axis of its coordinates.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ThreeMfOptions {
    /// The unit of the coordinates.
    pub unit: ThreeMfUnit,
    /// The world's up axis; 3MF's is +z, so another is turned there (module doc).
    pub up: Axis,
}

impl Default for ThreeMfOptions {
    fn default() -> Self {
        ThreeMfOptions { unit: ThreeMfUnit::Millimetre, up: Axis::Z }
    }
}

/// Writes `mesh` as a 3MF package to `w` (see the module doc). Fails for a model part
/// past 4 GiB (the archive has no ZIP64), and with `w`'s errors.
pub fn write_3mf(mesh: &TriangleMesh, options: &ThreeMfOptions, w: &mut dyn Write) -> std::io::Result<()> {
    let mut zip = DeflatedZip::new(w);
    zip.entry("[Content_Types].xml", |w| w.write_all(CONTENT_TYPES.as_bytes()))?;
    zip.entry("_rels/.rels", |w| w.write_all(RELATIONSHIPS.as_bytes()))?;
    zip.entry(MODEL_PATH, |w| write_model(mesh, options, w))?;
    zip.finish()
}

/// The build item's `transform` (3MF's 3x4 matrix, rows the images of x, y, z, then
/// the translation) turning `up` to +z; `None` for +z.
fn upright_transform(up: Axis) -> Option<&'static str> {
    match up {
        Axis::X => Some("0 0 1 0 1 0 -1 0 0 0 0 0"),
        Axis::Y => Some("1 0 0 0 0 1 0 -1 0 0 0 0"),
        Axis::Z => None,
    }
}

/// The model part: the mesh as one object and one build item.
fn write_model(mesh: &TriangleMesh, options: &ThreeMfOptions, w: &mut dyn Write) -> std::io::Result<()> {
    writeln!(w, r#"<?xml version="1.0" encoding="UTF-8"?>"#)?;
    writeln!(
        w,
        r#"<model unit="{}" xml:lang="en-US" xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">"#,
        options.unit.name()
    )?;
    w.write_all(
        concat!(
            r#"<metadata name="Application">octsolid</metadata>"#,
            "\n<resources>\n<object id=\"1\" type=\"model\">\n<mesh>\n<vertices>\n"
        )
        .as_bytes(),
    )?;
    for v in &mesh.vertices {
        writeln!(w, r#"<vertex x="{}" y="{}" z="{}"/>"#, v.x, v.y, v.z)?;
    }
    w.write_all(b"</vertices>\n<triangles>\n")?;
    for t in &mesh.triangles {
        writeln!(w, r#"<triangle v1="{}" v2="{}" v3="{}"/>"#, t[0], t[1], t[2])?;
    }
    w.write_all(b"</triangles>\n</mesh>\n</object>\n</resources>\n<build>\n")?;
    match upright_transform(options.up) {
        Some(m) => writeln!(w, r#"<item objectid="1" transform="{m}"/>"#)?,
        None => writeln!(w, r#"<item objectid="1"/>"#)?,
    }
    w.write_all(b"</build>\n</model>\n")
}

/// The general-purpose flag that says an entry's CRC-32 and sizes follow its data (a
/// data descriptor) and are zero in its local header: the data is written as it is
/// made, never held whole.
const SIZES_AFTER_DATA: u16 = 0x0008;

/// Bytes of an entry's data handed to the compressor at once.
const COMPRESS_BLOCK: usize = 1 << 16;

/// A ZIP archive of deflated entries written front to back: each entry's local header,
/// its data compressed as it is made, its data descriptor; then the central directory
/// and its end record.
struct DeflatedZip<'a> {
    w: &'a mut dyn Write,
    /// Bytes written so far: the next local header's offset.
    offset: u64,
    /// The central directory's records, written at the end.
    directory: Vec<u8>,
    entries: u16,
}

/// A writer that counts (and, given a hasher, checksums) what passes through it.
struct Counted<W: Write> {
    w: W,
    bytes: u64,
    crc: Option<crc32fast::Hasher>,
}

impl<W: Write> Counted<W> {
    fn new(w: W, crc: bool) -> Self {
        Counted { w, bytes: 0, crc: crc.then(crc32fast::Hasher::new) }
    }
}

impl<W: Write> Write for Counted<W> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let n = self.w.write(buf)?;
        if let Some(crc) = &mut self.crc {
            crc.update(&buf[..n]);
        }
        self.bytes += n as u64;
        Ok(n)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.w.flush()
    }
}

/// The error of an archive past 4 GiB.
fn too_large() -> std::io::Error {
    std::io::Error::other("the 3MF model part passes 4 GiB (no ZIP64): write .ply instead")
}

impl<'a> DeflatedZip<'a> {
    fn new(w: &'a mut dyn Write) -> Self {
        DeflatedZip { w, offset: 0, directory: Vec::new(), entries: 0 }
    }

    /// Writes one deflated entry `name` whose data `body` writes.
    fn entry(&mut self, name: &str, body: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> std::io::Result<()> {
        let offset = u32::try_from(self.offset).map_err(|_| too_large())?;
        let local = local_header(name);
        self.w.write_all(&local)?;
        let (bytes, packed_bytes, crc) = {
            // The XML comes a line at a time: buffered, the compressor runs on large blocks.
            let encoder = DeflateEncoder::new(Counted::new(&mut *self.w, false), Compression::fast());
            let mut plain = Counted::new(BufWriter::with_capacity(COMPRESS_BLOCK, encoder), true);
            body(&mut plain)?;
            let Counted { w: buffered, bytes, crc } = plain;
            let encoder = buffered.into_inner().map_err(std::io::IntoInnerError::into_error)?;
            (bytes, encoder.finish()?.bytes, crc.map_or(0, crc32fast::Hasher::finalize))
        };
        let size = u32::try_from(bytes).map_err(|_| too_large())?;
        let packed_size = u32::try_from(packed_bytes).map_err(|_| too_large())?;
        let mut descriptor = Vec::with_capacity(16);
        descriptor.extend_from_slice(&0x0807_4b50u32.to_le_bytes());
        descriptor.extend_from_slice(&crc.to_le_bytes());
        descriptor.extend_from_slice(&packed_size.to_le_bytes());
        descriptor.extend_from_slice(&size.to_le_bytes());
        self.w.write_all(&descriptor)?;

        let d = &mut self.directory;
        d.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
        d.extend_from_slice(&20u16.to_le_bytes()); // version made by: 2.0, MS-DOS
        d.extend_from_slice(&header_fields(name, crc, packed_size, size));
        d.extend_from_slice(&[0; 8]); // extra and comment lengths, disk, internal attributes
        d.extend_from_slice(&0u32.to_le_bytes()); // external attributes
        d.extend_from_slice(&offset.to_le_bytes());
        d.extend_from_slice(name.as_bytes());

        self.offset += local.len() as u64 + u64::from(packed_size) + descriptor.len() as u64;
        self.entries += 1;
        Ok(())
    }

    /// Writes the central directory and its end record.
    fn finish(self) -> std::io::Result<()> {
        let at = u32::try_from(self.offset).map_err(|_| too_large())?;
        self.w.write_all(&self.directory)?;
        let mut end = Vec::with_capacity(22);
        end.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
        end.extend_from_slice(&[0; 4]); // this disk, the directory's disk
        end.extend_from_slice(&self.entries.to_le_bytes());
        end.extend_from_slice(&self.entries.to_le_bytes());
        end.extend_from_slice(&(self.directory.len() as u32).to_le_bytes());
        end.extend_from_slice(&at.to_le_bytes());
        end.extend_from_slice(&0u16.to_le_bytes()); // comment length
        self.w.write_all(&end)
    }
}

/// An entry's local header: its CRC-32 and sizes zero, given by the data descriptor.
fn local_header(name: &str) -> Vec<u8> {
    let mut local = Vec::with_capacity(30 + name.len());
    local.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
    local.extend_from_slice(&header_fields(name, 0, 0, 0));
    local.extend_from_slice(&0u16.to_le_bytes()); // extra field length
    local.extend_from_slice(name.as_bytes());
    local
}

/// The fields the local and central headers share: version needed 2.0, the flag of
/// [`SIZES_AFTER_DATA`], deflated, no date (1980-01-01), the CRC-32, the compressed and
/// uncompressed sizes, the name's length.
fn header_fields(name: &str, crc: u32, packed_size: u32, size: u32) -> Vec<u8> {
    let mut f = Vec::with_capacity(24);
    f.extend_from_slice(&20u16.to_le_bytes());
    f.extend_from_slice(&SIZES_AFTER_DATA.to_le_bytes());
    f.extend_from_slice(&8u16.to_le_bytes()); // method: deflated
    f.extend_from_slice(&0u16.to_le_bytes()); // time
    f.extend_from_slice(&0x21u16.to_le_bytes()); // date: 1980-01-01
    f.extend_from_slice(&crc.to_le_bytes());
    f.extend_from_slice(&packed_size.to_le_bytes());
    f.extend_from_slice(&size.to_le_bytes());
    f.extend_from_slice(&(name.len() as u16).to_le_bytes());
    f
}
