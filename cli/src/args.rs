//! Flag definitions: the help text comes from here.

use std::path::PathBuf;

use clap::{Parser, Subcommand, ValueEnum};
use glam::DVec3;
use octsolid::shape::ShapeSpec;

/// octsolid: solid modeling on linear octrees.
#[derive(Parser, Debug)]
#[command(name = "octsolid", version, about, long_about = None)]
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
    Shape(ShapeArgs),
    /// Combine .oct files by a set operation.
    Csg {
        /// The operation (difference: the first minus all the others).
        op: CsgOp,
        /// Input .oct files (at least two), all over the same domain and depth.
        #[arg(required = true, num_args = 2..)]
        inputs: Vec<PathBuf>,
        /// Output .oct file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Print what an .oct file holds.
    Info {
        /// The .oct file.
        file: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Draw a cross-section of an .oct file as a PNG.
    Slice {
        /// The .oct file.
        file: PathBuf,
        /// Axis the cutting plane is perpendicular to.
        #[arg(long, default_value = "z")]
        axis: octsolid::shape::Axis,
        /// World coordinate of the plane along the axis (default: the domain's middle).
        #[arg(long, allow_negative_numbers = true)]
        at: Option<f64>,
        /// Image edge in pixels.
        #[arg(long, default_value_t = 768)]
        size: u32,
        /// Output PNG file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Voxelize a mesh (OBJ, STL, PLY) or a Bezier patch set (.patches) into an .oct file.
    #[command(allow_negative_numbers = true)]
    Voxelize {
        /// Input file: .obj, .stl, .ply or .patches.
        input: PathBuf,
        /// Octree depth (1..=21).
        #[arg(long, default_value_t = 8)]
        depth: u8,
        /// What to keep: the enclosed solid, every voxel the surface touches, or a thin shell.
        #[arg(long, default_value = "solid")]
        fill: octsolid::import::Fill,
        /// Inside rule for solids: parity (watertight meshes), winding (robust), or auto.
        #[arg(long, default_value = "auto")]
        inside: octsolid::mesh::InsideRule,
        /// Domain cube MINX,MINY,MINZ,EDGE (default: the input's bounding cube with a 2% margin).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_domain)]
        domain: Option<[f64; 4]>,
        /// Output .oct file.
        #[arg(short, long)]
        output: PathBuf,
    },
    /// Write the boundary of an .oct solid as a closed, manifold triangle mesh (OBJ, STL, PLY).
    Export {
        /// The .oct file.
        file: PathBuf,
        /// Output mesh: .obj, .stl or .ply.
        #[arg(short, long)]
        output: PathBuf,
        /// One voxel face = two triangles (default: coplanar faces merged into rectangles).
        #[arg(long)]
        unit_faces: bool,
    },
    /// Print a mesh's polygon-table diagnostics: edges, holes, non-manifold edges, volume.
    MeshInfo {
        /// Input file: .obj, .stl, .ply or .patches.
        input: PathBuf,
        /// Print one JSON object instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Render a scene file (.toml), an .oct file, or a mesh (voxelized first) to a PNG.
    Render(RenderArgs),
    /// Octree traversal against the BVH crates obvhs and bvh: build time, bytes, rays a second.
    Bench {
        /// Write the report: the section of --out between its bvh-report markers, and plots in docs/images/ beside it.
        #[arg(long)]
        report: bool,
        /// A smaller matrix (depths 8 and 10, fewer rays, fewer runs).
        #[arg(long)]
        quick: bool,
        /// The Markdown file of the report.
        #[arg(long, default_value = "BENCHMARKS.md")]
        out: PathBuf,
        /// Threads of the "all threads" runs (default: all hardware threads).
        #[arg(long)]
        threads: Option<usize>,
        /// Folder holding stanford-bunny.obj.
        #[arg(long, default_value = "models")]
        models: PathBuf,
    },
    /// Build the bundled showcase scene and render it to demo.png.
    Demo {
        /// Output image.
        #[arg(short, long, default_value = "demo.png")]
        output: PathBuf,
        /// Octree depth of the showcase solid.
        #[arg(long, default_value_t = 9)]
        depth: u8,
    },
}

/// Visibility methods of `render`.
/// Polygon interpolation shading.
#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum Shading {
    /// One colour a triangle.
    Flat,
    /// Vertex colours interpolated.
    Gouraud,
    /// Vertex normals interpolated, lit at every pixel.
    Phong,
}

impl From<Shading> for octsolid::render::polygon::Interpolation {
    fn from(s: Shading) -> Self {
        match s {
            Shading::Flat => Self::Flat,
            Shading::Gouraud => Self::Gouraud,
            Shading::Phong => Self::Phong,
        }
    }
}

/// Shading normals.
#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum Normals {
    /// The entered voxel face's axis normal.
    Axis,
    /// The source shape's normal where the solid has one, else the octree's estimate.
    Smooth,
    /// Estimated from the octree's occupancy around the hit, always.
    Octree,
}

impl From<Normals> for octsolid::render::Normals {
    fn from(n: Normals) -> Self {
        match n {
            Normals::Axis => octsolid::render::Normals::Axis,
            Normals::Smooth => octsolid::render::Normals::Smooth,
            Normals::Octree => octsolid::render::Normals::Octree,
        }
    }
}

#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum Method {
    /// Ray tracing through the octree.
    Trace,
    /// Meagher's front-to-back octree display.
    FrontToBack,
    /// Painter's algorithm (far to near, overwrite).
    Painter,
    /// Z-buffer.
    Zbuffer,
    /// Scan-line Z-buffer (polygon, edge, active polygon and active edge tables).
    Scanline,
}

