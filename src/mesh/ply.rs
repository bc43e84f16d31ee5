//! PLY, ASCII and binary little-endian, with the line or byte offset of every error.
//!
//! Written here because errors must say where, and the subset meshes use is small: a
//! header of `element` and `property` lines, then the elements in order. Vertices need
//! `x`, `y`, `z`; faces need a list property `vertex_indices` (or `vertex_index`),
//! fan-triangulated. Other elements and properties are read and skipped.

use std::path::Path;

use glam::DVec3;

use super::TriangleMesh;
use crate::error::{Error, Result};

/// A scalar type of the format.
#[derive(Clone, Copy, Debug)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn parse(name: &str) -> Option<Scalar> {
        Some(match name {
            "char" | "int8" => Scalar::I8,
            "uchar" | "uint8" => Scalar::U8,
            "short" | "int16" => Scalar::I16,
            "ushort" | "uint16" => Scalar::U16,
            "int" | "int32" => Scalar::I32,
            "uint" | "uint32" => Scalar::U32,
            "float" | "float32" => Scalar::F32,
            "double" | "float64" => Scalar::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Scalar::I8 | Scalar::U8 => 1,
            Scalar::I16 | Scalar::U16 => 2,
            Scalar::I32 | Scalar::U32 | Scalar::F32 => 4,
            Scalar::F64 => 8,
        }
    }

    /// Reads one little-endian value.
    fn read(self, b: &[u8]) -> f64 {
        match self {
            Scalar::I8 => f64::from(b[0] as i8),
            Scalar::U8 => f64::from(b[0]),
            Scalar::I16 => f64::from(i16::from_le_bytes([b[0], b[1]])),
            Scalar::U16 => f64::from(u16::from_le_bytes([b[0], b[1]])),
            Scalar::I32 => f64::from(i32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::U32 => f64::from(u32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F32 => f64::from(f32::from_le_bytes([b[0], b[1], b[2], b[3]])),
            Scalar::F64 => f64::from_le_bytes(b[..8].try_into().expect("8 bytes")),
        }
    }
}

/// A property: a scalar, or a list with a count type and an item type.
#[derive(Clone, Debug)]
struct Property {
    name: String,
    list: Option<Scalar>,
    ty: Scalar,
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

/// Where values come from: lines of text, or little-endian bytes.
enum Body<'a> {
    Ascii { tokens: Vec<(usize, &'a str)>, next: usize, last_line: usize },
    Binary { bytes: &'a [u8], pos: usize },
}

impl Body<'_> {
    /// Reads one value of type `ty`; errors say the line or byte offset.
    fn value(&mut self, ty: Scalar, path: &Path) -> Result<f64> {
        match self {
            Body::Ascii { tokens, next, last_line } => {
                let Some(&(line, t)) = tokens.get(*next) else {
                    return Err(Error::Parse {
                        path: path.to_path_buf(),
                        line: *last_line,
                        reason: "file ends before all elements were read (truncated)".into(),
                    });
                };
                *next += 1;
                t.parse::<f64>().map_err(|_| Error::Parse {
                    path: path.to_path_buf(),
                    line,
                    reason: format!("'{t}' is not a number"),
                })
            }
            Body::Binary { bytes, pos } => {
                let end = *pos + ty.size();
                if end > bytes.len() {
                    return Err(Error::Format {
                        path: path.to_path_buf(),
                        offset: *pos as u64,
                        reason: "file ends before all elements were read (truncated)".into(),
                    });
                }
                let v = ty.read(&bytes[*pos..end]);
                *pos = end;
                Ok(v)
            }
        }
    }

    /// Where the next value starts, for error messages.
    fn place(&self) -> String {
        match self {
            Body::Ascii { tokens, next, last_line } => {
                format!("line {}", tokens.get(*next).map_or(*last_line, |t| t.0))
            }
            Body::Binary { pos, .. } => format!("byte {pos}"),
        }
    }
}

/// The header: the body's format, its elements in order, where the body starts and
/// how many lines the header has.
struct Header {
    format: Option<String>,
    elements: Vec<Element>,
    body_start: usize,
    lines: usize,
}

/// Parses PLY bytes into a mesh (not yet welded).
pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<TriangleMesh> {
    // Step 1: the header, line by line, up to "end_header".
    let header = parse_header(bytes, path)?;
    // Step 2: the body, as text tokens or little-endian bytes.
    let mut body = body(bytes, &header, path)?;
    // Step 3: the elements in order; vertices and faces are kept.
    let mut mesh = TriangleMesh::default();
    let mut vertex_count = None;
    for el in &header.elements {
        let reader = ElementReader::new(el, vertex_count, header.lines, path)?;
        for item in 0..el.count {
            reader.read_item(item, &mut body, &mut mesh)?;
        }
        if reader.is_vertex {
            vertex_count = Some(el.count);
        }
    }
    if mesh.triangles.is_empty() {
        return Err(Error::Parse {
            path: path.to_path_buf(),
            line: header.lines,
            reason: "the file has no faces".into(),
        });
    }
    Ok(mesh)
}

/// Reads the header up to its `end_header` line.
fn parse_header(bytes: &[u8], path: &Path) -> Result<Header> {
    let fail = |line: usize, reason: String| Error::Parse { path: path.to_path_buf(), line, reason };
    let mut pos = 0;
    let mut line_no = 0;
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    loop {
        let Some(len) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            return Err(fail(line_no + 1, "header has no 'end_header' line (truncated)".into()));
        };
        let line = String::from_utf8_lossy(&bytes[pos..pos + len]).trim().to_string();
        pos += len + 1;
        line_no += 1;
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["ply"] if line_no == 1 => {}
            _ if line_no == 1 => return Err(fail(1, "not a PLY file (first line is not 'ply')".into())),
            ["format", f, _] => format = Some(f.to_string()),
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => {
                let count =
                    count.parse().map_err(|_| fail(line_no, format!("element count '{count}' is not a number")))?;
                elements.push(Element { name: name.to_string(), count, properties: Vec::new() });
            }
            ["property", "list", count_ty, item_ty, name] => {
                let (Some(c), Some(t)) = (Scalar::parse(count_ty), Scalar::parse(item_ty)) else {
                    return Err(fail(line_no, format!("unknown list types '{count_ty} {item_ty}'")));
                };
                let el = elements.last_mut().ok_or_else(|| fail(line_no, "property before any element".into()))?;
                el.properties.push(Property { name: name.to_string(), list: Some(c), ty: t });
            }
            ["property", ty, name] => {
                let t = Scalar::parse(ty).ok_or_else(|| fail(line_no, format!("unknown property type '{ty}'")))?;
                let el = elements.last_mut().ok_or_else(|| fail(line_no, "property before any element".into()))?;
                el.properties.push(Property { name: name.to_string(), list: None, ty: t });
            }
            ["end_header"] => break,
            _ => return Err(fail(line_no, format!("unexpected header line '{line}'"))),
        }
    }
    Ok(Header { format, elements, body_start: pos, lines: line_no })
}

/// The body after `header`, in the header's format.
fn body<'a>(bytes: &'a [u8], header: &Header, path: &Path) -> Result<Body<'a>> {
    let fail = |line: usize, reason: String| Error::Parse { path: path.to_path_buf(), line, reason };
    let (pos, header_lines) = (header.body_start, header.lines);
    match header.format.as_deref() {
        Some("ascii") => {
            let text = std::str::from_utf8(&bytes[pos..]).map_err(|e| Error::Format {
                path: path.to_path_buf(),
                offset: (pos + e.valid_up_to()) as u64,
                reason: "ASCII body is not text".into(),
            })?;
            let tokens: Vec<(usize, &str)> = text
                .lines()
                .enumerate()
                .flat_map(|(i, l)| l.split_whitespace().map(move |t| (header_lines + i + 1, t)))
                .collect();
            Ok(Body::Ascii { tokens, next: 0, last_line: header_lines + text.lines().count().max(1) })
        }
        Some("binary_little_endian") => Ok(Body::Binary { bytes, pos }),
        Some(other) => Err(fail(2, format!("format '{other}' is not supported (use ascii or binary_little_endian)"))),
        None => Err(fail(header_lines, "header has no 'format' line".into())),
    }
}

