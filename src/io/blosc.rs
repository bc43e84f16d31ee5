//! Decompression of the compressed buffers OpenVDB writes: zlib streams (`COMPRESS_ZIP`)
//! and Blosc 1 frames (`COMPRESS_BLOSC`) whose blocks are LZ4 or zlib, byte-shuffled
//! or not. Written from the formats' documentation: Blosc's `README_HEADER.rst` (the
//! 16-byte header, block starts, split streams, the flags) and LZ4's
//! `lz4_Block_format.md` (token, literals, offset, match length).
//!
//! Blosc frame: `version, versionlz, flags, typesize, nbytes: u32, blocksize: u32,
//! cbytes: u32`, then one `i32` start a block, then each block as one stream or (when
//! flag `0x10` is clear, the block is not the short last one and holds at least 128
//! items of at most 16 bytes) `typesize` streams, each an `i32` size and its bytes
//! (a size equal to the stream's length means stored raw). Flag `0x01`: the block
//! was byte-shuffled (byte `j` of item `i` at `j * items + i`); `0x02`: the whole
//! frame is stored raw after the header. Codec = `flags >> 5`.
//!
//! Supported codecs: LZ4 (OpenVDB's choice) and zlib. Refused by name: BloscLZ, Snappy,
//! Zstd, bit-shuffle and delta filters. Every length is checked before use and the
//! output never grows beyond the size the caller expects, so a corrupt or hostile
//! buffer gives an error, never a panic or a large allocation.

use std::io::Read;

/// The codec names of Blosc's compressor codes.
const CODECS: [&str; 8] = ["blosclz", "lz4", "snappy", "zlib", "zstd", "code 5", "code 6", "code 7"];

/// Inflates a zlib stream into exactly `len` bytes.
pub(crate) fn inflate(src: &[u8], len: usize) -> Result<Vec<u8>, String> {
    let mut out = Vec::with_capacity(len);
    let mut decoder = flate2::read::ZlibDecoder::new(src).take(len as u64 + 1);
    decoder.read_to_end(&mut out).map_err(|e| format!("zlib: {e}"))?;
    if out.len() != len {
        return Err(format!("zlib data inflates to {} bytes, expected {len}", out.len()));
    }
    Ok(out)
}

/// Decompresses a Blosc 1 frame into exactly `len` bytes (module doc).
pub(crate) fn decompress(src: &[u8], len: usize) -> Result<Vec<u8>, String> {
    let frame = frame_header(src, len)?;
    if frame.flags & 0x02 != 0 {
        return src.get(16..16 + len).map(<[u8]>::to_vec).ok_or_else(|| "blosc raw frame is truncated".into());
    }
    let codec = supported_codec(frame.flags)?;
    if len == 0 {
        return Ok(Vec::new());
    }
    let (typesize, blocksize, cbytes) = (frame.typesize, frame.blocksize, frame.cbytes);
    if blocksize == 0 {
        return Err("blosc block size 0".into());
    }
    let blocks = len.div_ceil(blocksize);
    let leftover = len % blocksize;
    if 16 + 4 * blocks > cbytes {
        return Err(format!("blosc frame of {cbytes} bytes cannot hold {blocks} block starts"));
    }
    let mut out = vec![0u8; len];
    let mut tmp = vec![0u8; blocksize.min(len)];
    for b in 0..blocks {
        let last_short = b + 1 == blocks && leftover != 0;
        let bsize = if last_short { leftover } else { blocksize };
        let split = frame.flags & 0x10 == 0 && (1..=16).contains(&typesize) && bsize / typesize >= 128 && !last_short;
        let streams = if split { typesize } else { 1 };
        if bsize % streams != 0 {
            return Err(format!("blosc block of {bsize} bytes does not split into {streams} streams"));
        }
        decompress_streams(src, &frame, codec, b, streams, &mut tmp[..bsize])?;
        let block = &mut out[b * blocksize..b * blocksize + bsize];
        if frame.flags & 0x01 != 0 && typesize > 1 {
            unshuffle(&tmp[..bsize], typesize, block);
        } else {
            block.copy_from_slice(&tmp[..bsize]);
        }
    }
    Ok(out)
}

/// The fields of a Blosc frame's 16-byte header that decompression uses.
struct FrameHeader {
    /// Shuffle, raw, bit-shuffle, delta and split flags, and the codec in the top 3 bits.
    flags: u8,
    /// Bytes an item, the stride of shuffling and the number of split streams.
    typesize: usize,
    /// Bytes a block once decompressed.
    blocksize: usize,
    /// Bytes of the whole frame, header included.
    cbytes: usize,
}

/// The little-endian `u32` at `o` in `src`.
fn u32_at(src: &[u8], o: usize) -> usize {
    u32::from_le_bytes(src[o..o + 4].try_into().expect("4 bytes")) as usize
}

/// The frame's header, checked to hold `len` bytes and to claim no more bytes than
/// `src` has.
fn frame_header(src: &[u8], len: usize) -> Result<FrameHeader, String> {
    if src.len() < 16 {
        return Err(format!("blosc frame of {} bytes is shorter than its 16-byte header", src.len()));
    }
    let (flags, typesize) = (src[2], usize::from(src[3]));
    let (nbytes, blocksize, cbytes) = (u32_at(src, 4), u32_at(src, 8), u32_at(src, 12));
    if nbytes != len {
        return Err(format!("blosc frame holds {nbytes} bytes, expected {len}"));
    }
    if cbytes > src.len() || cbytes < 16 {
        return Err(format!("blosc frame claims {cbytes} bytes, {} available", src.len()));
    }
    Ok(FrameHeader { flags, typesize, blocksize, cbytes })
}

