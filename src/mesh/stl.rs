//! STL, ASCII and binary, with the line or byte offset of every error.
//!
//! Written here rather than taken from a crate because errors must say where: the
//! format is tiny (binary: an 80-byte header, a `u32` count, 50 bytes a triangle;
//! ASCII: `solid NAME`, then `facet normal / outer loop / vertex x3 / endloop /
//! endfacet` a triangle, then `endsolid NAME`).
//!
//! Which of the two a file is cannot be read off its first bytes: binary exporters
//! often begin the header with `solid` too. A file is binary when its size is exactly
//! `84 + 50 n` for the count `n` it declares, or when it does not start with `solid`.
//! Otherwise it is ASCII when the word after its first line is `facet` or `endsolid`,
//! or when its first [`SNIFF_BYTES`] hold no NUL byte (a binary triangle nearly always
//! has one: its attribute count, a coordinate's low byte); else binary.
//!
//! Binary: the triangles the header declares must fit in the file; bytes after the
//! last one are ignored with a warning (some exporters pad). ASCII: the names after
//! `solid` and `endsolid` may hold any bytes (they are skipped to the end of the line,
//! and a line that is not UTF-8 reads as Latin-1, see [`crate::text`]); several solids
//! may follow one another and all are read. Facet normals are read as numbers and
//! dropped (the triangle's corners orient it), so a `nan` normal, which exporters write
//! for degenerate facets, is accepted; corners must be finite.

use std::path::Path;

use glam::DVec3;

use super::TriangleMesh;
use crate::error::{Result, quoted};
use crate::text::Text;
use crate::warning::{Place, Warning};

/// How many leading bytes of a file starting with `solid` are searched for a NUL byte.
pub const SNIFF_BYTES: usize = 512;

/// Parses STL bytes into a mesh (not yet welded), pushing what it skipped to `warnings`.
pub(super) fn parse(bytes: &[u8], path: &Path, warnings: &mut Vec<Warning>) -> Result<TriangleMesh> {
    if is_ascii(bytes) { parse_ascii(bytes, path, warnings) } else { parse_binary(bytes, path, warnings) }
}

/// Whether `bytes` are ASCII STL, by the rule of the module docs.
fn is_ascii(bytes: &[u8]) -> bool {
    let declared = bytes.get(80..84).map(|b| u64::from(u32::from_le_bytes(b.try_into().expect("4 bytes"))));
    let text = bytes.trim_ascii_start();
    if declared.is_some_and(|n| 84 + 50 * n == bytes.len() as u64) || !text.starts_with(b"solid") {
        return false;
    }
    let first_line_end = text.iter().position(|&b| b == b'\n' || b == b'\r');
    let next_word = first_line_end.and_then(|end| text[end..].split(u8::is_ascii_whitespace).find(|w| !w.is_empty()));
    matches!(next_word, Some(b"facet" | b"endsolid")) || !bytes[..bytes.len().min(SNIFF_BYTES)].contains(&0)
}

fn parse_binary(bytes: &[u8], path: &Path, warnings: &mut Vec<Warning>) -> Result<TriangleMesh> {
    let fail = |offset: usize, reason: String| Place::Byte(offset as u64).error(path, reason);
    if bytes.len() < 84 {
        return Err(fail(
            bytes.len(),
            format!("binary STL of {} bytes is shorter than its 84-byte header", bytes.len()),
        ));
    }
    let n = u32::from_le_bytes(bytes[80..84].try_into().expect("4 bytes")) as usize;
    let need = 84 + 50 * n as u64;
    if need > bytes.len() as u64 {
        return Err(fail(
            80,
            format!("header declares {n} triangles ({need} bytes) but the file has {} bytes", bytes.len()),
        ));
    }
    if n == 0 {
        return Err(fail(80, "the file has no triangles".into()));
    }
    if need < bytes.len() as u64 {
        let extra = bytes.len() as u64 - need;
        warnings
            .push(Place::Byte(need).warning(path, format!("{extra} bytes after the last of {n} triangles ignored")));
    }
    let mut mesh = TriangleMesh::default();
    mesh.vertices.reserve(3 * n);
    for t in 0..n {
        let base = 84 + 50 * t;
        for corner in 0..3 {
            let at = base + 12 + 12 * corner;
            let f = |i: usize| f32::from_le_bytes(bytes[at + 4 * i..at + 4 * i + 4].try_into().expect("4 bytes"));
            let v = DVec3::new(f64::from(f(0)), f64::from(f(1)), f64::from(f(2)));
            if !v.is_finite() {
                return Err(fail(at, format!("triangle {t}: vertex {v} is NaN or infinite")));
            }
            mesh.vertices.push(v);
        }
        let i = 3 * t as u32;
        mesh.triangles.push([i, i + 1, i + 2]);
    }
    Ok(mesh)
}

