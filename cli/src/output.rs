//! Output files by extension: a solid is written in the format its `-o` extension
//! names (octsolid's `.oct`, the voxel formats, or its boundary as a mesh), a picture
//! as PNG; any other extension is refused before any work, listing what is accepted.

use std::path::Path;

use anyhow::{Context, Result, bail};
use octsolid::io::oct::{self, Metadata};
use octsolid::io::{WriteOptions, write_solid};
use octsolid::mesh::{BoundaryOptions, save_mesh, try_boundary_mesh};
use octsolid::octree::LinearOctree;
use octsolid::sharded::{self, StreamOptions};
use octsolid::{FileKind, MemoryBudget};

use crate::progress_bar::Bar;

/// What a solid can be written as, by extension.
pub(crate) const SOLID_EXTENSIONS: &[&str] = &["oct", "octs", "vox", "binvox", "vdb", "glb", "obj", "stl", "ply"];

fn extension(path: &Path) -> String {
    path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default()
}

/// Whether the format `path` names holds several solids, each with its colour (`.vox`,
/// `.vdb`, `.glb`); the others hold one, and get the union.
pub(crate) fn holds_many_solids(path: &Path) -> bool {
    ["vox", "vdb", "glb"].contains(&extension(path).as_str())
}

/// Refuses `path` unless its extension is one of `accepted`.
pub(crate) fn check_extension(path: &Path, accepted: &[&str]) -> Result<()> {
    let found = extension(path);
    if accepted.contains(&found.as_str()) {
        return Ok(());
    }
    let found = if found.is_empty() { "has no extension".to_string() } else { format!("has extension .{found}") };
    bail!("{}: {found}, which names no format written here; accepted: {}", path.display(), accepted.join(", "))
}

/// Refuses an output that is one of the inputs (the same file, through any spelling
/// or link): writing it would replace what the command reads.
pub(crate) fn check_not_an_input(output: &Path, inputs: &[&Path]) -> Result<()> {
    if let Some(input) = inputs.iter().find(|i| octsolid::io::same_file(output, i)) {
        bail!("{}: the output is the input {}; choose another output name", output.display(), input.display());
    }
    Ok(())
}

/// Writes `tree` to `path` in the format the extension names: `.oct` with `meta`, a
/// voxel format, or the boundary mesh (merged faces) as OBJ, STL or PLY. Returns the
/// file size in bytes.
pub(crate) fn write_solid_file(path: &Path, tree: &LinearOctree, meta: &Metadata, budget: MemoryBudget) -> Result<u64> {
    check_extension(path, SOLID_EXTENSIONS)?;
    let ext = extension(path);
    if ext == "oct" {
        return Ok(oct::save_with(tree, meta, path)?);
    }
    if ext == "octs" {
        // At the default cell level; commands with --shard-level write their own.
        let options = StreamOptions { budget, ..StreamOptions::default() };
        let index = sharded::save(tree, *meta, path, &options)?.expect("every cell: an index");
        return Ok(index.shards.iter().map(|s| s.bytes).sum());
    }
    if FileKind::MESHES.iter().any(|k| k.extension() == ext) {
        if tree.is_empty() {
            bail!("{}: the solid is empty; there is no boundary to write as a mesh", path.display());
        }
        let mesh = try_boundary_mesh(tree, &BoundaryOptions::default(), budget, &Bar::new("meshing"))
            .with_context(|| format!("{}: cannot mesh the solid", path.display()))?;
        return Ok(save_mesh(&mesh, path)?);
    }
    Ok(write_solid(path, tree, None, &WriteOptions { budget, ..WriteOptions::default() })?)
}
