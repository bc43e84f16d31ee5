//! Recursive adaptive anti-aliasing, as POV-Ray's `+AM2` does it: a sample at every
//! corner of every pixel; a square whose four corner samples differ by at least the
//! threshold is split into four, with new samples at the midpoints of its edges and at
//! its centre, up to `depth` times. A square that is not split is the mean of its
//! four corners; a split one, the mean of its four quarters.
//!
//! Contrast of two samples: the `adaptive` method's, the sum over red, green and blue
//! of the difference of their displayed (exposed, 8-bit sRGB) values, over 255.
//! A square is split when some pair of its corners differs by at least the threshold.
//!
//! Samples are shared. The corners of the pixels are traced once for the picture
//! (`(W + 1) (H + 1)` rays), the points inside a pixel once for that pixel (its lattice
//! of `2^depth + 1` points a side remembers what it traced). A point on the edge
//! between two split pixels is traced by both: the same ray, the same bits, so which
//! pixel traces it changes the ray count, never the picture, and the picture does not
//! depend on the thread count.
//!
//! The filter: with threshold 0 every square splits `depth` times, so a pixel is the
//! mean of `4^depth` squares, each the mean of its corners: the lattice's points
//! weighted 1 (the pixel's corners), 2 (its edges) and 4 (inside), over `4^(depth + 1)`.
//! That is a tent-like filter reaching half a square past the pixel's samples, not the
//! box of uniform sampling, as in POV-Ray. Where nothing differs, a pixel costs one
//! ray (its top-left corner), against `n x n` uniform and one, plus `n x n` where a
//! neighbour differs, by the non-recursive method.

use glam::DVec3;
use image::Rgb;
use rayon::prelude::*;

use super::adaptive::contrast;
use super::film::resolve::srgb8_pixel;
use super::film::{Camera, Picture, View};
use super::scene::{Scene, SceneHit};
use super::shade::{ShadeOptions, radiance};
use super::trace::PACKET;
use crate::progress::Progress;
use crate::ray::{Ray, RayCast};

/// The most times a square of a pixel may be split: 65 x 65 points a pixel at most.
pub const MAX_AA_DEPTH: u32 = 6;

/// The picture's size and how its pixels are sampled.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Film {
    pub width: u32,
    pub height: u32,
    /// Most splits of a square (1..=[`MAX_AA_DEPTH`]).
    pub depth: u32,
    /// Contrast at which a square is split.
    pub threshold: f64,
    /// The exposure's factor.
    pub scale: f64,
}

/// What a render traced: primary rays, those that saw a solid, the shading's rays, and
/// the pixels split at least once.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Counts {
    pub samples: u64,
    pub hits: u64,
    pub secondary_rays: u64,
    pub split: u64,
}

impl Counts {
    fn add(self, o: Counts) -> Counts {
        Counts {
            samples: self.samples + o.samples,
            hits: self.hits + o.hits,
            secondary_rays: self.secondary_rays + o.secondary_rays,
            split: self.split + o.split,
        }
    }
}

/// A traced point: its radiance and how it is displayed (exposed, 8-bit sRGB).
#[derive(Clone, Copy, Debug)]
struct Sample {
    light: DVec3,
    shown: Rgb<u8>,
}

/// The points of one pixel's lattice traced so far, reused from pixel to pixel: an
/// entry belongs to the current pixel when its stamp is the pixel's.
struct Lattice {
    /// Points a side: `2^depth + 1`.
    side: usize,
    stamps: Vec<u64>,
    samples: Vec<Sample>,
    pixel: u64,
}

impl Lattice {
    fn new(depth: u32) -> Self {
        let side = (1usize << depth) + 1;
        let blank = Sample { light: DVec3::ZERO, shown: Rgb([0; 3]) };
        Lattice { side, stamps: vec![u64::MAX; side * side], samples: vec![blank; side * side], pixel: 0 }
    }

    fn get(&self, i: usize, j: usize) -> Option<Sample> {
        let k = j * self.side + i;
        (self.stamps[k] == self.pixel).then_some(self.samples[k])
    }

    fn put(&mut self, i: usize, j: usize, s: Sample) {
        let k = j * self.side + i;
        (self.stamps[k], self.samples[k]) = (self.pixel, s);
    }
}

/// The scene seen through a view, sampled at points of the image.
struct Sampler<'a> {
    scene: &'a Scene,
    view: View,
    shading: &'a ShadeOptions,
    film: Film,
}

