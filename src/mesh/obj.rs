//! Wavefront OBJ: positions, polygons and their groups, with the line of every error.
//!
//! Read (in `f64`, every coordinate checked finite): positions `v x y z`, where a fourth
//! value alone is the weight `w` the others are divided by and more values (a colour)
//! are dropped; faces `f` of `v`, `v/vt`, `v//vn` or `v/vt/vn` references, one-based,
//! negative ones counting back from the last vertex so far, positive ones possibly
//! forward; groups and objects `g`, `o` (one [`Group`] a name: the rest of the line,
//! `unnamed_object` when empty or before any); the material libraries `mtllib` names
//! (returned for [`super::mtl`] to check, materials themselves are not used). Skipped:
//! texture coordinates, normals, `usemtl`, smoothing groups, lines `l`, points `p`,
//! free-form geometry, comments (`#` to the end of a line). Faces of one or two
//! corners are skipped with a warning; polygons are cut by [`EarClipper`].
//!
//! Each group gets the vertices its faces use, in the order the faces first use them,
//! so a vertex two groups share appears in both (tobj's layout, which octsolid used
//! before: meshes load as they did); [`super::read_mesh`] welds them when the mesh is
//! not closed as it is. Lines that are not UTF-8 read as Latin-1 and UTF-16 with a
//! byte-order mark is transcoded ([`crate::text`]), so only names can be lossy.

use std::path::Path;

use glam::DVec3;

use super::triangulate::{EarClipper, FanTally};
use super::{Group, TriangleMesh};
use crate::error::{Result, quoted};
use crate::text::Text;
use crate::warning::{Place, Tally, Warning};

/// A parsed OBJ file: the mesh (not yet welded) and the material libraries it names.
pub(super) struct ObjFile {
    /// The triangles, grouped.
    pub mesh: TriangleMesh,
    /// `(line, file name)` of every `mtllib`.
    pub material_libraries: Vec<(usize, String)>,
}

/// A face: the line it is on and its corners' range in [`Reader::corners`].
struct Face {
    line: usize,
    corners: std::ops::Range<usize>,
}

/// The file as read so far.
#[derive(Default)]
struct Reader {
    positions: Vec<DVec3>,
    /// How many `v` lines the file has (positive references may point forward).
    total_vertices: u32,
    /// Every face's corners, zero-based into `positions`.
    corners: Vec<u32>,
    faces: Vec<Face>,
    /// `(name, index of its first face)`.
    groups: Vec<(String, usize)>,
    material_libraries: Vec<(usize, String)>,
    short_faces: Tally,
    /// How many polylines `l` and points `p` there are (not surfaces).
    lines: usize,
    points: usize,
}

/// Parses OBJ bytes into a mesh (not yet welded), pushing what it skipped to `warnings`.
pub(super) fn parse(bytes: &[u8], path: &Path, warnings: &mut Vec<Warning>) -> Result<ObjFile> {
    let text = Text::decode(bytes);
    warnings.extend(text.warnings(path));
    let total_vertices = text.lines().filter(|(_, l)| l.split_whitespace().next() == Some("v")).count();
    let Ok(total_vertices) = u32::try_from(total_vertices) else {
        return Err(Place::File.error(path, format!("{total_vertices} vertices are more than 2^32 - 1")));
    };
    let mut r = Reader { groups: vec![("unnamed_object".into(), 0)], total_vertices, ..Default::default() };
    for (line_no, line) in text.lines() {
        let fail = |reason: String| Place::Line(line_no).error(path, reason);
        let mut words = line.split_whitespace();
        let Some(keyword) = words.next() else { continue };
        let data = || line.split_whitespace().skip(1).take_while(|w| !w.starts_with('#'));
        match keyword {
            "v" => r.vertex(data()).map_err(fail)?,
            "f" | "fo" => r.face(line_no, data()).map_err(fail)?,
            "g" | "o" => r.group(line.trim_start()[1..].trim()),
            "mtllib" => r.material_libraries.push((line_no, line.trim_start()[6..].trim().to_string())),
            "l" => r.lines += 1,
            "p" => r.points += 1,
            _ => {}
        }
    }
    let material_libraries = std::mem::take(&mut r.material_libraries);
    if r.faces.is_empty() {
        let skipped = match (r.lines, r.points) {
            (0, 0) => String::new(),
            (lines, points) => format!(" (polylines 'l': {lines}, points 'p': {points}; neither is a surface)"),
        };
        return Err(Place::Line(text.last_line()).error(path, format!("the file has no faces{skipped}")));
    }
    warnings.extend(r.short_faces.warning(path, |n| format!("faces with fewer than three corners, skipped: {n}")));
    let mesh = r.mesh(warnings, path);
    Ok(ObjFile { mesh, material_libraries })
}

