//! A shooting patch (Cohen, Chen, Wallace and Greenberg 1988: a patch's light leaves
//! from the whole patch): a rectangle of the voxels' boundary or a tile of a planar
//! region of the true surface, with its element grid. `patches` cuts them; the
//! true surface's tiles come from `surface_patches`.

use std::sync::Arc;

use glam::DVec3;

use super::cover::Cover;
use crate::mesh::BoundaryRect;

/// A shooting patch: a rectangle of one face plane of one solid, or a tile of a
/// region of its true surface.
#[derive(Clone, Debug)]
pub(crate) struct Patch {
    /// The solid it belongs to.
    pub solid: u32,
    /// Its rectangle in the solid's lattice, for a patch of the voxels' boundary
    /// (`None`: a tile of the true surface).
    pub face: Option<BoundaryRect>,
    /// The part of a tile the surface covers, where it covers only part of it
    /// (`None`: all of it).
    pub cover: Option<Arc<Cover>>,
    /// World corner at the rectangle's lowest `(u, v)`, and its world edges along `u`
    /// and `v`.
    pub corner: DVec3,
    pub du: DVec3,
    pub dv: DVec3,
    /// Outward unit normal: an axis for a voxel-boundary patch, its region's plane's
    /// for a tile.
    pub normal: DVec3,
    /// Area (world units squared): of the surface, for a partly covered tile.
    pub area: f64,
    /// Diffuse reflectance, `color * kd`.
    pub reflectance: DVec3,
    /// Emitted radiance.
    pub emission: DVec3,
    /// Its first element and its element grid (`nu` along `u`, `nv` along `v`; element
    /// `(i, j)` is `first + j nu + i`).
    pub first: u32,
    pub nu: u32,
    pub nv: u32,
    /// Offset off the face for rays leaving it: a thousandth of the solid's voxel on
    /// a voxel face; off a tile, far enough that the voxel holding the lifted point is
    /// empty (half a voxel times the normal's 1-norm, and a little).
    pub lift: f64,
}

impl Patch {
    /// The world point at fractions `(s, t)` of the patch along `u` and `v`.
    pub fn point(&self, s: f64, t: f64) -> DVec3 {
        self.corner + self.du * s + self.dv * t
    }

    /// The four corners, counter-clockwise or clockwise (the form factor takes either).
    pub fn corners(&self) -> [DVec3; 4] {
        [self.corner, self.corner + self.du, self.corner + self.du + self.dv, self.corner + self.dv]
    }

    /// The centre.
    pub fn center(&self) -> DVec3 {
        self.point(0.5, 0.5)
    }

    /// The area of its rectangle (its `area` unless it is partly covered).
    pub fn rect_area(&self) -> f64 {
        self.du.length() * self.dv.length()
    }
}
