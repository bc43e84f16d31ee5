//! A rendered picture before any display encoding: each pixel's linear radiance (the
//! mean of its samples' radiance, times the exposure's `2^stops`), unclamped, in
//! linear RGB with the Rec. 709 primaries the shading works in.
//!
//! It is what every render makes first. A PNG shows it through [`Picture::to_srgb8`]
//! (each channel clamped to `[0, 1]` and sRGB-encoded to 8 bits, as pictures always
//! were); an OpenEXR file (`io::exr`) keeps the values themselves, above 1 too.
//! Values are `f64` so that the 8-bit encoding of a picture is the same bits as the
//! encoding of the samples' mean straight away (an `f32` on the way could round a
//! value across an 8-bit step).

use glam::DVec3;
use image::RgbImage;

use super::resolve::srgb8_pixel;

/// A picture of linear radiance, row-major from the top-left pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct Picture {
    width: u32,
    height: u32,
    pixels: Vec<DVec3>,
}

impl Picture {
    /// A black picture of `width x height` pixels.
    #[must_use]
    pub fn new(width: u32, height: u32) -> Self {
        Picture { width, height, pixels: vec![DVec3::ZERO; width as usize * height as usize] }
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// `(width, height)`.
    #[must_use]
    pub fn dimensions(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// The radiance of pixel `(x, y)` (column, row from the top). Panics outside the
    /// picture, as slice indexing does.
    #[must_use]
    pub fn get(&self, x: u32, y: u32) -> DVec3 {
        assert!(x < self.width && y < self.height, "pixel ({x}, {y}) outside {}x{}", self.width, self.height);
        self.pixels[y as usize * self.width as usize + x as usize]
    }

    /// Sets pixel `(x, y)`. Panics outside the picture.
    pub fn set(&mut self, x: u32, y: u32, radiance: DVec3) {
        assert!(x < self.width && y < self.height, "pixel ({x}, {y}) outside {}x{}", self.width, self.height);
        self.pixels[y as usize * self.width as usize + x as usize] = radiance;
    }

    /// Every pixel, row-major.
    #[must_use]
    pub fn pixels(&self) -> &[DVec3] {
        &self.pixels
    }

    /// Every pixel, row-major, to write.
    pub fn pixels_mut(&mut self) -> &mut [DVec3] {
        &mut self.pixels
    }

    /// The picture as 8-bit sRGB (each channel clamped to `[0, 1]`): what a PNG shows.
    #[must_use]
    pub fn to_srgb8(&self) -> RgbImage {
        let mut img = RgbImage::new(self.width, self.height);
        for (px, c) in img.pixels_mut().zip(&self.pixels) {
            *px = srgb8_pixel(*c);
        }
        img
    }
}
