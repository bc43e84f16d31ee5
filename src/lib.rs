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
//! Modules, bottom up: [`morton`], [`shape`], [`octree`], [`mesh`], [`patch`],
//! [`slice`](mod@slice), [`render`], [`io`], [`import`], [`sharded`], the door for solid
//! files ([`SolidFile::read`], [`write_solid_file`]), [`scene_file`], [`samples`], and
//! at the top any drawable file opened as `octsolid render` opens it ([`Drawing::open`]:
//! a scene, a solid file or a mesh, its camera from a [`render::CameraRequest`], its
//! options from [`render::RenderOverrides`]) and a solid to a PNG in one call
//! ([`quick`]). Every file's kind is read off its extension by [`FileKind`]. Across
//! them: one [`Error`] with the file and place of every failure, [`Warning`]s as values
//! for what a loader read past, a [`MemoryBudget`] every large job is checked against
//! before it allocates, [`Progress`] for long jobs (the library never prints), and
//! [`Ray`] with the one query interface of everything a ray can hit,
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
// run in order by tests/readme_walkthrough.rs; rustdoc leaves its `python` blocks
// alone: python/tests/test_readme.py runs each of them).
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeRustBlocks;

mod aabb;
mod atomic;
mod budget;
pub mod color;
mod drawing;
mod error;
mod fields;
mod file_kind;
mod fnv;
pub mod import;
mod input_file;
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
mod solid_file;
mod spelling;
pub mod surface;
#[cfg(test)]
mod test_util;
mod text;
mod warning;

pub use aabb::Aabb;
pub use budget::MemoryBudget;
pub use drawing::{Drawing, DrawingOptions, DrawingStage};
pub use error::{Error, Result, human_bytes, printable};
pub use file_kind::FileKind;
pub use progress::{NoProgress, Progress, Stages};
pub use quick::quick;
pub use ray::{Ray, RayCast};
pub use solid_file::{GlbSurfaces, SolidFile, write_glb_surfaces, write_mesh_file, write_solid_file};
pub use warning::{Place, Warning};

/// The two crates whose types octsolid's API uses, re-exported so a caller names the
/// versions octsolid was built with: [`glam`]'s `DVec3`, `DMat3` and `DMat4` for
/// points, vectors and maps (every geometric argument), and [`image`]'s `RgbImage` for
/// 8-bit sRGB pictures (what [`slice::slice_image`], [`render::Picture::to_srgb8`] and
/// the PNG writer take or give). Both are part of octsolid's API: a release that moves
/// either to a new major version is a major release of octsolid.
pub use glam;
pub use image;

pub mod prelude {
    //! Everything a CSG script needs, in one import:
    //!
    //! - solids: [`Domain`], [`LinearOctree`] (with its set operators `|`, `&`, `-`, `^`),
    //!   [`voxelize`] and its [`VoxelizeOptions`], [`SetOp`], [`CoarsenRule`];
    //! - shapes: the primitives ([`Sphere`], [`Ellipsoid`], [`Cuboid`], [`Cylinder`], [`Cone`],
    //!   [`Torus`], [`HalfSpace`], [`Menger`], [`DisplacedSphere`]), [`Csg`] trees and
    //!   [`CsgNode`]s, [`Transformed`] and [`ShapeExt`] (`.translate()`, `.rotate()`, `.scale()`, `.transform()`),
    //!   the patterns ([`linear_array`], [`polar_array`], [`mirrored`], [`Placement`]), the
    //!   offset nodes ([`offset`], [`shell`], [`round`], made on a lattice by
    //!   [`resolve_offsets`] before [`voxelize`]), the
    //!   [`Shape`] trait with [`Surface`] and [`Axis`], and [`MeshShape`] with
    //!   [`read_mesh`] for a closed mesh as a shape;
    //! - files and pictures: the [`oct`] and [`png`] modules, [`slice_image`];
    //! - [`Aabb`], [`Error`], [`Result`], [`MemoryBudget`], and glam's [`DVec3`], [`DMat3`],
    //!   [`DMat4`].

    pub use crate::io::{oct, png};
    pub use crate::mesh::{MeshShape, read_mesh};
    pub use crate::octree::{CoarsenRule, Domain, LinearOctree, SetOp, VoxelizeOptions, voxelize};
    pub use crate::shape::{
        Axis, Cone, Csg, CsgNode, Cuboid, Cylinder, DisplacedSphere, Ellipsoid, HalfSpace, Menger, Placement, Shape,
        ShapeExt, Sphere, Surface, Torus, Transformed, linear_array, mirrored, offset, polar_array, round, shell,
    };
    pub use crate::slice::slice_image;
    pub use crate::surface::resolve_offsets;
    pub use crate::{Aabb, Error, MemoryBudget, Result};
    pub use glam::{DMat3, DMat4, DVec3};
}