impl Reader {
    /// A `v` line's values.
    fn vertex<'a>(&mut self, values: impl Iterator<Item = &'a str>) -> Result<(), String> {
        let values: Vec<&str> = values.collect();
        if values.len() < 3 {
            return Err(format!("vertex needs three numbers, got {}", quoted(values.join(" ").as_bytes())));
        }
        let number = |s: &str| -> Result<f64, String> {
            let x: f64 = s.parse().map_err(|_| format!("{} is not a number", quoted(s.as_bytes())))?;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(format!("vertex coordinate {} is NaN or infinite", quoted(s.as_bytes())))
            }
        };
        let mut p = DVec3::new(number(values[0])?, number(values[1])?, number(values[2])?);
        if values.len() == 4 {
            let w = number(values[3])?;
            if w == 0.0 {
                return Err("vertex weight w is 0".into());
            }
            p /= w;
            if !p.is_finite() {
                return Err(format!("vertex {p} divided by w = {w} is not finite"));
            }
        }
        self.positions.push(p);
        Ok(())
    }

    /// An `f` line's corner references.
    fn face<'a>(&mut self, line: usize, refs: impl Iterator<Item = &'a str>) -> Result<(), String> {
        let start = self.corners.len();
        let (seen, total) = (self.positions.len() as i64, i64::from(self.total_vertices));
        for r in refs {
            let index = r.split('/').next().unwrap_or("");
            let Ok(v) = index.parse::<i64>() else {
                return Err(format!("{} is not a vertex reference", quoted(r.as_bytes())));
            };
            let resolved = if v < 0 { seen.saturating_add(v) } else { v - 1 };
            if v == 0 || !(0..total).contains(&resolved) {
                let from = if v < 0 { format!(" ({seen} vertices before this line)") } else { String::new() };
                return Err(format!("vertex index {v} is out of range (1..={total}){from}"));
            }
            self.corners.push(resolved as u32);
        }
        match self.corners.len() - start {
            0 => Err("face needs three or more vertices, got 0".into()),
            1 | 2 => {
                self.corners.truncate(start);
                self.short_faces.add(Place::Line(line));
                Ok(())
            }
            _ => {
                self.faces.push(Face { line, corners: start..self.corners.len() });
                Ok(())
            }
        }
    }

    /// A `g` or `o` line: a new group, or a new name for the current one while it has
    /// no faces.
    fn group(&mut self, name: &str) {
        let name = if name.is_empty() { "unnamed_object".to_string() } else { name.to_string() };
        let current = self.groups.last_mut().expect("there is always a group");
        if current.1 == self.faces.len() {
            current.0 = name;
        } else {
            self.groups.push((name, self.faces.len()));
        }
    }

    /// The mesh: each group's vertices in first-use order, its faces triangulated.
    fn mesh(&self, warnings: &mut Vec<Warning>, path: &Path) -> TriangleMesh {
        let mut builder = GroupBuilder::new(self.positions.len());
        let mut mesh = TriangleMesh::default();
        for (g, (name, first_face)) in self.groups.iter().enumerate() {
            let end = self.groups.get(g + 1).map_or(self.faces.len(), |next| next.1);
            let first = mesh.triangles.len();
            for face in &self.faces[*first_face..end] {
                builder.face(&self.positions, &self.corners[face.corners.clone()], face.line, &mut mesh);
            }
            builder.next_group();
            mesh.groups.push(Group { name: name.clone(), first, count: mesh.triangles.len() - first });
        }
        warnings.extend(builder.fanned.warnings(path));
        mesh
    }
}

/// Builds a group's vertex table and triangles, one face at a time.
struct GroupBuilder {
    /// The group that last used a position, and its index in the mesh's vertices then.
    owner: Vec<u32>,
    index: Vec<u32>,
    group: u32,
    polygon: Vec<u32>,
    triangles: Vec<[u32; 3]>,
    clipper: EarClipper,
    fanned: FanTally,
}

impl GroupBuilder {
    fn new(positions: usize) -> Self {
        GroupBuilder {
            owner: vec![u32::MAX; positions],
            index: vec![0; positions],
            group: 0,
            polygon: Vec::new(),
            triangles: Vec::new(),
            clipper: EarClipper::default(),
            fanned: FanTally::default(),
        }
    }

    /// Adds a face's corners (checked, zero-based) as triangles of the current group,
    /// giving corners it has not used yet the next vertex indices, in corner order.
    fn face(&mut self, positions: &[DVec3], corners: &[u32], line: usize, mesh: &mut TriangleMesh) {
        self.polygon.clear();
        for &c in corners {
            let c = c as usize;
            if self.owner[c] != self.group {
                self.owner[c] = self.group;
                self.index[c] = mesh.vertices.len() as u32;
                mesh.vertices.push(positions[c]);
            }
            self.polygon.push(c as u32);
        }
        self.triangles.clear();
        let how = self.clipper.triangulate(positions, &self.polygon, &mut self.triangles);
        self.fanned.add(how, Place::Line(line));
        mesh.triangles.extend(self.triangles.iter().map(|t| t.map(|c| self.index[c as usize])));
    }

    /// Starts the next group: it uses positions anew.
    fn next_group(&mut self) {
        self.group += 1;
    }
}
