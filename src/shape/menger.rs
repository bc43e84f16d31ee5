//! The Menger sponge: a cube with the middle cross of thirds removed, recursively.
//!
//! A point with unit-cube coordinates `t` is removed at level `d` when two or more of
//! its base-3 digits `floor(t * 3^d) mod 3` are the middle digit 1. A box is decided
//! by walking down the levels while it stays inside one cell of the level: a removed
//! cell makes it Outside, a cell kept to the last level Inside, a box spanning cells
//! Boundary. Each level keeps 20 of 27 sub-cubes: volume `size^3 (20/27)^level`.

use glam::DVec3;

use super::bounds::{finite, positive};
use super::{Class, Shape};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// The level-`level` Menger sponge filling an axis-aligned cube.
#[derive(Clone, Debug, PartialEq)]
pub struct Menger {
    min: DVec3,
    size: f64,
    level: u32,
}

impl Menger {
    /// The sponge of `level` (at most 30) in the cube centred on `center` with edge `size`.
    pub fn new(center: DVec3, size: f64, level: u32) -> Result<Self> {
        if level > 30 {
            return Err(Error::invalid("level", format!("{level} is above 30")));
        }
        let size = positive("size", size)?;
        Ok(Menger { min: finite("center", center)? - DVec3::splat(size / 2.0), size, level })
    }

    /// Volume: `size^3 (20/27)^level`.
    #[must_use]
    pub fn volume(&self) -> f64 {
        self.size.powi(3) * (20.0f64 / 27.0).powi(self.level as i32)
    }

    /// Unit-cube coordinates of `p`.
    fn unit(&self, p: DVec3) -> DVec3 {
        (p - self.min) / self.size
    }
}

/// The cell of unit coordinate `t` at `level` (`3^level` cells a side).
fn cell(t: DVec3, level: u32) -> DVec3 {
    (t * 3f64.powi(level as i32)).floor()
}

/// Whether the cell `c` of its level is a removed middle cross: two or more of its
/// last base-3 digits are 1.
fn removed(c: DVec3) -> bool {
    c.to_array().iter().filter(|&&c| c.rem_euclid(3.0) == 1.0).count() >= 2
}

impl Shape for Menger {
    fn contains(&self, p: DVec3) -> bool {
        let t = self.unit(p);
        t.cmpge(DVec3::ZERO).all() && t.cmplt(DVec3::ONE).all() && (1..=self.level).all(|d| !removed(cell(t, d)))
    }

    fn classify(&self, b: &Aabb) -> Class {
        let (lo, hi) = (self.unit(b.min), self.unit(b.max));
        if hi.cmplt(DVec3::ZERO).any() || lo.cmpge(DVec3::ONE).any() {
            return Class::Outside;
        }
        if lo.cmplt(DVec3::ZERO).any() || hi.cmpge(DVec3::ONE).any() {
            return Class::Boundary;
        }
        // Every point of the box lies between lo and hi, so in their cells (floor is
        // monotone): while those agree, the box shares the fate of one cell.
        for d in 1..=self.level {
            let c = cell(lo, d);
            if c != cell(hi, d) {
                return Class::Boundary;
            }
            if removed(c) {
                return Class::Outside;
            }
        }
        Class::Inside
    }

    /// The cube's corner on `d`'s side (the sponge keeps its corners).
    fn support(&self, d: DVec3) -> Option<DVec3> {
        Some(self.min + DVec3::select(d.cmpge(DVec3::ZERO), DVec3::splat(self.size), DVec3::ZERO))
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(Aabb::new(self.min, self.min + DVec3::splat(self.size)))
    }
}
