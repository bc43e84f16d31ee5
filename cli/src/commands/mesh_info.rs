//! `octsolid mesh-info IN [--json]`: a mesh's polygon-table diagnostics.

use std::path::PathBuf;

use anyhow::{Context, Result};
use octsolid::MemoryBudget;

use super::read_input;

/// Arguments of `octsolid mesh-info`.
#[derive(clap::Args, Debug)]
pub struct MeshInfoArgs {
    /// Input file: .obj, .stl, .ply or .patches.
    pub input: PathBuf,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// `octsolid mesh-info IN [--json]`
pub fn run(a: &MeshInfoArgs, budget: MemoryBudget) -> Result<()> {
    let (input, json) = (&a.input, a.json);
    let report = read_input(input)?.report(budget).with_context(|| format!("{}: cannot measure", input.display()))?;
    if json {
        out!("{}", serde_json::to_string(&report)?);
        return Ok(());
    }
    out!("file               {}", input.display());
    out!("vertices           {}", report.vertices);
    out!("triangles          {}", report.triangles);
    out!("edges              {}", report.edges);
    out!("degenerate faces   {}", report.degenerate_faces);
    out!("boundary edges     {}", report.boundary_edges);
    out!("non-manifold edges {}", report.non_manifold_edges);
    out!("misoriented edges  {}", report.misoriented_edges);
    out!("watertight         {}", if report.watertight { "yes" } else { "no" });
    out!(
        "volume             {:.6} (signed tetrahedra{})",
        report.volume,
        if report.watertight { "" } else { "; not closed" }
    );
    out!("area               {:.6}", report.area);
    out!("bounds             {} .. {}", crate::human::point(report.bounds_min), crate::human::point(report.bounds_max));
    for (name, count) in &report.groups {
        out!("group              {name:?}: {count} triangles");
    }
    Ok(())
}
