//! `octsolid info FILE [--json]`: what a solid file (`.oct`, `.vox`, `.binvox`, `.vdb`)
//! holds, and its measurements (boundary area, centre of mass, inertia tensor,
//! connected components) of the union of its solids. A file of another tool also lists
//! its solids (a `.vox` palette colour or a `.vdb` grid each) with their colours; an
//! `.oct` file's output is what it always was.

use std::path::PathBuf;

use anyhow::{Context, Result};
use octsolid::io::{Solids, oct};
use octsolid::surface::{ExtractOptions, extract};
use octsolid::{FileKind, MemoryBudget, human_bytes};
use serde::Serialize;

use super::print_summary;
use crate::progress_bar::Bar;
use crate::solid_input::{ReadFlags, read_solid_file};

/// Arguments of `octsolid info`.
#[derive(clap::Args, Debug)]
pub struct InfoArgs {
    /// The solid file: .oct, .vox, .binvox or .vdb.
    pub file: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
    #[command(flatten)]
    pub read: ReadFlags,
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
    /// The source's up axis recorded in the file ("x", "y", "z"), or null.
    up: Option<&'static str>,
    /// The length unit recorded in the file ("mm", ...), or null.
    units: Option<&'static str>,
    /// The boundary's area: of the true surface where the file carries crossings (the
    /// smooth export's mesh), else the voxels' estimate.
    surface_area: f64,
    /// Which: `true surface` or `voxel estimate`.
    area_from: &'static str,
    /// The voxels' estimate of the area (`LinearOctree::surface_area`).
    voxel_estimate_area: f64,
    /// The voxel boundary's own area.
    voxel_face_area: f64,
    /// `[x, y, z]`, `null` for the empty solid.
    centre_of_mass: Option<[f64; 3]>,
    /// About the centre of mass, unit density: three rows of three.
    inertia: [[f64; 3]; 3],
    /// Face-connected components.
    components: u64,
    /// The format ("vox", "binvox", "vdb"); absent for .oct.
    #[serde(skip_serializing_if = "Option::is_none")]
    format: Option<&'static str>,
    /// The file's solids; absent for .oct (one solid, no colour).
    #[serde(skip_serializing_if = "Option::is_none")]
    solids: Option<Vec<SolidInfo>>,
}

/// One solid of a file of another tool.
#[derive(Serialize)]
pub(crate) struct SolidInfo {
    /// `colour N` for a .vox palette index, the grid's name for .vdb, the file's stem
    /// for binvox.
    pub(crate) name: String,
    /// Linear RGB, or null.
    pub(crate) color: Option<[f64; 3]>,
    /// The .vox palette index, or null.
    pub(crate) palette_index: Option<u8>,
    pub(crate) voxels: u64,
}

/// The solids of `solids`, for the summaries.
pub(crate) fn solid_infos(solids: &Solids) -> Vec<SolidInfo> {
    solids
        .solids
        .iter()
        .map(|s| SolidInfo {
            name: s.name.clone(),
            color: s.color.map(|c| c.to_array()),
            palette_index: s.palette_index,
            voxels: s.tree.voxel_count(),
        })
        .collect()
}

/// Prints one line a solid: name, voxels, colour (as sRGB bytes, as palettes say it).
pub(crate) fn print_solids(solids: &[SolidInfo]) {
    for (i, s) in solids.iter().enumerate() {
        let label = if i == 0 { "solids" } else { "" };
        let colour = s.color.map_or_else(
            || "no colour".to_string(),
            |c| {
                let [r, g, b] = c.map(octsolid::render::to_srgb8);
                format!("sRGB #{r:02x}{g:02x}{b:02x}")
            },
        );
        out!("{label:<10} {}: {} voxels, {colour}", octsolid::printable(&s.name), s.voxels);
    }
}

#[derive(Serialize)]
struct DomainInfo {
    min: [f64; 3],
    edge: f64,
    /// A voxel's edge: `edge / 2^depth`.
    voxel_size: f64,
}

#[derive(Serialize)]
struct BoundsInfo {
    min: [f64; 3],
    max: [f64; 3],
}

