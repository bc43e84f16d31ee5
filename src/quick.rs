//! One call from a solid to a picture file, for library users who want to look at a
//! solid without setting up a scene: [`quick`]. It is `octsolid render solid.oct`
//! without flags, made of the same library calls, so the two write the same bytes: the
//! default scene of a solid ([`Scene::of_solid`]: default material and lights, z up),
//! the camera of an empty [`CameraRequest`] over the solid's silhouette
//! ([`Framing::of_solid`]: the silhouette fills the picture from
//! [`Camera::default_view`](crate::render::Camera::default_view)), the default options
//! ([`RenderOptions::default`]), the picture of linear radiance encoded as 8-bit sRGB.
//! It sits above `render` and `io`, since it writes a file.

use std::path::Path;

use crate::error::{Error, Result};
use crate::io::png;
use crate::octree::LinearOctree;
use crate::progress::NoProgress;
use crate::render::{CameraRequest, Framing, RenderOptions, RenderStats, Scene, Up, render_picture};

/// Renders `solid` to the PNG file `path` as `octsolid render solid.oct -o path` does
/// (see the module doc): 960x720, 2x2 samples a pixel, shadows and smooth normals.
/// Returns what the render did.
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
/// let stats = octsolid::quick(&ball, &path)?;
/// assert!(stats.hits > 0);
/// # std::fs::remove_file(&path).ok();
/// # Ok(())
/// # }
/// ```
pub fn quick(solid: &LinearOctree, path: impl AsRef<Path>) -> Result<RenderStats> {
    if solid.is_empty() {
        return Err(Error::invalid("solid", "it is empty: there is nothing to frame"));
    }
    let up = Up::default();
    let framing = Framing::of_solid(solid, up);
    let options = RenderOptions::default();
    let aspect = f64::from(options.width) / f64::from(options.height);
    let camera = CameraRequest::default().camera(&framing, aspect)?;
    let scene = Scene::of_solid(solid.clone(), "solid", up);
    let (picture, stats) = render_picture(&scene, &camera, &options, &NoProgress)?;
    png::write(&picture.to_srgb8(), path)?;
    Ok(stats)
}
