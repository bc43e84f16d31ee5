//! The library's integration suites, one test binary: each suite is a file of its own
//! beside this one (`tests/offset.rs`, ...) and a module here, so the library's generic
//! code they use is compiled and linked once, not once a suite, and all their tests run
//! in one process, in parallel. Run one suite with its module's name as the filter:
//! `cargo test --release --test library offset::`.
//!
//! Each suite is loaded with `#[path]`, so the `mod common;` and `#[path]`s inside it
//! resolve from `tests/`, as when every suite was a test binary of its own.
//! `tests/writer_budgets.rs` stays one: its counting global allocator measures the
//! whole process, which the other suites' tests would share.

// Every suite keeps its own `mod common;`, as when it was a crate of its own, so a
// file of tests/common/ is a module of each suite that uses it.
#![allow(clippy::duplicate_mod)]

#[path = "appearance.rs"]
mod appearance;
#[path = "boundary.rs"]
mod boundary;
#[path = "bvh.rs"]
mod bvh;
#[path = "cancel.rs"]
mod cancel;
#[path = "csg_many.rs"]
mod csg_many;
#[path = "exact_surface.rs"]
mod exact_surface;
#[path = "formats.rs"]
mod formats;
#[path = "gathering.rs"]
mod gathering;
#[path = "hostile_input.rs"]
mod hostile_input;
#[path = "loaders.rs"]
mod loaders;
#[path = "measure.rs"]
mod measure;
#[path = "mesh.rs"]
mod mesh;
#[path = "mesh_shape.rs"]
mod mesh_shape;
#[path = "oct_file.rs"]
mod oct_file;
#[path = "octree.rs"]
mod octree;
#[path = "offset.rs"]
mod offset;
#[path = "painter.rs"]
mod painter;
#[path = "patches.rs"]
mod patches;
#[path = "picture.rs"]
mod picture;
#[path = "polygon.rs"]
mod polygon;
#[path = "profiles.rs"]
mod profiles;
#[path = "radiosity.rs"]
mod radiosity;
#[path = "render.rs"]
mod render;
#[path = "scene_file.rs"]
mod scene_file;
#[path = "shapes.rs"]
mod shapes;
#[path = "sharded.rs"]
mod sharded;
#[path = "sharded_offset.rs"]
mod sharded_offset;
#[path = "sharded_surface.rs"]
mod sharded_surface;
#[path = "stl_export.rs"]
mod stl_export;
#[path = "surface_adaptive.rs"]
mod surface_adaptive;
#[path = "surface_extract.rs"]
mod surface_extract;
#[path = "surface_file.rs"]
mod surface_file;
#[path = "surface_sources.rs"]
mod surface_sources;
#[path = "three_mf.rs"]
mod three_mf;
#[path = "transform.rs"]
mod transform;
#[path = "traverse.rs"]
mod traverse;
#[path = "voxelize.rs"]
mod voxelize;
#[path = "whitted.rs"]
mod whitted;
