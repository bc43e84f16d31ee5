//! The exact Euclidean distance from each voxel centre to the nearest voxel (as a
//! cube) of the other phase: separable lower envelopes, in integers; the
//! one-dimensional transforms, which [`super::tiles`] and, naming each voxel's nearest
//! site, [`super::features`] run along lines of tiles.
//!
//! Formula: the squared distance from a centre `p` to the cube of the voxel `s` is a
//! sum over the axes of `c(p_a - s_a) / 4`, where `c(o) = (2|o| - 1)^2` (`c(0) = 0`:
//! the gap to the cube's nearest face is `|o| - 1/2`), so `4 d^2(p) = min_s sum_a
//! c(p_a - s_a) = min_{s_z} (c(p_z - s_z) + min_{s_y} (c(p_y - s_y) + min_{s_x} c(p_x -
//! s_x)))`: three passes of the one-dimensional transform `D(x) = min_i (c(x - i) +
//! g(i))`, along x, then y, then z (Saito and Toriwaki 1994; Meijster, Roerdink and
//! Hesselink 2000; Felzenszwalb and Huttenlocher, "Distance transforms of sampled
//! functions", Theory of Computing 8, 2012). Each pass is the lower envelope of the
//! translates `c(x - i) + g(i)`, kept on a stack: a new one `u` beats the top `v` from
//! the first `x` where it is strictly lower, and pops the top when that is at or
//! before the top's own start.
//!
//! Each transform can name the entry its winning value came from (the first of equal
//! ones along the line), from which [`super::features`] carries each voxel's nearest
//! site (the feature transform, Maurer, Qi and Raghavan 2003).
//!
//! Where this departs from the papers:
//! - the papers' cost is the squared distance between centres, `o^2`; this one, to
//!   the cube, makes a dilation the Minkowski sum of the voxel solid (not of its
//!   centres) with the ball, which is what Steiner's formula measures. `c` is convex,
//!   so two translates cross once (Meijster's condition for a separator), found by
//!   walking from where the parabolas `4 o^2` without `c`'s linear part cross (a step
//!   or two) rather than by a closed form;
//! - a cap: a step only asks whether a distance is under its radius (or, along a
//!   surface, near it), so each pass drops values over the cap (the later passes only
//!   add to them), and a line of a pass with none left is not transformed at all;
//! - integers throughout, so the result is exact and the same bits on every machine;
//!   infinite values (no site on the line) are left out of the envelope rather than
//!   carried as a large number;
//! - the first pass, whose input is 0 (a site) or infinite, is the cost to the nearest
//!   site along the row, two sweeps, not an envelope.

/// The value of a voxel with no site in reach.
pub(super) const FAR: i64 = i64::MAX / 4;

/// Four times the squared distance, along one axis, from a voxel's centre to the voxel
/// `o` voxels away (its nearest face, half a voxel nearer than its centre): `(2|o| -
/// 1)^2`, or 0 for the voxel itself. Convex, so any two of its translates cross once.
pub(super) fn axis_cost(o: i64) -> i64 {
    if o == 0 { 0 } else { (2 * o.abs() - 1).pow(2) }
}

/// `out[x - lo] = min_i (axis_cost(x - i) + g[i])` over the `g[i]` at most `cap`, for
/// `x` in `lo..lo + out.len()`, `FAR` where there is none (see the module doc); with
/// `nearest = (of, to)`, `to[x - lo] = of[i]` for the minimizing `i` (the first of equal
/// ones along the line).
pub(super) fn lower_envelope(
    g: &[i64],
    lo: usize,
    cap: i64,
    out: &mut [i64],
    sites: &mut Vec<usize>,
    starts: &mut Vec<i64>,
    nearest: Option<(&[u32], &mut [u32])>,
) {
    let (lo_x, hi_x) = (lo as i64, (lo + out.len()) as i64);
    sites.clear();
    starts.clear();
    for (u, &gu) in g.iter().enumerate() {
        if gu > cap {
            continue;
        }
        loop {
            let Some(&v) = sites.last() else {
                sites.push(u);
                starts.push(lo_x);
                break;
            };
            let a = separator(g, v, u, lo_x, hi_x);
            if a <= *starts.last().expect("one start a site") {
                sites.pop();
                starts.pop();
                continue;
            }
            if a < hi_x {
                sites.push(u);
                starts.push(a);
            }
            break;
        }
    }
    if sites.is_empty() {
        out.fill(FAR);
        return;
    }
    let mut k = 0;
    let mut nearest = nearest;
    for (j, o) in out.iter_mut().enumerate() {
        let x = lo_x + j as i64;
        while k + 1 < sites.len() && starts[k + 1] <= x {
            k += 1;
        }
        *o = axis_cost(x - sites[k] as i64) + g[sites[k]];
        if let Some((of, to)) = nearest.as_mut() {
            to[j] = of[sites[k]];
        }
    }
}

