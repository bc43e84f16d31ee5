//! Making a picture: primary visibility per sample, then the shading stage, with
//! `n x n` stratified supersampling (sample centres of an `n x n` grid in the pixel).

use image::{Rgb, RgbImage};
use rayon::prelude::*;

use super::camera::Camera;
use super::scene::Scene;
use super::shade::{shade, to_srgb8};
use crate::error::{Error, Result};
use crate::progress::Progress;

/// Largest image edge in pixels.
pub const MAX_IMAGE_SIZE: u32 = 16_384;

/// Image size and quality.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RenderOptions {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Samples a pixel side: `spp x spp` stratified samples.
    pub spp: u32,
    /// Trace shadow rays.
    pub shadows: bool,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { width: 960, height: 720, spp: 2, shadows: true }
    }
}

/// What a render did.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RenderStats {
    /// Primary rays traced.
    pub primary_rays: u64,
    /// Samples that hit a solid.
    pub hits: u64,
}

/// Ray-traces `scene` through `camera`; progress counts rows.
pub fn render(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    progress: &dyn Progress,
) -> Result<(RgbImage, RenderStats)> {
    let RenderOptions { width, height, spp, shadows } = *options;
    if !(1..=MAX_IMAGE_SIZE).contains(&width) || !(1..=MAX_IMAGE_SIZE).contains(&height) {
        return Err(Error::invalid("image size", format!("{width}x{height} is outside 1..={MAX_IMAGE_SIZE} a side")));
    }
    if !(1..=16).contains(&spp) {
        return Err(Error::invalid("samples", format!("{spp} a side is outside 1..=16")));
    }
    let aspect = f64::from(width) / f64::from(height);
    progress.start(u64::from(height));
    let rows: Vec<(Vec<Rgb<u8>>, u64)> = (0..height)
        .into_par_iter()
        .map(|row| {
            let mut hits = 0;
            let pixels = (0..width)
                .map(|col| {
                    let mut sum = glam::DVec3::ZERO;
                    for sy in 0..spp {
                        for sx in 0..spp {
                            // Sample centre of stratum (sx, sy), mapped to [-1, 1]^2, y up.
                            let fx = (f64::from(col) + (f64::from(sx) + 0.5) / f64::from(spp)) / f64::from(width);
                            let fy = (f64::from(row) + (f64::from(sy) + 0.5) / f64::from(spp)) / f64::from(height);
                            let (o, d) = camera.ray(2.0 * fx - 1.0, 1.0 - 2.0 * fy, aspect);
                            sum += match scene.hit(o, d, f64::INFINITY) {
                                Some(h) => {
                                    hits += 1;
                                    shade(scene, o, d, &h, shadows)
                                }
                                None => scene.background,
                            };
                        }
                    }
                    let c = sum / f64::from(spp * spp);
                    Rgb([to_srgb8(c.x), to_srgb8(c.y), to_srgb8(c.z)])
                })
                .collect();
            progress.advance(1);
            (pixels, hits)
        })
        .collect();
    progress.finish();
    let mut img = RgbImage::new(width, height);
    let mut stats = RenderStats { primary_rays: u64::from(width) * u64::from(height) * u64::from(spp * spp), hits: 0 };
    for (row, (pixels, hits)) in rows.into_iter().enumerate() {
        stats.hits += hits;
        for (col, p) in pixels.into_iter().enumerate() {
            img.put_pixel(col as u32, row as u32, p);
        }
    }
    Ok((img, stats))
}
