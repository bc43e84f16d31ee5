//! Unsigned LEB128 varints, as `.oct` files store their node gaps and the records of
//! their surface section (docs/FORMAT.md): seven bits a byte, the lowest first, the
//! high bit set on every byte but the last.

/// The most bytes a `u128` takes.
const MAX_BYTES: usize = 19;

/// Writes `v` at the start of `out`, which must hold it (19 bytes hold any value);
/// returns its length.
#[inline]
pub(super) fn put(out: &mut [u8], mut v: u128) -> usize {
    let mut len = 0;
    while v >= 0x80 {
        out[len] = (v as u8) | 0x80;
        v >>= 7;
        len += 1;
    }
    out[len] = v as u8;
    len + 1
}

/// Appends `v` to `out` in one piece.
#[inline]
pub(super) fn write(out: &mut Vec<u8>, v: u128) {
    let mut bytes = [0u8; MAX_BYTES];
    let len = put(&mut bytes, v);
    out.extend_from_slice(&bytes[..len]);
}

/// Reads a varint at `*pos`, advancing it; `None` when truncated or longer than
/// `max_bytes` bytes.
#[inline]
pub(super) fn read(bytes: &[u8], pos: &mut usize, max_bytes: usize) -> Option<u128> {
    // Most varints are one byte: neighbouring nodes, the faces of one voxel.
    let b = *bytes.get(*pos)?;
    if b & 0x80 == 0 {
        *pos += 1;
        return Some(u128::from(b));
    }
    read_long(bytes, pos, max_bytes)
}

fn read_long(bytes: &[u8], pos: &mut usize, max_bytes: usize) -> Option<u128> {
    let mut v = 0u128;
    for shift in (0..128).step_by(7).take(max_bytes.min(MAX_BYTES)) {
        let b = *bytes.get(*pos)?;
        *pos += 1;
        v |= u128::from(b & 0x7f) << shift;
        if b & 0x80 == 0 {
            return Some(v);
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_read_back_and_overlong_or_truncated_ones_are_refused() {
        for v in [0u128, 1, 0x7f, 0x80, 0x3fff, 0x4000, u128::from(u64::MAX), u128::MAX] {
            let mut out = Vec::new();
            write(&mut out, v);
            // The length LEB128 gives: one byte per started seven bits.
            let bits = 128 - v.leading_zeros() as usize;
            assert_eq!(out.len(), bits.div_ceil(7).max(1), "{v}");
            let mut pos = 0;
            assert_eq!(read(&out, &mut pos, MAX_BYTES), Some(v));
            assert_eq!(pos, out.len());
            if out.len() > 1 {
                assert_eq!(read(&out, &mut 0, out.len() - 1), None, "{v}: longer than allowed");
                assert_eq!(read(&out[..out.len() - 1], &mut 0, MAX_BYTES), None, "{v}: truncated");
            }
        }
    }
}
