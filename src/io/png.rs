//! PNG output (8-bit RGB), written atomically, and fed row by row.
//!
//! The bytes are those of the `image` crate's default PNG encoder (the `png` crate's
//! `Compression::Fast`, adaptive filtering), which earlier releases wrote and the
//! tests hold as the oracle: each row filtered by the filter of the four (Up, Sub,
//! Average, Paeth; PNG specification section 9) whose bytes, read as signed, have the
//! least sum of magnitudes (ties to the later), the filtered rows compressed by
//! `fdeflate` a row a call, and the image stored uncompressed instead when that would
//! be smaller. One IHDR, one IDAT, one IEND. Feeding rows as they are made is what
//! lets a viewer's frame be encoded while its later strips are still being drawn
//! ([`PngRows`]).

use std::io::Cursor;
use std::path::Path;

use image::RgbImage;

use crate::atomic::write_atomic;
use crate::error::{Error, Result};
use crate::file_kind::FileKind;
use crate::progress::Progress;
#[cfg(doc)]
use crate::render::render;
use crate::render::{Camera, RenderOptions, RenderStats, Scene, render_streamed};

/// Writes `img` as an 8-bit RGB PNG to `path` through a temporary file; returns the bytes written.
///
/// # Errors
/// A `path` not named `.png` is refused before anything is written (a picture written
/// over a solid or a scene named by mistake lost it), as are the writer's own errors.
pub fn write(img: &RgbImage, path: impl AsRef<Path>) -> Result<u64> {
    FileKind::of(path.as_ref(), &[FileKind::Png])?;
    let bytes = encode(img)?;
    write_atomic(path.as_ref(), |w| w.write_all(&bytes))
}

/// The bytes [`write()`] writes, in memory (a viewer's frames are the files `render`
/// writes). Fails only for an image the PNG format cannot hold (no pixels).
pub fn encode(img: &RgbImage) -> Result<Vec<u8>> {
    let mut rows = PngRows::new(img.width(), img.height())?;
    rows.push(img.as_raw());
    rows.finish(img.as_raw())
}

/// Renders `scene` as [`render`] does and encodes the picture as [`encode`] does,
/// each strip of rows as soon as it is drawn ([`render_streamed`]), so that the
/// encoding overlaps the drawing (what a viewer does for a frame).
pub fn render_png(
    scene: &Scene,
    camera: &Camera,
    options: &RenderOptions,
    progress: &dyn Progress,
) -> Result<(Vec<u8>, RenderStats)> {
    let mut png = PngRows::new(options.width, options.height)?;
    let (img, stats) =
        render_streamed(scene, camera, options, progress, Some(&mut |rows| png.push(rows.as_flattened())))?;
    Ok((png.finish(img.as_raw())?, stats))
}

/// Bytes a pixel.
const CHANNELS: usize = 3;

/// A PNG being encoded from its rows, top to bottom: [`encode`]'s bytes for the same
/// pixels, whatever the rows a [`PngRows::push`].
pub struct PngRows {
    width: u32,
    height: u32,
    /// The zlib stream of the filtered rows so far.
    compressor: fdeflate::Compressor<Cursor<Vec<u8>>>,
    /// The last row pushed (zeros before the first), what Up, Average and Paeth predict from.
    previous: Vec<u8>,
    /// The filter chosen for the row (its byte) and the row filtered by it, as compressed.
    best: Vec<u8>,
    /// A candidate filter's byte and bytes.
    trial: Vec<u8>,
    rows: u32,
}

impl PngRows {
    /// An encoder for a `width x height` picture; fails when the PNG format cannot hold
    /// it (no pixels, or a side above `2^31 - 1`).
    pub fn new(width: u32, height: u32) -> Result<Self> {
        let limit = (1u32 << 31) - 1;
        if width == 0 || height == 0 || width > limit || height > limit {
            return Err(Error::invalid("image", format!("a PNG cannot hold a {width}x{height} picture")));
        }
        let len = width as usize * CHANNELS;
        let compressor = fdeflate::Compressor::new(Cursor::new(Vec::new())).map_err(io_error)?;
        Ok(PngRows {
            width,
            height,
            compressor,
            previous: vec![0; len],
            best: vec![0; len + 1],
            trial: vec![0; len + 1],
            rows: 0,
        })
    }