/// The first `x` of `lo..hi` where the translate of site `u` lies strictly below that of
/// the earlier site `v` (`g[u] + axis_cost(x - u) < g[v] + axis_cost(x - v)`), else `hi`.
///
/// Their difference only falls as `x` grows (the cost is convex), so the answer is
/// unique; it is walked to from where the parabolas `4 o^2` (the cost without its
/// linear part, which moves the crossing by at most a voxel) cross, `x > (u + v) / 2 +
/// (g[u] - g[v]) / (8 (u - v))`, a step or two rather than a bisection.
fn separator(g: &[i64], v: usize, u: usize, lo: i64, hi: i64) -> i64 {
    let (ui, vi, gu, gv) = (u as i64, v as i64, g[u], g[v]);
    let below = |x: i64| gu + axis_cost(x - ui) < gv + axis_cost(x - vi);
    let estimate = (4 * (ui + vi) * (ui - vi) + gu - gv).div_euclid(8 * (ui - vi)) + 1;
    let mut x = estimate.clamp(lo, hi);
    while x > lo && below(x - 1) {
        x -= 1;
    }
    while x < hi && !below(x) {
        x += 1;
    }
    x
}

/// `out[x - lo]`: [`axis_cost`] from `x` to the nearest set entry of `row`,
/// `FAR` when none is or that is over `cap`: the first pass, whose input is 0 or
/// infinite, as two sweeps;
/// with `nearest = (base, to)`, `to[x - lo] = base + ` that entry's index (the
/// earlier of two as near).
pub(super) fn nearest_site_along_row(
    row: &[bool],
    lo: usize,
    cap: i64,
    out: &mut [i64],
    nearest: Option<(u32, &mut [u32])>,
) {
    let hi = lo + out.len();
    if !row.contains(&true) {
        out.fill(FAR);
        return;
    }
    let mut nearest = nearest;
    // The nearest site at or before each x, then at or after it.
    let mut last: Option<usize> = row[..lo].iter().rposition(|&s| s);
    for x in lo..hi {
        if row[x] {
            last = Some(x);
        }
        out[x - lo] = match last.map(|s| (s, axis_cost((x - s) as i64))) {
            Some((s, cost)) if cost <= cap => {
                if let Some((base, to)) = nearest.as_mut() {
                    to[x - lo] = *base + s as u32;
                }
                cost
            }
            _ => FAR,
        };
    }
    let mut next: Option<usize> = row[hi..].iter().position(|&s| s).map(|i| hi + i);
    for x in (lo..hi).rev() {
        if row[x] {
            next = Some(x);
        }
        if let Some(s) = next {
            let cost = axis_cost((s - x) as i64);
            if cost < out[x - lo] && cost <= cap {
                out[x - lo] = cost;
                if let Some((base, to)) = nearest.as_mut() {
                    to[x - lo] = *base + s as u32;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::Rng;

    #[test]
    fn lower_envelope_is_the_brute_force_minimum() {
        let mut rng = Rng(7);
        let (mut sites, mut starts) = (Vec::new(), Vec::new());
        for _ in 0..2000 {
            let n = 1 + rng.below(40) as usize;
            let g: Vec<i64> = (0..n).map(|_| if rng.below(3) == 0 { rng.below(200) as i64 } else { FAR }).collect();
            let lo = rng.below(n as u64) as usize;
            let len = 1 + rng.below((n - lo) as u64) as usize;
            let cap = if rng.below(2) == 0 { FAR - 1 } else { rng.below(300) as i64 };
            let mut out = vec![0; len];
            lower_envelope(&g, lo, cap, &mut out, &mut sites, &mut starts, None);
            for (j, &o) in out.iter().enumerate() {
                let x = (lo + j) as i64;
                let brute = g
                    .iter()
                    .enumerate()
                    .filter(|(_, gi)| **gi <= cap)
                    .map(|(i, gi)| axis_cost(x - i as i64) + gi)
                    .min()
                    .unwrap_or(FAR);
                assert_eq!(o, brute, "g {g:?} lo {lo} x {x}");
            }
        }
    }
}
