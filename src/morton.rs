//! 3-D Morton (Z-order) codes for 21-bit integer coordinates.
//!
//! The code interleaves the bits of `x`, `y` and `z`: bit `i` of `x` lands at bit
//! `3i`, bit `i` of `y` at `3i + 1`, bit `i` of `z` at `3i + 2`. Three coordinates of
//! 21 bits fill 63 bits, so every voxel of a depth-21 domain has a code below `2^63`.
//! Sorting voxels by code visits octree nodes depth first with children in the order
//! `(x, y, z) = (0,0,0), (1,0,0), (0,1,0), (1,1,0), (0,0,1), ...`; a node at `k` levels
//! above the voxels covers the contiguous code range of length `8^k` starting at its
//! first voxel's code.

/// Largest number of bits a coordinate may have.
pub const MAX_BITS: u32 = 21;

/// Spreads the low 21 bits of `v` so that bit `i` moves to bit `3i`.
#[inline]
#[must_use]
pub fn spread(v: u32) -> u64 {
    let mut x = u64::from(v) & 0x1f_ffff;
    // Standard magic-number bit spreading: each step halves the run length.
    x = (x | (x << 32)) & 0x001f_0000_0000_ffff;
    x = (x | (x << 16)) & 0x001f_0000_ff00_00ff;
    x = (x | (x << 8)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x << 4)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x << 2)) & 0x1249_2492_4924_9249;
    x
}

/// Inverse of [`spread`]: gathers bits `0, 3, 6, ...` of `x` into the low 21 bits.
#[inline]
#[must_use]
pub fn compact(x: u64) -> u32 {
    let mut x = x & 0x1249_2492_4924_9249;
    x = (x | (x >> 2)) & 0x10c3_0c30_c30c_30c3;
    x = (x | (x >> 4)) & 0x100f_00f0_0f00_f00f;
    x = (x | (x >> 8)) & 0x001f_0000_ff00_00ff;
    x = (x | (x >> 16)) & 0x001f_0000_0000_ffff;
    x = (x | (x >> 32)) & 0x1f_ffff;
    x as u32
}

/// Morton code of the voxel `(x, y, z)`; each coordinate must fit in 21 bits.
#[inline]
#[must_use]
pub fn encode(x: u32, y: u32, z: u32) -> u64 {
    debug_assert!(x < 1 << MAX_BITS && y < 1 << MAX_BITS && z < 1 << MAX_BITS);
    spread(x) | (spread(y) << 1) | (spread(z) << 2)
}

/// Coordinates `(x, y, z)` of the voxel with Morton code `code`.
#[inline]
#[must_use]
pub fn decode(code: u64) -> [u32; 3] {
    [compact(code), compact(code >> 1), compact(code >> 2)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    /// Bit-by-bit reference interleave.
    fn slow_encode(x: u32, y: u32, z: u32) -> u64 {
        (0..MAX_BITS).fold(0, |acc, i| {
            acc | (u64::from((x >> i) & 1) << (3 * i))
                | (u64::from((y >> i) & 1) << (3 * i + 1))
                | (u64::from((z >> i) & 1) << (3 * i + 2))
        })
    }

    #[test]
    fn matches_bitwise_reference_and_round_trips() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..10_000 {
            let s = rng.next();
            let [x, y, z] = [s as u32 & 0x1f_ffff, (s >> 21) as u32 & 0x1f_ffff, (s >> 42) as u32 & 0x1f_ffff];
            let c = encode(x, y, z);
            assert_eq!(c, slow_encode(x, y, z));
            assert_eq!(decode(c), [x, y, z]);
        }
        let m = (1 << MAX_BITS) - 1;
        assert_eq!(encode(m, m, m), (1u64 << 63) - 1);
    }
}
