//! # octsolid
//!
//! Solid modeling and rendering on **linear octrees**. A solid is the sorted,
//! canonical list of its full octree nodes ([`LinearOctree`]), 8 bytes a node, over a
//! cubic [`Domain`] of depth up to 21. Solids come from [`Shape`]s (quadrics, boxes,
//! CSG trees of them) by adaptive [`voxelize`], combine by set operations in one linear
//! merge, transform, and save to the `.oct` format.
//!
//! ```
//! use octsolid::prelude::*;
//!
//! # fn main() -> octsolid::Result<()> {
//! let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6)?;
//! let ball = voxelize(&Sphere::new(DVec3::ZERO, 0.9)?, domain, &Default::default())?;
//! let cube = voxelize(&Cuboid::new(DVec3::ZERO, DVec3::splat(1.4))?, domain, &Default::default())?;
//! let shell = &ball - &cube;
//! shell.validate()?;
//! assert!(shell.volume() < ball.volume());
//! # Ok(())
//! # }
//! ```

#![deny(missing_docs)]

pub mod aabb;
pub mod budget;
pub mod color;
pub mod error;
pub mod file_kind;
pub mod import;
pub mod io;
pub mod mesh;
pub mod morton;
pub mod octree;
pub mod patch;
pub mod progress;
pub mod ray;
pub mod render;
pub mod samples;
pub mod scene_file;
pub mod shape;
pub mod slice;
#[cfg(test)]
mod test_util;

pub use aabb::Aabb;
pub use error::{Error, Result};
pub use file_kind::FileKind;
pub use octree::{Domain, LinearOctree, Node, NodeKey, voxelize};
pub use ray::{Ray, RayCast};
pub use shape::{Class, Shape};

/// Everything a CSG script needs, in one import.
pub mod prelude {
    pub use crate::aabb::Aabb;
    pub use crate::budget::MemoryBudget;
    pub use crate::error::{Error, Result};
    pub use crate::io::{oct, png};
    pub use crate::octree::{CoarsenRule, Domain, LinearOctree, SetOp, VoxelizeOptions, voxelize};
    pub use crate::shape::*;
    pub use crate::slice::slice_image;
    pub use glam::{DMat3, DMat4, DVec3};
}
