//! A solid moved by a similarity (scale, turns about the axes, translation), exactly
//! where the move maps voxels to voxels and by resampling otherwise.
//!
//! The map is `p -> t + R_n ... R_1 (s p)`: scale about the origin first, then each
//! turn about its axis through the origin in the order given (right-handed: a
//! positive turn about z takes +x towards +y), then the translation; as OpenSCAD's
//! `translate(t) rotate(..) scale(s)` reads.
//!
//! Exact case: every turn a multiple of 90 degrees and the scale a power of two. The
//! image of the domain cube is then an axis-aligned cube of edge `s E`, and the solid
//! in it is the source's keys turned about the domain centre
//! ([`LinearOctree::rotate90`]): with `c` the centre and `m'` the image cube's lowest
//! corner, `m' + s (R (p - c) + c - m) = t + s R p` because `m' = t + s R c - s E / 2`
//! and `c = m + E / 2`. No voxel is sampled, so the result is exact at any
//! translation, and the domain moves with the solid (nothing clips).
//!
//! Otherwise the solid is sampled ([`LinearOctree::resample`]) into the cube around
//! the image of its bounds, grown by 2% a side, at the source's depth: the voxel edge
//! follows the solid's size.

use glam::{DAffine3, DMat3, DVec3};

use super::domain::Domain;
use super::driver::VoxelizeOptions;
use super::fit::{Fit, image_domain};
use super::linear::LinearOctree;
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

    /// The quarter turns of each turn when all are whole quarter turns and the scale
    /// is a power of two (the exact case), else `None`.
    fn quarter_turns(&self) -> Option<Vec<(Axis, i32)>> {
        let k = self.scale.log2().round();
        if (self.scale - k.exp2()).abs() > 1e-12 * self.scale {
            return None;
        }
        self.turns
            .iter()
            .map(|t| {
                let q = (t.degrees / 90.0).round();
                ((t.degrees - 90.0 * q).abs() <= 1e-9 && q.abs() < 1e9).then_some((t.axis, q as i32))
            })
            .collect()
    }

    fn check(&self) -> Result<()> {
        let finite = self.translate.is_finite() && self.turns.iter().all(|t| t.degrees.is_finite());
        if !finite || !self.scale.is_finite() || self.scale <= 0.0 {
            return Err(Error::invalid("transform", format!("{self:?}: needs finite numbers and a positive scale")));
        }
        Ok(())
    }
}

impl LinearOctree {
    /// The solid moved by `motion` into the domain `target` makes of the default one
    /// (the moved domain in the exact case, else the cube around the moved bounds; see
    /// the module doc): pass `Ok` to keep the default. Exact where the move maps
    /// voxels to voxels and the target's lattice nests in the moved one, else sampled
    /// once, straight from this solid; says which.
    pub fn transformed(
        &self,
        motion: &Motion,
        target: impl FnOnce(Domain) -> Result<Domain>,
        options: &VoxelizeOptions,
    ) -> Result<(LinearOctree, Fit)> {
        motion.check()?;
        let map = motion.affine();
        let d = self.domain();
        if let Some(turns) = motion.quarter_turns() {
            let mut tree = turns.iter().fold(self.clone(), |t, &(axis, q)| t.rotate90(axis.index(), q));
            let moved = image_domain(&d.aabb(), map, 0.0, d.depth())?;
            let moved = Domain::new(moved.min(), d.edge() * motion.scale, d.depth())?;
            tree = LinearOctree::from_canonical(moved, tree.keys().to_vec());
            let (tree, fit) = tree.fit_to(target(moved)?, options)?;
            let fit = match fit {
                Fit::Same => Fit::Exact { refined: 0, offset: [0; 3] },
                other => other,
            };
            return Ok((tree, fit));
        }
        let default = match self.bounds() {
            Some(b) => image_domain(&b, map, 0.02, d.depth())?,
            None => image_domain(&d.aabb(), map, 0.0, d.depth())?,
        };
        Ok((self.resample(map, target(default)?, options)?, Fit::Resampled))
    }
}
