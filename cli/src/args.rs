//! The command line: global flags and the subcommands (each defined with its flags in
//! `commands/`), and the parsers of values that several subcommands take. The help
//! text comes from these definitions.

use clap::{Parser, Subcommand};

use crate::commands::{bench, csg, demo, export, info, mesh_info, render, shape, slice, voxelize};

/// octsolid: solid modeling on linear octrees.
#[derive(Parser, Debug)]
#[command(name = "octsolid", version, long_about = None)]
pub struct Args {
    /// Refuse jobs whose estimated memory exceeds this (e.g. 512MiB, 8GiB; default: half the RAM).
    #[arg(long, global = true, value_parser = parse_bytes)]
    pub memory_budget: Option<u64>,

    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// Voxelize a primitive shape into an .oct file.
    Shape(shape::ShapeArgs),
    /// Combine .oct files by a set operation.
    Csg(csg::CsgArgs),
    /// Print what an .oct file holds and measure it (area, centre of mass, inertia, components).
    Info(info::InfoArgs),
    /// Draw a cross-section of an .oct file as a PNG.
    Slice(slice::SliceArgs),
    /// Voxelize a mesh (OBJ, STL, PLY) or a Bezier patch set (.patches) into an .oct file.
    Voxelize(voxelize::VoxelizeArgs),
    /// Write the boundary of an .oct solid as a closed, manifold triangle mesh (OBJ, STL, PLY).
    Export(export::ExportArgs),
    /// Print a mesh's polygon-table diagnostics: edges, holes, non-manifold edges, volume.
    MeshInfo(mesh_info::MeshInfoArgs),
    /// Render a scene file (.toml), an .oct file, or a mesh (voxelized first) to a PNG.
    Render(render::RenderArgs),
    /// Octree traversal against the BVH crates obvhs and bvh: build time, bytes, rays a second.
    Bench(bench::BenchArgs),
    /// Build the bundled showcase scene and render it to demo.png.
    Demo(demo::DemoArgs),
}

/// Parses `X,Y,Z`.
pub(crate) fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let v = parse_floats(s, 3)?;
    Ok([v[0], v[1], v[2]])
}

/// Parses `WIDTHxHEIGHT`.
pub(crate) fn parse_size(s: &str) -> Result<[u32; 2], String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("'{s}' is not a size like 960x720"))?;
    let parse = |t: &str| t.trim().parse::<u32>().map_err(|_| format!("'{t}' is not a whole number of pixels"));
    Ok([parse(w)?, parse(h)?])
}

/// Parses `MINX,MINY,MINZ,EDGE`.
pub(crate) fn parse_domain(s: &str) -> Result<[f64; 4], String> {
    let v = parse_floats(s, 4)?;
    Ok([v[0], v[1], v[2], v[3]])
}

fn parse_floats(s: &str, n: usize) -> Result<Vec<f64>, String> {
    let v: Vec<f64> = s
        .split(',')
        .map(|t| t.trim().parse::<f64>().map_err(|_| format!("'{t}' is not a number")))
        .collect::<Result<_, _>>()?;
    if v.len() != n {
        return Err(format!("expected {n} comma-separated numbers, got {}", v.len()));
    }
    if let Some(bad) = v.iter().find(|x| !x.is_finite()) {
        return Err(format!("{bad} is not a finite number"));
    }
    Ok(v)
}

/// Parses a byte size such as `4096`, `512MiB`, `8GiB`, `2G`.
pub(crate) fn parse_bytes(s: &str) -> Result<u64, String> {
    let s = s.trim();
    let split = s.find(|c: char| !c.is_ascii_digit() && c != '.').unwrap_or(s.len());
    let (num, unit) = s.split_at(split);
    let num: f64 = num.parse().map_err(|_| format!("'{s}' is not a size like 512MiB or 8GiB"))?;
    let scale: u64 = match unit.trim().to_ascii_lowercase().as_str() {
        "" | "b" => 1,
        "k" | "kb" | "kib" => 1 << 10,
        "m" | "mb" | "mib" => 1 << 20,
        "g" | "gb" | "gib" => 1 << 30,
        "t" | "tb" | "tib" => 1 << 40,
        other => return Err(format!("unknown unit '{other}' (use B, KiB, MiB, GiB or TiB)")),
    };
    Ok((num * scale as f64) as u64)
}
