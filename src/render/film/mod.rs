//! The film: where rays start and pixels end. Cameras and their per-image frames
//! ([`Camera`], [`View`]), camera placement by named views, orbit angles and
//! silhouette framing (`framing`), the sample grid of a picture ([`SampleGrid`]), the camera
//! rays of a whole grid from per-row and per-column terms (`ray_grid`), and the
//! average of a pixel's samples with the sRGB transfer function (`resolve`).

mod camera;
mod framing;
pub(crate) mod ray_grid;
pub(crate) mod resolve;
mod sample_grid;

pub use camera::{Camera, DEFAULT_VIEW, Projection, View};
pub use framing::{NamedView, default_orbit, orbit_direction, silhouette_points, up_for};
pub use resolve::{from_srgb8, to_srgb8};
pub use sample_grid::SampleGrid;
