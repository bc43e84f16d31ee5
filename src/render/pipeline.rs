//! Making a picture: primary visibility of every sample (by any [`Method`]), then the
//! one shading stage (local Phong and Whitted's secondary rays), with `n x n` stratified
//! supersampling (sample centres of an `n x n` grid in the pixel). A render makes a
//! [`Picture`] of linear radiance (each pixel's mean times the exposure's `2^stops`);
//! [`render`] gives it as the 8-bit sRGB picture a PNG holds.

use image::RgbImage;
use rayon::prelude::*;

use glam::DVec3;

use super::adaptive;
use super::film::resolve::{exposure_scale, resolve};
use super::film::{Camera, Picture, SampleGrid};
use super::scene::{Scene, SceneHit};
use super::shade::{Normals, ShadeOptions, radiance};
use super::visibility::{Method, visibility};
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::progress::Progress;

/// Largest image edge in pixels.
pub const MAX_IMAGE_SIZE: u32 = 16_384;
/// Longest chain of secondary rays: the shading recursion's depth, bounded so that a
/// hall of mirrors cannot overflow a thread's stack.
pub const MAX_RAY_DEPTH: u32 = 64;

/// The adaptive anti-aliasing threshold when none is given: POV-Ray's common `+A0.3`.
pub const DEFAULT_AA_THRESHOLD: f64 = 0.3;

/// How a pixel's samples are chosen.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum AntiAliasing {
    /// `spp x spp` samples in every pixel.
    #[default]
    Uniform,
    /// One sample a pixel, then `spp x spp` where the contrast with a neighbour is at
    /// least `threshold` (see the `adaptive` module: POV-Ray's `+A` method 1).
    Adaptive {
        /// Contrast that triggers supersampling: the sum of the red, green and blue
        /// differences of two neighbouring pixels, displayed values in `[0, 1]`.
        threshold: f64,
    },
}

/// Image size and quality.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RenderOptions {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Samples a pixel side: `spp x spp` stratified samples (in every pixel, or in the
    /// pixels adaptive anti-aliasing picks).
    pub spp: u32,
    /// Uniform or adaptive supersampling.
    pub aa: AntiAliasing,
    /// Trace shadow rays.
    pub shadows: bool,
    /// Which normal shades surfaces (default [`Normals::Smooth`]).
    pub normals: Normals,
    /// Longest chain of reflected and refracted rays (0: local shading only).
    pub max_depth: u32,
    /// How primary visibility is decided.
    pub method: Method,
    /// Refuse a picture whose sample buffers would exceed this, before allocating.
    pub budget: MemoryBudget,
    /// Exposure in stops: every pixel's radiance is scaled by `2^exposure` (finite,
    /// within [`MAX_EXPOSURE_STOPS`](super::film::MAX_EXPOSURE_STOPS); default 0, no
    /// change). Adaptive anti-aliasing compares the exposed pixels.
    pub exposure: f64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 960,
            height: 720,
            spp: 2,
            aa: AntiAliasing::Uniform,
            shadows: true,
            normals: Normals::default(),
            max_depth: ShadeOptions::default().max_depth,
            method: Method::Trace,
            budget: MemoryBudget::default(),
            exposure: 0.0,
        }
    }
}

/// What a render did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Samples (primary rays for the tracer).
    pub samples: u64,
    /// Samples that see a solid.
    pub hits: u64,
    /// Voxel faces drawn by a raster method (0 when ray tracing).
    pub faces_drawn: u64,
    /// Rays cast by the shading stage: reflected, refracted and shadow rays (the
    /// samples are the primary rays).
    pub secondary_rays: u64,
    /// Pixels given `spp x spp` samples by adaptive anti-aliasing (every pixel when
    /// uniform).
    pub supersampled: u64,
}

/// The memory a picture's buffers take: a hit record and a depth a sample (what
/// every visibility method keeps), and the finished rows of linear radiance.
#[must_use]
pub fn estimate_bytes(samples: &SampleGrid) -> u64 {
    let count = u64::from(samples.columns()) * u64::from(samples.rows());
    let per_sample = (std::mem::size_of::<Option<SceneHit>>() + std::mem::size_of::<f64>()) as u64;
    let per_pixel = std::mem::size_of::<DVec3>() as u64;
    count.saturating_mul(per_sample) + u64::from(samples.width) * u64::from(samples.height) * per_pixel
}

/// Renders `scene` through `camera` as [`render_picture`] does, encoded as 8-bit sRGB
/// ([`Picture::to_srgb8`]): the picture a PNG holds.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    progress: &dyn Progress,
) -> Result<(RgbImage, RenderStats)> {
    let (picture, stats) = render_picture(scene, camera, options, progress)?;
    Ok((picture.to_srgb8(), stats))
}