impl From<Method> for octsolid::render::Method {
    fn from(m: Method) -> Self {
        match m {
            Method::Trace => octsolid::render::Method::Trace,
            Method::FrontToBack => octsolid::render::Method::FrontToBack,
            Method::Painter => octsolid::render::Method::Painter,
            Method::Zbuffer => octsolid::render::Method::ZBuffer,
            Method::Scanline => octsolid::render::Method::ScanLine,
        }
    }
}

/// A set operation over files.
#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum CsgOp {
    /// Voxels in any input.
    Union,
    /// Voxels in every input.
    Intersect,
    /// Voxels in the first input and no other.
    Difference,
    /// Voxels in an odd number of inputs.
    Xor,
}

/// The primitive kinds of `octsolid shape`.
#[derive(ValueEnum, Clone, Copy, Debug)]
pub enum ShapeKind {
    /// Ball of --radius.
    Sphere,
    /// Ellipsoid filling a box of --size.
    Ellipsoid,
    /// Box of --size.
    Box,
    /// Capped cylinder of --radius and --height along --axis.
    Cylinder,
    /// Capped cone of base --radius and --height along --axis (apex towards +axis).
    Cone,
    /// Torus of --radius (centre to tube centre) and --tube radius around --axis.
    Torus,
}

/// Arguments of `octsolid shape`.
#[derive(clap::Args, Debug)]
#[command(allow_negative_numbers = true)]
pub struct ShapeArgs {
    /// Which shape.
    pub kind: ShapeKind,
    /// Radius (sphere, cylinder, cone base, torus centre line).
    #[arg(long, default_value_t = 1.0)]
    pub radius: f64,
    /// Box edge lengths, or the ellipsoid's bounding box.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_vec3, default_value = "2,2,2")]
    pub size: [f64; 3],
    /// Height of a cylinder or cone.
    #[arg(long, default_value_t = 2.0)]
    pub height: f64,
    /// Tube radius of a torus.
    #[arg(long, default_value_t = 0.25)]
    pub tube: f64,
    /// Axis of a cylinder, cone or torus.
    #[arg(long, default_value = "z")]
    pub axis: octsolid::shape::Axis,
    /// Centre of the shape's bounding box.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_vec3, default_value = "0,0,0")]
    pub center: [f64; 3],
    /// Octree depth (1..=21): 2^depth voxels a side.
    #[arg(long, default_value_t = 8)]
    pub depth: u8,
    /// Domain cube MINX,MINY,MINZ,EDGE (default: a cube around the shape).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_domain)]
    pub domain: Option<[f64; 4]>,
    /// Output .oct file.
    #[arg(short, long)]
    pub output: PathBuf,
}

