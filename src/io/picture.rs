//! A rendered picture to a file in the format its extension names: `.png` (8-bit
//! sRGB, each channel clamped to `[0, 1]`: [`Picture::to_srgb8`]) or `.exr` (the
//! linear radiance itself, `io::exr`). Any other extension is refused, naming the
//! file, before anything is written.

use std::path::Path;

use super::{exr, png};
use crate::error::{Error, Result};
use crate::render::Picture;

/// The picture file formats, by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PictureFormat {
    /// PNG, 8-bit sRGB.
    Png,
    /// OpenEXR, 32-bit float linear RGB.
    Exr,
}

impl PictureFormat {
    /// The extensions a picture can be written with.
    pub const EXTENSIONS: &'static [&'static str] = &["png", "exr"];

    /// The format `path`'s extension names (case-insensitive).
    pub fn of(path: impl AsRef<Path>) -> Result<PictureFormat> {
        let path = path.as_ref();
        let ext = path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()).unwrap_or_default();
        match ext.as_str() {
            "png" => Ok(PictureFormat::Png),
            "exr" => Ok(PictureFormat::Exr),
            _ => Err(Error::invalid(
                "picture file",
                format!("{}: extension {ext:?} is not a picture format (png, exr)", path.display()),
            )),
        }
    }
}

/// Writes `picture` to `path` in the format its extension names, atomically; returns
/// the bytes written.
pub fn save_picture(picture: &Picture, path: impl AsRef<Path>) -> Result<u64> {
    let path = path.as_ref();
    match PictureFormat::of(path)? {
        PictureFormat::Png => png::save(&picture.to_srgb8(), path),
        PictureFormat::Exr => exr::save(picture, path),
    }
}
