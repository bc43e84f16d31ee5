//! Making a picture: primary visibility of every sample (by any [`Method`]), then the
//! one shading stage (local Phong and Whitted's secondary rays), with `n x n` stratified
//! supersampling (sample centres of an `n x n` grid in the pixel), in every pixel or
//! where neighbours differ (`adaptive`), or by recursive adaptive sampling of the
//! pixels' corners (`recursive_aa`). A render makes a
//! [`Picture`] of linear radiance (each pixel's mean times the exposure's `2^stops`);
//! [`render`] gives it as the 8-bit sRGB picture a PNG holds.
//!
//! The front-to-back display goes a strip of sample rows at a time (visibility of the
//! strip, then its shading, in one task), so a frame never holds every sample's hit;
//! the other methods decide every sample first. The pixels are the same either way.
//! [`render_streamed`] hands the finished rows over as strips finish, in order, so a
//! caller can encode a picture while the rest is drawn.

use std::sync::{Mutex, mpsc};

use image::RgbImage;
use rayon::prelude::*;

use glam::DVec3;

use super::adaptive;
use super::film::ray_grid::RayGrid;
use super::film::resolve::{exposure_scale, resolve, srgb8_pixel};
use super::film::{Camera, Picture, SampleGrid, View};
use super::raster::{Display, Strip};
use super::recursive_aa::{self, MAX_AA_DEPTH};
use super::scene::{Scene, SceneHit};
use super::shade::{ShadeOptions, radiance};
use super::visibility::{Method, visibility_or_stop};
use crate::budget::MemoryBudget;
use crate::error::{Error, Result};
use crate::progress::{Progress, stop_if_cancelled};

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
    /// Samples at the pixels' corners, and a square split in four where its corners
    /// differ by at least `threshold`, up to `depth` times (see the `recursive_aa`
    /// module: POV-Ray's `+AM2`); `spp` is not used.
    Recursive {
        /// Contrast that splits a square: the sum of the red, green and blue
        /// differences of two of its corners, displayed values in `[0, 1]`.
        threshold: f64,
        /// Most times a square is split, 1 to [`MAX_AA_DEPTH`].
        depth: u32,
    },
}

impl AntiAliasing {
    /// Which of the three ways this is.
    #[must_use]
    pub fn kind(self) -> AntiAliasingKind {
        match self {
            AntiAliasing::Uniform => AntiAliasingKind::Uniform,
            AntiAliasing::Adaptive { .. } => AntiAliasingKind::Adaptive,
            AntiAliasing::Recursive { .. } => AntiAliasingKind::Recursive,
        }
    }
}

/// The way a pixel's samples are chosen, without its numbers: what `--aa` and a scene
/// file's `aa` name (`uniform`, `adaptive`, `recursive`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum AntiAliasingKind {
    /// [`AntiAliasing::Uniform`].
    Uniform,
    /// [`AntiAliasing::Adaptive`].
    Adaptive,
    /// [`AntiAliasing::Recursive`].
    Recursive,
}

impl AntiAliasingKind {
    /// Every value, in the order `--help` lists them.
    pub const ALL: [AntiAliasingKind; 3] =
        [AntiAliasingKind::Uniform, AntiAliasingKind::Adaptive, AntiAliasingKind::Recursive];

    /// The value's one spelling (the command line's, a scene file's, `Display`'s).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            AntiAliasingKind::Uniform => "uniform",
            AntiAliasingKind::Adaptive => "adaptive",
            AntiAliasingKind::Recursive => "recursive",
        }
    }
}

crate::spelling::spelled!(AntiAliasingKind);

/// The recursive anti-aliasing depth when none is given: POV-Ray's common `+R3`.
pub const DEFAULT_AA_DEPTH: u32 = 3;

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
    /// How surfaces are shaded: shadow rays, shading normals (default
    /// [`Normals::Smooth`](super::Normals::Smooth)), the longest chain of reflected and refracted rays (0: local
    /// shading only) and the share of a pixel below which such a ray is not traced
    /// (POV-Ray's `adc_bailout`, 1/255 there; default 0.001).
    pub shade: ShadeOptions,
    /// How primary visibility is decided (default [`Method::FrontToBack`]: every
    /// method finds the same hits, and the display finds a whole image's fastest).
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
            shade: ShadeOptions::default(),
            method: Method::FrontToBack,
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
    render_streamed(scene, camera, options, progress, None)
}

