//! The exact squared Euclidean distance transform of one brick of voxels, read with a
//! halo: separable lower envelopes of parabolas, in integers.
//!
//! Formula: for sites `S` (the voxels of one phase) the squared distance of a voxel `p`
//! is `d^2(p) = min_{s in S} |p - s|^2 = min_{s_z} ((p_z - s_z)^2 + min_{s_y} ((p_y -
//! s_y)^2 + min_{s_x} (p_x - s_x)^2))`, so three passes of the one-dimensional transform
//! `D(x) = min_i ((x - i)^2 + g(i))`, along x, then y, then z, give it exactly (Saito and
//! Toriwaki 1994; Meijster, Roerdink and Hesselink 2000; Felzenszwalb and Huttenlocher,
//! "Distance transforms of sampled functions", Theory of Computing 8, 2012). Each pass
//! is the lower envelope of the parabolas `(x - i)^2 + g(i)`: kept on a stack, a new
//! parabola `u` beats the top `v` from `x = floor(N / (2 (u - v))) + 1` on, where `N =
//! g(u) + u^2 - g(v) - v^2`, and pops the top when it beats it from the top's own start.
//!
//! Where this departs from the papers:
//! - integers throughout (Meijster's separator, floored, not Felzenszwalb and
//!   Huttenlocher's real intersection), so the result is exact and the same bits on
//!   every machine; infinite values (no site on the line) are left out of the envelope
//!   rather than carried as a large number;
//! - the first pass, whose input is 0 (a site) or infinite, is the distance to the
//!   nearest site along the row, two sweeps, not an envelope;
//! - each pass computes only the part later passes read: the input is the brick and a
//!   halo of `R` voxels each side (`H = B + 2R` a side), pass one (x) gives the `B`
//!   columns of the brick for all `H^2` rows, pass two (y) the `B x B` of the brick for
//!   all `H` layers, pass three (z) the brick: `H^3 + B H^2 + B^2 H` line steps rather
//!   than `3 H^3`. Distances are exact for every voxel of the brick whose nearest site
//!   is within `R` voxels on each axis, in particular whenever `d <= R`; elsewhere they
//!   are the distance to the nearest site in the halo, never less than the true one.

/// The squared distance of a voxel with no site in reach.
pub(super) const FAR: i64 = i64::MAX / 4;

/// Scratch buffers of one thread, reused brick after brick.
#[derive(Default)]
pub(super) struct Scratch {
    line: Vec<i64>,
    out: Vec<i64>,
    sites: Vec<usize>,
    starts: Vec<i64>,
    pass_x: Vec<i64>,
    pass_y: Vec<i64>,
}

/// `out[x - lo] = min_i ((x - i)^2 + g[i])` for `x` in `lo..lo + out.len()`, `FAR`
/// where every `g[i]` is `FAR` (see the module doc).
fn lower_envelope(g: &[i64], lo: usize, out: &mut [i64], sites: &mut Vec<usize>, starts: &mut Vec<i64>) {
    let (lo_x, hi_x) = (lo as i64, (lo + out.len()) as i64);
    sites.clear();
    starts.clear();
    for (u, &gu) in g.iter().enumerate() {
        if gu >= FAR {
            continue;
        }
        loop {
            let Some(&v) = sites.last() else {
                sites.push(u);
                starts.push(lo_x);
                break;
            };
            let (ui, vi) = (u as i64, v as i64);
            let n = gu + ui * ui - g[v] - vi * vi;
            let from = n.div_euclid(2 * (ui - vi)) + 1;
            if from <= *starts.last().expect("one start a site") {
                sites.pop();
                starts.pop();
                continue;
            }
            if from < hi_x {
                sites.push(u);
                starts.push(from);
            }
            break;
        }
    }
    if sites.is_empty() {
        out.fill(FAR);
        return;
    }
    let mut k = 0;
    for (j, o) in out.iter_mut().enumerate() {
        let x = lo_x + j as i64;
        while k + 1 < sites.len() && starts[k + 1] <= x {
            k += 1;
        }
        let dx = x - sites[k] as i64;
        *o = dx * dx + g[sites[k]];
    }
}

