//! Loading meshes by file extension.

use std::path::Path;

use super::TriangleMesh;
use crate::error::{Error, Result};

/// Mesh file formats octsolid reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Wavefront OBJ (polygons are triangulated, groups kept).
    Obj,
    /// STL, ASCII or binary.
    Stl,
    /// PLY, ASCII or binary little-endian.
    Ply,
}

impl MeshFormat {
    /// The format of `path` by its extension, case-insensitive.
    pub fn of(path: &Path) -> Result<MeshFormat> {
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("").to_ascii_lowercase();
        match ext.as_str() {
            "obj" => Ok(MeshFormat::Obj),
            "stl" => Ok(MeshFormat::Stl),
            "ply" => Ok(MeshFormat::Ply),
            _ => Err(Error::Format {
                path: path.to_path_buf(),
                offset: 0,
                reason: format!("unknown mesh extension '{ext}' (use .obj, .stl or .ply)"),
            }),
        }
    }
}

/// Reads the mesh at `path` (format by extension), checks it and welds equal vertices,
/// unless the file's own indices already make the mesh watertight: then its duplicate
/// positions are deliberate (a boundary mesh keeps one vertex a sheet where two voxels
/// touch only along an edge, see [`super::boundary_mesh`]) and are kept. STL has no
/// indices, so it is always welded.
///
/// Errors name the file and the line (text formats) or byte offset (binary ones):
/// missing file, truncated data, indices out of range, NaN or infinite coordinates,
/// a mesh without triangles.
pub fn load_mesh(path: &Path) -> Result<TriangleMesh> {
    let bytes = std::fs::read(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })?;
    let mut mesh = match MeshFormat::of(path)? {
        MeshFormat::Obj => super::obj::parse(&bytes, path)?,
        MeshFormat::Stl => super::stl::parse(&bytes, path)?,
        MeshFormat::Ply => super::ply::parse(&bytes, path)?,
    };
    mesh.check().map_err(|e| Error::Format { path: path.to_path_buf(), offset: 0, reason: e.to_string() })?;
    if !mesh.is_watertight() {
        mesh.weld();
    }
    Ok(mesh)
}
