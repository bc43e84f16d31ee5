//! `octsolid demo`: the bundled showcase scene, voxelized and ray-traced.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use glam::DVec3;
use octsolid::MemoryBudget;
use octsolid::io::png;
use octsolid::octree::VoxelizeOptions;
use octsolid::render::{Camera, DEFAULT_VIEW, RenderOptions};
use octsolid::samples;

use super::render_with_bar;
use crate::progress_bar::Bar;

/// Arguments of `octsolid demo`.
#[derive(clap::Args, Debug)]
pub struct DemoArgs {
    /// Output image.
    #[arg(short, long, default_value = "demo.png")]
    pub output: PathBuf,
    /// Octree depth of the showcase solid.
    #[arg(long, default_value_t = 9)]
    pub depth: u8,
}

/// `octsolid demo`: the showcase scene, voxelized and ray-traced.
pub fn run(a: &DemoArgs, budget: MemoryBudget) -> Result<()> {
    let (output, depth) = (&a.output, a.depth);
    if output.extension().is_none_or(|e| !e.eq_ignore_ascii_case("png")) {
        bail!("{}: the demo writes a PNG image; give a .png path", output.display());
    }
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
    let options = RenderOptions { width: 1200, height: 720, spp: 3, budget, ..Default::default() };
    let camera = Camera::frame(&bounds, DEFAULT_VIEW, DVec3::Z, f64::from(options.width) / f64::from(options.height));
    let img = render_with_bar(&scene, &camera, &options)?;
    png::save(&img, output)?;
    out!("wrote {} ({}x{})", output.display(), img.width(), img.height());
    Ok(())
}
