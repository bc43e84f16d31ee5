//! A similarity as a user gives it (scale, turns about the axes, translation), the
//! map [`LinearOctree::transformed`](crate::octree::LinearOctree::transformed) moves a
//! solid by.
//!
//! The map is `p -> t + R_n ... R_1 (s p)`: scale about the origin first, then each
//! turn about its axis through the origin in the order given (right-handed: a
//! positive turn about z takes +x towards +y), then the translation; as OpenSCAD's
//! `translate(t) rotate(..) scale(s)` reads.
//!
//! Quarter turns and any positive scale are exact there (a cube symmetry times a
//! scale); other turns resample.

use glam::{DAffine3, DMat3, DVec3};

use crate::error::{Error, Result};
use crate::shape::Axis;

/// A turn about a coordinate axis through the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Turn {
    /// The axis turned about.
    pub axis: Axis,
    /// The angle, right-handed.
    pub degrees: f64,
}

/// A similarity: `p -> translate + turns (scale p)` (see the module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct Motion {
    /// Uniform scale about the origin, positive.
    pub scale: f64,
    /// Turns applied in order after the scale.
    pub turns: Vec<Turn>,
    /// Translation applied last.
    pub translate: DVec3,
}

impl Default for Motion {
    fn default() -> Self {
        Motion { scale: 1.0, turns: Vec::new(), translate: DVec3::ZERO }
    }
}

impl Motion {
    /// The map as an affine transform.
    #[must_use]
    pub fn affine(&self) -> DAffine3 {
        let turns = self
            .turns
            .iter()
            .fold(DMat3::IDENTITY, |acc, t| DMat3::from_axis_angle(t.axis.unit(), t.degrees.to_radians()) * acc);
        DAffine3::from_mat3_translation(turns * DMat3::from_diagonal(DVec3::splat(self.scale)), self.translate)
    }

    /// The map as an affine transform, checked: finite numbers and a positive scale.
    pub fn checked_affine(&self) -> Result<DAffine3> {
        if !self.scale.is_finite() || self.scale <= 0.0 {
            return Err(Error::invalid(
                "transform",
                format!("scale {} must be finite and positive", crate::error::Number(self.scale)),
            ));
        }
        if let Some(t) = self.turns.iter().find(|t| !t.degrees.is_finite()) {
            return Err(Error::invalid("transform", format!("the turn of {} degrees is not finite", t.degrees)));
        }
        if !self.translate.is_finite() {
            return Err(Error::invalid("transform", format!("the move {} is not finite", self.translate)));
        }
        let map = self.affine();
        crate::shape::check_invertible(&map)?;
        Ok(map)
    }
}