impl Sampler<'_> {
    /// The primary ray through `(px, py)` pixels from the image's top-left corner (x
    /// right, y down).
    fn ray(&self, px: f64, py: f64) -> Ray {
        let (width, height) = (f64::from(self.film.width), f64::from(self.film.height));
        self.view.ray(2.0 * px / width - 1.0, 1.0 - 2.0 * py / height)
    }

    /// The sample at `(px, py)` (see [`Sampler::ray`]).
    fn trace(&self, px: f64, py: f64, counts: &mut Counts) -> Sample {
        let ray = self.ray(px, py);
        self.shade(&ray, self.scene.hit(&ray).as_ref(), counts)
    }

    /// The sample of the primary ray `ray` whose first hit is `hit`.
    fn shade(&self, ray: &Ray, hit: Option<&SceneHit>, counts: &mut Counts) -> Sample {
        counts.samples += 1;
        let light = match hit {
            Some(hit) => {
                counts.hits += 1;
                let (light, cast) = radiance(self.scene, ray, hit, self.shading);
                counts.secondary_rays += cast;
                light
            }
            None => self.scene.background,
        };
        Sample { light, shown: srgb8_pixel(light * self.film.scale) }
    }

    /// The samples at the corners `0..=width` of the pixels of row `row` (its top
    /// edge), their rays walked as packets of [`PACKET`].
    fn corner_row(&self, row: u32, counts: &mut Counts) -> Vec<Sample> {
        let rays: Vec<Ray> = (0..=self.film.width).map(|col| self.ray(f64::from(col), f64::from(row))).collect();
        let mut hits = [None; PACKET];
        let mut samples = Vec::with_capacity(rays.len());
        for packet in rays.chunks(PACKET) {
            let hits = &mut hits[..packet.len()];
            self.scene.hit_packet(packet, hits);
            samples.extend(packet.iter().zip(hits.iter()).map(|(ray, hit)| self.shade(ray, hit.as_ref(), counts)));
        }
        samples
    }

    /// Whether some two of `corners` differ by at least the threshold.
    fn differ(&self, corners: &[Sample; 4]) -> bool {
        (0..4).any(|a| (a + 1..4).any(|b| contrast(&corners[a].shown, &corners[b].shown) >= self.film.threshold))
    }

    /// The pixel `(col, row)` of the corner samples `corners` (top left, top right,
    /// bottom left, bottom right): its mean radiance (a split pixel is counted).
    fn pixel(&self, (col, row): (u32, u32), corners: [Sample; 4], lattice: &mut Lattice, counts: &mut Counts) -> DVec3 {
        lattice.pixel += 1;
        let n = lattice.side - 1;
        for (k, &(i, j)) in [(0, 0), (n, 0), (0, n), (n, n)].iter().enumerate() {
            lattice.put(i, j, corners[k]);
        }
        let before = counts.samples;
        let light = self.square((col, row), (0, 0), n, lattice, counts);
        counts.split += u64::from(counts.samples > before);
        light
    }

    /// The square of the pixel `(col, row)` at lattice point `(i, j)` (its top-left
    /// corner), `size` lattice steps a side, its corners traced: the mean of its
    /// corners, or of its quarters when it is split.
    fn square(
        &self,
        pixel: (u32, u32),
        (i, j): (usize, usize),
        size: usize,
        lattice: &mut Lattice,
        counts: &mut Counts,
    ) -> DVec3 {
        let at = |lattice: &Lattice, i, j| lattice.get(i, j).expect("a square's corners are traced before it");
        let corners =
            [at(lattice, i, j), at(lattice, i + size, j), at(lattice, i, j + size), at(lattice, i + size, j + size)];
        if size == 1 || !self.differ(&corners) {
            return (corners[0].light + corners[1].light + corners[2].light + corners[3].light) * 0.25;
        }
        let h = size / 2;
        let n = (lattice.side - 1) as f64;
        for (a, b) in [(i + h, j), (i, j + h), (i + h, j + h), (i + size, j + h), (i + h, j + size)] {
            if lattice.get(a, b).is_none() {
                // Dyadic fractions of a pixel: exact, so a point on a pixel's edge is
                // the same point (and ray) for the pixel on its other side.
                let (px, py) = (f64::from(pixel.0) + a as f64 / n, f64::from(pixel.1) + b as f64 / n);
                let s = self.trace(px, py, counts);
                lattice.put(a, b, s);
            }
        }
        let quarters =
            [(i, j), (i + h, j), (i, j + h), (i + h, j + h)].map(|q| self.square(pixel, q, h, lattice, counts));
        (quarters[0] + quarters[1] + quarters[2] + quarters[3]) * 0.25
    }
}

/// Renders every pixel of `picture` (`film`'s size) by recursive adaptive sampling:
/// each pixel's mean radiance times the film's scale. `progress` counts the rows of
/// corners, then the rows of pixels.
pub(crate) fn render(
    scene: &Scene,
    camera: &Camera,
    film: Film,
    shading: &ShadeOptions,
    picture: &mut Picture,
    progress: &dyn Progress,
) -> Counts {
    let Film { width, height, depth, scale, .. } = film;
    let view = camera.view(f64::from(width) / f64::from(height));
    let sampler = Sampler { scene, view, shading, film };
    progress.start(u64::from(2 * height + 1));
    let corners: Vec<(Vec<Sample>, Counts)> = (0..=height)
        .into_par_iter()
        .map(|row| {
            let mut counts = Counts::default();
            if progress.cancelled() {
                return (Vec::new(), counts); // The caller returns `Cancelled`.
            }
            let samples = sampler.corner_row(row, &mut counts);
            progress.advance(1);
            (samples, counts)
        })
        .collect();
    // A row skipped for the stop is empty (the caller returns `Cancelled`).
    if corners.iter().any(|(row, _)| row.is_empty()) {
        return Counts::default();
    }
    let rows: Vec<(Vec<DVec3>, Counts)> = (0..height)
        .into_par_iter()
        .map_init(
            || Lattice::new(depth),
            |lattice, row| {
                if progress.cancelled() {
                    return (Vec::new(), Counts::default());
                }
                let (above, below) = (&corners[row as usize].0, &corners[row as usize + 1].0);
                let mut counts = Counts::default();
                let pixels = (0..width)
                    .map(|col| {
                        let c = col as usize;
                        let square = [above[c], above[c + 1], below[c], below[c + 1]];
                        sampler.pixel((col, row), square, lattice, &mut counts) * scale
                    })
                    .collect();
                progress.advance(1);
                (pixels, counts)
            },
        )
        .collect();
    progress.finish();
    let mut counts = corners.iter().fold(Counts::default(), |sum, (_, c)| sum.add(*c));
    for (row, (pixels, c)) in rows.into_iter().enumerate() {
        for (col, p) in pixels.into_iter().enumerate() {
            picture.set(col as u32, row as u32, p);
        }
        counts = counts.add(c);
    }
    counts
}
