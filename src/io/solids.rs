//! The voxel solid formats written from one place: [`write_voxel_solids`] writes
//! borrowed solids ([`SolidsRef`]) as `.oct`, `.vox`, `.binvox`, `.vdb` or `.glb`, by
//! the [`FileKind`] the caller read off the path. The door above it,
//! [`crate::write_solid_file`], adds `.oct`'s metadata, sharded `.octs` and meshes;
//! [`crate::SolidFile::read`] reads them back.
//!
//! | kind      | read | write | holds |
//! |-----------|------|-------|-------|
//! | `.oct`    | yes  | yes   | one solid, exact domain (`docs/FORMAT.md`) |
//! | `.vox`    | yes  | yes   | one solid a palette colour (MagicaVoxel, [`super::vox`]) |
//! | `.binvox` | yes  | yes   | one solid (binvox, [`super::binvox`]) |
//! | `.vdb`    | yes  | yes   | one grid read; one fog-volume grid a solid written ([`super::vdb`]) |
//! | `.glb`    | no   | yes   | one mesh a solid (its surface, [`crate::write_glb_surfaces`]; the staircase here), PBR base colour ([`super::gltf`]) |
//!
//! Every reader names the file and the place (byte offset, chunk or line) of what it
//! refuses, checks the memory a header claims against [`super::ReadOptions::budget`]
//! before allocating it, and never panics; every writer writes atomically.

use std::path::Path;
use std::sync::Arc;

use super::oct::{self, Metadata};
use super::solid_set::{SolidsRef, file_stem};
use super::{binvox, gltf, vdb, vox};
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::file_kind::FileKind;
use crate::octree::LinearOctree;
use crate::shape::Axis;
use crate::surface::{HermiteData, Style};

/// How files are written.
#[derive(Clone, Debug, PartialEq)]
pub struct WriteOptions {
    /// Memory limit for building the file, checked before anything is built (`.vox`
    /// follows the voxels, `.glb` the boundary, `.vdb` its tree's nodes; `.binvox` is
    /// refused where reading it back would exceed the same limit; a mesh its boundary).
    pub budget: MemoryBudget,
    /// `.vdb`: compression of the value buffers.
    pub vdb_compression: vdb::Compression,
    /// The world's up axis where [`WriteOptions::meta`] records none (`.glb` turns it
    /// to glTF's +Y; default z, octsolid's own).
    pub up: Axis,
    /// What `.oct` and `.octs` record about the solid's source (up axis, units).
    pub meta: Metadata,
    /// `.oct`: the solid's surface data, written in a surface section (its faces must
    /// be boundary faces of the solid written); the mesh outputs' smooth surface is
    /// contoured on it (estimated from the voxels without it); other formats leave it
    /// out.
    pub surface: Option<Arc<HermiteData>>,
    /// The mesh outputs (`.obj`, `.stl`, `.ply`, `.3mf`) and `.glb`: the true surface
    /// (the default) or the voxels' staircase.
    pub mesh_style: Style,
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions {
            budget: MemoryBudget::default(),
            vdb_compression: vdb::Compression::Zip,
            up: Axis::Z,
            meta: Metadata::default(),
            surface: None,
            mesh_style: Style::Smooth,
        }
    }
}

/// Writes `solids` to `path` as `kind`, one of `.oct`, `.vox`, `.binvox`, `.vdb` and
/// `.glb`: `.vox` one palette colour each, `.vdb` one grid each (one empty grid when
/// there are no solids), `.glb` one mesh each; `.oct` (with `options.meta` and
/// `options.surface`) and
/// `.binvox` hold one solid and refuse more. Returns the file size in bytes.
pub(crate) fn write_voxel_solids(
    path: &Path,
    kind: FileKind,
    solids: &SolidsRef<'_>,
    options: &WriteOptions,
) -> Result<u64> {
    solids.validate()?;
    // A .vdb keeps its domain in its grids: no solids (an empty .vox) are written as
    // one empty grid named by the file, so the file reads back, as an empty .oct does.
    let empty_tree;
    let empty;
    let solids = if kind == FileKind::Vdb && solids.solids.is_empty() {
        empty_tree = LinearOctree::empty(solids.domain);
        empty = SolidsRef::one(file_stem(path), None, &empty_tree);
        &empty
    } else {
        solids
    };
    match kind {
        FileKind::Oct => {
            oct::write_with_surface(one_solid(path, solids)?, &options.meta, options.surface.as_deref(), path)
        }
        FileKind::Binvox => binvox::write(path, one_solid(path, solids)?, options.budget),
        FileKind::Vox => vox::write(path, solids, options.budget),
        FileKind::Vdb => vdb::write(path, solids, options.vdb_compression, options.budget),
        FileKind::Glb => gltf::write(path, solids, options.meta.up.unwrap_or(options.up), options.budget),
        other => unreachable!("{other:?} is not a voxel solid output"),
    }
}

/// The one solid of `solids`, for a format that holds one; else the error that says so.
pub(crate) fn one_solid<'a>(path: &Path, solids: &SolidsRef<'a>) -> Result<&'a LinearOctree> {
    match solids.solids.as_slice() {
        [one] => Ok(one.tree),
        many => Err(Error::invalid(
            "solids",
            format!(
                "{}: the format holds one solid and {} were given; union them first, or write .vox, .vdb or .glb",
                path.display(),
                many.len()
            ),
        )),
    }
}
