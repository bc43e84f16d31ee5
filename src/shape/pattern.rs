//! Patterns: many placed copies of one shape as one CSG union, the CAD kernel's
//! linear array, polar (circular) array and mirror.
//!
//! - [`linear_array`]: copies at `(i sx, j sy, k sz)` for `i < nx`, `j < ny`,
//!   `k < nz` (a hole grid: `plate - linear_array(hole, [20, 20, 1], step)?`).
//! - [`polar_array`]: `n` copies turned by `i * step` about an axis through a centre,
//!   `step` defaulting to `360 / n` degrees (a bolt circle, gear teeth).
//! - [`mirrored`]: the shape and its reflection in a plane, `p - 2 ((p - o) . n) n`.
//!
//! A pattern is one [`CsgNode::Placed`](super::CsgNode::Placed) node: the shape, shared,
//! under one [`Placement`] a copy. Copy 0 is the shape itself; copy `i > 0` is a
//! translation (a linear array's, `p - offset`) or the affine map of a
//! [`super::Transformed`] (the same bits), so a pattern is exactly the union of the
//! same copies placed one by one, and a voxelizer that prunes CSG trees
//! ([`super::PrunedCsg`]) culls copies by their bounds. Copies may overlap (the union
//! is taken).
//!
//! At most [`MAX_COPIES`] copies in all: patterns nested in patterns multiply
//! ([`Csg::copies`]), so three nested arrays of 100 make 1,000,000 copies of their
//! shape and are refused, with the count, before anything is built.

use glam::{DAffine3, DMat3, DQuat, DVec3};

use super::bounds::finite;
use super::{Axis, Csg, Placement};
use crate::error::{Error, Result};

/// The most copies of any one shape: a pattern's count times the counts of the
/// patterns it is nested in.
pub const MAX_COPIES: u64 = 100_000;

/// The union of the copies of `shape` at `(i step.x, j step.y, k step.z)` for
/// `[i, j, k] < count`; fails for a count of zero, more than [`MAX_COPIES`] copies
/// (counting the copies `shape`'s own patterns make) or a step that is not finite.
pub fn linear_array(shape: impl Into<Csg>, count: [u32; 3], step: DVec3) -> Result<Csg> {
    let shape = shape.into();
    check_linear(count, step, shape.copies())?;
    let offsets = (0..count[2])
        .flat_map(move |k| (0..count[1]).flat_map(move |j| (0..count[0]).map(move |i| [i, j, k].map(f64::from))));
    let placements = offsets.enumerate().map(|(n, [i, j, k])| {
        if n == 0 { Placement::Identity } else { Placement::Translation(DVec3::new(i, j, k) * step) }
    });
    Csg::placed(shape, placements.collect())
}

/// The union of `count` copies of `shape` turned by `i * step_degrees` (default
/// `360 / count`) about the line through `center` along `axis`; fails for a count of
/// zero or over [`MAX_COPIES`] (with `shape`'s own copies), or a centre or step that
/// is not finite.
pub fn polar_array(
    shape: impl Into<Csg>,
    axis: Axis,
    center: DVec3,
    count: u32,
    step_degrees: Option<f64>,
) -> Result<Csg> {
    let shape = shape.into();
    let step = check_polar(center, count, step_degrees, shape.copies())?;
    let about_center = |i: u32| {
        let turn = DQuat::from_axis_angle(axis.unit(), (step * f64::from(i)).to_radians());
        DAffine3::from_translation(center) * DAffine3::from_quat(turn) * DAffine3::from_translation(-center)
    };
    copies(shape, (0..count).map(about_center))
}

/// The union of `shape` and its reflection in the plane through `point` with normal
/// `normal` (need not be unit); fails for a zero or non-finite normal, or over
/// [`MAX_COPIES`] copies of `shape`'s leaves.
pub fn mirrored(shape: impl Into<Csg>, normal: DVec3, point: DVec3) -> Result<Csg> {
    let (n, o) = check_mirror(normal, point)?;
    // Householder reflection I - 2 n n^T about the plane through o.
    let reflect = DMat3::IDENTITY - 2.0 * DMat3::from_cols(n * n.x, n * n.y, n * n.z);
    let map = DAffine3::from_translation(o) * DAffine3::from_mat3(reflect) * DAffine3::from_translation(-o);
    copies(shape.into(), [DAffine3::IDENTITY, map].into_iter())
}

/// Checks a [`linear_array`]'s count and step, for a shape whose own patterns make
/// `inner` copies.
pub(crate) fn check_linear(count: [u32; 3], step: DVec3, inner: u64) -> Result<()> {
    finite("step", step)?;
    check_count(count.iter().map(|&n| u64::from(n)).product(), &format!("{count:?}"), inner)
}

