//! One call from a solid to a picture file, for library users who want to look at a
//! solid without setting up a scene: [`quick`]. It is `octsolid render solid.oct`
//! without flags, made of the same library calls, so the two write the same bytes: the
//! solid's [`Drawing`] ([`Drawing::of_solid`], what `render` opens a file of one solid
//! without a colour as: the default scene of a solid, default material and lights, z
//! up, framed by its silhouette), the camera of an empty [`CameraRequest`] (the
//! silhouette fills the picture from
//! [`Camera::default_view`](crate::render::Camera::default_view)), the options of no
//! [`RenderOverrides`] (the defaults), the picture of linear radiance encoded as 8-bit
//! sRGB. It sits above `drawing` and `io`, since it writes a file.

use std::path::Path;

use crate::budget::MemoryBudget;
use crate::drawing::Drawing;
use crate::error::Result;
use crate::io::png;
use crate::octree::LinearOctree;
use crate::progress::NoProgress;
use crate::render::{CameraRequest, RenderOverrides, RenderStats, Up, render_picture};

/// Renders `solid` to the PNG file `path` as `octsolid render solid.oct -o path` does
/// (see the module doc): 960x720, 2x2 samples a pixel, shadows and smooth normals.
/// Returns what the render did.
///
/// # Errors
/// [`Error::InvalidArgument`](crate::Error::InvalidArgument) for an empty solid
/// (nothing to frame), [`Error::Io`](crate::Error::Io)
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
    let drawing = Drawing::of_solid(solid.clone(), "solid", Up::default())?;
    let (request, overrides) = (CameraRequest::default(), RenderOverrides::default());
    let camera = drawing.camera(&request, &overrides, None)?;
    let options = drawing.options(&overrides, MemoryBudget::default());
    let scene = drawing.into_scene(None);
    let (picture, stats) = render_picture(&scene, &camera, &options, &NoProgress)?;
    png::write(&picture.to_srgb8(), path)?;
    Ok(stats)
}
