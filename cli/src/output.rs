//! Output files by extension: a solid is written in the format its `-o` extension
//! names (octsolid's `.oct`, the voxel formats, or its true surface as a mesh), a picture
//! as PNG; any other extension, or a folder that does not exist, is refused before any
//! work, listing what is accepted.
//! The extension is read by [`FileKind::of`]; the writing is the library's
//! [`octsolid::write_solid_file`].

use std::path::Path;
use std::sync::Arc;

use anyhow::{Result, bail};
use octsolid::io::oct::Metadata;
use octsolid::io::{SolidsRef, WriteOptions};
use octsolid::octree::LinearOctree;
use octsolid::surface::HermiteData;
use octsolid::{FileKind, MemoryBudget, NoProgress, Progress};

use crate::progress_bar::Bar;

/// The kind of `path` if it is one of `accepted`; else refused, naming the file and
/// listing what is accepted.
pub(crate) fn check_extension(path: &Path, accepted: &[FileKind]) -> Result<FileKind> {
    match FileKind::of(path, accepted) {
        Ok(kind) => {
            check_folder(path)?;
            Ok(kind)
        }
        Err(octsolid::Error::UnknownExtension { found, accepted, .. }) => {
            let found = found.to_ascii_lowercase();
            let found =
                if found.is_empty() { "has no extension".to_string() } else { format!("has extension .{found}") };
            bail!("{}: {found}, which names no format written here; accepted: {}", path.display(), accepted.join(", "))
        }
        Err(e) => Err(e.into()),
    }
}

/// Refuses an output whose folder does not exist, before any work (the file itself is
/// written at the end, through a temporary file beside it).
pub(crate) fn check_folder(path: &Path) -> Result<()> {
    match path.parent() {
        Some(folder) if !folder.as_os_str().is_empty() && !folder.is_dir() => {
            bail!("cannot write {}: the folder {} does not exist", path.display(), folder.display())
        }
        _ => Ok(()),
    }
}

/// Refuses an output that is one of the inputs (the same file, through any spelling
/// or link): writing it would replace what the command reads.
pub(crate) fn check_not_an_input(output: &Path, inputs: &[&Path]) -> Result<()> {
    if let Some(input) = inputs.iter().find(|i| octsolid::io::same_file(output, i)) {
        bail!("{}: the output is the input {}; choose another output name", output.display(), input.display());
    }
    Ok(())
}

/// Writes `tree` to `path` in the format the extension names
/// ([`octsolid::write_solid_file`]: `.oct` with `meta` and `surface`, a voxel format,
/// or the true surface contoured on `surface` as OBJ, STL, PLY, 3MF or glTF, with a bar
/// while it is meshed). Returns the file size in bytes.
pub(crate) fn write_solid_file(
    path: &Path,
    tree: &LinearOctree,
    meta: &Metadata,
    surface: Option<HermiteData>,
    budget: MemoryBudget,
) -> Result<u64> {
    let kind = check_extension(path, FileKind::SOLID_OUTPUTS)?;
    let bar = kind.meshes_solid().then(|| Bar::new("meshing"));
    let progress: &dyn Progress = bar.as_ref().map_or(&NoProgress, |b| b);
    let options = WriteOptions { budget, meta: *meta, surface: surface.map(Arc::new), ..WriteOptions::default() };
    Ok(octsolid::write_solid_file(path, &SolidsRef::of_file(path, tree), &options, progress)?)
}
