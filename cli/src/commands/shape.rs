//! `octsolid shape KIND ...`: a primitive voxelized into an .oct file.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use clap::ValueEnum;
use glam::DVec3;
use octsolid::io::oct::Metadata;
use octsolid::octree::Domain;
use octsolid::shape::{Shape, ShapeSpec};
use octsolid::sharded;
use octsolid::{FileKind, MemoryBudget, human_bytes};

use super::{print_summary, surface_for, voxelize_with_bar};
use crate::output::{check_extension, write_solid_file};
use crate::sharded_output::{ShardFlags, is_sharded};
use crate::values::{parse_domain, parse_vec3};

/// The depth without `--depth` or `--voxel-size`.
const DEFAULT_DEPTH: u8 = 8;

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
    #[arg(long, default_value_t = 1.0, value_parser = crate::values::parse_finite)]
    pub radius: f64,
    /// Box edge lengths, or the ellipsoid's bounding box.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_vec3, default_value = "2,2,2")]
    pub size: [f64; 3],
    /// Height of a cylinder or cone.
    #[arg(long, default_value_t = 2.0, value_parser = crate::values::parse_finite)]
    pub height: f64,
    /// Tube radius of a torus.
    #[arg(long, default_value_t = 0.25, value_parser = crate::values::parse_finite)]
    pub tube: f64,
    /// Axis of a cylinder, cone or torus.
    #[arg(long, default_value = "z")]
    pub axis: octsolid::shape::Axis,
    /// Centre of the shape's bounding box.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_vec3, default_value = "0,0,0")]
    pub center: [f64; 3],
    /// Octree depth (1..=21): 2^depth voxels a side (default 8; with --voxel-size the
    /// least that holds the shape).
    #[arg(long)]
    pub depth: Option<u8>,
    /// Domain cube MINX,MINY,MINZ,EDGE (default: a cube around the shape).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_domain)]
    pub domain: Option<[f64; 4]>,
    /// A voxel's edge S instead of a domain: voxel planes on the multiples of S, so a
    /// shape whose faces lie on them keeps its dimensions exactly (a 80 mm box at
    /// --voxel-size 0.5 is 80 mm, not 80 give or take half a voxel).
    #[arg(long, conflicts_with = "domain", value_parser = crate::values::parse_finite)]
    pub voxel_size: Option<f64>,
    /// Output file: .oct, a sharded solid (.octs, voxelized cell by cell), or .vox,
    /// .binvox, .vdb, or a mesh (.obj, .stl, .ply, .3mf, .glb).
    #[arg(short, long)]
    pub output: PathBuf,
    #[command(flatten)]
    pub shards: ShardFlags,
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

/// `octsolid shape KIND ...`
pub fn run(a: &ShapeArgs, budget: MemoryBudget) -> Result<()> {
    check_extension(&a.output, FileKind::SOLID_OUTPUTS)?;
    let spec = a.spec();
    let shape = spec.build()?;
    let bounds = || shape.bounds().context("the shape is unbounded; give --domain");
    let depth = a.depth.unwrap_or(DEFAULT_DEPTH);
    let domain = match (a.domain, a.voxel_size) {
        (Some([x, y, z, edge]), _) => Domain::new(DVec3::new(x, y, z), edge, depth)?,
        (None, Some(voxel)) => Domain::on_grid(&bounds()?, voxel, a.depth)?,
        (None, None) => Domain::around(&bounds()?, 0.02, depth)?,
    };
    a.shards.check_for(&a.output)?;
    if is_sharded(&a.output) {
        return a.shards.write(&a.output, budget, Instant::now(), |options| {
            Ok(sharded::voxelize_shape(&shape, domain, Metadata::default(), &a.output, options)?)
        });
    }
    let tree = voxelize_with_bar(&shape, domain, budget)?;
    if tree.is_empty() {
        warn!("the solid is empty: no voxel centre of the shape lies in the domain");
    } else if let (Some(volume), Some(b)) = (spec.volume(), shape.bounds())
        && (b.min.cmplt(domain.aabb().min).any() || b.max.cmpgt(domain.aabb().max).any())
        && tree.volume() < 0.9 * volume
    {
        warn!("the shape reaches past the domain: what lies outside it is cut off");
    }
    let surface = surface_for(&a.output, &shape, &tree)?;
    let bytes = write_solid_file(&a.output, &tree, &Metadata::default(), surface, budget)?;
    out!("wrote {} ({})", a.output.display(), human_bytes(bytes));
    print_summary(&tree, spec.volume());
    Ok(())
}
