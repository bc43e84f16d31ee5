//! # octsolid
//!
//! Solid modeling and rendering on **linear octrees**. A solid is the sorted,
//! canonical list of its full octree nodes ([`octree::LinearOctree`]), 8 bytes a node,
//! over a cubic [`octree::Domain`] of depth up to 21. Solids come from shapes
//! ([`shape::Shape`]: quadrics, boxes, CSG trees of them, any type of yours) by
//! adaptive [`octree::voxelize`], and from triangle meshes and Bezier patches
//! ([`mesh`], [`patch`], [`import`]); they combine by set operations in one linear
//! merge, move exactly or by resampling, are measured ([`octree::Measures`]: boundary
//! area, centre of mass, inertia tensor, components), travel in files ([`io`]:
//! `.oct`, MagicaVoxel, binvox, OpenVDB, glTF, PNG) and are drawn by an octree
//! renderer ([`render`]: the ray walk through the octree itself, Meagher's
//! front-to-back display and the classic visibility algorithms, Phong, shadows,
//! Whitted, textures) from code or from scene files ([`scene_file`]).
//!
//! Modules, bottom up: [`morton`], [`shape`], [`octree`], [`mesh`], [`patch`], [`io`],
//! [`slice`](mod@slice), [`render`], [`import`], [`sharded`], [`scene_file`], [`samples`]. Across them: one
//! [`Error`] with the file and place of every failure, [`Warning`]s as values for what
//! a loader read past, a [`MemoryBudget`] every large
//! job is checked against before it allocates, [`Progress`] for long jobs (the library
//! never prints), and [`Ray`] with the one query interface of everything a ray can hit,
//! [`RayCast`]. A CSG script needs one import, [`prelude`].
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

// Every Rust block of the README compiles (`cargo test --doc`; its shell commands are
// run in order by tests/readme_walkthrough.rs).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeRustBlocks;

mod aabb;
mod budget;
pub mod color;
mod error;
mod file_kind;
mod fnv;
pub mod import;
pub mod io;
pub mod mesh;
pub mod morton;
pub mod octree;
mod owner;
pub mod patch;
mod progress;
mod quick;
mod ray;
pub mod render;
pub mod samples;
pub mod scene_file;
pub mod shape;
pub mod sharded;
pub mod slice;
#[cfg(test)]
mod test_util;
mod text;
mod warning;

pub use aabb::Aabb;
pub use budget::MemoryBudget;
pub use error::{Error, Result, human_bytes, printable};
pub use file_kind::FileKind;
pub use progress::{NoProgress, Progress};
pub use quick::quick;
pub use ray::{Ray, RayCast};
pub use warning::{Place, Warning};

/// Everything a CSG script needs, in one import.
pub mod prelude {
    pub use crate::io::{oct, png};
    pub use crate::mesh::{MeshShape, load_mesh};
    pub use crate::octree::{CoarsenRule, Domain, LinearOctree, SetOp, VoxelizeOptions, voxelize};
    pub use crate::shape::*;
    pub use crate::slice::slice_image;
    pub use crate::{Aabb, Error, MemoryBudget, Result};
    pub use glam::{DMat3, DMat4, DVec3};
}