    /// Appends whole rows (`width` RGB pixels each, row-major) below those pushed before.
    ///
    /// # Panics
    /// When `rows` is not whole rows or goes past the last row.
    pub fn push(&mut self, rows: &[u8]) {
        let len = self.previous.len();
        assert!(rows.len().is_multiple_of(len), "whole rows");
        for row in rows.chunks_exact(len) {
            assert!(self.rows < self.height, "past the last row");
            adaptive(&self.previous, row, &mut self.best, &mut self.trial);
            // One call a row, filter byte and bytes together, as the `png` crate makes
            // them (the stream depends on the calls). Writing to memory cannot fail.
            self.compressor.write_data(&self.best).expect("writes to memory");
            self.previous.copy_from_slice(row);
            self.rows += 1;
        }
    }

    /// The PNG's bytes. `whole` is the picture's pixels (every row pushed), stored
    /// uncompressed when compressing made them larger.
    ///
    /// # Panics
    /// When a row is missing.
    pub fn finish(self, whole: &[u8]) -> Result<Vec<u8>> {
        assert_eq!(self.rows, self.height, "every row pushed");
        let raw = (self.previous.len() + 1) * self.height as usize;
        let mut zlib = self.compressor.finish().map_err(io_error)?.into_inner();
        if zlib.len() > fdeflate::StoredOnlyCompressor::<()>::compressed_size(raw) {
            let mut stored = fdeflate::StoredOnlyCompressor::new(Cursor::new(Vec::new())).map_err(io_error)?;
            for row in whole.chunks_exact(self.previous.len()) {
                stored.write_data(&[0]).map_err(io_error)?;
                stored.write_data(row).map_err(io_error)?;
            }
            zlib = stored.finish().map_err(io_error)?.into_inner();
        }
        let mut png = Vec::with_capacity(zlib.len() + 64);
        png.extend_from_slice(b"\x89PNG\r\n\x1a\n");
        let mut header = [0u8; 13];
        header[..4].copy_from_slice(&self.width.to_be_bytes());
        header[4..8].copy_from_slice(&self.height.to_be_bytes());
        // 8 bits a channel, truecolour, deflate, adaptive filtering, no interlace.
        header[8..].copy_from_slice(&[8, 2, 0, 0, 0]);
        chunk(&mut png, b"IHDR", &header);
        chunk(&mut png, b"IDAT", &zlib);
        chunk(&mut png, b"IEND", &[]);
        Ok(png)
    }
}

fn io_error(e: std::io::Error) -> Error {
    Error::invalid("PNG encoding", e.to_string())
}

/// Appends a chunk: length, type, data, CRC-32 of type and data.
fn chunk(png: &mut Vec<u8>, kind: &[u8; 4], data: &[u8]) {
    let len = u32::try_from(data.len()).expect("a chunk under 4 GiB");
    png.extend_from_slice(&len.to_be_bytes());
    png.extend_from_slice(kind);
    png.extend_from_slice(data);
    let mut crc = flate2::Crc::new();
    crc.update(kind);
    crc.update(data);
    png.extend_from_slice(&crc.sum().to_be_bytes());
}

/// The PNG row filters (specification, section 9.2).
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Filter {
    Sub = 1,
    Up = 2,
    Average = 3,
    Paeth = 4,
}

/// Filters `row` (below `previous`) by the filter of least cost, trying Up, Sub,
/// Average, Paeth in that order, ties to the later, stopping at a cost of 0; leaves the
/// filter's byte and the filtered bytes in `best`. `trial` is scratch; both are a byte
/// longer than the row.
fn adaptive(previous: &[u8], row: &[u8], best: &mut Vec<u8>, trial: &mut Vec<u8>) {
    let mut least = u64::MAX;
    for filter in [Filter::Up, Filter::Sub, Filter::Average, Filter::Paeth] {
        trial[0] = filter as u8;
        apply(filter, previous, row, &mut trial[1..]);
        let cost = cost(&trial[1..]);
        if cost <= least {
            least = cost;
            std::mem::swap(best, trial);
            if cost == 0 {
                break;
            }
        }
    }
}

