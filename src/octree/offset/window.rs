//! The minimum over a window of a line's values and where along the line it lies, in
//! 16-bit lanes: the one-dimensional transform of [`super::edt`] for small reaches,
//! `out(x) = min over |o| <= w of (c(o) + g(x + o))`, by every tap of the window in
//! turn instead of the lower envelope, with the first `o` that gives it.
//!
//! A line of a tile's pass is [`LANES`] lines side by side (the tile's rows across the
//! pass's axis), so a tap is one saturating add, one comparison, one minimum and one
//! select of a vector of lanes. The lanes are taken [`BLOCK`] at a time, held in
//! registers while all `2 w + 1` taps pass over them (one load a vector a tap). The
//! taps go in increasing `o` and a later one wins only when strictly lower, so the
//! first of equal ones is kept (the envelope's rule, [`super::edt`]). Signed 16-bit
//! lanes, whose minimum and comparison the x86-64 baseline has: values under
//! `i16::MAX`, which stands for none (a saturating sum with it stays none).
//!
//! Where AVX2 is present (checked at run time) the same loop is compiled with it,
//! sixteen lanes a register against eight. The values are integers, so both give the
//! same bits.

/// Lanes of a line: the lines of a tile's row side by side.
pub(super) const LANES: usize = 8;

/// Lanes held while the taps pass over them.
const BLOCK: usize = 64;

/// For every `x` of `out` in a block `need` marks: `out[LANES x + a] = min_j (g[LANES
/// (x + j) + a] + taps[j])`, saturating, and `at[LANES x + a]` the first `j` giving it
/// (0 where every sum is none); the blocks are of [`BLOCK`] lanes. `g` holds
/// `out.len() + LANES (taps.len() - 1)` lanes, `taps` at most `i16::MAX` of them.
/// Compiled with AVX2 too, used where the CPU has it ([`has_avx2`]); never inlined into
/// its caller, whose other values would push the lanes out of the registers.
pub(super) fn window_argmin(g: &[i16], taps: &[i16], out: &mut [i16], at: &mut [i16], need: &[bool]) {
    assert!(
        out.len() == at.len()
            && out.len() == BLOCK * need.len()
            && g.len() + LANES >= out.len() + LANES * taps.len()
            && taps.len() <= i16::MAX as usize,
        "a window beyond the line"
    );
    #[cfg(target_arch = "x86_64")]
    if has_avx2() {
        // SAFETY: the CPU has AVX2 (checked at run time).
        return unsafe { window_argmin_avx2(g, taps, out, at, need) };
    }
    window_argmin_lanes(g, taps, out, at, need);
}

/// [`window_argmin`] compiled with AVX2.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline(never)]
fn window_argmin_avx2(g: &[i16], taps: &[i16], out: &mut [i16], at: &mut [i16], need: &[bool]) {
    window_argmin_lanes(g, taps, out, at, need);
}

/// [`window_argmin`], a block of [`BLOCK`] lanes at a time.
#[inline(always)]
fn window_argmin_lanes(g: &[i16], taps: &[i16], out: &mut [i16], at: &mut [i16], need: &[bool]) {
    let blocks = out.chunks_exact_mut(BLOCK).zip(at.chunks_exact_mut(BLOCK)).zip(need).enumerate();
    for (b, ((out, at), _)) in blocks.filter(|(_, (_, need))| **need) {
        let (mut least, mut first) = ([i16::MAX; BLOCK], [0i16; BLOCK]);
        for (j, &c) in taps.iter().enumerate() {
            let from: &[i16; BLOCK] = g[BLOCK * b + LANES * j..][..BLOCK].try_into().expect("a block of lanes");
            let j = j as i16;
            for ((m, f), &d) in least.iter_mut().zip(&mut first).zip(from) {
                // Selects as masks, not branches (which would not vectorize).
                let s = d.saturating_add(c);
                let lower = -i16::from(s < *m);
                *m = (*m).min(s);
                *f = (*f & !lower) | (j & lower);
            }
        }
        out.copy_from_slice(&least);
        at.copy_from_slice(&first);
    }
}

/// Whether this CPU has AVX2 (asked at run time; the answer is cached).
pub(super) fn has_avx2() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    #[test]
    fn the_window_gives_the_brute_force_minimum_and_its_first_tap() {
        let mut rng = Rng(0x18);
        for _ in 0..200 {
            let taps: Vec<i16> = (0..1 + rng.below(40)).map(|_| rng.below(300) as i16).collect();
            let len = BLOCK * (1 + rng.below(3) as usize);
            let g: Vec<i16> = (0..len + LANES * (taps.len() - 1))
                .map(|_| if rng.below(3) == 0 { i16::MAX } else { rng.below(20) as i16 })
                .collect();
            // As run here (with AVX2 where the CPU has it), and without AVX2.
            let (mut out, mut at) = (vec![0; len], vec![0; len]);
            window_argmin(&g, &taps, &mut out, &mut at, &vec![true; len / BLOCK]);
            let (mut base_out, mut base_at) = (vec![0; len], vec![0; len]);
            window_argmin_lanes(&g, &taps, &mut base_out, &mut base_at, &vec![true; len / BLOCK]);
            assert_eq!((&out, &at), (&base_out, &base_at));
            for x in 0..len {
                let sums: Vec<i16> =
                    taps.iter().enumerate().map(|(j, &c)| g[x + LANES * j].saturating_add(c)).collect();
                let least = *sums.iter().min().unwrap();
                assert_eq!(out[x], least);
                let first = if least == i16::MAX { 0 } else { sums.iter().position(|&s| s == least).unwrap() };
                assert_eq!(at[x] as usize, first);
            }
        }
    }
}
