//! PNG output, written atomically.

use std::path::Path;

use image::{ImageEncoder, RgbImage, codecs::png::PngEncoder};

use super::atomic::write_atomic;
use crate::error::{Error, Result};

/// Writes `img` as an 8-bit RGB PNG to `path` through a temporary file; returns the bytes written.
pub fn save(img: &RgbImage, path: impl AsRef<Path>) -> Result<u64> {
    let path = path.as_ref();
    write_atomic(path, |w| encode_to(img, w))
}

/// The bytes [`save`] writes, in memory (a viewer's frames are the files `render`
/// writes). Fails only for an image the PNG format cannot hold (no pixels).
pub fn encode(img: &RgbImage) -> Result<Vec<u8>> {
    let mut bytes = Vec::new();
    encode_to(img, &mut bytes).map_err(|e| Error::invalid("image", e.to_string()))?;
    Ok(bytes)
}

fn encode_to(img: &RgbImage, w: &mut dyn std::io::Write) -> std::io::Result<()> {
    PngEncoder::new(w)
        .write_image(img.as_raw(), img.width(), img.height(), image::ExtendedColorType::Rgb8)
        .map_err(std::io::Error::other)
}