/// `octsolid info FILE [--json]`
pub fn run(a: &InfoArgs, budget: MemoryBudget) -> Result<()> {
    let (file, json) = (&a.file, a.json);
    if FileKind::of(file, FileKind::SOLIDS)? == FileKind::Octs {
        return sharded_info(file, json, budget);
    }
    let mut read = read_solid_file(file, &a.read, budget)?;
    let (kind, meta) = (read.kind, read.meta);
    let crossings = read.surface.take();
    let surface_faces = crossings.as_ref().map(octsolid::surface::HermiteData::len);
    let solids = (kind != FileKind::Oct).then(|| solid_infos(&read.solids));
    let tree = read.into_union();
    let bytes_file = std::fs::metadata(file).with_context(|| format!("{}", file.display()))?.len();
    let d = tree.domain();
    let measures = tree.measure();
    // With the file's crossings, the area of the true surface (its dual contouring).
    let true_area = match &crossings {
        Some(crossings) => {
            let options = ExtractOptions { budget, ..ExtractOptions::default() };
            let surface = extract(&tree, crossings, &options, &Bar::new("measuring the true surface"))
                .with_context(|| format!("{}: cannot measure its surface", file.display()))?;
            Some(surface.mesh.area())
        }
        None => None,
    };
    let info = Info {
        depth: d.depth(),
        domain: DomainInfo { min: d.min().to_array(), edge: d.edge(), voxel_size: d.voxel_size() },
        nodes: tree.node_count(),
        voxels: tree.voxel_count(),
        volume: tree.volume(),
        bounds: tree.bounds().map(|b| BoundsInfo { min: b.min.to_array(), max: b.max.to_array() }),
        bytes_memory: tree.bytes(),
        bytes_file,
        up: meta.up.map(|a| ["x", "y", "z"][a.index()]),
        units: meta.units.map(oct::Units::name),
        surface_area: true_area.unwrap_or(measures.surface_area),
        area_from: if true_area.is_some() { "true surface" } else { "voxel estimate" },
        voxel_estimate_area: measures.surface_area,
        voxel_face_area: measures.voxel_face_area,
        centre_of_mass: measures.centre_of_mass.map(|c| c.to_array()),
        inertia: std::array::from_fn(|i| measures.inertia.row(i).to_array()),
        components: measures.components,
        format: (kind != FileKind::Oct).then(|| kind.extension()),
        solids,
    };
    if json {
        out!("{}", serde_json::to_string(&info)?);
        return Ok(());
    }
    out!("file       {}", file.display());
    out!(
        "depth      {} ({} voxels a side, voxel edge {})",
        info.depth,
        d.resolution(),
        crate::human::num(d.voxel_size())
    );
    out!("domain     min {} edge {}", crate::human::point(info.domain.min), crate::human::num(info.domain.edge));
    out!("up         {} (units {})", info.up.unwrap_or("not recorded: z"), info.units.unwrap_or("not recorded"));
    if let (Some(format), Some(solids)) = (info.format, &info.solids) {
        out!(
            "format     .{format}, {} solid{} (measured together)",
            solids.len(),
            if solids.len() == 1 { "" } else { "s" }
        );
        print_solids(solids);
    }
    print_summary(&tree, None);
    let per_node = |b: f64| if info.nodes == 0 { 0.0 } else { b / info.nodes as f64 };
    out!("on disk    {} ({:.2} bytes a node)", human_bytes(bytes_file), per_node(bytes_file as f64));
    if let Some(faces) = surface_faces {
        let from = if kind == FileKind::Vdb { "the level set's distances" } else { "the file's surface section" };
        out!("surface    {faces} boundary faces carry a crossing and a normal ({from})");
    }
    print_measures(&info);
    Ok(())
}

