//! A rendered picture to a file in the format its extension names
//! ([`FileKind::PICTURES`]): `.png` (8-bit sRGB, each channel clamped to `[0, 1]`:
//! [`Picture::to_srgb8`]) or `.exr` (the linear radiance itself, `io::exr`). Any other
//! extension is refused ([`crate::Error::UnknownExtension`], naming the file and both),
//! before anything is written.

use std::path::Path;

use super::{exr, png};
use crate::error::Result;
use crate::file_kind::FileKind;
use crate::render::Picture;

/// Writes `picture` to `path` in the format its extension names, atomically; returns
/// the bytes written.
pub fn write_picture(picture: &Picture, path: impl AsRef<Path>) -> Result<u64> {
    let path = path.as_ref();
    match FileKind::of(path, FileKind::PICTURES)? {
        FileKind::Png => png::write(&picture.to_srgb8(), path),
        FileKind::Exr => exr::write(picture, path),
        other => unreachable!("{other:?} is not in FileKind::PICTURES"),
    }
}
