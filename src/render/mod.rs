//! Rendering octree solids. Read bottom-up, each layer using only those below it:
//!
//! - [`film`]: cameras, the sample grid, camera rays of a grid, the pixel average and
//!   sRGB.
//! - [`trace`]: the traversal octree and its exact ray walk, with the beam pre-pass
//!   for packets of primary rays.
//! - [`scene`]: what a picture shows: solids with materials and textures, lights.
//! - [`raster`]: object-order visibility: front-to-back, painter's, Z-buffer and
//!   scan-line over voxel faces, and triangle meshes as polygons.
//! - [`shade`]: the shading stage: normals, Phong with shadows, Whitted.
//! - `visibility`: which solid, voxel and face each sample sees, by any [`Method`]
//!   (the ray walk or a raster method: the same hits, bit for bit).
//! - `pipeline`: [`render`]: visibility, then shading, averaged over each pixel's
//!   samples.

pub mod film;
mod pipeline;
pub mod raster;
pub mod scene;
pub mod shade;
pub mod trace;
mod visibility;

pub use film::{Camera, DEFAULT_VIEW, Projection, SampleGrid, View};
pub use pipeline::{MAX_IMAGE_SIZE, RenderOptions, RenderStats, render};
pub use scene::{Bump, Light, Material, Scene, SceneHit, SceneSolid};
pub use shade::{Normals, ShadeOptions};
pub use trace::{Hit, PACKET, TILE, Traversal, VoxelRay};
pub use visibility::{Method, VisibilityStats, visibility, visibility_into};