/// Renders `scene` through `camera` to linear radiance: visibility of every sample by
/// `options.method`, then the shading stage, each pixel the mean of its samples times
/// `2^options.exposure`; progress counts shaded rows.
pub fn render_picture(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    progress: &dyn Progress,
) -> Result<(Picture, RenderStats)> {
    let RenderOptions { width, height, spp, aa, shadows, normals, max_depth, exposure, .. } = *options;
    if !(1..=MAX_IMAGE_SIZE).contains(&width) || !(1..=MAX_IMAGE_SIZE).contains(&height) {
        return Err(Error::invalid("image size", format!("{width}x{height} is outside 1..={MAX_IMAGE_SIZE} a side")));
    }
    if !(1..=16).contains(&spp) {
        return Err(Error::invalid("samples", format!("{spp} a side is outside 1..=16")));
    }
    if max_depth > MAX_RAY_DEPTH {
        return Err(Error::invalid("max depth", format!("{max_depth} is above the limit of {MAX_RAY_DEPTH}")));
    }
    camera.check()?;
    let scale = exposure_scale(exposure)?;
    let shading = ShadeOptions { shadows, normals, max_depth, ..ShadeOptions::default() };
    match aa {
        AntiAliasing::Adaptive { threshold } if !(threshold.is_finite() && threshold >= 0.0) => {
            Err(Error::invalid("anti-aliasing threshold", format!("{threshold} must be finite and at least 0")))
        }
        AntiAliasing::Adaptive { threshold } if spp > 1 => {
            // One sample a pixel, then the pixels that differ from a neighbour.
            let first = RenderOptions { spp: 1, aa: AntiAliasing::Uniform, ..*options };
            let (mut picture, stats) = uniform(scene, camera, &first, &shading, scale, &crate::NoProgress)?;
            let refine = adaptive::needs_samples(&picture.to_srgb8(), threshold);
            let film = adaptive::Film { samples: SampleGrid { width, height, spp }, scale };
            let (hits, rays) = adaptive::supersample(scene, camera, film, &shading, &refine, &mut picture, progress);
            let supersampled = refine.iter().filter(|&&r| r).count() as u64;
            let stats = RenderStats {
                samples: stats.samples + supersampled * u64::from(spp * spp),
                hits: stats.hits + hits,
                secondary_rays: stats.secondary_rays + rays,
                supersampled,
                ..stats
            };
            Ok((picture, stats))
        }
        _ => uniform(scene, camera, options, &shading, scale, progress),
    }
}

/// `spp x spp` samples in every pixel: the visibility of every sample, then shading;
/// each pixel's mean times `scale`.
fn uniform(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    shading: &ShadeOptions,
    scale: f64,
    progress: &dyn Progress,
) -> Result<(Picture, RenderStats)> {
    let RenderOptions { width, height, spp, method, budget, .. } = *options;
    let samples = SampleGrid { width, height, spp };
    budget.check(format!("a {width}x{height} picture at {spp}x{spp} samples a pixel"), estimate_bytes(&samples))?;
    // Step 1: what each sample sees.
    let (seen, visible) = visibility(scene, camera, &samples, method);
    // Step 2: shading, the same for every method, averaged over each pixel's samples.
    progress.start(u64::from(height));
    let columns = samples.columns() as usize;
    // The camera's frame once, not once a sample (`Camera::ray` is `view(aspect).ray`).
    let view = camera.view(samples.aspect());
    let rows: Vec<(Vec<DVec3>, u64)> = (0..height)
        .into_par_iter()
        .map(|row| {
            let mut rays = 0;
            let pixels = (0..width)
                .map(|col| {
                    let mut sum = DVec3::ZERO;
                    for sy in 0..spp {
                        for sx in 0..spp {
                            let (c, r) = (col * spp + sx, row * spp + sy);
                            let (x, y) = samples.point(c, r);
                            sum += match &seen[r as usize * columns + c as usize] {
                                Some(h) => {
                                    let (light, cast) = radiance(scene, &view.ray(x, y), h, shading);
                                    rays += cast;
                                    light
                                }
                                None => scene.background,
                            };
                        }
                    }
                    resolve(sum, spp * spp, scale)
                })
                .collect();
            progress.advance(1);
            (pixels, rays)
        })
        .collect();
    progress.finish();
    let secondary_rays = rows.iter().map(|(_, rays)| rays).sum();
    let mut picture = Picture::new(width, height);
    for (row, (pixels, _)) in rows.into_iter().enumerate() {
        for (col, p) in pixels.into_iter().enumerate() {
            picture.set(col as u32, row as u32, p);
        }
    }
    let stats = RenderStats {
        samples: seen.len() as u64,
        hits: seen.iter().filter(|s| s.is_some()).count() as u64,
        faces_drawn: visible.faces_drawn,
        secondary_rays,
        supersampled: if spp > 1 { u64::from(width) * u64::from(height) } else { 0 },
    };
    Ok((picture, stats))
}