/// Takes the pixels of whole rows of a picture, top to bottom (RGB, 8 bits a channel).
pub type RowSink<'a> = Rows<'a, [u8; 3]>;

/// Takes the pixels of whole rows of a picture, top to bottom.
type Rows<'a, P> = &'a mut dyn FnMut(&[P]);

/// [`render`], handing the picture's rows to `rows` top to bottom, every row once, as
/// they are finished: with the front-to-back display at uniform sampling, strips are
/// drawn in order by every thread and `rows` takes each strip on the calling thread
/// while later strips are drawn (a viewer encodes its frame meanwhile); otherwise all
/// rows at the end. The picture is [`render`]'s.
pub fn render_streamed(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    progress: &dyn Progress,
    mut rows: Option<RowSink<'_>>,
) -> Result<(RgbImage, RenderStats)> {
    let uniform_samples = match options.aa {
        AntiAliasing::Uniform => true,
        AntiAliasing::Adaptive { .. } => options.spp == 1,
        AntiAliasing::Recursive { .. } => false,
    };
    if uniform_samples {
        // Encoded as each row is shaded: no picture of linear radiance in between (the
        // same bytes as its encoding, `srgb8_pixel` of the same values).
        let (width, height) = (options.width, options.height);
        let (scale, shading) = check(camera, options)?;
        let mut img = RgbImage::new(width, height);
        let (pixels, []) = img.as_mut().as_chunks_mut::<3>() else { unreachable!("3 bytes a pixel") };
        let encode = |c| srgb8_pixel(c).0;
        let stats = uniform(scene, camera, options, &shading, scale, progress, encode, pixels, rows.take())?;
        return Ok((img, stats));
    }
    let (picture, stats) = render_picture(scene, camera, options, progress)?;
    let img = picture.to_srgb8();
    if let Some(rows) = rows {
        let (pixels, []) = img.as_chunks::<3>() else { unreachable!("3 bytes a pixel") };
        rows(pixels);
    }
    Ok((img, stats))
}

impl RenderOptions {
    /// Checks every option against its range: the image size (1 to
    /// [`MAX_IMAGE_SIZE`] a side), 1 to 16 samples a side, the ray depth (at most
    /// [`MAX_RAY_DEPTH`]), the cutoff (0 to 1), the anti-aliasing threshold (finite, at
    /// least 0) and depth (1 to [`MAX_AA_DEPTH`]), and the exposure. Rendering calls it
    /// first; the error names the option.
    pub fn validate(&self) -> Result<()> {
        let RenderOptions { width, height, spp, aa, shade, exposure, .. } = *self;
        let ShadeOptions { max_depth, cutoff, .. } = shade;
        if !(1..=MAX_IMAGE_SIZE).contains(&width) || !(1..=MAX_IMAGE_SIZE).contains(&height) {
            return Err(Error::invalid(
                "image size",
                format!("{width}x{height} is outside 1..={MAX_IMAGE_SIZE} a side"),
            ));
        }
        if !(1..=16).contains(&spp) {
            return Err(Error::invalid("samples", format!("{spp} a side is outside 1..=16")));
        }
        if max_depth > MAX_RAY_DEPTH {
            return Err(Error::invalid("max depth", format!("{max_depth} is above the limit of {MAX_RAY_DEPTH}")));
        }
        if !(0.0..=1.0).contains(&cutoff) {
            return Err(Error::invalid("ray cutoff", format!("{} is outside 0..=1", crate::error::Number(cutoff))));
        }
        if let AntiAliasing::Adaptive { threshold } | AntiAliasing::Recursive { threshold, .. } = aa
            && !(threshold.is_finite() && threshold >= 0.0)
        {
            return Err(Error::invalid(
                "anti-aliasing threshold",
                format!("{} must be finite and at least 0", crate::error::Number(threshold)),
            ));
        }
        if let AntiAliasing::Recursive { depth, .. } = aa
            && !(1..=MAX_AA_DEPTH).contains(&depth)
        {
            return Err(Error::invalid("anti-aliasing depth", format!("{depth} is outside 1..={MAX_AA_DEPTH}")));
        }
        exposure_scale(exposure)?;
        Ok(())
    }
}

