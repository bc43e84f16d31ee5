//! Measurements of a solid: volume, boundary area, centre of mass, inertia tensor and
//! connected components ([`LinearOctree::measure`]), each also on its own:
//! [`LinearOctree::mass_properties`] (exact sums over the nodes, `mass`),
//! [`LinearOctree::surface_area`] (an estimate that converges to a smooth surface's
//! area, and the raw voxel face area, `area`), [`LinearOctree::components`]
//! (face-connected, `components`). All work on the key list; none builds a grid.

mod area;
mod beyond;
mod bricks;
mod components;
mod mass;
mod rows;

use glam::{DMat3, DVec3};

pub use area::SurfaceArea;
pub use mass::MassProperties;

use crate::octree::LinearOctree;

/// What [`LinearOctree::measure`] finds, in world units at unit density.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Measures {
    /// Volume (and mass): full voxels times `h^3`.
    pub volume: f64,
    /// The boundary's area, estimated so that it converges to a smooth surface's
    /// ([`SurfaceArea::estimate`]).
    pub surface_area: f64,
    /// The voxel boundary's own area, exposed voxel faces times `h^2` (about 1.5 times
    /// a curved surface's).
    pub voxel_face_area: f64,
    /// Centre of mass; `None` for the empty solid.
    pub centre_of_mass: Option<DVec3>,
    /// Inertia tensor about the centre of mass (symmetric); zero for the empty solid.
    pub inertia: DMat3,
    /// Face-connected components of the full voxels.
    pub components: u64,
}

impl LinearOctree {
    /// Every measurement of [`Measures`] (see the module doc for each), the three
    /// parts side by side on the thread pool.
    #[must_use]
    pub fn measure(&self) -> Measures {
        let (area, (mass, components)) =
            rayon::join(|| self.surface_area(), || rayon::join(|| self.mass_properties(), || self.components()));
        Measures {
            volume: mass.volume,
            surface_area: area.estimate,
            voxel_face_area: area.voxel_faces,
            centre_of_mass: mass.centre_of_mass,
            inertia: mass.inertia,
            components,
        }
    }
}