/// The sum of the bytes' magnitudes read as signed (`min(b, 256 - b)`), summed in
/// 16-bit lanes a 64-byte chunk (at most 64 x 128), so that it vectorizes.
fn cost(bytes: &[u8]) -> u64 {
    let magnitude = |b: u8| u16::from(b.min(b.wrapping_neg()));
    let mut chunks = bytes.chunks_exact(64);
    let mut sum = 0;
    for chunk in &mut chunks {
        sum += u64::from(chunk.iter().map(|&b| magnitude(b)).sum::<u16>());
    }
    sum + chunks.remainder().iter().map(|&b| u64::from(magnitude(b))).sum::<u64>()
}

/// `row` filtered by `filter` against `previous` into `out` (the bytes left of the
/// first pixel are 0).
fn apply(filter: Filter, previous: &[u8], row: &[u8], out: &mut [u8]) {
    const C: usize = CHANNELS;
    // The first pixel, whose left and upper left are 0; then the rest, `x` against
    // left `a`, above `b`, upper left `c`.
    let (head, rest) = out.split_at_mut(C);
    let (x, a, b, c) = (&row[C..], &row[..row.len() - C], &previous[C..], &previous[..previous.len() - C]);
    match filter {
        Filter::Sub => {
            each(head, &row[..C], &previous[..C], |x, _| x);
            each4(rest, x, a, b, c, |x, a, _, _| x.wrapping_sub(a));
        }
        Filter::Up => each(out, row, previous, |x, b| x.wrapping_sub(b)),
        Filter::Average => {
            each(head, &row[..C], &previous[..C], |x, b| x.wrapping_sub(b / 2));
            // The mean of two bytes without a wider type.
            each4(rest, x, a, b, c, |x, a, b, _| x.wrapping_sub((a & b) + ((a ^ b) >> 1)));
        }
        Filter::Paeth => {
            each(head, &row[..C], &previous[..C], |x, b| x.wrapping_sub(paeth(0, b, 0)));
            each4(rest, x, a, b, c, |x, a, b, c| x.wrapping_sub(paeth(a, b, c)));
        }
    }
}

/// `out[i] = f(x[i], b[i])`.
#[inline(always)]
fn each(out: &mut [u8], x: &[u8], b: &[u8], f: impl Fn(u8, u8) -> u8) {
    for ((o, &x), &b) in out.iter_mut().zip(x).zip(b) {
        *o = f(x, b);
    }
}

/// `out[i] = f(x[i], a[i], b[i], c[i])` over slices of `out`'s length, in fixed chunks
/// of 32 bytes, which the compiler vectorizes.
#[inline(always)]
fn each4(out: &mut [u8], x: &[u8], a: &[u8], b: &[u8], c: &[u8], f: impl Fn(u8, u8, u8, u8) -> u8) {
    const N: usize = 32;
    let n = out.len();
    let (x, a, b, c) = (&x[..n], &a[..n], &b[..n], &c[..n]);
    let whole = n - n % N;
    for k in (0..whole).step_by(N) {
        let o: &mut [u8; N] = (&mut out[k..k + N]).try_into().expect("a chunk");
        let x: &[u8; N] = x[k..k + N].try_into().expect("a chunk");
        let a: &[u8; N] = a[k..k + N].try_into().expect("a chunk");
        let b: &[u8; N] = b[k..k + N].try_into().expect("a chunk");
        let c: &[u8; N] = c[k..k + N].try_into().expect("a chunk");
        for i in 0..N {
            o[i] = f(x[i], a[i], b[i], c[i]);
        }
    }
    for i in whole..n {
        out[i] = f(x[i], a[i], b[i], c[i]);
    }
}

