//! Rendering octree solids. Read bottom-up, each layer using only those below it:
//!
//! - `film`: cameras ([`Camera`]), the sample grid ([`SampleGrid`]), camera rays of a
//!   grid, the pixel average, exposure and sRGB, the picture of linear radiance a
//!   render makes ([`Picture`]).
//! - `trace`: the traversal octree ([`Traversal`]) and its exact ray walk, with the
//!   beam pre-pass for packets of primary rays.
//! - `scene`: what a picture shows ([`Scene`]): solids with materials and textures,
//!   lights.
//! - `raster`: object-order visibility: front-to-back, painter's, Z-buffer and
//!   scan-line over voxel faces, and triangle meshes as polygons ([`polygon`]).
//! - [`radiosity`]: diffuse interreflection solved on the solids' boundary patches
//!   (form factors by rays through the octree, progressive refinement), saved as
//!   `.rad` files and shown through [`Scene::illumination`].
//! - `shade`: the shading stage: normals, Phong with shadows, Whitted ([`radiance`]).
//! - `visibility`: which solid, voxel and face each sample sees, by any [`Method`]
//!   (the ray walk or a raster method: the same hits, bit for bit).
//! - `pipeline`: [`render_picture`]: visibility, then shading, averaged over each
//!   pixel's samples, in every pixel or where adaptive anti-aliasing asks
//!   (`adaptive`), or by recursive adaptive anti-aliasing (`recursive_aa`), to
//!   linear radiance; [`render`]: the same as 8-bit sRGB (a solid to a PNG file in one
//!   call is [`crate::quick`], above `io`).

mod adaptive;
mod film;
mod names;
mod overrides;
mod pipeline;
pub mod radiosity;
mod raster;
mod recursive_aa;
mod scene;
mod shade;
mod trace;
mod visibility;

pub use film::{
    Camera, CameraRequest, DEFAULT_FOV, DEFAULT_VIEW, Framing, MAX_EXPOSURE_STOPS, NamedView, Picture, Projection,
    SampleGrid, Up, View, default_orbit, exposure_scale, from_srgb8, orbit_direction, silhouette_points, to_srgb8,
    up_for,
};
pub use overrides::RenderOverrides;
pub use pipeline::{
    AntiAliasing, AntiAliasingKind, DEFAULT_AA_DEPTH, DEFAULT_AA_THRESHOLD, MAX_IMAGE_SIZE, MAX_RAY_DEPTH,
    RenderOptions, RenderStats, RowSink, estimate_bytes, render, render_picture, render_streamed,
};
pub use raster::polygon;
pub use recursive_aa::MAX_AA_DEPTH;
pub use scene::{
    Bump, Cast, Illumination, Light, Mapping, Material, Scene, SceneHit, SceneSolid, Section, Texture, Walker,
};
pub use shade::{Normals, ShadeOptions, radiance, reflect, refract};
pub use trace::{Hit, PACKET, TILE, Traversal, Tree64};
pub use visibility::{Method, VisibilityStats, visibility, visibility_into};