impl ShapeArgs {
    /// The flags as a shape specification, the form scene files write: the ellipsoid
    /// fills the box of `--size`, the cone's base sits `--height / 2` below `--center`.
    #[must_use]
    pub fn spec(&self) -> ShapeSpec {
        let (center, axis, radius, height) = (self.center, self.axis, self.radius, self.height);
        match self.kind {
            ShapeKind::Sphere => ShapeSpec::Sphere { center, radius },
            ShapeKind::Ellipsoid => {
                ShapeSpec::Ellipsoid { center, radii: (DVec3::from_array(self.size) * 0.5).to_array() }
            }
            ShapeKind::Box => ShapeSpec::Box { center, size: self.size },
            ShapeKind::Cylinder => ShapeSpec::Cylinder { center, axis, radius, height },
            ShapeKind::Cone => {
                let base = DVec3::from_array(center) - axis.unit() * (height * 0.5);
                ShapeSpec::Cone { base: base.to_array(), axis, radius, height }
            }
            ShapeKind::Torus => ShapeSpec::Torus { center, axis, radius, tube: self.tube },
        }
    }
}

/// Arguments of `octsolid render`.
#[derive(clap::Args, Debug)]
pub struct RenderArgs {
    /// Scene (.toml), solid (.oct) or mesh (.obj, .stl, .ply, .patches).
    pub input: PathBuf,
    /// Output PNG (default: the input's name with .png, in the current folder).
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Image size WIDTHxHEIGHT (default: the scene's, or 960x720).
    #[arg(long, value_parser = parse_size)]
    pub size: Option<[u32; 2]>,
    /// Samples a pixel side: N x N stratified samples (default: the scene's, or 2).
    #[arg(long)]
    pub spp: Option<u32>,
    /// How primary visibility is decided.
    #[arg(long, default_value = "trace")]
    pub method: Method,
    /// Depth to voxelize a mesh at.
    #[arg(long, default_value_t = 9)]
    pub depth: u8,
    /// The world's up axis for solids and meshes without a scene (default by the
    /// file's extension: y for .obj and .ply, y-up by convention, as the bunny and
    /// Spot are; z otherwise, as octsolid's shapes are: pass --up z to view a shape
    /// exported to .obj or .ply as it was built).
    #[arg(long)]
    pub up: Option<octsolid::shape::Axis>,
    /// Skip shadow rays.
    #[arg(long)]
    pub no_shadows: bool,
    /// Shading normals: axis (the voxel faces'), smooth (the source shape's where a
    /// solid has one, else estimated from the octree) or octree (always estimated).
    #[arg(long)]
    pub normals: Option<Normals>,
    /// Longest chain of reflected and refracted rays (default: the scene's, or 6).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Render a mesh (or Bezier patches, tessellated) as polygons with this
    /// interpolation shading instead of voxelizing it.
    #[arg(long)]
    pub shading: Option<Shading>,
}

/// Parses `X,Y,Z`.
fn parse_vec3(s: &str) -> Result<[f64; 3], String> {
    let v = parse_floats(s, 3)?;
    Ok([v[0], v[1], v[2]])
}

/// Parses `WIDTHxHEIGHT`.
fn parse_size(s: &str) -> Result<[u32; 2], String> {
    let (w, h) = s.split_once(['x', 'X']).ok_or_else(|| format!("'{s}' is not a size like 960x720"))?;
    let parse = |t: &str| t.trim().parse::<u32>().map_err(|_| format!("'{t}' is not a whole number of pixels"));
    Ok([parse(w)?, parse(h)?])
}

/// Parses `MINX,MINY,MINZ,EDGE`.
fn parse_domain(s: &str) -> Result<[f64; 4], String> {
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
fn parse_bytes(s: &str) -> Result<u64, String> {
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