/// How one element's items are read: which properties are the vertex coordinates
/// and the face's vertex list.
struct ElementReader<'a> {
    el: &'a Element,
    path: &'a Path,
    is_vertex: bool,
    is_face: bool,
    /// Property indices of x, y and z (vertices).
    xyz: [usize; 3],
    /// Property index of the vertex index list (faces).
    index_prop: Option<usize>,
    /// Vertices read before this element (faces index them).
    vertex_count: usize,
}

impl<'a> ElementReader<'a> {
    /// Checks that vertices have x, y, z and faces a vertex list after the vertices.
    fn new(el: &'a Element, vertex_count: Option<usize>, header_lines: usize, path: &'a Path) -> Result<Self> {
        let fail = |reason: &str| Error::Parse { path: path.to_path_buf(), line: header_lines, reason: reason.into() };
        let (is_vertex, is_face) = (el.name == "vertex", el.name == "face");
        let scalar = |n: &str| el.properties.iter().position(|p| p.name == n && p.list.is_none());
        let xyz = [scalar("x"), scalar("y"), scalar("z")];
        if is_vertex && xyz.iter().any(Option::is_none) {
            return Err(fail("vertex element lacks x, y or z"));
        }
        let index_prop = el
            .properties
            .iter()
            .position(|p| p.list.is_some() && (p.name == "vertex_indices" || p.name == "vertex_index"));
        if is_face && index_prop.is_none() {
            return Err(fail("face element lacks a 'vertex_indices' list"));
        }
        if is_face && vertex_count.is_none() {
            return Err(fail("faces come before vertices"));
        }
        let xyz = xyz.map(|i| i.unwrap_or(0));
        Ok(ElementReader { el, path, is_vertex, is_face, xyz, index_prop, vertex_count: vertex_count.unwrap_or(0) })
    }

