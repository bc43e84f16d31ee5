//! Solid files in: octsolid's `.oct` (with the up axis and units it records), sharded
//! `.octs` and the voxel formats of other tools (MagicaVoxel `.vox`, `.binvox`, OpenVDB
//! `.vdb`) through the library's [`SolidFile::read`], and the flags that steer reading
//! them, shared by every command that reads a solid.
//!
//! A `.vox` file holds one solid a palette colour and a `.vdb` file one a grid read;
//! commands that work on one solid (`info`, `csg`, `slice`, `transform`, meshes out of
//! `export`) take their union ([`SolidFile::union`]), `render`, `convert` and `.glb`
//! keep them apart with their colours.

use std::path::Path;

use anyhow::{Result, bail};
use octsolid::io::ReadOptions;
use octsolid::{FileKind, MemoryBudget, SolidFile};

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
    pub(crate) fn options(&self, path: &Path, kind: FileKind, budget: MemoryBudget) -> Result<ReadOptions> {
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

/// Reads the solid file at `path`: `.oct`, a sharded `.octs` (whole, within the
/// budget), `.vox`, `.binvox` or `.vdb` by extension (any other is refused, listing
/// these).
pub fn read_solid_file(path: &Path, flags: &ReadFlags, budget: MemoryBudget) -> Result<SolidFile> {
    let kind = FileKind::of(path, FileKind::SOLIDS)?;
    let options = flags.options(path, kind, budget)?;
    let _spinner = Spinner::new("reading");
    SolidFile::read(path, &options)
        .map_err(|e| if kind == FileKind::Octs { over_budget_hint(e, path) } else { e.into() })
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
