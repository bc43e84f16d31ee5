//! The `.patches` text format: a line with the patch count, one line a patch with 16
//! one-based control-point indices (row-major 4x4), a line with the point count, one
//! line a point `x,y,z`.
//!
//! Every number is checked finite, every index in range, with the line; a line that is
//! not UTF-8 reads as Latin-1 ([`crate::text`]), so its bytes show, escaped, in the
//! error about the number they break.

use std::path::Path;

use glam::DVec3;

use super::BezierPatch;
use crate::error::{Error, Result, quoted};
use crate::text::Text;

/// Reads a patch set; errors name the file and line.
pub fn read_patches(path: impl AsRef<Path>) -> Result<Vec<BezierPatch>> {
    let path = path.as_ref();
    let bytes = crate::input_file::read(path)?;
    let text = Text::decode(&bytes);
    let fail = |line: usize, reason: String| Error::Parse { path: path.to_path_buf(), line, reason };
    let mut lines = text.lines().map(|(n, l)| (n, l.trim())).filter(|(_, l)| !l.is_empty());
    let last = text.last_line();
    let mut next = |what: &str| lines.next().ok_or_else(|| fail(last, format!("file ends before {what} (truncated)")));
    let count = |(line, l): (usize, &str), what: &str| -> Result<usize> {
        l.parse::<usize>().map_err(|_| fail(line, format!("{} is not a {what} count", quoted(l.as_bytes()))))
    };
    let patches = count(next("the patch count")?, "patch")?;
    // Each patch and point takes a line: the counts cannot reserve more than the file holds.
    let mut indices = Vec::with_capacity(patches.min(last));
    for k in 0..patches {
        let (line, l) = next("all patches")?;
        let idx: Vec<usize> = l
            .split(',')
            .map(|t| {
                let t = t.trim();
                t.parse::<usize>()
                    .map_err(|_| fail(line, format!("patch {k}: {} is not an index", quoted(t.as_bytes()))))
            })
            .collect::<Result<_>>()?;
        if idx.len() != 16 {
            return Err(fail(line, format!("patch {k} has {} indices, needs 16", idx.len())));
        }
        indices.push((line, idx));
    }
    let points = count(next("the point count")?, "point")?;
    let mut vertices = Vec::with_capacity(points.min(last));
    for k in 0..points {
        let (line, l) = next("all points")?;
        let c: Vec<f64> = l
            .split(',')
            .map(|t| {
                let t = t.trim();
                t.parse::<f64>().map_err(|_| fail(line, format!("point {k}: {} is not a number", quoted(t.as_bytes()))))
            })
            .collect::<Result<_>>()?;
        let v = match c.as_slice() {
            [x, y, z] => DVec3::new(*x, *y, *z),
            _ => return Err(fail(line, format!("point {k} has {} coordinates, needs 3", c.len()))),
        };
        if !v.is_finite() {
            return Err(fail(line, format!("point {k} is NaN or infinite")));
        }
        vertices.push(v);
    }
    if patches == 0 {
        return Err(fail(1, "the file has no patches".into()));
    }
    indices
        .into_iter()
        .enumerate()
        .map(|(k, (line, idx))| {
            let mut p = [[DVec3::ZERO; 4]; 4];
            for (n, &i) in idx.iter().enumerate() {
                if i == 0 || i > vertices.len() {
                    return Err(fail(line, format!("patch {k}: index {i} is out of range 1..={}", vertices.len())));
                }
                p[n / 4][n % 4] = vertices[i - 1];
            }
            Ok(BezierPatch { p })
        })
        .collect()
}
