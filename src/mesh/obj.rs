//! Wavefront OBJ through `tobj`, with line numbers for every error.
//!
//! `tobj` parses and triangulates (fan); its errors carry no position, so on failure,
//! and for checks it does not make (NaN or infinite coordinates), a light scan of the
//! text finds the offending line.

use std::path::Path;

use glam::DVec3;

use super::{Group, TriangleMesh};
use crate::error::{Error, Result};

/// Parses OBJ text into a mesh (not yet welded).
pub(super) fn parse(bytes: &[u8], path: &Path) -> Result<TriangleMesh> {
    let parse_error = |line: usize, reason: String| Error::Parse { path: path.to_path_buf(), line, reason };
    let text = std::str::from_utf8(bytes).map_err(|e| Error::Format {
        path: path.to_path_buf(),
        offset: e.valid_up_to() as u64,
        reason: "not UTF-8 text".into(),
    })?;
    let options =
        tobj::LoadOptions { triangulate: true, ignore_points: true, ignore_lines: true, ..Default::default() };
    let (models, _materials) =
        tobj::load_obj_buf(&mut text.as_bytes(), &options, |_| Err(tobj::LoadError::OpenFileFailed)).map_err(|e| {
            let (line, reason) = locate(text).unwrap_or((0, String::new()));
            if line == 0 { parse_error(1, format!("{e}")) } else { parse_error(line, format!("{e}: {reason}")) }
        })?;

    let mut mesh = TriangleMesh::default();
    for model in &models {
        let base = mesh.vertices.len() as u32;
        let p = &model.mesh.positions;
        mesh.vertices.extend(p.chunks_exact(3).map(|c| DVec3::new(f64::from(c[0]), f64::from(c[1]), f64::from(c[2]))));
        let first = mesh.triangles.len();
        mesh.triangles.extend(model.mesh.indices.chunks_exact(3).map(|t| [t[0] + base, t[1] + base, t[2] + base]));
        mesh.groups.push(Group { name: model.name.clone(), first, count: mesh.triangles.len() - first });
    }
    // Non-finite coordinates: tobj accepts "nan" and "inf"; find the vertex line.
    if let Some(line) = vertex_lines(text).find(|(_, v)| v.iter().any(|c| !c.is_finite())).map(|(l, _)| l) {
        return Err(parse_error(line, "vertex coordinate is NaN or infinite".into()));
    }
    if mesh.triangles.is_empty() {
        return Err(parse_error(text.lines().count().max(1), "the file has no faces".into()));
    }
    Ok(mesh)
}

/// `(line number, coordinates)` of every `v` line that parses.
fn vertex_lines(text: &str) -> impl Iterator<Item = (usize, Vec<f64>)> + '_ {
    text.lines().enumerate().filter_map(|(i, l)| {
        let mut it = l.split_whitespace();
        (it.next() == Some("v")).then(|| (i + 1, it.take(3).filter_map(|t| t.parse().ok()).collect()))
    })
}

/// The first line that breaks a rule `tobj` enforces, with the reason.
fn locate(text: &str) -> Option<(usize, String)> {
    let total_vertices = text.lines().filter(|l| l.split_whitespace().next() == Some("v")).count() as i64;
    let mut seen = 0i64;
    for (i, line) in text.lines().enumerate() {
        let mut fields = line.split_whitespace();
        match fields.next() {
            Some("v") => {
                seen += 1;
                let coords: Vec<&str> = fields.collect();
                if coords.len() < 3 || coords.iter().take(3).any(|c| c.parse::<f64>().is_err()) {
                    return Some((i + 1, format!("vertex needs three numbers, got '{}'", coords.join(" "))));
                }
            }
            Some("f") => {
                let refs: Vec<&str> = fields.collect();
                if refs.len() < 3 {
                    return Some((i + 1, format!("face needs three or more vertices, got {}", refs.len())));
                }
                for r in refs {
                    let idx = r.split('/').next().unwrap_or("");
                    let Ok(v) = idx.parse::<i64>() else {
                        return Some((i + 1, format!("'{r}' is not a vertex reference")));
                    };
                    let resolved = if v < 0 { seen + v } else { v - 1 };
                    if v == 0 || resolved < 0 || resolved >= total_vertices {
                        return Some((i + 1, format!("vertex index {v} is out of range (1..={total_vertices})")));
                    }
                }
            }
            _ => {}
        }
    }
    None
}