    /// Reads item `item` of the element; a vertex or a face goes into `mesh`
    /// (polygons fan-triangulated).
    fn read_item(&self, item: usize, body: &mut Body, mesh: &mut TriangleMesh) -> Result<()> {
        let (el, path) = (self.el, self.path);
        let place = body.place();
        let mut values = [0.0; 3];
        let mut polygon: Vec<u32> = Vec::new();
        for (pi, p) in el.properties.iter().enumerate() {
            let Some(count_ty) = p.list else {
                let v = body.value(p.ty, path)?;
                if let Some(k) = self.xyz.iter().position(|&i| i == pi) {
                    values[k] = v;
                }
                continue;
            };
            let n = body.value(count_ty, path)?;
            if !(0.0..=1e6).contains(&n) || n.fract() != 0.0 {
                return Err(fail_at(path, &place, format!("{} {item}: list length {n} is invalid", el.name)));
            }
            for _ in 0..n as usize {
                let v = body.value(p.ty, path)?;
                if self.is_face && Some(pi) == self.index_prop {
                    let nv = self.vertex_count;
                    if v < 0.0 || v >= nv as f64 || v.fract() != 0.0 {
                        let reason = format!("face {item}: vertex index {v} is out of range (0..{nv})");
                        return Err(fail_at(path, &place, reason));
                    }
                    polygon.push(v as u32);
                }
            }
        }
        if self.is_vertex {
            let v = DVec3::from_array(values);
            if !v.is_finite() {
                return Err(fail_at(path, &place, format!("vertex {item}: {v} is NaN or infinite")));
            }
            mesh.vertices.push(v);
        }
        if self.is_face {
            if polygon.len() < 3 {
                return Err(fail_at(path, &place, format!("face {item} has {} vertices", polygon.len())));
            }
            for k in 1..polygon.len() - 1 {
                mesh.triangles.push([polygon[0], polygon[k], polygon[k + 1]]);
            }
        }
        Ok(())
    }
}

/// An error at a place given as "line N" or "byte N".
fn fail_at(path: &Path, place: &str, reason: String) -> Error {
    match place.split_once(' ') {
        Some(("line", n)) => Error::Parse { path: path.to_path_buf(), line: n.parse().unwrap_or(0), reason },
        Some((_, n)) => Error::Format { path: path.to_path_buf(), offset: n.parse().unwrap_or(0), reason },
        None => Error::Format { path: path.to_path_buf(), offset: 0, reason },
    }
}
