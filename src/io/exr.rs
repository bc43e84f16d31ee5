//! OpenEXR output of a rendered picture, written atomically: linear radiance as it
//! was rendered (no sRGB, no clamp: values above 1 and below the 8-bit steps kept).
//!
//! One layer of three 32-bit float channels R, G and B (full `f32`, not `half`: half's
//! largest value, 65504, and its 11-bit mantissa would cut what a picture of bright
//! emitters holds), in scan lines, increasing, ZIP-compressed 16 lines a block (lossless,
//! the compression every OpenEXR reader has), written by the `exr` crate on all cores
//! (blocks in order: the same bytes on any number of threads). The picture's `f64`
//! values are rounded to the nearest `f32`.

use std::io::Cursor;
use std::path::Path;

use exr::prelude::{Encoding, Image, SpecificChannels, Vec2, WritableImage};

use crate::atomic::write_atomic;
use crate::error::{Error, Result};
use crate::render::Picture;

/// Writes `picture` as an RGB `f32` OpenEXR file to `path` through a temporary file;
/// returns the bytes written.
pub fn write(picture: &Picture, path: impl AsRef<Path>) -> Result<u64> {
    let bytes = encode(picture)?;
    write_atomic(path, |w| w.write_all(&bytes))
}

/// The bytes [`write()`] writes, in memory. Fails only for a picture OpenEXR cannot hold
/// (no pixels).
pub fn encode(picture: &Picture) -> Result<Vec<u8>> {
    let (width, height) = picture.dimensions();
    if width == 0 || height == 0 {
        return Err(Error::invalid("image", format!("a {width}x{height} picture has no pixels to write")));
    }
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let c = picture.get(x as u32, y as u32);
        (c.x as f32, c.y as f32, c.z as f32)
    });
    let mut bytes = Vec::new();
    Image::from_encoded_channels((width as usize, height as usize), Encoding::SMALL_LOSSLESS, channels)
        .write()
        .to_buffered(Cursor::new(&mut bytes))
        .map_err(|e| Error::invalid("image", format!("cannot encode OpenEXR: {e}")))?;
    Ok(bytes)
}
