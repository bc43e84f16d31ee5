//! One call from a solid to a picture file, for library users who want to look at a
//! solid without setting up a scene: [`quick`].

use std::path::Path;

use super::film::{Camera, DEFAULT_VIEW};
use super::pipeline::{RenderOptions, RenderStats, render};
use super::scene::Scene;
use crate::error::{Error, Result};
use crate::io::png;
use crate::octree::LinearOctree;
use crate::progress::NoProgress;

/// Renders `solid` to the PNG file `path` at the default size (960x720, 2x2 samples a
/// pixel: [`RenderOptions::default`]) as `octsolid render solid.oct` does: the scene of
/// [`Scene::from_solid`] (default material and lights), seen by [`Camera::frame`] from
/// [`DEFAULT_VIEW`] with z up, with shadows and the default smooth normals (the
/// octree's estimate). Returns what the render did.
///
/// # Errors
/// [`Error::InvalidArgument`] for an empty solid (nothing to frame), [`Error::Io`]
/// naming `path` when the file cannot be written.
///
/// # Example
/// ```
/// use octsolid::prelude::*;
///
/// # fn main() -> octsolid::Result<()> {
/// let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6)?;
/// let ball = voxelize(&Sphere::new(DVec3::ZERO, 0.8)?, domain, &VoxelizeOptions::default())?;
/// let path = std::env::temp_dir().join(format!("octsolid-quick-doc-{}.png", std::process::id()));
/// let stats = octsolid::render::quick(&ball, &path)?;
/// assert!(stats.hits > 0);
/// # std::fs::remove_file(&path).ok();
/// # Ok(())
/// # }
/// ```
pub fn quick(solid: &LinearOctree, path: impl AsRef<Path>) -> Result<RenderStats> {
    let bounds = solid.bounds().ok_or_else(|| Error::invalid("solid", "it is empty: there is nothing to frame"))?;
    let options = RenderOptions::default();
    let aspect = f64::from(options.width) / f64::from(options.height);
    let camera = Camera::frame(&bounds, DEFAULT_VIEW, glam::DVec3::Z, aspect);
    let (img, stats) = render(&Scene::from_solid(solid.clone()), &camera, &options, &NoProgress)?;
    png::save(&img, path)?;
    Ok(stats)
}
