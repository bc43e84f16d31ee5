//! PLY, ASCII and binary little-endian, with the line or byte offset of every error.
//!
//! Written here because errors must say where, and the subset meshes use is small: a
//! header of `element` and `property` lines, then the elements in order. Vertices need
//! `x`, `y`, `z` (finite); faces need a list property `vertex_indices` (or
//! `vertex_index`), cut into triangles by [`EarClipper`]. Other elements and
//! properties are read and skipped.
//!
//! The header (Turk, "The PLY Polygon File Format", 1994): `comment` and `obj_info`
//! lines are skipped; a line with any other unknown keyword (exporters write free text
//! there) is skipped with a warning; a broken `format`, `element` or `property` line is
//! an error. Before reading, every element's count is checked against what is left of
//! the file (an item takes at least a byte a scalar, or a word of ASCII, a property),
//! and an element without properties, which takes no room at all, may declare at most
//! [`MAX_EMPTY_ITEMS`]: so a header cannot make the reader loop or allocate beyond the
//! file's size. A body line that is not UTF-8 reads as Latin-1 ([`crate::text`]).

use std::path::Path;

use glam::DVec3;

use super::TriangleMesh;
use super::triangulate::{EarClipper, FanTally};
use crate::error::{Result, quoted};
use crate::text::Text;
use crate::warning::{Place, Warning};

/// Most items an element without properties may declare.
pub const MAX_EMPTY_ITEMS: u64 = 1 << 20;

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

impl Property {
    /// The fewest bytes (binary) an item of this property takes.
    fn min_bytes(&self) -> u64 {
        self.list.unwrap_or(self.ty).size() as u64
    }
}

#[derive(Clone, Debug)]
struct Element {
    name: String,
    count: u64,
    properties: Vec<Property>,
    /// Its header line.
    line: usize,
}

/// The body's encodings octsolid reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Ascii,
    BinaryLittleEndian,
}