/// The Paeth predictor: of left `a`, above `b` and upper left `c`, the one nearest
/// `p = a + b - c`, ties in that order. In bytes, so that it vectorizes 16 lanes wide:
/// `|p - a| = |b - c|`, `|p - b| = |a - c|`, and `|p - c| = |(a - c) + (b - c)|` is
/// their difference when the two have opposite signs, else their sum, which is at
/// least either, so 255 decides the same (after Versari's FPNGE).
#[inline(always)]
fn paeth(a: u8, b: u8, c: u8) -> u8 {
    let (pa, pb) = (b.max(c) - b.min(c), a.max(c) - a.min(c));
    let pc = if (a < c) == (b < c) { u8::MAX } else { pa.max(pb) - pa.min(pb) };
    let b_or_c = if pb <= pc { b } else { c };
    if pa <= pb && pa <= pc { a } else { b_or_c }
}

#[cfg(test)]
mod tests {
    use image::{ImageEncoder, codecs::png::PngEncoder};

    use super::*;

    /// The `image` crate's encoder: the oracle.
    fn oracle(img: &RgbImage) -> Vec<u8> {
        let mut bytes = Vec::new();
        PngEncoder::new(&mut bytes)
            .write_image(img.as_raw(), img.width(), img.height(), image::ExtendedColorType::Rgb8)
            .unwrap();
        bytes
    }

    /// Pictures of every kind a filter meets: flat, gradients, edges, noise (stored
    /// uncompressed), one pixel, one row, one column.
    fn pictures() -> Vec<RgbImage> {
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut noise = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state as u8
        };
        let mut out = vec![
            RgbImage::from_pixel(37, 21, image::Rgb([40, 90, 200])),
            RgbImage::from_fn(64, 48, |x, y| image::Rgb([(x * 4) as u8, (y * 5) as u8, ((x + y) * 3) as u8])),
            RgbImage::from_fn(50, 50, |x, y| {
                let inside = (x as i32 - 25).pow(2) + (y as i32 - 25).pow(2) < 300;
                image::Rgb(if inside { [250, 20, 20] } else { [10, 10, 10] })
            }),
            RgbImage::from_fn(1, 1, |_, _| image::Rgb([1, 2, 3])),
            RgbImage::from_fn(97, 1, |x, _| image::Rgb([x as u8, 0, 255 - x as u8])),
            RgbImage::from_fn(1, 33, |_, y| image::Rgb([y as u8 * 7, 3, 9])),
        ];
        out.push(RgbImage::from_fn(40, 30, |_, _| image::Rgb([noise(), noise(), noise()])));
        out.push(RgbImage::from_fn(120, 80, |x, y| {
            let n = noise() % 9;
            image::Rgb([(x + y) as u8 / 2 + n, 128 - (y as u8 / 2), n * 20])
        }));
        out
    }

    #[test]
    fn bytes_are_the_image_crates_encoders() {
        let mut stored = 0;
        for img in pictures() {
            let bytes = encode(&img).unwrap();
            assert!(bytes == oracle(&img), "{}x{}", img.width(), img.height());
            stored += usize::from(bytes.len() > img.as_raw().len());
        }
        assert!(stored > 0, "the noise is stored uncompressed");
    }

    #[test]
    fn rows_pushed_in_any_grouping_give_the_same_bytes() {
        for img in pictures() {
            let whole = encode(&img).unwrap();
            let row = img.width() as usize * CHANNELS;
            for group in [1, 2, 5, 64] {
                let mut rows = PngRows::new(img.width(), img.height()).unwrap();
                img.as_raw().chunks(row * group).for_each(|part| rows.push(part));
                assert!(rows.finish(img.as_raw()).unwrap() == whole, "{}x{}, {group} rows", img.width(), img.height());
            }
        }
    }

    #[test]
    fn a_picture_without_pixels_is_refused() {
        assert!(PngRows::new(0, 5).is_err());
        assert!(encode(&RgbImage::new(4, 0)).is_err());
    }
}
