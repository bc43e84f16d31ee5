//! `octsolid demo`: the bundled showcase scene, voxelized and ray-traced, to a PNG or
//! an OpenEXR file (by `-o`'s extension).

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use glam::DVec3;
use octsolid::io::write_picture;
use octsolid::octree::VoxelizeOptions;
use octsolid::render::{Camera, DEFAULT_VIEW, RenderOptions};
use octsolid::samples;
use octsolid::{FileKind, MemoryBudget};

use super::render_with_bar;
use crate::output::check_extension;
use crate::progress_bar::Bar;

/// Arguments of `octsolid demo`.
#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// Output picture: .png (8-bit sRGB) or .exr (linear radiance, 32-bit float).
    #[arg(short, long, default_value = "demo.png")]
    pub output: PathBuf,
    /// Exposure in stops: every pixel's radiance is scaled by 2^STOPS before it is
    /// written (default 0).
    #[arg(long, value_name = "STOPS", default_value_t = 0.0, allow_negative_numbers = true,
          value_parser = crate::values::parse_finite)]
    pub exposure: f64,
    /// Octree depth of the showcase solid.
    #[arg(long, default_value_t = 9)]
    pub depth: u8,
}

/// `octsolid demo`: the showcase scene, voxelized and ray-traced.
pub fn run(a: &DemoArgs, budget: MemoryBudget) -> Result<()> {
    let (output, depth) = (&a.output, a.depth);
    check_extension(output, FileKind::PICTURES)?;
    out!("showcase: {}", samples::SCENE_DESCRIPTION);
    let started = Instant::now();
    let bar = Bar::new("voxelizing");
    let scene = samples::showcase_scene(depth, &VoxelizeOptions { budget, progress: &bar })?;
    let nodes: usize = scene.solids.iter().map(|s| s.tree.node_count()).sum();
    out!(
        "voxelized {} solids at depth {depth}: {nodes} nodes in {:.0} ms",
        scene.solids.len(),
        started.elapsed().as_secs_f64() * 1e3
    );
    let bounds = scene.bounds().context("the showcase is empty")?;
    let options =
        RenderOptions { width: 1200, height: 720, spp: 3, budget, exposure: a.exposure, ..Default::default() };
    let camera = Camera::frame(&bounds, DEFAULT_VIEW, DVec3::Z, f64::from(options.width) / f64::from(options.height));
    let picture = render_with_bar(&scene, &camera, &options)?;
    write_picture(&picture, output)?;
    out!("wrote {} ({}x{})", output.display(), picture.width(), picture.height());
    Ok(())
}
