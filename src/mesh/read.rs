//! Loading meshes by file extension (read by [`FileKind::of`]).

use std::path::Path;

use super::TriangleMesh;
use crate::error::{Error, Result};
use crate::file_kind::FileKind;
use crate::warning::Warning;

/// Reads the mesh at `path` (format by extension), checks it and welds equal vertices,
/// unless the file's own indices already make the mesh watertight: then its duplicate
/// positions are deliberate (a boundary mesh keeps one vertex a sheet where two voxels
/// touch only along an edge, see [`super::boundary_mesh`]) and are kept. STL has no
/// indices, so it is always welded.
///
/// Errors name the file and the line (text formats) or byte offset (binary ones):
/// missing file, truncated data, indices out of range, NaN or infinite coordinates,
/// a mesh without triangles. What the loader reads past is dropped; see
/// [`read_mesh_and_warnings`] to have it.
pub fn read_mesh(path: impl AsRef<Path>) -> Result<TriangleMesh> {
    read_mesh_and_warnings(path).map(|(mesh, _)| mesh)
}

/// [`read_mesh`], with what the loader read past without refusing the file, in file
/// order: lines that are not UTF-8 (read as Latin-1), a missing or broken `.mtl`, PLY
/// header lines it does not know, faces that are not polygons, bytes after a binary
/// STL's last triangle.
pub fn read_mesh_and_warnings(path: impl AsRef<Path>) -> Result<(TriangleMesh, Vec<Warning>)> {
    let path = path.as_ref();
    let bytes = crate::input_file::read(path)?;
    mesh_from_bytes(&bytes, path)
}

/// [`read_mesh_and_warnings`] of a file already in memory: `bytes` are the file's
/// contents and `path` stands for the file (its extension picks the format, it names
/// the file in errors and warnings, and an OBJ's `mtllib` names are looked up beside
/// it).
pub fn mesh_from_bytes(bytes: &[u8], path: &Path) -> Result<(TriangleMesh, Vec<Warning>)> {
    let mut warnings = Vec::new();
    let mut mesh = match FileKind::of(path, FileKind::MESHES)? {
        FileKind::Obj => {
            let obj = super::obj::parse(bytes, path, &mut warnings)?;
            for (line, name) in &obj.material_libraries {
                super::mtl::check(path, *line, name, &mut warnings);
            }
            obj.mesh
        }
        FileKind::Stl => super::stl::parse(bytes, path, &mut warnings)?,
        FileKind::Ply => super::ply::parse(bytes, path, &mut warnings)?,
        other => unreachable!("{other:?} is not in FileKind::MESHES"),
    };
    mesh.validate().map_err(|e| Error::Format { path: path.to_path_buf(), offset: 0, reason: e.to_string() })?;
    if !mesh.is_watertight() {
        mesh.weld();
    }
    Ok((mesh, warnings))
}
