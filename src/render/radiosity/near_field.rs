//! The near field of a shooting patch, and how its light is split between near and far
//! receivers so that none is made or lost.
//!
//! A departure from Cohen et al. 1988, in the spirit of hierarchical radiosity's
//! refinement of the shooter (Hanrahan, Salzman and Aupperle 1991): an element within
//! [`NEAR`] patch edges (the longer) of a patch's centre receives from the patch's base
//! elements one by one, `sum_k F(dA_e -> A_k) B_k`, instead of from the patch's mean,
//! `F(dA_e -> A_i) B_i`. Where a receiver is close, its form factor is concentrated on
//! the nearest part of the patch, whose light is not the mean: the dark floor in a
//! block's shadow lit the block's foot as if it had the floor patch's mean radiosity
//! (Mitsuba's Cornell box: the short block's front 11% too bright, its foot 40 to
//! 90%). A partly covered tile, or a patch of one element, always gives its mean.
//!
//! The split. With the mean everywhere a shot is conservative: receivers take
//! `pi sum_e A_e F(dA_e -> A_i) B_i`, at most what the patch sends (the form factors
//! sum to at most one). Taking the elements' own light near and the mean far is not:
//! where near receivers see the patch's brighter elements more than its darker ones,
//! the shot delivers more than it sends (a closed room lit by a point light, 4.3% more
//! absorbed than emitted). Element `k` sends `pi A_k B_k`; if every element's light
//! reaches the scene in the same fraction `G` (exactly one in a closed room), then what
//! reaches the far receivers is `pi (G A_i B_i - sum_k N_k B_k)`, with
//! `N_k = sum_{e near} A_e F(dA_e -> A_k)` the near receivers' share of element `k`,
//! while the mean gives them `pi (G A_i - sum_k N_k) B_i`. So the far receivers take
//! the mean less the near receivers' excess, spread over them in proportion to their
//! form factors:
//!
//! ```text
//! B_far = B_i - (sum_k N_k B_k - B_i sum_k N_k) / M,    M = sum_{e far} A_e F(dA_e -> A_i)
//! ```
//!
//! each far receiver taking `F(dA_e -> A_i) B_far`: the shot again delivers exactly
//! what the mean would, and the far receivers' share is right where `G` is the same
//! for all elements (a closed room). `B_far` is linear in the elements' `B_k`,
//! so gathering (module `gather`) solves the same system as shooting. Departures: a
//! channel of `B_far` is kept from changing sign (an open scene whose far receivers see
//! little of the patch could otherwise take negative light; the split then gives more
//! than it sends), and a patch with no far receivers (`M = 0`: a small scene) gives its
//! near receivers its mean.

use glam::DVec3;

use super::patch::Patch;
use super::patches::Element;

/// Receivers within this many patch edges (the longer) of a shooting patch's centre
/// receive from its elements one by one (module doc). Two, not the 1.5 the near field
/// began with: with the far receivers' light balanced, the Mitsuba Cornell box's short
/// block front (a dark face whose upper elements were far from the shadowed floor in
/// front of it, so took some of the light its shadow's near receivers left) was 5.2%
/// bright at 1.5 and is 4.5% at 2, for 5% more rays a shot.
pub(crate) const NEAR: f64 = 2.0;

/// Patch `shooter`'s base elements as rectangles of their own, each with its value
/// of `values` (the patch's elements' slice), for the receivers near it: none for a
/// partly covered tile or a patch of one element.
pub(super) fn element_parts(shooter: &Patch, values: &[DVec3]) -> Vec<(Patch, DVec3)> {
    let count = values.len();
    if shooter.cover.is_some() || count <= 1 {
        return Vec::new();
    }
    let (du, dv) = (shooter.du / f64::from(shooter.nu), shooter.dv / f64::from(shooter.nv));
    let area = shooter.area / count as f64;
    values
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let (col, row) = (f64::from(k as u32 % shooter.nu), f64::from(k as u32 / shooter.nu));
            (Patch { corner: shooter.corner + du * col + dv * row, du, dv, area, ..shooter.clone() }, *v)
        })
        .collect()
}

/// Whether `e` is a near receiver of `shooter` (within [`NEAR`] edges of its centre).
pub(super) fn is_near(e: &Element, shooter: &Patch) -> bool {
    (e.center - shooter.center()).length() < NEAR * shooter.du.length().max(shooter.dv.length())
}

/// The light far receivers take of a patch of mean light `mean`, given the near
/// receivers' `excess` (`sum_{e near} A_e sum_k F(dA_e -> A_k) (B_k - mean)`, that is
/// `sum_k N_k B_k - mean sum_k N_k`) and the far receivers' `far_weight` (`M`): the
/// module doc's `B_far`, each channel kept from changing sign; `mean` when there are
/// no far receivers.
pub(super) fn far_light(mean: DVec3, excess: DVec3, far_weight: f64) -> DVec3 {
    if far_weight <= 0.0 {
        return mean;
    }
    let far = mean - excess / far_weight;
    let keep_sign = |f: f64, m: f64| if m >= 0.0 { f.max(0.0) } else { f.min(0.0) };
    DVec3::new(keep_sign(far.x, mean.x), keep_sign(far.y, mean.y), keep_sign(far.z, mean.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_light_gives_back_what_the_near_receivers_took_in_excess() {
        let (mean, far_weight) = (DVec3::new(1.0, 2.0, 0.5), 4.0);
        let excess = DVec3::new(0.4, -0.8, 0.0);
        let far = far_light(mean, excess, far_weight);
        // What the receivers take in all equals what the mean would give them.
        let delivered = far * far_weight + excess;
        assert!((delivered - mean * far_weight).abs().max_element() < 1e-12, "{delivered}");
    }

    #[test]
    fn far_light_keeps_each_channels_sign_and_falls_back_to_the_mean() {
        let far = far_light(DVec3::new(1.0, -1.0, 0.0), DVec3::new(10.0, -10.0, 1.0), 1.0);
        assert_eq!(far, DVec3::new(0.0, 0.0, 0.0));
        assert_eq!(far_light(DVec3::ONE, DVec3::splat(5.0), 0.0), DVec3::ONE);
    }
}
