//! One file a subcommand: its flags (a `clap::Args` struct) and its `run`, which
//! validates them, makes one library call and prints a summary; and the summaries
//! several commands share.

pub mod bench;
pub mod build;
pub mod convert;
pub mod csg;
pub mod demo;
pub mod export;
pub mod hull;
pub mod info;
pub mod join;
pub mod mesh_info;
pub mod offset;
pub mod radiosity;
pub mod render;
pub mod shape;
pub mod slice;
pub mod transform;
pub mod view;
pub mod voxelize;

use std::time::Instant;

use std::path::Path;

use anyhow::Result;
use octsolid::Warning;
use octsolid::import::Input;
use octsolid::octree::{Clipping, Domain, LinearOctree, VoxelizeOptions, voxelize};
use octsolid::render::{Camera, Picture, RenderOptions, Scene};
use octsolid::shape::Shape;
use octsolid::surface::HermiteData;
use octsolid::{FileKind, MemoryBudget, human_bytes};

use crate::progress_bar::Bar;

/// Loads a mesh or patch set, printing what the loader read past to stderr.
pub(crate) fn read_input(path: &Path) -> Result<Input> {
    let (input, warnings) = Input::read_and_warnings(path)?;
    print_warnings(&warnings);
    Ok(input)
}

/// Prints each warning to stderr as `warning: FILE: PLACE: message`.
pub(crate) fn print_warnings(warnings: &[Warning]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Voxelizes with a progress bar and prints the time taken.
pub(crate) fn voxelize_with_bar(shape: &dyn Shape, domain: Domain, budget: MemoryBudget) -> Result<LinearOctree> {
    let bar = Bar::new("voxelizing");
    let started = Instant::now();
    let tree = voxelize(shape, domain, &VoxelizeOptions { budget, progress: &bar })?;
    out!("voxelized at depth {} in {:.1} ms", domain.depth(), started.elapsed().as_secs_f64() * 1e3);
    Ok(tree)
}

/// Whether a file written as `output` uses the solid's surface data
/// ([`FileKind::uses_surface`]).
pub(crate) fn uses_surface(output: &Path) -> bool {
    FileKind::of(output, FileKind::SOLID_OUTPUTS).is_ok_and(FileKind::uses_surface)
}

/// The surface data of `shape` on the boundary faces of `tree`, its voxelization, when
/// `output` uses it ([`uses_surface`]: an `.oct` file stores it, a mesh is contoured on
/// it; [`HermiteData::from_shape`]), with the time it took printed; `None` for other
/// outputs.
pub(crate) fn surface_for(
    output: &Path,
    shape: &(impl Shape + ?Sized),
    tree: &LinearOctree,
) -> Result<Option<HermiteData>> {
    if !uses_surface(output) {
        return Ok(None);
    }
    let started = Instant::now();
    let surface = HermiteData::from_shape_with(shape, tree, &Bar::new("surface"))?;
    let ms = started.elapsed().as_secs_f64() * 1e3;
    out!("surface    {} boundary faces' crossings and normals from the shape in {ms:.1} ms", surface.len());
    Ok(Some(surface))
}

/// Warns when `result` reaches a face of its domain that `input` kept clear of (what
/// the operation made past it is cut off), or is empty when `input` was not
/// ([`octsolid::octree::clipping`]).
pub(crate) fn warn_if_clipped(input: &LinearOctree, result: &LinearOctree, what: &str) {
    let domain = result.domain();
    match octsolid::octree::clipping(input, result) {
        None => {}
        Some(Clipping::Emptied) => warn!("the {what} is empty: no voxel is left"),
        Some(Clipping::AtFaces(_)) => warn!(
            "the {what} reaches the edge of the domain (min {}, edge {}): what lies past it is cut off; give the \
             input a larger domain first (transform IN --domain MINX,MINY,MINZ,EDGE -o OUT)",
            crate::human::point(domain.min()),
            crate::human::num(domain.edge())
        ),
    }
}

/// Prints nodes, voxels, volume (with the exact one when known), bounds and memory.
pub(crate) fn print_summary(tree: &LinearOctree, exact_volume: Option<f64>) {
    out!("nodes      {}", tree.node_count());
    out!("voxels     {}", tree.voxel_count());
    match exact_volume {
        Some(v) => {
            out!("volume     {:.6} (analytic {:.6}, {:+.3}%)", tree.volume(), v, 100.0 * (tree.volume() - v) / v)
        }
        None => out!("volume     {:.6}", tree.volume()),
    }
    match tree.bounds() {
        Some(b) => out!("bounds     {} .. {}", crate::human::point(b.min), crate::human::point(b.max)),
        None => out!("bounds     (empty)"),
    }
    let per_node = if tree.node_count() == 0 { 0.0 } else { tree.bytes() as f64 / tree.node_count() as f64 };
    out!("in memory  {} ({per_node:.2} bytes a node)", human_bytes(tree.bytes() as u64));
}

/// Renders with a progress bar and prints samples and rays a second (and faces drawn by
/// a raster method).
pub(crate) fn render_with_bar(scene: &Scene, camera: &Camera, options: &RenderOptions) -> Result<Picture> {
    let bar = Bar::new("rendering");
    let started = Instant::now();
    let (picture, stats) = octsolid::render::render_picture(scene, camera, options, &bar)?;
    let seconds = started.elapsed().as_secs_f64();
    let secondary = stats.secondary_rays;
    // Every sample is a primary ray: walked, or answered by the front-to-back display.
    let rays = stats.samples + secondary;
    let rate = rays as f64 / seconds / 1e6;
    // Recursive anti-aliasing walks every primary ray, whatever the method.
    let method = match options.aa {
        octsolid::render::AntiAliasing::Recursive { .. } => octsolid::render::Method::Trace,
        _ => options.method,
    };
    let walked = if method == options.method { "" } else { ", its corner samples traced whatever --method" };
    let visibility = match method {
        octsolid::render::Method::Trace => {
            format!("{rays} rays: {} primary, {secondary} secondary and shadow; {rate:.2} M rays/s", stats.samples)
        }
        octsolid::render::Method::FrontToBack => format!(
            "{rays} rays: {} primary ({} faces drawn), {secondary} secondary and shadow; {rate:.2} M rays/s",
            stats.samples, stats.faces_drawn
        ),
        _ => format!("{} faces drawn, {secondary} secondary and shadow rays", stats.faces_drawn),
    };
    let sampling = match options.aa {
        octsolid::render::AntiAliasing::Uniform => format!("{}x{} samples a pixel", options.spp, options.spp),
        octsolid::render::AntiAliasing::Adaptive { threshold } => format!(
            "adaptive anti-aliasing (threshold {threshold}: {}x{} samples in {} of {} pixels)",
            options.spp,
            options.spp,
            stats.supersampled,
            u64::from(options.width) * u64::from(options.height)
        ),
        octsolid::render::AntiAliasing::Recursive { threshold, depth } => format!(
            "recursive anti-aliasing (threshold {threshold}, depth {depth}: {} of {} pixels split)",
            stats.supersampled,
            u64::from(options.width) * u64::from(options.height)
        ),
    };
    out!(
        "rendered {}x{} at {sampling}{walked} by {} in {:.2} s ({:.2} M samples/s; {visibility})",
        options.width,
        options.height,
        crate::human::method(method),
        seconds,
        stats.samples as f64 / seconds / 1e6,
    );
    if options.exposure != 0.0 {
        out!("exposure {:+} stops (radiance times {})", options.exposure, options.exposure.exp2());
    }
    Ok(picture)
}
