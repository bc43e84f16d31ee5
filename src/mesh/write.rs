//! Writing meshes: OBJ (text), STL (binary), PLY (binary little-endian) and 3MF
//! ([`super::write_3mf`]), chosen by extension, written atomically.
//!
//! OBJ, PLY and 3MF store the vertex table and the triangles' indices, so a mesh reloads
//! with the same vertices. STL stores three `f32` corners a triangle and readers weld
//! them by position, so vertices that share a position (a boundary mesh's sheets
//! where voxels touch only along an edge or at a corner) would come back as one;
//! [`write_mesh`] therefore writes a closed mesh through [`super::separate_sheets`].

use std::io::Write;
use std::path::Path;

use rayon::prelude::*;

use super::TriangleMesh;
use super::separate::separate;
use super::three_mf::ThreeMfOptions;
use crate::atomic::write_atomic;
use crate::error::{Error, Result};
use crate::file_kind::FileKind;

/// Writes `mesh` to `path` in the format its extension names; returns the bytes written.
///
/// A closed mesh ([`TriangleMesh::is_watertight`]) goes to STL with the copies of each
/// shared position moved apart ([`super::separate_sheets`]: by a thousandth of the
/// shortest edge there, towards its own faces), so that a reader welding by position gets
/// the same closed, manifold mesh back; a mesh without shared positions is written as
/// it is. Other meshes (open ones, triangle soups meant to be welded) are written as
/// they are.
///
/// # Errors
/// The extension names no mesh format; writing fails; an STL of a closed mesh whose
/// vertices `f32` cannot keep apart (coordinates far larger than the edges; the
/// error names the vertices and suggests OBJ or PLY).
pub fn write_mesh(mesh: &TriangleMesh, path: impl AsRef<Path>) -> Result<u64> {
    write_mesh_with(mesh, path, &ThreeMfOptions::default())
}

/// [`write_mesh`] with what a file records beside the triangles where its format can:
/// a 3MF model's unit and the up axis its build item turns to +z ([`super::write_3mf`]);
/// OBJ, STL and PLY record neither.
///
/// # Errors
/// As [`write_mesh`].
pub fn write_mesh_with(mesh: &TriangleMesh, path: impl AsRef<Path>, options: &ThreeMfOptions) -> Result<u64> {
    let path = path.as_ref();
    let format = FileKind::of(path, FileKind::MESH_OUTPUTS)?;
    let separated;
    let mesh = if format == FileKind::Stl && !mesh.triangles.is_empty() && mesh.is_watertight() {
        mesh.validate()?;
        separated = separate(mesh).map_err(|reason| {
            Error::invalid("STL output", format!("{}: {reason}; write .obj or .ply instead", path.display()))
        })?;
        &separated
    } else {
        mesh
    };
    write_atomic(path, |w| match format {
        FileKind::Obj => write_obj(mesh, w),
        FileKind::Stl => write_stl(mesh, w),
        FileKind::Ply => write_ply(mesh, w),
        FileKind::ThreeMf => super::write_3mf(mesh, options, w),
        other => unreachable!("{other:?} is not in FileKind::MESH_OUTPUTS"),
    })
}

/// OBJ: `v x y z` lines, then `f a b c` with one-based indices. Coordinates are
/// written with Rust's shortest round-trip formatting, so they reload exactly.
/// The lines are formatted in parallel, a few thousand a task, and written in order.
pub fn write_obj(mesh: &TriangleMesh, w: &mut dyn Write) -> std::io::Result<()> {
    writeln!(w, "# written by octsolid")?;
    write_lines(&mesh.vertices, w, |out, v| writeln!(out, "v {} {} {}", v.x, v.y, v.z))?;
    write_lines(&mesh.triangles, w, |out, t| writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1))
}

/// Lines of text a formatting task makes.
const LINES_A_TASK: usize = 1 << 14;
/// Tasks formatted side by side before their text is written (so a batch holds a few
/// megabytes, never the whole file).
const TASKS_A_BATCH: usize = 16;

/// Writes `line` of each of `items` to `w`, in order: batches of tasks formatted in
/// parallel into memory, each batch written before the next is made.
fn write_lines<T: Sync>(
    items: &[T],
    w: &mut dyn Write,
    line: impl Fn(&mut Vec<u8>, &T) -> std::io::Result<()> + Sync,
) -> std::io::Result<()> {
    for batch in items.chunks(LINES_A_TASK * TASKS_A_BATCH) {
        let texts = batch
            .par_chunks(LINES_A_TASK)
            .map(|chunk| {
                let mut text = Vec::with_capacity(48 * chunk.len());
                for item in chunk {
                    line(&mut text, item)?;
                }
                Ok(text)
            })
            .collect::<std::io::Result<Vec<Vec<u8>>>>()?;
        for text in &texts {
            w.write_all(text)?;
        }
    }
    Ok(())
}

/// Binary STL (coordinates as `f32`, facet normals from the corners), every corner as
/// it is: vertices that share a position stay together (see [`write_mesh`]).
pub fn write_stl(mesh: &TriangleMesh, w: &mut dyn Write) -> std::io::Result<()> {
    let mut header = [0u8; 80];
    header[..20].copy_from_slice(b"octsolid binary STL ");
    w.write_all(&header)?;
    w.write_all(&(mesh.triangles.len() as u32).to_le_bytes())?;
    for t in 0..mesh.triangles.len() {
        let [a, b, c] = mesh.corners(t);
        let n = (b - a).cross(c - a).normalize_or_zero();
        for v in [n, a, b, c] {
            for x in v.to_array() {
                w.write_all(&(x as f32).to_le_bytes())?;
            }
        }
        w.write_all(&[0, 0])?;
    }
    Ok(())
}

/// Binary little-endian PLY with `double` coordinates and `int` indices.
pub fn write_ply(mesh: &TriangleMesh, w: &mut dyn Write) -> std::io::Result<()> {
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment written by octsolid\nelement vertex {}\n\
         property double x\nproperty double y\nproperty double z\nelement face {}\n\
         property list uchar int vertex_indices\nend_header\n",
        mesh.vertices.len(),
        mesh.triangles.len()
    )?;
    for v in &mesh.vertices {
        for x in v.to_array() {
            w.write_all(&x.to_le_bytes())?;
        }
    }
    for t in &mesh.triangles {
        w.write_all(&[3])?;
        for i in t {
            w.write_all(&(*i as i32).to_le_bytes())?;
        }
    }
    Ok(())
}
