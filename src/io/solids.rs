//! One entry point for every solid file: [`read_solids`] reads any format octsolid
//! reads into [`Solids`] (one domain, one or more coloured solids), [`write_solid`] and
//! [`write_solids`] write any format octsolid writes, each chosen by the file's
//! extension ([`SolidFormat::of`]).
//!
//! | extension | read | write | holds |
//! |-----------|------|-------|-------|
//! | `.oct`    | yes  | yes   | one solid, exact domain (`docs/FORMAT.md`) |
//! | `.vox`    | yes  | yes   | one solid a palette colour (MagicaVoxel, [`super::vox`]) |
//! | `.binvox` | yes  | yes   | one solid (binvox, [`super::binvox`]) |
//! | `.vdb`    | yes  | yes   | one grid read; one fog-volume grid a solid written ([`super::vdb`]) |
//! | `.glb`    | no   | yes   | one boundary mesh a solid, PBR base colour ([`super::gltf`]) |
//!
//! Every reader names the file and the place (byte offset, chunk or line) of what it
//! refuses, checks the memory a header claims against [`ReadOptions::budget`] before
//! allocating it, and never panics; every writer writes atomically.

use std::path::Path;

use glam::DVec3;

use super::solid_set::{ColouredSolid, ReadOptions, Solids};
use super::{binvox, gltf, oct, vdb, vox};
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::octree::LinearOctree;
use crate::shape::Axis;

/// How files are written.
#[derive(Clone, Debug, PartialEq)]
pub struct WriteOptions {
    /// Memory limit for building the file, checked before anything is built (`.vox`
    /// follows the voxels, `.glb` the boundary, `.vdb` its tree's nodes; `.binvox` is
    /// refused where reading it back would exceed the same limit).
    pub budget: MemoryBudget,
    /// `.vdb`: compression of the value buffers.
    pub vdb_compression: vdb::Compression,
    /// The world's up axis (`.glb` turns it to glTF's +Y; default z, octsolid's own).
    pub up: Axis,
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions { budget: MemoryBudget::default(), vdb_compression: vdb::Compression::Zip, up: Axis::Z }
    }
}

/// The solid file formats, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SolidFormat {
    /// octsolid's native `.oct`.
    Oct,
    /// MagicaVoxel `.vox`.
    Vox,
    /// binvox `.binvox`.
    Binvox,
    /// OpenVDB `.vdb`.
    Vdb,
    /// glTF 2.0 binary `.glb` (written only).
    Glb,
}

impl SolidFormat {
    /// The format `path`'s extension names (case-insensitive).
    pub fn of(path: impl AsRef<Path>) -> Result<SolidFormat> {
        let path = path.as_ref();
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
        Ok(match ext.as_str() {
            "oct" => SolidFormat::Oct,
            "vox" => SolidFormat::Vox,
            "binvox" => SolidFormat::Binvox,
            "vdb" => SolidFormat::Vdb,
            "glb" => SolidFormat::Glb,
            _ => {
                return Err(Error::invalid(
                    "solid file",
                    format!("{}: extension {ext:?} is not a solid format (oct, vox, binvox, vdb, glb)", path.display()),
                ));
            }
        })
    }
}

/// Reads the solid file at `path` (format by extension) into one domain and its solids.
pub fn read_solids(path: impl AsRef<Path>, options: &ReadOptions) -> Result<Solids> {
    let path = path.as_ref();
    let solids = match SolidFormat::of(path)? {
        SolidFormat::Oct => {
            let tree = oct::load(path, options.budget)?;
            Solids { domain: *tree.domain(), solids: vec![ColouredSolid::new(stem(path), None, tree)] }
        }
        SolidFormat::Vox => vox::read(path, options)?,
        SolidFormat::Binvox => {
            let tree = binvox::read(path, options.budget)?;
            Solids { domain: *tree.domain(), solids: vec![ColouredSolid::new(stem(path), None, tree)] }
        }
        SolidFormat::Vdb => vdb::read(path, options)?,
        SolidFormat::Glb => {
            return Err(Error::invalid(
                "solid file",
                format!("{}: .glb is written only; voxelize a mesh (OBJ, STL, PLY) instead", path.display()),
            ));
        }
    };
    debug_assert!(solids.validate().is_ok());
    Ok(solids)
}

/// Writes one solid with an optional colour to `path` (format by extension); returns
/// the file size in bytes.
pub fn write_solid(
    path: impl AsRef<Path>,
    tree: &LinearOctree,
    color: Option<DVec3>,
    options: &WriteOptions,
) -> Result<u64> {
    let path = path.as_ref();
    let solids = Solids { domain: *tree.domain(), solids: vec![ColouredSolid::new(stem(path), color, tree.clone())] };
    write_solids(path, &solids, options)
}

/// Writes several solids over one domain to `path` (format by extension): `.vox` one
/// palette colour each, `.vdb` one grid each (one empty grid when there are no solids),
/// `.glb` one mesh each; `.oct` and `.binvox` hold one solid and refuse more. Returns
/// the file size in bytes.
pub fn write_solids(path: impl AsRef<Path>, solids: &Solids, options: &WriteOptions) -> Result<u64> {
    let path = path.as_ref();
    solids.validate()?;
    let format = SolidFormat::of(path)?;
    // A .vdb keeps its domain in its grids: no solids (an empty .vox) are written as
    // one empty grid named by the file, so the file reads back, as an empty .oct does.
    let empty;
    let solids = if format == SolidFormat::Vdb && solids.solids.is_empty() {
        let domain = solids.domain;
        empty = Solids { domain, solids: vec![ColouredSolid::new(stem(path), None, LinearOctree::empty(domain))] };
        &empty
    } else {
        solids
    };
    let single = || -> Result<&LinearOctree> {
        match solids.solids.as_slice() {
            [one] => Ok(&one.tree),
            many => Err(Error::invalid(
                "solids",
                format!(
                    "{}: the format holds one solid and {} were given; union them first, or write .vox, .vdb or .glb",
                    path.display(),
                    many.len()
                ),
            )),
        }
    };
    match format {
        SolidFormat::Oct => oct::save(single()?, path),
        SolidFormat::Binvox => binvox::write(path, single()?, options.budget),
        SolidFormat::Vox => vox::write(path, solids, options.budget),
        SolidFormat::Vdb => vdb::write(path, solids, options.vdb_compression, options.budget),
        SolidFormat::Glb => gltf::write(path, solids, options.up, options.budget),
    }
}

/// The file's stem, the default solid name.
fn stem(path: &Path) -> String {
    path.file_stem().map_or_else(|| "solid".into(), |s| s.to_string_lossy().into_owned())
}