/// Checks `options` and `camera`, and the picture's memory against the budget before
/// anything is allocated; gives the exposure's factor and the shading options.
fn check(camera: &Camera, options: &RenderOptions) -> Result<(f64, ShadeOptions)> {
    options.validate()?;
    let RenderOptions { width, height, spp, aa, shade, exposure, budget, .. } = *options;
    camera.validate()?;
    let scale = exposure_scale(exposure)?;
    // Recursive sampling keeps a sample a pixel corner, within one sample a pixel's.
    let spp = if matches!(aa, AntiAliasing::Recursive { .. }) { 1 } else { spp };
    let samples = SampleGrid { width, height, spp };
    budget.check(format!("a {width}x{height} picture at {spp}x{spp} samples a pixel"), estimate_bytes(&samples))?;
    Ok((scale, shade))
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
    let RenderOptions { width, height, spp, aa, .. } = *options;
    let (scale, shading) = check(camera, options)?;
    let linear = |c: DVec3| c;
    match aa {
        AntiAliasing::Adaptive { threshold } if spp > 1 => {
            // One sample a pixel, then the pixels that differ from a neighbour.
            let first = RenderOptions { spp: 1, aa: AntiAliasing::Uniform, ..*options };
            let mut picture = Picture::new(width, height);
            let stats = uniform(
                scene,
                camera,
                &first,
                &shading,
                scale,
                &crate::NoProgress,
                linear,
                picture.pixels_mut(),
                None,
            )?;
            let refine = adaptive::needs_samples(&picture.to_srgb8(), threshold);
            let film = adaptive::Film { samples: SampleGrid { width, height, spp }, scale };
            let (hits, rays) = adaptive::supersample(scene, camera, film, &shading, &refine, &mut picture, progress);
            stop_if_cancelled(progress)?;
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
        AntiAliasing::Recursive { threshold, depth } => {
            let mut picture = Picture::new(width, height);
            let film = recursive_aa::Film { width, height, depth, threshold, scale };
            let counts = recursive_aa::render(scene, camera, film, &shading, &mut picture, progress);
            stop_if_cancelled(progress)?;
            let stats = RenderStats {
                samples: counts.samples,
                hits: counts.hits,
                faces_drawn: 0,
                secondary_rays: counts.secondary_rays,
                supersampled: counts.split,
            };
            Ok((picture, stats))
        }
        _ => {
            let mut picture = Picture::new(width, height);
            let stats = uniform(scene, camera, options, &shading, scale, progress, linear, picture.pixels_mut(), None)?;
            Ok((picture, stats))
        }
    }
}

/// `spp x spp` samples in every pixel: the visibility of every sample, then shading;
/// each pixel's mean times `scale`. The front-to-back display goes a strip of whole
/// pixel rows at a time: each task draws a strip into a strip-sized buffer of its own
/// and shades it at once, so the frame's samples (32 bytes each) are never all held,
/// filled and read back; the pixels are the same.
/// Each pixel goes into `out` (row-major, `width x height`) as `encode` makes it of
/// the linear value; `rows`, when given, gets every row of `out` once, top to bottom
/// (as strips finish, see [`strips_in_order`], or at the end).
#[allow(clippy::too_many_arguments)]
fn uniform<P: Send + Sync + Clone>(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    shading: &ShadeOptions,
    scale: f64,
    progress: &dyn Progress,
    encode: impl Fn(DVec3) -> P + Sync,
    out: &mut [P],
    rows: Option<Rows<'_, P>>,
) -> Result<RenderStats> {
    let RenderOptions { width, height, spp, method, .. } = *options;
    let samples = SampleGrid { width, height, spp };
    let columns = samples.columns() as usize;
    // The camera's frame once, not once a sample (`Camera::ray` is `view(aspect).ray`).
    let view = camera.view(samples.aspect());
    let shader = Shader::new(scene, &view, &samples, shading, scale, progress);
    debug_assert_eq!(out.len(), width as usize * height as usize);
    let pixel_row = width as usize;
    let (hits, faces_drawn, secondary_rays) = if method == Method::FrontToBack {
        let display = Display::new(scene, &view, &samples);
        progress.start(u64::from(height));
        // Strips of whole pixel rows.
        let strip_rows = display.strip_rows;
        let strip_pixels = pixel_row * (strip_rows / spp as usize);
        let init = || (display.strip(), Vec::new());
        let draw = |(strip, seen): &mut (Strip, Vec<_>), k: usize, out: &mut [P]| {
            if progress.cancelled() {
                return Counts::default();
            }
            seen.clear();
            seen.resize(out.len() / pixel_row * spp as usize * columns, None);
            let faces = display.draw_strip(k, strip, seen);
            let hits = seen.iter().filter(|s| s.is_some()).count() as u64;
            Counts(hits, faces, shader.rows(seen, (k * strip_rows) as u32 / spp, &encode, out))
        };
        match rows {
            // Not from within the pool: the calling thread waits on the strips.
            Some(rows) if rayon::current_thread_index().is_none() => {
                strips_in_order(out, strip_pixels, init, draw, rows)
            }
            rows => {
                // A strip a task: a frame has few strips (12 at 720 rows) of unequal
                // work, and rayon's default split would leave runs of three to one thread.
                let counts = out
                    .par_chunks_mut(strip_pixels)
                    .enumerate()
                    .with_max_len(1)
                    .map_init(init, |state, (k, out)| draw(state, k, out))
                    .reduce(Counts::default, Counts::add);
                if let Some(rows) = rows {
                    rows(out);
                }
                counts
            }
        }
        .into()
    } else {
        // Step 1: what each sample sees.
        let (seen, visible) = visibility_or_stop(scene, camera, &samples, method, progress);
        // Step 2: shading, the same for every method, averaged over each pixel's samples.
        progress.start(u64::from(height));
        let rays = out
            .par_chunks_mut(pixel_row)
            .zip(seen.par_chunks(spp as usize * columns))
            .zip(0..height)
            .map(|((out, seen), row)| shader.rows(seen, row, &encode, out))
            .sum();
        if let Some(rows) = rows {
            rows(out);
        }
        (seen.iter().filter(|s| s.is_some()).count() as u64, visible.faces_drawn, rays)
    };
    stop_if_cancelled(progress)?;
    progress.finish();
    let stats = RenderStats {
        samples: u64::from(samples.columns()) * u64::from(samples.rows()),
        hits,
        faces_drawn,
        secondary_rays,
        supersampled: if spp > 1 { u64::from(width) * u64::from(height) } else { 0 },
    };
    Ok(stats)
}

/// A strip's hits, faces drawn and secondary rays.
#[derive(Clone, Copy, Default)]
struct Counts(u64, u64, u64);

impl Counts {
    fn add(self, other: Counts) -> Counts {
        Counts(self.0 + other.0, self.1 + other.1, self.2 + other.2)
    }
}

impl From<Counts> for (u64, u64, u64) {
    fn from(Counts(hits, faces, rays): Counts) -> Self {
        (hits, faces, rays)
    }
}

/// Draws the strips `out.chunks_mut(len)` (strip `k` by `draw(state, k, strip)`, a
/// `state` made by `init` a thread) on every thread of rayon's pool, each taking the
/// first strip not yet taken, so that strips finish about in order; the calling thread
/// hands each finished strip to `rows`, in order, while the later ones are drawn.
/// Sums the strips' counts. (The pixels do not depend on the order: strips are
/// independent.)
fn strips_in_order<P: Send + Sync, S>(
    out: &mut [P],
    len: usize,
    init: impl Fn() -> S + Sync,
    draw: impl Fn(&mut S, usize, &mut [P]) -> Counts + Sync,
    rows: &mut dyn FnMut(&[P]),
) -> Counts {
    let strips = out.len().div_ceil(len);
    let queue = Mutex::new(out.chunks_mut(len).enumerate());
    let (finished, arrivals) = mpsc::channel::<(usize, &[P], Counts)>();
    let (queue, init, draw) = (&queue, &init, &draw);
    let mut total = Counts::default();
    rayon::in_place_scope(|scope| {
        for _ in 0..rayon::current_num_threads().min(strips) {
            let finished = finished.clone();
            scope.spawn(move |_| {
                let mut state = init();
                // A poisoned lock means a strip panicked: that panic is the scope's.
                while let Some((k, strip)) = queue.lock().map_or(None, |mut q| q.next()) {
                    let counts = draw(&mut state, k, strip);
                    // The receiver outlives the scope's tasks.
                    let _ = finished.send((k, strip, counts));
                }
            });
        }
        drop(finished);
        let mut waiting: Vec<Option<&[P]>> = vec![None; strips];
        let mut next = 0;
        for (k, strip, counts) in arrivals {
            total = total.add(counts);
            waiting[k] = Some(strip);
            while let Some(strip) = waiting.get_mut(next).and_then(Option::take) {
                rows(strip);
                next += 1;
            }
        }
    });
    total
}

/// Step 2, the shading of whole pixel rows.
struct Shader<'a> {
    scene: &'a Scene,
    /// The samples' camera rays (`View::ray` at `SampleGrid::point`, bit for bit).
    rays: RayGrid,
    samples: &'a SampleGrid,
    shading: &'a ShadeOptions,
    progress: &'a dyn Progress,
    /// The exposure's factor.
    scale: f64,
    /// A pixel whose samples all miss: the background's sum resolved, worked out once
    /// (the same additions in the same order as a pixel's).
    missed: DVec3,
}

