//! `octsolid info FILE [--json]`: what an .oct file holds.

use std::path::PathBuf;

use anyhow::{Context, Result};
use octsolid::io::oct;
use octsolid::{MemoryBudget, human_bytes};
use serde::Serialize;

use super::print_summary;

/// Arguments of `octsolid info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// The .oct file.
    pub file: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// What `octsolid info --json` prints; the key names are a contract.
#[derive(Serialize)]
struct Info {
    depth: u8,
    domain: DomainInfo,
    nodes: usize,
    voxels: u64,
    volume: f64,
    bounds: Option<BoundsInfo>,
    bytes_memory: usize,
    bytes_file: u64,
}

#[derive(Serialize)]
struct DomainInfo {
    min: [f64; 3],
    edge: f64,
}

#[derive(Serialize)]
struct BoundsInfo {
    min: [f64; 3],
    max: [f64; 3],
}

/// `octsolid info FILE [--json]`
pub fn run(a: &InfoArgs, budget: MemoryBudget) -> Result<()> {
    let (file, json) = (&a.file, a.json);
    let tree = oct::load(file, budget)?;
    let bytes_file = std::fs::metadata(file).with_context(|| format!("{}", file.display()))?.len();
    let d = tree.domain();
    let info = Info {
        depth: d.depth(),
        domain: DomainInfo { min: d.min().to_array(), edge: d.edge() },
        nodes: tree.node_count(),
        voxels: tree.voxel_count(),
        volume: tree.volume(),
        bounds: tree.bounds().map(|b| BoundsInfo { min: b.min.to_array(), max: b.max.to_array() }),
        bytes_memory: tree.bytes(),
        bytes_file,
    };
    if json {
        out!("{}", serde_json::to_string(&info)?);
        return Ok(());
    }
    out!("file       {}", file.display());
    out!("depth      {} ({} voxels a side, voxel edge {})", info.depth, d.resolution(), d.voxel_size());
    out!("domain     min {:?} edge {}", info.domain.min, info.domain.edge);
    print_summary(&tree, None);
    let per_node = |b: f64| if info.nodes == 0 { 0.0 } else { b / info.nodes as f64 };
    out!("on disk    {} ({:.2} bytes a node)", human_bytes(bytes_file), per_node(bytes_file as f64));
    Ok(())
}
