//! The command line: global flags and the subcommands (each defined with its flags in
//! `commands/`), and the parsers of values that several subcommands take. The help
//! text comes from these definitions.

use clap::{Parser, Subcommand};
use glam::DVec3;
use octsolid::octree::Turn;
use octsolid::shape::Axis;

use crate::commands::{
    bench, csg, demo, export, info, mesh_info, radiosity, render, shape, slice, transform, voxelize,
};

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
    /// Combine .oct files by a set operation (bringing them into one domain first).
    Csg(csg::CsgArgs),
    /// Move, turn or scale an .oct solid, or bring it into another domain or depth.
    Transform(transform::TransformArgs),
    /// Print what an .oct file holds and measure it (area, centre of mass, inertia, components).
    Info(info::InfoArgs),
    /// Draw a cross-section of an .oct file as a PNG.
    Slice(slice::SliceArgs),
    /// Voxelize a mesh (OBJ, STL, PLY) or a Bezier patch set (.patches) into an .oct file.
    Voxelize(voxelize::VoxelizeArgs),
    /// Write the boundary of an .oct solid as a closed, manifold triangle mesh (OBJ, STL, PLY).
    ///
    /// Where voxels touch only along an edge or at a corner the mesh keeps one vertex
    /// for each sheet of the surface. OBJ and PLY store those vertices as they are. STL
    /// stores only positions, and readers join equal ones, so there each copy is moved
    /// by a thousandth of its shortest edge towards its own faces (more, up to a
    /// sixteenth, where f32 coordinates are too coarse for that; beyond, the export is
    /// refused). The STL reads back closed and manifold; each moved vertex changes its
    /// volume by at most the step times a third of the area of its faces (under 6e-4
    /// voxel volumes at a voxel corner of --unit-faces).
    Export(export::ExportArgs),
    /// Print a mesh's polygon-table diagnostics: edges, holes, non-manifold edges, volume.
    MeshInfo(mesh_info::MeshInfoArgs),
    /// Render a scene file (.toml), an .oct file, or a mesh (voxelized first) to a PNG.
    Render(render::RenderArgs),
    /// Solve a scene's diffuse interreflection (radiosity) and save the solution (.rad).
    Radiosity(radiosity::RadiosityArgs),
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

/// Parses `AXIS,DEG` (x, y or z, and an angle in degrees).
pub(crate) fn parse_turn(s: &str) -> Result<Turn, String> {
    let (axis, degrees) = s.split_once(',').ok_or_else(|| format!("'{s}' is not AXIS,DEG like z,90"))?;
    let axis = axis.trim().parse::<Axis>().map_err(|e| format!("'{s}': {e}"))?;
    let degrees = parse_floats(degrees, 1)?[0];
    Ok(Turn { axis, degrees })
}

/// Parses the up direction: an axis (`x`, `y`, `z`) or a vector `X,Y,Z`.
pub(crate) fn parse_up(s: &str) -> Result<Up, String> {
    if let Ok(axis) = s.trim().parse::<Axis>() {
        return Ok(Up::Axis(axis));
    }
    let v = DVec3::from(parse_vec3(s).map_err(|e| format!("'{s}' is neither x, y, z nor X,Y,Z: {e}"))?);
    if v.length() < 1e-12 {
        return Err(format!("'{s}': the up vector is zero"));
    }
    Ok(Up::Vector(v))
}

/// An up direction from the command line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Up {
    /// A coordinate axis: also names the frame of `--view` and the orbit angles.
    Axis(Axis),
    /// Any vector: views are named in the frame of the axis nearest to it.
    Vector(DVec3),
}

impl Up {
    /// The nearest coordinate axis (the frame views are named in).
    pub(crate) fn axis(self) -> Axis {
        match self {
            Up::Axis(a) => a,
            Up::Vector(v) => {
                let a = v.abs();
                if a.x >= a.y && a.x >= a.z {
                    Axis::X
                } else if a.y >= a.z {
                    Axis::Y
                } else {
                    Axis::Z
                }
            }
        }
    }

    /// The up vector.
    pub(crate) fn vector(self) -> DVec3 {
        match self {
            Up::Axis(a) => a.unit(),
            Up::Vector(v) => v.normalize(),
        }
    }
}

/// Parses `WIDTHxHEIGHT`.
pub(crate) fn parse_size(s: &str) -> Result<[u32; 2], String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("'{s}' is not a size like 960x720"))?;
    let parse = |t: &str| t.trim().parse::<u32>().map_err(|_| format!("'{t}' is not a whole number of pixels"));
    Ok([parse(w)?, parse(h)?])
}

/// Parses one finite number (`nan` and `inf` are refused where they enter).
pub(crate) fn parse_finite(s: &str) -> Result<f64, String> {
    Ok(parse_floats(s, 1)?[0])
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
