//! Rendering octree solids: the traversal octree and its exact ray walk, cameras,
//! scenes, the Phong shading stage with shadows, and supersampled frames.
//!
//! Pipeline: for each sample, visibility (the nearest solid and voxel along the primary
//! ray, with the entered face's axis normal) then shading (Phong, shadow rays through
//! the same octrees), averaged over the pixel's samples and encoded as sRGB.

pub mod beam;
pub mod camera;
mod display;
mod face;
pub mod frame;
pub mod light;
pub mod normals;
pub mod optics;
mod plane_times;
pub mod polygon;
pub mod raster;
mod ray_grid;
pub mod scene;
pub mod shade;
pub mod texture;
pub mod traverse;
pub mod whitted;

pub use beam::{PACKET, TILE};
pub use camera::{Camera, DEFAULT_VIEW, Projection, View};
pub use frame::{RenderOptions, RenderStats, render};
pub use light::{Bump, Light, Material};
pub use raster::{Method, Samples, VisibilityStats, visibility, visibility_into};
pub use scene::{Scene, SceneHit};
pub use shade::{Normals, ShadeOptions};
pub use traverse::{Hit, Traversal, VoxelRay};