/// The words of an ASCII STL with their lines, read one at a time.
struct Words<'a> {
    words: Vec<(usize, &'a str)>,
    next: usize,
    last_line: usize,
    path: &'a Path,
}

impl<'a> Words<'a> {
    fn peek(&self) -> Option<&'a str> {
        self.words.get(self.next).map(|w| w.1)
    }

    /// The next word, which must be `word`; its line.
    fn expect(&mut self, word: &str) -> Result<usize> {
        let found = self.words.get(self.next).copied();
        self.next += 1;
        match found {
            Some((line, w)) if w == word => Ok(line),
            Some((line, w)) => {
                Err(Place::Line(line).error(self.path, format!("expected '{word}', found {}", quoted(w.as_bytes()))))
            }
            None => Err(self.truncated(&format!("where '{word}' was expected"))),
        }
    }

    /// Skips the rest of the line of the word just read (a solid's name).
    fn skip_line(&mut self, line: usize) {
        while self.words.get(self.next).is_some_and(|w| w.0 == line) {
            self.next += 1;
        }
    }

    /// The next word as a number.
    fn number(&mut self) -> Result<f64> {
        let found = self.words.get(self.next).copied();
        self.next += 1;
        let Some((line, w)) = found else { return Err(self.truncated("inside a facet")) };
        w.parse::<f64>()
            .map_err(|_| Place::Line(line).error(self.path, format!("{} is not a number", quoted(w.as_bytes()))))
    }

    fn truncated(&self, where_: &str) -> crate::Error {
        Place::Line(self.last_line).error(self.path, format!("file ends {where_} (truncated)"))
    }
}

fn parse_ascii(bytes: &[u8], path: &Path, warnings: &mut Vec<Warning>) -> Result<TriangleMesh> {
    let text = Text::decode(bytes);
    warnings.extend(text.warnings(path));
    let words = text.lines().flat_map(|(n, l)| l.split_whitespace().map(move |w| (n, w))).collect();
    let mut words = Words { words, next: 0, last_line: text.last_line(), path };
    let mut mesh = TriangleMesh::default();
    loop {
        let line = words.expect("solid")?;
        words.skip_line(line);
        while words.peek() != Some("endsolid") {
            if words.peek().is_none() {
                return Err(words.truncated("before 'endsolid'"));
            }
            facet(&mut words, &mut mesh)?;
        }
        let line = words.expect("endsolid")?;
        words.skip_line(line);
        match words.words.get(words.next) {
            None => break,
            Some((_, "solid")) => {}
            Some(&(line, _)) => {
                warnings.push(Place::Line(line).warning(path, "text after the last 'endsolid' ignored"));
                break;
            }
        }
    }
    if mesh.triangles.is_empty() {
        return Err(Place::Line(text.last_line()).error(path, "the file has no facets"));
    }
    Ok(mesh)
}

/// One `facet ... endfacet`.
fn facet(words: &mut Words, mesh: &mut TriangleMesh) -> Result<()> {
    words.expect("facet")?;
    words.expect("normal")?;
    for _ in 0..3 {
        words.number()?;
    }
    words.expect("outer")?;
    words.expect("loop")?;
    for _ in 0..3 {
        let line = words.expect("vertex")?;
        let v = DVec3::new(words.number()?, words.number()?, words.number()?);
        if !v.is_finite() {
            return Err(Place::Line(line).error(words.path, format!("vertex {v} is NaN or infinite")));
        }
        mesh.vertices.push(v);
    }
    words.expect("endloop")?;
    words.expect("endfacet")?;
    let i = mesh.vertices.len() as u32 - 3;
    mesh.triangles.push([i, i + 1, i + 2]);
    Ok(())
}
