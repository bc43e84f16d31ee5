//! STL, ASCII and binary, with the line or byte offset of every error.
//!
//! Written here rather than taken from a crate because errors must say where: the
//! format is tiny (binary: an 80-byte header, a `u32` count, 50 bytes a triangle;
//! ASCII: `facet normal / outer loop / vertex x3 / endloop / endfacet`). A file is
//! binary when its size is exactly `84 + 50 n` for the count `n` it declares, or when
//! it does not start with `solid`.

use std::path::Path;

use glam::DVec3;

use super::TriangleMesh;
use crate::error::{Error, Result};

/// Parses STL bytes into a mesh (not yet welded).
pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<TriangleMesh> {
    let declared = bytes.get(80..84).map(|b| u64::from(u32::from_le_bytes(b.try_into().expect("4 bytes"))));
    let is_binary_size = declared.is_some_and(|n| 84 + 50 * n == bytes.len() as u64);
    if is_binary_size || !bytes.trim_ascii_start().starts_with(b"solid") {
        parse_binary(bytes, path)
    } else {
        parse_ascii(bytes, path)
    }
}

fn parse_binary(bytes: &[u8], path: &Path) -> Result<TriangleMesh> {
    let fail =
        |offset: usize, reason: String| Error::Format { path: path.to_path_buf(), offset: offset as u64, reason };
    if bytes.len() < 84 {
        return Err(fail(
            bytes.len(),
            format!("binary STL of {} bytes is shorter than its 84-byte header", bytes.len()),
        ));
    }
    let n = u32::from_le_bytes(bytes[80..84].try_into().expect("4 bytes")) as usize;
    let need = 84 + 50 * n as u64;
    if need != bytes.len() as u64 {
        return Err(fail(
            80,
            format!("header declares {n} triangles ({need} bytes) but the file has {} bytes", bytes.len()),
        ));
    }
    if n == 0 {
        return Err(fail(80, "the file has no triangles".into()));
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

fn parse_ascii(bytes: &[u8], path: &Path) -> Result<TriangleMesh> {
    let fail = |line: usize, reason: String| Error::Parse { path: path.to_path_buf(), line, reason };
    let text = std::str::from_utf8(bytes).map_err(|e| Error::Format {
        path: path.to_path_buf(),
        offset: e.valid_up_to() as u64,
        reason: "not UTF-8 text".into(),
    })?;
    let mut tokens =
        text.lines().enumerate().flat_map(|(i, l)| l.split_whitespace().map(move |t| (i + 1, t))).peekable();
    let last_line = text.lines().count().max(1);
    let expect = |word: &str, tokens: &mut std::iter::Peekable<_>| -> Result<usize> {
        match Iterator::next(tokens) {
            Some((line, t)) if t == word => Ok(line),
            Some((line, t)) => Err(fail(line, format!("expected '{word}', found '{t}'"))),
            None => Err(fail(last_line, format!("file ends where '{word}' was expected (truncated)"))),
        }
    };
    expect("solid", &mut tokens)?;
    // The solid's name: everything up to the first "facet" or "endsolid".
    while let Some((_, t)) = tokens.peek() {
        if *t == "facet" || *t == "endsolid" {
            break;
        }
        tokens.next();
    }
    let mut mesh = TriangleMesh::default();
    loop {
        match tokens.peek() {
            Some((_, "endsolid")) => break,
            Some(_) => {}
            None => return Err(fail(last_line, "file ends before 'endsolid' (truncated)".into())),
        }
        expect("facet", &mut tokens)?;
        expect("normal", &mut tokens)?;
        for _ in 0..3 {
            number(&mut tokens, last_line, path)?;
        }
        expect("outer", &mut tokens)?;
        expect("loop", &mut tokens)?;
        for _ in 0..3 {
            let line = expect("vertex", &mut tokens)?;
            let v = DVec3::new(
                number(&mut tokens, last_line, path)?,
                number(&mut tokens, last_line, path)?,
                number(&mut tokens, last_line, path)?,
            );
            if !v.is_finite() {
                return Err(fail(line, format!("vertex {v} is NaN or infinite")));
            }
            mesh.vertices.push(v);
        }
        expect("endloop", &mut tokens)?;
        expect("endfacet", &mut tokens)?;
        let i = mesh.vertices.len() as u32 - 3;
        mesh.triangles.push([i, i + 1, i + 2]);
    }
    if mesh.triangles.is_empty() {
        return Err(fail(last_line, "the file has no facets".into()));
    }
    Ok(mesh)
}

/// The next token as a number.
fn number<'a>(tokens: &mut impl Iterator<Item = (usize, &'a str)>, last_line: usize, path: &Path) -> Result<f64> {
    match tokens.next() {
        Some((line, t)) => t.parse::<f64>().map_err(|_| Error::Parse {
            path: path.to_path_buf(),
            line,
            reason: format!("'{t}' is not a number"),
        }),
        None => Err(Error::Parse {
            path: path.to_path_buf(),
            line: last_line,
            reason: "file ends inside a facet (truncated)".into(),
        }),
    }
}
