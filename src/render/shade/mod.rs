//! The shading stage, the same for every visibility method: the shading normal
//! (`normals`), the local Phong term with shadows (`phong`), and Whitted's reflected
//! and transmitted rays (`whitted`, with the laws of reflection and refraction in
//! `optics`); secondary rays pass the voxel staircase a smooth surface leaves out
//! (`slivers`).

mod normals;
mod optics;
mod phong;
mod slivers;
mod whitted;

pub use normals::Normals;
pub use optics::{reflect, refract};
pub(crate) use phong::phong;
pub use whitted::radiance;

/// How the shading stage works.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ShadeOptions {
    /// Trace shadow rays.
    pub shadows: bool,
    /// Which normal shades (default [`Normals::Smooth`]).
    pub normals: Normals,
    /// Longest chain of reflected and refracted rays after the primary one (0: local
    /// shading only; at most [`MAX_RAY_DEPTH`](crate::render::MAX_RAY_DEPTH) in a
    /// render).
    pub max_depth: u32,
    /// A secondary ray is traced only when its weight in the pixel exceeds this
    /// (POV-Ray's `adc_bailout`, 1/255 there; default 0.001; within `0..=1` in a
    /// render).
    pub cutoff: f64,
}

impl Default for ShadeOptions {
    fn default() -> Self {
        ShadeOptions { shadows: true, normals: Normals::default(), max_depth: 6, cutoff: 1e-3 }
    }
}