impl<'a> Shader<'a> {
    fn new(
        scene: &'a Scene,
        view: &'a View,
        samples: &'a SampleGrid,
        shading: &'a ShadeOptions,
        scale: f64,
        progress: &'a dyn Progress,
    ) -> Self {
        let n = samples.spp * samples.spp;
        let missed = resolve((0..n).fold(DVec3::ZERO, |sum, _| sum + scene.background), n, scale);
        Shader { scene, rays: RayGrid::new(view, samples), samples, shading, progress, scale, missed }
    }

    /// Shades the pixel rows from `first` into `out` (as `encode` makes each pixel)
    /// from `seen`, their samples (row-major from the first's first sample row);
    /// returns the secondary rays cast. Each pixel is the mean of its `spp x spp`
    /// samples' radiance times the exposure's factor.
    fn rows<P: Clone>(
        &self,
        seen: &[Option<SceneHit>],
        first: u32,
        encode: &impl Fn(DVec3) -> P,
        out: &mut [P],
    ) -> u64 {
        let Shader { scene, samples, shading, .. } = *self;
        let missed = encode(self.missed);
        let (width, spp) = (samples.width, samples.spp);
        let columns = samples.columns() as usize;
        let mut rays = 0;
        for (row, out) in (first..).zip(out.chunks_exact_mut(width as usize)) {
            if self.progress.cancelled() {
                break; // The frame is dropped: `uniform` returns `Cancelled`.
            }
            for (col, pixel) in (0..width).zip(out.iter_mut()) {
                let mut sum = DVec3::ZERO;
                let mut hit = false;
                for sy in 0..spp {
                    for sx in 0..spp {
                        let (c, r) = (col * spp + sx, row * spp + sy);
                        sum += match &seen[(r - first * spp) as usize * columns + c as usize] {
                            Some(h) => {
                                hit = true;
                                let ray = self.rays.ray(c as usize, r as usize);
                                let (light, cast) = radiance(scene, &ray, h, shading);
                                rays += cast;
                                light
                            }
                            None => scene.background,
                        };
                    }
                }
                *pixel = if hit { encode(resolve(sum, spp * spp, self.scale)) } else { missed.clone() };
            }
            self.progress.advance(1);
        }
        rays
    }
}