/// The codec of a compressed frame's `flags` (1 LZ4, 3 zlib), or the refusal of its
/// filter or codec.
fn supported_codec(flags: u8) -> Result<usize, String> {
    let codec = usize::from(flags >> 5);
    if flags & 0x04 != 0 {
        return Err("bit-shuffled blosc data is not supported; re-save with zip or no compression".into());
    }
    if flags & 0x08 != 0 {
        return Err("blosc's delta filter is not supported; re-save with zip or no compression".into());
    }
    if codec != 1 && codec != 3 {
        return Err(format!(
            "blosc compression with the {} codec is not supported (lz4 and zlib are); re-save with zip or no compression",
            CODECS[codec]
        ));
    }
    Ok(codec)
}

/// Block `b`'s `streams` streams, each decompressed (or copied when stored raw) into
/// its equal share of `dst`, every size checked against the frame.
fn decompress_streams(
    src: &[u8],
    frame: &FrameHeader,
    codec: usize,
    b: usize,
    streams: usize,
    dst: &mut [u8],
) -> Result<(), String> {
    let cbytes = frame.cbytes;
    let each = dst.len() / streams;
    let mut pos = u32_at(src, 16 + 4 * b);
    for s in 0..streams {
        if pos + 4 > cbytes {
            return Err(format!("blosc block {b} starts beyond the frame"));
        }
        let csize = i32::from_le_bytes(src[pos..pos + 4].try_into().expect("4 bytes"));
        pos += 4;
        let csize = usize::try_from(csize).ok().filter(|&c| c > 0 && pos + c <= cbytes);
        let Some(csize) = csize else {
            return Err(format!("blosc block {b} stream {s} overruns the frame"));
        };
        let stream = &src[pos..pos + csize];
        let dst = &mut dst[s * each..(s + 1) * each];
        if csize == each {
            dst.copy_from_slice(stream);
        } else if codec == 1 {
            lz4_block(stream, dst)?;
        } else {
            dst.copy_from_slice(&inflate(stream, each)?);
        }
        pos += csize;
    }
    Ok(())
}

/// Undoes Blosc's byte shuffle: byte `j` of item `i` was stored at `j * items + i`;
/// the bytes past the last whole item are stored as they were.
fn unshuffle(src: &[u8], typesize: usize, dst: &mut [u8]) {
    let items = src.len() / typesize;
    for i in 0..items {
        for j in 0..typesize {
            dst[i * typesize + j] = src[j * items + i];
        }
    }
    dst[items * typesize..].copy_from_slice(&src[items * typesize..]);
}

/// Decodes one LZ4 block into exactly `dst.len()` bytes.
///
/// A sequence is a token (high nibble: literal length, low: match length - 4; 15
/// extends with bytes up to and including the first below 255), the literals, then a
/// little-endian 16-bit offset back into the output and the match; the last sequence
/// ends after its literals.
pub(crate) fn lz4_block(src: &[u8], dst: &mut [u8]) -> Result<(), String> {
    let truncated = || "lz4 block is truncated".to_string();
    let (mut ip, mut op) = (0usize, 0usize);
    let extend = |ip: &mut usize, mut n: usize| -> Result<usize, String> {
        loop {
            let b = *src.get(*ip).ok_or_else(truncated)?;
            *ip += 1;
            n += usize::from(b);
            if b != 255 {
                return Ok(n);
            }
        }
    };
    loop {
        let token = *src.get(ip).ok_or_else(truncated)?;
        ip += 1;
        let mut literals = usize::from(token >> 4);
        if literals == 15 {
            literals = extend(&mut ip, literals)?;
        }
        if ip + literals > src.len() || op + literals > dst.len() {
            return Err("lz4 literals overrun the block".into());
        }
        dst[op..op + literals].copy_from_slice(&src[ip..ip + literals]);
        ip += literals;
        op += literals;
        if ip == src.len() {
            break;
        }
        if ip + 2 > src.len() {
            return Err(truncated());
        }
        let offset = usize::from(u16::from_le_bytes([src[ip], src[ip + 1]]));
        ip += 2;
        if offset == 0 || offset > op {
            return Err(format!("lz4 match offset {offset} before the block's start"));
        }
        let mut length = usize::from(token & 15) + 4;
        if token & 15 == 15 {
            length = extend(&mut ip, length)?;
        }
        if op + length > dst.len() {
            return Err("lz4 match overruns the block".into());
        }
        // Byte by byte: the match may overlap the bytes it produces.
        for i in 0..length {
            dst[op + i] = dst[op + i - offset];
        }
        op += length;
    }
    if op != dst.len() {
        return Err(format!("lz4 block decodes to {op} bytes, expected {}", dst.len()));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lz4_sequences_decode_by_hand() {
        // "abcabcabcabcX": literals "abc", a match of 9 at offset 3, literal "X".
        let block = [0x35, b'a', b'b', b'c', 3, 0, 0x10, b'X'];
        let mut out = [0u8; 13];
        lz4_block(&block, &mut out).unwrap();
        assert_eq!(&out, b"abcabcabcabcX");
        assert!(lz4_block(&block[..5], &mut out).is_err());
        let mut short = [0u8; 12];
        assert!(lz4_block(&block, &mut short).is_err());
        // An offset before the start.
        assert!(lz4_block(&[0x10, b'a', 5, 0, 0x10, b'b'], &mut out).is_err());
    }

    #[test]
    fn unshuffle_restores_items() {
        let items: Vec<u8> = (0..10).collect(); // five 2-byte items
        let shuffled = [0, 2, 4, 6, 8, 1, 3, 5, 7, 9];
        let mut out = [0u8; 10];
        unshuffle(&shuffled, 2, &mut out);
        assert_eq!(out.to_vec(), items);
    }
}
