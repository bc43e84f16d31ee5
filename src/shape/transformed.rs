//! Any shape moved by an affine map (translate, rotate, scale, shear, any matrix).
//!
//! `contains(p)` asks the inner shape about `M^-1 p`. `classify(box)` maps the box's
//! eight corners into the inner shape's frame and classifies their bounding box: it
//! holds the mapped box (an affine image of a box is the hull of its corners), so the
//! answer stays conservative; it is looser for rotations, which only costs a few more
//! boundary nodes.

use glam::{DAffine3, DMat3, DQuat, DVec3};

use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// A shape seen through an affine transform: the solid `{ M p : p in inner }`.
#[derive(Clone, Debug)]
pub struct Transformed<S> {
    inner: S,
    to_world: DAffine3,
    to_local: DAffine3,
}

impl<S: Shape> Transformed<S> {
    /// `inner` mapped by `to_world`, which must be finite and invertible.
    pub fn new(inner: S, to_world: DAffine3) -> Result<Self> {
        check_invertible(&to_world)?;
        Ok(Transformed { inner, to_world, to_local: to_world.inverse() })
    }

    /// The wrapped shape.
    #[must_use]
    pub fn inner(&self) -> &S {
        &self.inner
    }

    /// The map from the inner shape's frame to the world.
    #[must_use]
    pub fn to_world(&self) -> DAffine3 {
        self.to_world
    }

    /// The map from the world to the inner shape's frame.
    #[must_use]
    pub fn to_local(&self) -> DAffine3 {
        self.to_local
    }
}

/// The bounding box of `b`'s corners mapped by `m`.
pub(super) fn map_box(m: &DAffine3, b: &Aabb) -> Aabb {
    Aabb::from_points((0..8).map(|i| m.transform_point3(b.corner(i)))).expect("eight corners")
}

impl<S: Shape> Shape for Transformed<S> {
    fn classify(&self, b: &Aabb) -> Class {
        self.inner.classify(&map_box(&self.to_local, b))
    }

    fn contains(&self, p: DVec3) -> bool {
        self.inner.contains(self.to_local.transform_point3(p))
    }

    /// The inner shape's surface at the local point: normals map by the inverse
    /// transpose `g = M^-T n`, distances (first order) by `d / |g|`.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let s = self.inner.surface(self.to_local.transform_point3(p))?;
        let g = self.to_local.matrix3.transpose() * s.normal;
        Surface::from_field(s.distance, g)
    }

    /// `M s(M^T d)`: the inner support along the direction pulled back.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        let local = self.to_world.matrix3.transpose() * d;
        Some(self.to_world.transform_point3(self.inner.support(local)?))
    }

    fn bounds(&self) -> Option<Aabb> {
        self.inner.bounds().map(|b| map_box(&self.to_world, &b))
    }
}

/// Transform builders for every shape: `shape.rotate(DVec3::Z, 0.3).translate(v)`.
pub trait ShapeExt: Shape + Sized {
    /// Moved by `offset`.
    fn translate(self, offset: DVec3) -> Transformed<Self> {
        Transformed::new(self, DAffine3::from_translation(offset)).expect("a translation is invertible")
    }

    /// Rotated by `radians` about the unit `axis` through the origin (right-handed).
    ///
    /// # Panics
    /// When `axis` is zero or not finite.
    fn rotate(self, axis: DVec3, radians: f64) -> Transformed<Self> {
        let axis = axis.try_normalize().expect("rotation axis must be non-zero and finite");
        Transformed::new(self, DAffine3::from_quat(DQuat::from_axis_angle(axis, radians)))
            .expect("a rotation is invertible")
    }

    /// Scaled by `factors` about the origin; fails for a zero or non-finite factor.
    fn scale(self, factors: DVec3) -> Result<Transformed<Self>> {
        Transformed::new(self, DAffine3::from_mat3(DMat3::from_diagonal(factors)))
    }

    /// Mapped by any invertible affine transform.
    fn transform(self, to_world: DAffine3) -> Result<Transformed<Self>> {
        Transformed::new(self, to_world)
    }
}

impl<S: Shape> ShapeExt for S {}

/// `x` in plain digits when that is short, else in scientific notation.
fn short(x: f64) -> String {
    if x == 0.0 || (1e-4..1e6).contains(&x.abs()) { format!("{x}") } else { format!("{x:e}") }
}

/// Fails unless `map` is finite and invertible with a finite inverse (determinant at
/// least `1e-300` in size), naming its rows and determinant.
pub(crate) fn check_invertible(map: &DAffine3) -> Result<()> {
    let det = map.matrix3.determinant();
    if map.is_finite() && det.is_finite() && det.abs() >= 1e-300 && map.inverse().is_finite() {
        return Ok(());
    }
    let m = map.matrix3.transpose();
    let t = map.translation;
    let rows: Vec<String> = [m.x_axis, m.y_axis, m.z_axis]
        .iter()
        .zip(t.to_array())
        .map(|(r, t)| format!("[{} {} {} | {}]", short(r.x), short(r.y), short(r.z), short(t)))
        .collect();
    Err(Error::invalid(
        "transform",
        format!("the map {} (determinant {det:e}) is not finite and invertible", rows.join(" ")),
    ))
}