/// `out[x - lo]`: the squared distance from `x` to the nearest set entry of `row`,
/// `FAR` when none is: the first pass, whose input is 0 or infinite, as two sweeps.
fn nearest_site_along_row(row: &[bool], lo: usize, out: &mut [i64]) {
    let hi = lo + out.len();
    // The nearest site at or before each x, then at or after it.
    let mut last: Option<usize> = row[..lo].iter().rposition(|&s| s);
    for x in lo..hi {
        if row[x] {
            last = Some(x);
        }
        out[x - lo] = last.map_or(FAR, |s| ((x - s) as i64).pow(2));
    }
    let mut next: Option<usize> = row[hi..].iter().position(|&s| s).map(|i| hi + i);
    for x in (lo..hi).rev() {
        if row[x] {
            next = Some(x);
        }
        if let Some(s) = next {
            out[x - lo] = out[x - lo].min(((s - x) as i64).pow(2));
        }
    }
}

/// The squared distance from each voxel of a brick of `b` voxels a side to the nearest
/// site of a cube of `h = b + 2 r` voxels a side around it (`site[x + h (y + h z)]`,
/// the brick at offsets `r..r + b`), written to `dist[x + b (y + b z)]`.
pub(super) fn brick_distances(site: &[bool], b: usize, r: usize, scratch: &mut Scratch, dist: &mut Vec<i64>) {
    let h = b + 2 * r;
    debug_assert_eq!(site.len(), h * h * h);
    let Scratch { line, out, sites, starts, pass_x, pass_y } = scratch;
    line.resize(h, 0);
    out.resize(b, 0);
    // Pass one, along x: every row of the halo, the brick's columns.
    pass_x.resize(b * h * h, 0);
    for row in 0..h * h {
        nearest_site_along_row(&site[h * row..h * (row + 1)], r, &mut pass_x[b * row..b * (row + 1)]);
    }
    // Pass two, along y: the brick's columns of every layer.
    pass_y.resize(b * b * h, 0);
    for z in 0..h {
        for x in 0..b {
            for (y, l) in line.iter_mut().enumerate() {
                *l = pass_x[x + b * (y + h * z)];
            }
            lower_envelope(line, r, out, sites, starts);
            for (y, &d) in out.iter().enumerate() {
                pass_y[x + b * (y + b * z)] = d;
            }
        }
    }
    // Pass three, along z: the brick.
    dist.resize(b * b * b, 0);
    for y in 0..b {
        for x in 0..b {
            for (z, l) in line.iter_mut().enumerate() {
                *l = pass_y[x + b * (y + b * z)];
            }
            lower_envelope(line, r, out, sites, starts);
            for (z, &d) in out.iter().enumerate() {
                dist[x + b * (y + b * z)] = d;
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
            let mut out = vec![0; len];
            lower_envelope(&g, lo, &mut out, &mut sites, &mut starts);
            for (j, &o) in out.iter().enumerate() {
                let x = (lo + j) as i64;
                let brute = g
                    .iter()
                    .enumerate()
                    .filter(|(_, gi)| **gi < FAR)
                    .map(|(i, gi)| (x - i as i64).pow(2) + gi)
                    .min()
                    .unwrap_or(FAR);
                assert_eq!(o, brute, "g {g:?} lo {lo} x {x}");
            }
        }
    }

    #[test]
    fn brick_distances_are_the_brute_force_distances_to_the_halos_sites() {
        let mut rng = Rng(11);
        let mut scratch = Scratch::default();
        let mut dist = Vec::new();
        for _ in 0..20 {
            let (b, r) = (1 + rng.below(6) as usize, rng.below(4) as usize);
            let h = b + 2 * r;
            let sparse = 1 + rng.below(20);
            let site: Vec<bool> = (0..h * h * h).map(|_| rng.below(sparse) == 0).collect();
            brick_distances(&site, b, r, &mut scratch, &mut dist);
            for z in 0..b {
                for y in 0..b {
                    for x in 0..b {
                        let p = [x + r, y + r, z + r].map(|c| c as i64);
                        let brute = (0..h * h * h)
                            .filter(|&i| site[i])
                            .map(|i| {
                                let s = [i % h, i / h % h, i / (h * h)].map(|c| c as i64);
                                (0..3).map(|a| (p[a] - s[a]).pow(2)).sum::<i64>()
                            })
                            .min()
                            .unwrap_or(FAR);
                        assert_eq!(dist[x + b * (y + b * z)], brute);
                    }
                }
            }
        }
    }
}
