//! The film: where rays start and pixels end. Cameras and their per-image frames
//! ([`Camera`], [`View`]), camera placement by named views, orbit angles and
//! silhouette framing (`framing`), the camera a user asks for over a framing
//! ([`CameraRequest`], `request`) with its up ([`Up`]), the sample grid of a picture ([`SampleGrid`]), the camera
//! rays of a whole grid from per-row and per-column terms (`ray_grid`), the average
//! of a pixel's samples with the exposure and the sRGB transfer function (`resolve`),
//! and the picture of linear radiance a render makes ([`Picture`]).

mod camera;
mod framing;
mod picture;
pub(crate) mod ray_grid;
mod request;
pub(crate) mod resolve;
mod sample_grid;
mod up;

pub use camera::{Camera, DEFAULT_VIEW, Projection, View};
pub use framing::{NamedView, default_orbit, orbit_direction, silhouette_points, up_for};
pub use picture::Picture;
pub use request::{CameraRequest, DEFAULT_FOV, Framing};
pub use resolve::{MAX_EXPOSURE_STOPS, exposure_scale, from_srgb8, to_srgb8};
pub use sample_grid::SampleGrid;
pub use up::Up;