/// What `octsolid info --json` prints of a sharded solid; the key names are a contract.
#[derive(Serialize)]
struct ShardedInfo {
    depth: u8,
    domain: DomainInfo,
    nodes: u64,
    voxels: u64,
    volume: f64,
    bounds: Option<BoundsInfo>,
    /// The shard files' bytes together.
    bytes_file: u64,
    up: Option<&'static str>,
    units: Option<&'static str>,
    /// "octs".
    format: &'static str,
    /// The cells' level: the domain is cut into 8^level cells.
    shard_level: u8,
    /// Shards: cells the surface passes through, a file each.
    shards: usize,
    /// Nodes of a cell or larger, kept in the index.
    full_nodes: usize,
    /// The largest shard's nodes.
    largest_shard_nodes: u64,
}

/// `info` of a sharded solid: what its index says, once every shard is checked
/// against it (one a thread at a time, within `budget`), so its counts and bounds are the
/// solid's (the measurements, which need every node, are left out).
fn sharded_info(dir: &std::path::Path, json: bool, budget: MemoryBudget) -> Result<()> {
    let solid = octsolid::sharded::ShardedSolid::open(dir)?;
    solid.verify(budget)?;
    let index = solid.index();
    let d = index.domain;
    let bounds = index
        .voxel_bounds()
        .map(|(lo, hi)| BoundsInfo { min: d.lattice_point(lo).to_array(), max: d.lattice_point(hi).to_array() });
    let info = ShardedInfo {
        depth: d.depth(),
        domain: DomainInfo { min: d.min().to_array(), edge: d.edge(), voxel_size: d.voxel_size() },
        nodes: index.nodes,
        voxels: index.voxels,
        volume: index.voxels as f64 * d.voxel_size().powi(3),
        bounds,
        bytes_file: index.shards.iter().map(|s| s.bytes).sum(),
        up: index.meta.up.map(|a| ["x", "y", "z"][a.index()]),
        units: index.meta.units.map(oct::Units::name),
        format: FileKind::Octs.extension(),
        shard_level: index.level,
        shards: index.shards.len(),
        full_nodes: index.full.len(),
        largest_shard_nodes: index.shards.iter().map(|s| s.nodes).max().unwrap_or(0),
    };
    if json {
        out!("{}", serde_json::to_string(&info)?);
        return Ok(());
    }
    out!("file       {} (sharded: index and every shard checked)", dir.display());
    out!(
        "depth      {} ({} voxels a side, voxel edge {})",
        info.depth,
        d.resolution(),
        crate::human::num(d.voxel_size())
    );
    out!("domain     min {} edge {}", crate::human::point(info.domain.min), crate::human::num(info.domain.edge));
    out!("up         {} (units {})", info.up.unwrap_or("not recorded: z"), info.units.unwrap_or("not recorded"));
    out!(
        "shards     {} at cell level {} ({} cells), the largest {} nodes; {} full nodes in the index",
        info.shards,
        info.shard_level,
        index.layout().cell_count(),
        info.largest_shard_nodes,
        info.full_nodes
    );
    crate::sharded_output::print_index_summary(index);
    let per_node = if info.nodes == 0 { 0.0 } else { info.bytes_file as f64 / info.nodes as f64 };
    out!("on disk    {} ({per_node:.2} bytes a node)", human_bytes(info.bytes_file));
    Ok(())
}

/// The measurements: area (and the voxel faces'), centre of mass, inertia, components.
fn print_measures(info: &Info) {
    if info.area_from == "true surface" {
        out!(
            "area       {:.6} (the true surface; the voxels' estimate {:.6}, voxel faces {:.6})",
            info.surface_area,
            info.voxel_estimate_area,
            info.voxel_face_area
        );
    } else {
        out!("area       {:.6} (voxel faces {:.6})", info.surface_area, info.voxel_face_area);
    }
    match info.centre_of_mass {
        Some(c) => out!("centre     [{:.6}, {:.6}, {:.6}]", c[0], c[1], c[2]),
        None => out!("centre     (empty)"),
    }
    for (i, row) in info.inertia.iter().enumerate() {
        let label = if i == 0 { "inertia" } else { "" };
        // Length to the fifth: any size, so significant digits rather than decimals.
        out!("{label:<10} [{:.6e}, {:.6e}, {:.6e}]", row[0], row[1], row[2]);
    }
    out!("components {}", info.components);
}