/// Where values come from: words of text, or little-endian bytes.
enum Body<'a> {
    Ascii { words: Vec<(usize, &'a str)>, next: usize, last_line: usize },
    Binary { bytes: &'a [u8], pos: usize },
}

impl Body<'_> {
    /// Reads one value of type `ty`; errors say the line or byte offset.
    fn value(&mut self, ty: Scalar, path: &Path) -> Result<f64> {
        let truncated = "file ends before all elements were read (truncated)";
        match self {
            Body::Ascii { words, next, last_line } => {
                let Some(&(line, w)) = words.get(*next) else {
                    return Err(Place::Line(*last_line).error(path, truncated));
                };
                *next += 1;
                w.parse::<f64>()
                    .map_err(|_| Place::Line(line).error(path, format!("{} is not a number", quoted(w.as_bytes()))))
            }
            Body::Binary { bytes, pos } => {
                let end = *pos + ty.size();
                if end > bytes.len() {
                    return Err(Place::Byte(*pos as u64).error(path, truncated));
                }
                let v = ty.read(&bytes[*pos..end]);
                *pos = end;
                Ok(v)
            }
        }
    }

    /// Where the next value starts, for messages.
    fn place(&self) -> Place {
        match self {
            Body::Ascii { words, next, last_line } => Place::Line(words.get(*next).map_or(*last_line, |w| w.0)),
            Body::Binary { pos, .. } => Place::Byte(*pos as u64),
        }
    }

    /// What is left to read: words (ASCII) or bytes (binary).
    fn left(&self) -> u64 {
        match self {
            Body::Ascii { words, next, .. } => (words.len() - next) as u64,
            Body::Binary { bytes, pos } => (bytes.len() - pos) as u64,
        }
    }
}

/// The header: the body's format, its elements in order, where the body starts and
/// how many lines the header has.
struct Header {
    format: Option<Format>,
    elements: Vec<Element>,
    body_start: usize,
    lines: usize,
}

/// Parses PLY bytes into a mesh (not yet welded), pushing what it skipped to `warnings`.
pub(super) fn parse(bytes: &[u8], path: &Path, warnings: &mut Vec<Warning>) -> Result<TriangleMesh> {
    // Step 1: the header, line by line, up to "end_header".
    let header = parse_header(bytes, path, warnings)?;
    // Step 2: the body, as words of text or little-endian bytes, with room for every
    // element the header declares.
    let Some(format) = header.format else {
        return Err(Place::Line(header.lines).error(path, "header has no 'format' line"));
    };
    let text = (format == Format::Ascii).then(|| Text::decode(&bytes[header.body_start..]).after_lines(header.lines));
    let mut body = match &text {
        Some(text) => {
            warnings.extend(text.warnings(path));
            let words = text.lines().flat_map(|(n, l)| l.split_whitespace().map(move |w| (n, w))).collect();
            Body::Ascii { words, next: 0, last_line: text.last_line() }
        }
        None => Body::Binary { bytes, pos: header.body_start },
    };
    check_room(&header.elements, &body, path)?;
    // Step 3: the elements in order; vertices and faces are kept.
    let mut mesh = TriangleMesh::default();
    let mut faces = FaceCutter::default();
    let mut vertex_count = None;
    for el in &header.elements {
        let reader = ElementReader::new(el, vertex_count, header.lines, path)?;
        if !el.properties.is_empty() {
            for item in 0..el.count {
                reader.read_item(item, &mut body, &mut mesh, &mut faces)?;
            }
        }
        if reader.is_vertex {
            vertex_count = Some(el.count as usize);
        }
    }
    warnings.extend(faces.fanned.warnings(path));
    if mesh.triangles.is_empty() {
        return Err(Place::Line(header.lines).error(path, "the file has no faces"));
    }
    Ok(mesh)
}

/// Refuses a header whose elements cannot fit in what follows it, and elements without
/// properties that declare more than [`MAX_EMPTY_ITEMS`].
fn check_room(elements: &[Element], body: &Body, path: &Path) -> Result<()> {
    let left = body.left();
    let unit = if matches!(body, Body::Ascii { .. }) { "words" } else { "bytes" };
    let mut need: u128 = 0;
    for el in elements {
        let fail = |reason: String| Place::Line(el.line).error(path, reason);
        if el.properties.is_empty() && el.count > MAX_EMPTY_ITEMS {
            return Err(fail(format!(
                "element {} has no properties but declares {} items (at most {MAX_EMPTY_ITEMS})",
                quoted(el.name.as_bytes()),
                el.count
            )));
        }
        let per_item: u64 = match body {
            Body::Ascii { .. } => el.properties.len() as u64,
            Body::Binary { .. } => el.properties.iter().map(Property::min_bytes).sum(),
        };
        need += u128::from(el.count) * u128::from(per_item);
        if need > u128::from(left) {
            return Err(fail(format!(
                "element {} declares {} items of at least {per_item} {unit}, more than the {left} {unit} after the header",
                quoted(el.name.as_bytes()),
                el.count
            )));
        }
    }
    Ok(())
}

/// Reads the header up to its `end_header` line.
fn parse_header(bytes: &[u8], path: &Path, warnings: &mut Vec<Warning>) -> Result<Header> {
    let mut pos = 0;
    let mut line_no = 0;
    let mut header = Header { format: None, elements: Vec::new(), body_start: 0, lines: 0 };
    loop {
        let Some(len) = bytes[pos..].iter().position(|&b| b == b'\n') else {
            return Err(Place::Line(line_no + 1).error(path, "header has no 'end_header' line (truncated)"));
        };
        let raw = bytes[pos..pos + len].trim_ascii();
        pos += len + 1;
        line_no += 1;
        let line = String::from_utf8_lossy(raw);
        let words: Vec<&str> = line.split_whitespace().collect();
        if line_no == 1 {
            if words != ["ply"] {
                return Err(Place::Line(1).error(path, "not a PLY file (first line is not 'ply')"));
            }
            continue;
        }
        if words == ["end_header"] {
            break;
        }
        header_line(&words, raw, line_no, &mut header, path, warnings)?;
    }
    header.body_start = pos;
    header.lines = line_no;
    Ok(header)
}

/// One header line between `ply` and `end_header`, as words (`raw` for messages).
fn header_line(
    words: &[&str],
    raw: &[u8],
    line_no: usize,
    header: &mut Header,
    path: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<()> {
    let place = Place::Line(line_no);
    let fail = |reason: String| place.error(path, reason);
    let q = |s: &str| quoted(s.as_bytes());
    let mut add = |property: Property| match header.elements.last_mut() {
        Some(el) => {
            el.properties.push(property);
            Ok(())
        }
        None => Err(fail("property before any element".into())),
    };
    match words {
        ["format", f, _] => {
            let format = match *f {
                "ascii" => Format::Ascii,
                "binary_little_endian" => Format::BinaryLittleEndian,
                other => {
                    let reason = format!("format {} is not supported (use ascii or binary_little_endian)", q(other));
                    return Err(fail(reason));
                }
            };
            header.format = Some(format);
        }
        ["comment", ..] | ["obj_info", ..] | [] => {}
        ["element", name, count] => {
            let count = count.parse().map_err(|_| fail(format!("element count {} is not a number", q(count))))?;
            header.elements.push(Element { name: name.to_string(), count, properties: Vec::new(), line: line_no });
        }
        ["property", "list", count_ty, item_ty, name] => {
            let (Some(c), Some(t)) = (Scalar::parse(count_ty), Scalar::parse(item_ty)) else {
                return Err(fail(format!("unknown list types {}", q(&format!("{count_ty} {item_ty}")))));
            };
            add(Property { name: name.to_string(), list: Some(c), ty: t })?;
        }
        ["property", ty, name] => {
            let t = Scalar::parse(ty).ok_or_else(|| fail(format!("unknown property type {}", q(ty))))?;
            add(Property { name: name.to_string(), list: None, ty: t })?;
        }
        ["format" | "element" | "property" | "end_header", ..] => {
            return Err(fail(format!("malformed header line {}", quoted(raw))));
        }
        _ => warnings.push(place.warning(path, format!("unknown header line {} skipped", quoted(raw)))),
    }
    Ok(())
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
        let fail = |reason: &str| Place::Line(header_lines).error(path, reason);
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

    /// Reads item `item` of the element; a vertex or a face goes into `mesh`.
    fn read_item(&self, item: u64, body: &mut Body, mesh: &mut TriangleMesh, faces: &mut FaceCutter) -> Result<()> {
        let (el, path) = (self.el, self.path);
        let place = body.place();
        let mut values = [0.0; 3];
        faces.polygon.clear();
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
                return Err(place.error(path, format!("{} {item}: list length {n} is invalid", el.name)));
            }
            for _ in 0..n as usize {
                let v = body.value(p.ty, path)?;
                if self.is_face && Some(pi) == self.index_prop {
                    let nv = self.vertex_count;
                    if v < 0.0 || v >= nv as f64 || v.fract() != 0.0 {
                        let reason = format!("face {item}: vertex index {v} is out of range (0..{nv})");
                        return Err(place.error(path, reason));
                    }
                    faces.polygon.push(v as u32);
                }
            }
        }
        if self.is_vertex {
            let v = DVec3::from_array(values);
            if !v.is_finite() {
                return Err(place.error(path, format!("vertex {item}: {v} is NaN or infinite")));
            }
            mesh.vertices.push(v);
        }
        if self.is_face {
            if faces.polygon.len() < 3 {
                return Err(place.error(path, format!("face {item} has {} vertices", faces.polygon.len())));
            }
            faces.cut(place, mesh);
        }
        Ok(())
    }
}

/// Cuts faces into triangles, counting the ones that had to be fanned.
#[derive(Default)]
struct FaceCutter {
    polygon: Vec<u32>,
    clipper: EarClipper,
    fanned: FanTally,
}

impl FaceCutter {
    /// The triangles of `self.polygon` (the face at `place`) into `mesh`.
    fn cut(&mut self, place: Place, mesh: &mut TriangleMesh) {
        let how = self.clipper.triangulate(&mesh.vertices, &self.polygon, &mut mesh.triangles);
        self.fanned.add(how, place);
    }
}