/// Checks a [`polar_array`]'s centre, count and step, for a shape whose own patterns
/// make `inner` copies; gives the step in degrees.
pub(crate) fn check_polar(center: DVec3, count: u32, step_degrees: Option<f64>, inner: u64) -> Result<f64> {
    finite("center", center)?;
    check_count(u64::from(count), &count.to_string(), inner)?;
    let step = step_degrees.unwrap_or(360.0 / f64::from(count));
    if step.is_finite() { Ok(step) } else { Err(Error::invalid("step_degrees", format!("{step} must be finite"))) }
}

/// Checks a [`mirrored`]'s plane; gives its unit normal and point.
pub(crate) fn check_mirror(normal: DVec3, point: DVec3) -> Result<(DVec3, DVec3)> {
    let n = finite("normal", normal)?
        .try_normalize()
        .ok_or_else(|| Error::invalid("normal", format!("{} must be non-zero", crate::error::Vector(normal))))?;
    Ok((n, finite("point", point)?))
}

/// Checks the copies of a mirror of a shape whose own patterns make `inner` copies.
pub(crate) fn check_mirror_copies(inner: u64) -> Result<()> {
    check_count(2, "a mirror", inner)
}

/// Fails unless `count` copies of a shape whose patterns make `inner` copies are 1 to
/// [`MAX_COPIES`] in all.
fn check_count(count: u64, given: &str, inner: u64) -> Result<()> {
    let total = count.saturating_mul(inner);
    if (1..=MAX_COPIES).contains(&total) {
        Ok(())
    } else if inner == 1 {
        Err(Error::invalid("count", format!("{given} makes {total} copies; a pattern makes 1 to {MAX_COPIES}")))
    } else {
        Err(Error::invalid(
            "count",
            format!(
                "{given} makes {count} copies of a shape whose patterns make {inner}: {total} copies; nested \
                 patterns make 1 to {MAX_COPIES} in all"
            ),
        ))
    }
}

/// The union of `shape` mapped by each of `maps`, the first of which must be the
/// identity (copy 0, the shape itself).
fn copies(shape: Csg, mut maps: impl Iterator<Item = DAffine3>) -> Result<Csg> {
    let first = maps.next();
    debug_assert_eq!(first, Some(DAffine3::IDENTITY));
    let placements = std::iter::once(Ok(Placement::Identity)).chain(maps.map(Placement::affine));
    Csg::placed(shape, placements.collect::<Result<_>>()?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::{Cuboid, Shape, Sphere};

    #[test]
    fn copies_land_where_the_pattern_says() {
        let ball = Sphere::new(DVec3::new(1.0, 0.0, 0.0), 0.25).unwrap();
        let grid = linear_array(ball.clone(), [3, 2, 1], DVec3::new(2.0, 5.0, 9.0)).unwrap();
        for (x, y, inside) in [(1.0, 0.0, true), (5.0, 5.0, true), (7.0, 5.0, false), (3.0, 2.5, false)] {
            assert_eq!(grid.contains(DVec3::new(x, y, 0.0)), inside, "({x}, {y})");
        }
        let circle = polar_array(ball.clone(), Axis::Z, DVec3::ZERO, 4, None).unwrap();
        for (x, y, inside) in [(0.0, 1.0, true), (-1.0, 0.0, true), (0.0, -1.0, true), (0.7, 0.7, false)] {
            assert_eq!(circle.contains(DVec3::new(x, y, 0.0)), inside, "({x}, {y})");
        }
        let pair = mirrored(ball, DVec3::new(3.0, 0.0, 0.0), DVec3::new(2.0, 0.0, 0.0)).unwrap();
        assert!(pair.contains(DVec3::new(1.0, 0.0, 0.0)) && pair.contains(DVec3::new(3.0, 0.0, 0.0)));
        assert!(!pair.contains(DVec3::new(2.0, 0.0, 0.0)));
    }

    #[test]
    fn bad_counts_and_steps_are_refused() {
        let cube = || Cuboid::new(DVec3::ZERO, DVec3::ONE).unwrap();
        assert!(linear_array(cube(), [0, 1, 1], DVec3::ONE).unwrap_err().to_string().contains("0 copies"));
        assert!(linear_array(cube(), [1000, 101, 1], DVec3::ONE).unwrap_err().to_string().contains("101000 copies"));
        assert!(linear_array(cube(), [2, 1, 1], DVec3::new(f64::NAN, 0.0, 0.0)).is_err());
        assert!(polar_array(cube(), Axis::X, DVec3::ZERO, 0, None).is_err());
        assert!(polar_array(cube(), Axis::X, DVec3::ZERO, 3, Some(f64::INFINITY)).is_err());
        assert!(mirrored(cube(), DVec3::ZERO, DVec3::ZERO).is_err());
    }
}
