//! Placements: where one copy of a pattern goes, as the map between the copy's frame
//! (the shape as written) and the world.
//!
//! A [`Placement`] is the identity (copy 0 of every pattern, the shape where it is), a
//! translation (a linear array's copies) or an invertible affine map (a polar array's
//! turns, a mirror, a `transform`). Each answers the questions a shape answers, in the
//! copy's frame: a point is mapped to the local frame (`p - offset`, `M^-1 p`), a box to
//! the bounding box of its mapped corners (a translation moves the box itself, the same
//! bits as its corners' hull), and a box or a surface found there back to the world
//! (normals by the inverse transpose `M^-T n`, distances to first order by `d / |M^-T n|`).
//!
//! These are the operations, and the floating-point operations, of [`super::Transformed`]
//! (and of the linear array's translations before patterns became placements), so a
//! tree of placed copies answers every question with the bits of the same copies made
//! one by one.

use glam::{DAffine3, DVec3};

use super::Surface;
use super::transformed::{check_invertible, map_box};
use crate::aabb::Aabb;
use crate::error::Result;

/// Where one copy goes: the map from its frame to the world (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub enum Placement {
    /// The copy is the shape itself.
    Identity,
    /// The copy is the shape moved by this offset.
    Translation(DVec3),
    /// The copy is the shape mapped by an invertible affine map.
    Affine {
        /// The map from the copy's frame to the world.
        to_world: DAffine3,
        /// Its inverse.
        to_local: DAffine3,
    },
}

impl Placement {
    /// The placement of the map `to_world`, which must be finite and invertible.
    pub fn affine(to_world: DAffine3) -> Result<Placement> {
        check_invertible(&to_world)?;
        Ok(Placement::Affine { to_world, to_local: to_world.inverse() })
    }

    /// The world point `p` in the copy's frame.
    #[inline]
    #[must_use]
    pub fn local_point(&self, p: DVec3) -> DVec3 {
        match self {
            Placement::Identity => p,
            Placement::Translation(offset) => p - *offset,
            Placement::Affine { to_local, .. } => to_local.transform_point3(p),
        }
    }

    /// A box holding the world box `b` in the copy's frame.
    #[inline]
    #[must_use]
    pub fn local_box(&self, b: &Aabb) -> Aabb {
        match self {
            Placement::Identity => *b,
            Placement::Translation(offset) => Aabb { min: b.min - *offset, max: b.max - *offset },
            Placement::Affine { to_local, .. } => map_box(to_local, b),
        }
    }

    /// A box holding the copy's box `b` in the world.
    #[must_use]
    pub fn world_box(&self, b: &Aabb) -> Aabb {
        match self {
            Placement::Identity => *b,
            Placement::Translation(offset) => Aabb { min: b.min + *offset, max: b.max + *offset },
            Placement::Affine { to_world, .. } => map_box(to_world, b),
        }
    }

    /// The copy's point `p` in the world.
    #[must_use]
    pub fn world_point(&self, p: DVec3) -> DVec3 {
        match self {
            Placement::Identity => p,
            Placement::Translation(offset) => p + *offset,
            Placement::Affine { to_world, .. } => to_world.transform_point3(p),
        }
    }

    /// The world direction `d` of a linear function `d . p` in the copy's frame (the
    /// function's gradient pulled back: `M^T d`).
    #[must_use]
    pub fn local_direction(&self, d: DVec3) -> DVec3 {
        match self {
            Placement::Identity | Placement::Translation(_) => d,
            Placement::Affine { to_world, .. } => to_world.matrix3.transpose() * d,
        }
    }

    /// The inverse of [`Placement::local_direction`]: `M^-T d`.
    #[must_use]
    pub fn world_direction(&self, d: DVec3) -> DVec3 {
        match self {
            Placement::Identity | Placement::Translation(_) => d,
            Placement::Affine { to_local, .. } => to_local.matrix3.transpose() * d,
        }
    }

    /// The copy's surface `s` (found at the local point) seen in the world; `None`
    /// where the mapped normal vanishes.
    #[must_use]
    pub fn world_surface(&self, s: Surface) -> Option<Surface> {
        match self {
            Placement::Identity | Placement::Translation(_) => Some(s),
            Placement::Affine { to_local, .. } => {
                Surface::from_field(s.distance, to_local.matrix3.transpose() * s.normal)
            }
        }
    }
}
