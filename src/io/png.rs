//! PNG output, written atomically.

use std::path::Path;

use image::{ImageEncoder, RgbImage, codecs::png::PngEncoder};

use super::atomic::write_atomic;
use crate::error::Result;

/// Writes `img` as an 8-bit RGB PNG to `path` through a temporary file; returns the bytes written.
pub fn save(img: &RgbImage, path: impl AsRef<Path>) -> Result<u64> {
    let path = path.as_ref();
    write_atomic(path, |w| {
        PngEncoder::new(w)
            .write_image(img.as_raw(), img.width(), img.height(), image::ExtendedColorType::Rgb8)
            .map_err(std::io::Error::other)
    })
}
