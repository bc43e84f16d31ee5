//! Solid files in: octsolid's `.oct` (with the up axis and units it records) and the
//! voxel formats of other tools (MagicaVoxel `.vox`, `.binvox`, OpenVDB `.vdb`) through
//! [`octsolid::io::read_solids`], and the flags that steer reading them, shared by every
//! command that reads a solid.
//!
//! A `.vox` file holds one solid a palette colour and a `.vdb` file one a grid read;
//! commands that work on one solid (`info`, `csg`, `slice`, `transform`, meshes out of
//! `export`) take their union ([`SolidFile::union`]), `render`, `convert` and `.glb`
//! keep them apart with their colours.

use std::path::Path;

use anyhow::{Result, bail};
use octsolid::io::oct::{self, Metadata};
use octsolid::io::{ColouredSolid, ReadOptions, Solids, read_solids};
use octsolid::octree::LinearOctree;
use octsolid::sharded::ShardedSolid;
use octsolid::{FileKind, MemoryBudget};

use crate::progress_bar::Spinner;

/// How solid files are read: flags for the formats that need them.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct ReadFlags {
    /// .vdb fog volumes: a voxel is inside where its value is above this (default
    /// 0.5; level sets are inside where negative, bool grids where true).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::values::parse_finite)]
    pub threshold: Option<f64>,
    /// .vdb: the grid to read, by name (default: the first float, double or bool grid).
    #[arg(long)]
    pub grid: Option<String>,
    /// .vox: the world edge of one voxel (default 1: a voxel is one world unit).
    #[arg(long, value_parser = crate::values::parse_finite)]
    pub voxel_size: Option<f64>,
}

impl ReadFlags {
    /// The library's read options with these flags over the defaults; warns about a
    /// flag the format of `path` does not use.
    fn options(&self, path: &Path, kind: FileKind, budget: MemoryBudget) -> Result<ReadOptions> {
        let mut options = ReadOptions { budget, ..ReadOptions::default() };
        let ignored = |flag: &str, format: &str| {
            warn!("{flag} is for {format} files; ignored for {}", path.display());
        };
        if let Some(t) = self.threshold {
            if kind == FileKind::Vdb { options.fog_threshold = t } else { ignored("--threshold", ".vdb") }
        }
        if let Some(g) = &self.grid {
            if kind == FileKind::Vdb { options.grid = Some(g.clone()) } else { ignored("--grid", ".vdb") }
        }
        if let Some(s) = self.voxel_size {
            if s <= 0.0 {
                bail!("--voxel-size {s}: a voxel's edge must be positive");
            }
            if kind == FileKind::Vox { options.voxel_size = s } else { ignored("--voxel-size", ".vox") }
        }
        Ok(options)
    }
}

/// A solid file as read: its kind, its solids over one domain, and what an `.oct` file
/// records about its source (nothing for the other formats).
pub struct SolidFile {
    /// The format, by extension.
    pub kind: FileKind,
    /// The solids (one for `.oct` and `.binvox`).
    pub solids: Solids,
    /// `.oct`'s up axis and units; the default elsewhere.
    pub meta: Metadata,
}

impl SolidFile {
    /// Every solid in one (the solid itself when there is one).
    pub fn union(&self) -> LinearOctree {
        match self.solids.solids.as_slice() {
            [one] => one.tree.clone(),
            _ => self.solids.union(),
        }
    }

    /// The union, taking the solid out when there is one.
    pub fn into_union(mut self) -> LinearOctree {
        if self.solids.solids.len() == 1 {
            return self.solids.solids.remove(0).tree;
        }
        self.solids.union()
    }
}

/// Reads the solid file at `path`: `.oct`, a sharded `.octs` (whole, within the
/// budget), `.vox`, `.binvox` or `.vdb` by extension (any other is refused, listing
/// these).
pub fn read_solid_file(path: &Path, flags: &ReadFlags, budget: MemoryBudget) -> Result<SolidFile> {
    let kind = FileKind::of(path, FileKind::SOLIDS)?;
    let options = flags.options(path, kind, budget)?;
    let _spinner = Spinner::new("reading");
    if kind == FileKind::Oct {
        let (tree, meta) = oct::load_with(path, budget)?;
        return Ok(SolidFile::one(path, kind, tree, meta));
    }
    if kind == FileKind::Octs {
        let solid = ShardedSolid::open(path)?;
        let tree = solid.load(budget).map_err(|e| over_budget_hint(e, path))?;
        return Ok(SolidFile::one(path, kind, tree, solid.index().meta));
    }
    Ok(SolidFile { kind, solids: read_solids(path, &options)?, meta: Metadata::default() })
}

/// Reads the solid file at `path` to be drawn: as [`read_solid_file`], but a sharded
/// solid larger than `budget` comes at the finest level of detail that fits it (said
/// on stderr).
pub fn read_for_display(path: &Path, flags: &ReadFlags, budget: MemoryBudget) -> Result<SolidFile> {
    if FileKind::of(path, FileKind::SOLIDS)? != FileKind::Octs {
        return read_solid_file(path, flags, budget);
    }
    let _spinner = Spinner::new("reading");
    let solid = ShardedSolid::open(path)?;
    let tree = solid.load_within(budget)?;
    let depth = solid.index().domain.depth();
    if tree.depth() < depth {
        warn!("{}: drawn at depth {} (its {depth} does not fit the memory budget)", path.display(), tree.depth());
    }
    Ok(SolidFile::one(path, FileKind::Octs, tree, solid.index().meta))
}

/// Says what to do when a sharded solid does not fit the budget.
fn over_budget_hint(e: octsolid::Error, path: &Path) -> anyhow::Error {
    match e {
        octsolid::Error::OverBudget { .. } => anyhow::anyhow!(
            "{e}\n{}: a sharded solid larger than memory streams through `csg` to a .octs output, and `render` draws it at a coarser level",
            path.display()
        ),
        e => e.into(),
    }
}

impl SolidFile {
    /// A file of one solid without a colour, named by the file's stem.
    fn one(path: &Path, kind: FileKind, tree: LinearOctree, meta: Metadata) -> SolidFile {
        let name = path.file_stem().map_or_else(|| "solid".into(), |s| s.to_string_lossy().into_owned());
        let solids = Solids { domain: *tree.domain(), solids: vec![ColouredSolid::new(name, None, tree)] };
        SolidFile { kind, solids, meta }
    }
}
