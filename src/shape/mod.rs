//! Shapes: anything that can classify a box as inside, outside or crossed by its
//! surface, and decide a point.
//!
//! A [`Shape`] answers two questions, the pair adaptive voxelization needs:
//! - [`Shape::classify`] of an axis-aligned box, **conservatively**: `Inside` only when
//!   every point of the box is inside, `Outside` only when none is; whenever in doubt
//!   (the surface crosses the box, or rounding could matter) `Boundary`.
//! - [`Shape::contains`] of a point, the rule that decides voxels at the finest level.
//!
//! Soundness contract: `classify(b) == Inside` implies `contains(p)` for every `p` in
//! `b`, and `Outside` implies `!contains(p)`. With it, voxelizing a CSG tree of shapes
//! gives exactly the CSG of the voxelized leaves.

use glam::DVec3;

use crate::aabb::Aabb;

/// Where a box lies relative to a solid.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Class {
    /// Every point of the box is in the solid.
    Inside,
    /// No point of the box is in the solid.
    Outside,
    /// Undecided: the surface may cross the box.
    Boundary,
}

impl Class {
    /// The class of the complement.
    #[must_use]
    pub fn complement(self) -> Class {
        match self {
            Class::Inside => Class::Outside,
            Class::Outside => Class::Inside,
            Class::Boundary => Class::Boundary,
        }
    }
}

/// A solid that voxelization can ask about boxes and points. See the module doc.
pub trait Shape: Send + Sync {
    /// Conservative classification of the closed box `b`.
    fn classify(&self, b: &Aabb) -> Class;

    /// Whether the point `p` is in the solid.
    fn contains(&self, p: DVec3) -> bool;

    /// A box holding the solid; `None` when it is unbounded (a half-space).
    fn bounds(&self) -> Option<Aabb>;

    /// The surface nearest `p` (signed distance and outward normal), for smooth
    /// shading; `None` (the default) when the shape cannot tell.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let _ = p;
        None
    }

    /// A point of the solid farthest along `direction` (a support point: `p` in the
    /// closed solid maximizing `direction . p`), what [`Hull`] builds convex hulls
    /// from; `None` (the default) when the shape cannot tell.
    fn support(&self, direction: DVec3) -> Option<DVec3> {
        let _ = direction;
        None
    }

    /// The CSG tree this shape is, if it is one: what lets a voxelizer see the tree's
    /// leaves and their bounds and prune it ([`PrunedCsg`]); `None` (the default) for
    /// a shape that is classified only as a whole.
    fn as_csg(&self) -> Option<&Csg> {
        None
    }

    /// The offset, shell or round node this shape is, if it is one: what
    /// `surface::resolve_offsets` replaces by its solid on a lattice ([`Morphed`]);
    /// `None` (the default) for every other shape.
    fn as_morphed(&self) -> Option<&Morphed> {
        None
    }
}

/// Shapes behind references and smart pointers are shapes.
macro_rules! forward_shape {
    ($($ptr:ty),*) => {$(
        impl<S: Shape + ?Sized> Shape for $ptr {
            fn classify(&self, b: &Aabb) -> Class {
                (**self).classify(b)
            }
            fn contains(&self, p: DVec3) -> bool {
                (**self).contains(p)
            }
            fn bounds(&self) -> Option<Aabb> {
                (**self).bounds()
            }
            fn surface(&self, p: DVec3) -> Option<Surface> {
                (**self).surface(p)
            }
            fn support(&self, direction: DVec3) -> Option<DVec3> {
                (**self).support(direction)
            }
            fn as_csg(&self) -> Option<&Csg> {
                (**self).as_csg()
            }
            fn as_morphed(&self) -> Option<&Morphed> {
                (**self).as_morphed()
            }
        }
    )*};
}

forward_shape!(&S, Box<S>, std::sync::Arc<S>);

mod axis;
mod bounds;
mod cone;
mod convex_hull;
mod csg;
mod cuboid;
mod cylinder;
mod displaced;
mod extrude;
mod half_space;
mod hull;
mod menger;
mod morphed;
mod pattern;
mod placement;
mod polytope;
mod profile;
mod pruned;
mod revolve;
mod spec;
mod sphere;
mod surface;
mod torus;
mod transformed;

pub use axis::Axis;
pub use cone::Cone;
pub(crate) use convex_hull::{LIMIT as HULL_LIMIT, convex_hull, distinct_planes};
pub use csg::{Csg, CsgNode, MAX_RECURSION};
pub use cuboid::Cuboid;
pub use cylinder::Cylinder;
pub use displaced::DisplacedSphere;
pub use extrude::Extrude;
pub use half_space::HalfSpace;
pub use hull::{Hull, HullOptions};
pub use menger::Menger;
pub use morphed::{
    Distance, Morphed, Morphology, VOXELS_ACROSS, has_morphed, morphed, offset, round, shell, unresolved,
};
pub use pattern::{MAX_COPIES, linear_array, mirrored, polar_array};
pub use placement::Placement;
pub use profile::{AREA_LEVELS, MAX_PROFILE_NESTING, Polygon, Profile, ProfileSpec, ProfileSurface};
pub use pruned::{PrunedCsg, Reduced, Residual};
pub use revolve::Revolve;
pub use spec::{FileLeaves, MAX_NESTING, ScaleSpec, ShapeSpec, TransformSpec};
pub use sphere::{Ellipsoid, Sphere};
pub use surface::Surface;
pub use torus::Torus;
pub(crate) use transformed::check_invertible;
pub use transformed::{ShapeExt, Transformed};
