//! Adaptive anti-aliasing, as POV-Ray's `+A` (sampling method 1) does it: one sample
//! at every pixel's centre, then `n x n` samples only in the pixels whose colour
//! differs from a neighbour's by at least the threshold.
//!
//! Contrast of two pixels: the sum over red, green and blue of the difference of their
//! displayed (sRGB) values in `[0, 1]`, so `0.3` (POV-Ray's common `+A0.3`) is about a
//! tenth of the range on each channel. A pixel is supersampled when its contrast with
//! any of its four neighbours is at least the threshold; POV-Ray compares each pixel
//! with the ones left of and above it and supersamples both of a differing pair, which
//! is the same set.
//!
//! The supersampled pixels take the uniform renderer's `n x n` samples at the same
//! points with the same rays, shaded in the same order, so a threshold of 0 (every
//! contrast is at least 0) gives the uniform picture bit for bit, and any threshold
//! gives the uniform picture wherever it supersamples. Visibility of the extra samples
//! is by the ray walk (a packet a pixel) whatever the first pass's method: every
//! method sees the same hits.

use image::{Rgb, RgbImage};
use rayon::prelude::*;

use glam::DVec3;

use super::film::resolve::resolve;
use super::film::{Camera, Picture, SampleGrid};
use super::scene::{Scene, SceneHit};
use super::shade::{ShadeOptions, radiance};
use crate::progress::Progress;
use crate::ray::Ray;

/// The contrast of two displayed colours (see the module doc): the sum of their red,
/// green and blue differences, over 255.
pub(crate) fn contrast(a: &Rgb<u8>, b: &Rgb<u8>) -> f64 {
    (0..3).map(|c| f64::from(a.0[c].abs_diff(b.0[c]))).sum::<f64>() / 255.0
}

/// Whether each pixel of `first` (one sample a pixel, displayed: the exposed picture
/// in 8-bit sRGB) needs supersampling at `threshold`, row-major.
pub(crate) fn needs_samples(first: &RgbImage, threshold: f64) -> Vec<bool> {
    let (w, h) = first.dimensions();
    (0..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .map(|(x, y)| {
            let p = first.get_pixel(x, y);
            let neighbours = [(x.wrapping_sub(1), y), (x + 1, y), (x, y.wrapping_sub(1)), (x, y + 1)];
            threshold <= 0.0
                || neighbours
                    .iter()
                    .filter(|&&(nx, ny)| nx < w && ny < h)
                    .any(|&(nx, ny)| contrast(p, first.get_pixel(nx, ny)) >= threshold)
        })
        .collect()
}

/// One row's supersampled pixels (column and radiance), the samples that saw a solid
/// and the secondary rays cast.
type Row = (Vec<(u32, DVec3)>, u64, u64);

/// The samples of a supersampled pixel and the exposure's scale of its mean.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Film {
    pub samples: SampleGrid,
    pub scale: f64,
}

/// The pixels of `refine` (row-major over the film's pixels) shaded from their
/// `spp^2` samples into `picture` (each mean times the film's scale); returns the
/// samples that saw a solid and the secondary rays cast. `progress` counts rows.
pub(crate) fn supersample(
    scene: &Scene,
    camera: &Camera,
    film: Film,
    shading: &ShadeOptions,
    refine: &[bool],
    picture: &mut Picture,
    progress: &dyn Progress,
) -> (u64, u64) {
    let Film { samples, scale } = film;
    let (width, spp) = (samples.width, samples.spp);
    let aspect = samples.aspect();
    let view = camera.view(aspect);
    progress.start(u64::from(samples.height));
    let rows: Vec<Row> = (0..samples.height)
        .into_par_iter()
        .map(|row| {
            let (mut hits_seen, mut rays_cast) = (0, 0);
            if progress.cancelled() {
                return (Vec::new(), 0, 0); // The caller returns `Cancelled`.
            }
            let mut rays: Vec<Ray> = Vec::with_capacity((spp * spp) as usize);
            let mut hits: Vec<Option<SceneHit>> = vec![None; (spp * spp) as usize];
            let mut pixels = Vec::new();
            for col in (0..width).filter(|&col| refine[(row * width + col) as usize]) {
                rays.clear();
                for sy in 0..spp {
                    for sx in 0..spp {
                        let (x, y) = samples.point(col * spp + sx, row * spp + sy);
                        rays.push(view.ray(x, y));
                    }
                }
                scene.hit_packet(&rays, &mut hits);
                let mut sum = DVec3::ZERO;
                // The rays just walked, in the same order (`Camera::ray` is `view.ray`).
                for (ray, hit) in rays.iter().zip(&hits) {
                    sum += match hit {
                        Some(h) => {
                            hits_seen += 1;
                            let (light, cast) = radiance(scene, ray, h, shading);
                            rays_cast += cast;
                            light
                        }
                        None => scene.background,
                    };
                }
                pixels.push((col, resolve(sum, spp * spp, scale)));
            }
            progress.advance(1);
            (pixels, hits_seen, rays_cast)
        })
        .collect();
    progress.finish();
    let (mut hits_seen, mut rays_cast) = (0, 0);
    for (row, (pixels, seen, cast)) in rows.into_iter().enumerate() {
        for (col, p) in pixels {
            picture.set(col, row as u32, p);
        }
        hits_seen += seen;
        rays_cast += cast;
    }
    (hits_seen, rays_cast)
}
