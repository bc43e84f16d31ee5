//! Shapes as Python values: `Shape` holds a [`ShapeSpec`], the library's shape tree as
//! data (what scene files write), and the primitives (`Sphere`, `Ellipsoid`, `Box`,
//! `Cylinder`, `Cone`, `Torus`, `HalfSpace`) are its subclasses, each checked by
//! building it when made (a negative radius raises at once). The operators build set
//! operation nodes (`a - b` is `Difference([a, b])`, so a chain folds as the Rust
//! operators do: `(a - b) - c`), the moves `Transform` nodes, the patterns `Array` and
//! `Polar` nodes, `offset`, `shell` and `round` their nodes (resolved on the lattice
//! by `voxelize`); [`ShapeSpec::build`] makes the [`Csg`] the voxelizer samples.
//!
//! Departure from `octsolid shape`: none for the primitives: `Cone(center, ...)` puts
//! its base `height / 2` below `center`, as `octsolid shape cone --center` does, and
//! `Ellipsoid(center, radii)` takes semi-axes (the CLI's `--size` is twice them).

use octsolid::glam::DVec3;
use octsolid::shape::{Axis, Csg, Shape as _, ShapeSpec};
use pyo3::prelude::*;
use pyo3::types::PyString;

use crate::errors::{ToPyResult, invalid};
use crate::ints::count_arg;

/// Reads an axis: `"x"`, `"y"` or `"z"`, or a unit vector along one of them.
pub fn axis_of(value: &Bound<'_, PyAny>) -> PyResult<Axis> {
    if let Ok(name) = value.cast::<PyString>() {
        let name = name.to_string_lossy().to_ascii_lowercase();
        return name.parse().map_err(|e: String| invalid("axis", e));
    }
    let v: [f64; 3] =
        value.extract().map_err(|_| invalid("axis", "give \"x\", \"y\", \"z\" or a unit vector along one"))?;
    match v {
        [1.0, 0.0, 0.0] => Ok(Axis::X),
        [0.0, 1.0, 0.0] => Ok(Axis::Y),
        [0.0, 0.0, 1.0] => Ok(Axis::Z),
        _ => Err(invalid("axis", format!("{v:?} is not x, y or z; turn the shape with .rotate for other axes"))),
    }
}

/// A vector or a number for all three components.
fn vec3_or_scalar(value: &Bound<'_, PyAny>) -> PyResult<[f64; 3]> {
    if let Ok(s) = value.extract::<f64>() {
        return Ok([s; 3]);
    }
    value.extract()
}

/// A shape: a CSG tree of primitives, set operations, moves and patterns. Combine
/// with `|` (union), `&` (intersection), `-` (difference), `^` (symmetric difference)
/// and `~` (complement); move with `.translate`, `.rotate`, `.scale`; make a solid of
/// it with `octsolid.voxelize`.
#[pyclass(subclass, frozen, module = "octsolid")]
#[derive(Clone)]
pub struct Shape {
    /// The tree as data.
    pub spec: ShapeSpec,
}

impl Shape {
    /// A shape of `spec`, refused (as `octsolid.ArgumentError`) when it does not build.
    pub fn checked(spec: ShapeSpec) -> PyResult<Shape> {
        spec.build().py()?;
        Ok(Shape { spec })
    }

    /// The shape the voxelizer samples.
    pub fn build(&self) -> PyResult<Csg> {
        self.spec.build().py()
    }

    /// A set operation node of `self` and `other`.
    fn op(&self, other: &Shape, make: fn(Vec<ShapeSpec>) -> ShapeSpec) -> PyResult<Shape> {
        Shape::checked(make(vec![self.spec.clone(), other.spec.clone()]))
    }

    /// `self` moved by a transform node.
    fn moved(
        &self,
        scale: Option<[f64; 3]>,
        rotate: Option<([f64; 3], f64)>,
        translate: Option<[f64; 3]>,
    ) -> PyResult<Shape> {
        Shape::checked(ShapeSpec::Transform {
            shape: Box::new(self.spec.clone()),
            scale,
            rotate_axis: rotate.map(|r| r.0),
            rotate_degrees: rotate.map(|r| r.1),
            translate,
        })
    }
}

#[pymethods]
impl Shape {
    fn __or__(&self, other: &Shape) -> PyResult<Shape> {
        self.op(other, ShapeSpec::Union)
    }
    fn __and__(&self, other: &Shape) -> PyResult<Shape> {
        self.op(other, ShapeSpec::Intersection)
    }
    fn __sub__(&self, other: &Shape) -> PyResult<Shape> {
        self.op(other, ShapeSpec::Difference)
    }
    fn __xor__(&self, other: &Shape) -> PyResult<Shape> {
        self.op(other, ShapeSpec::Xor)
    }
    fn __invert__(&self) -> PyResult<Shape> {
        Shape::checked(ShapeSpec::Complement(Box::new(self.spec.clone())))
    }

    /// The shape moved by the vector `v`.
    fn translate(&self, v: [f64; 3]) -> PyResult<Shape> {
        self.moved(None, None, Some(v))
    }

    /// The shape turned by `degrees` (right-handed) about `axis` through the origin:
    /// `"x"`, `"y"`, `"z"` or any non-zero vector.
    fn rotate(&self, axis: &Bound<'_, PyAny>, degrees: f64) -> PyResult<Shape> {
        let axis = match axis_of(axis) {
            Ok(a) => a.unit().to_array(),
            Err(_) => {
                axis.extract::<[f64; 3]>().map_err(|_| invalid("axis", "give \"x\", \"y\", \"z\" or a vector"))?
            }
        };
        self.moved(None, Some((axis, degrees)), None)
    }

    /// The shape scaled about the origin by `s`: a number, or factors along x, y, z.
    fn scale(&self, s: &Bound<'_, PyAny>) -> PyResult<Shape> {
        self.moved(Some(vec3_or_scalar(s)?), None, None)
    }

    /// The shape grown (positive `by`) or shrunk (negative) by a ball of radius `|by|`
    /// world units (`voxels=True`: `by` counts voxels): an offset node, made on the
    /// lattice it is voxelized into as `Solid.offset` makes it.
    #[pyo3(signature = (by, voxels=false))]
    fn offset(&self, by: f64, voxels: bool) -> PyResult<Shape> {
        let (by, voxels) = if voxels { (None, Some(by)) } else { (Some(by), None) };
        Shape::checked(ShapeSpec::Offset { solid: Box::new(self.spec.clone()), by, voxels })
    }

    /// The wall `thickness` world units thick inside the shape's surface
    /// (`outward=True`: outside it): a shell node, as `Solid.shell`.
    #[pyo3(signature = (thickness, outward=false))]
    fn shell(&self, thickness: f64, outward: bool) -> PyResult<Shape> {
        Shape::checked(ShapeSpec::Shell { solid: Box::new(self.spec.clone()), thickness, outward: Some(outward) })
    }

    /// The shape with its edges rounded to `radius` world units, both kinds unless
    /// `convex` or `concave` picks one: a round node, as `Solid.round`.
    #[pyo3(signature = (radius, convex=false, concave=false))]
    fn round(&self, radius: f64, convex: bool, concave: bool) -> PyResult<Shape> {
        let (convex, concave) = if convex || concave { (convex, concave) } else { (true, true) };
        Shape::checked(ShapeSpec::Round {
            solid: Box::new(self.spec.clone()),
            radius,
            convex: Some(convex),
            concave: Some(concave),
        })
    }

    /// The shape's bounding box `(min, max)`, or `None` when it is unbounded.
    #[getter]
    fn bounds(&self) -> PyResult<Option<([f64; 3], [f64; 3])>> {
        Ok(self.build()?.bounds().map(|b| (b.min.to_array(), b.max.to_array())))
    }

    /// The exact volume where there is a closed form (a primitive, a moved one), else `None`.
    #[getter]
    fn volume(&self) -> Option<f64> {
        self.spec.volume()
    }

    fn __repr__(&self) -> String {
        format!("<octsolid.Shape {:?}>", self.spec)
    }
}

/// A ball of `radius` around `center`.
#[pyclass(extends = Shape, frozen, module = "octsolid")]
pub struct Sphere;

#[pymethods]
impl Sphere {
    #[new]
    fn new(center: [f64; 3], radius: f64) -> PyResult<PyClassInitializer<Sphere>> {
        Ok(PyClassInitializer::from(Shape::checked(ShapeSpec::Sphere { center, radius })?).add_subclass(Sphere))
    }
}

/// An axis-aligned ellipsoid of semi-axes `radii` around `center`.
#[pyclass(extends = Shape, frozen, module = "octsolid")]
pub struct Ellipsoid;

#[pymethods]
impl Ellipsoid {
    #[new]
    fn new(center: [f64; 3], radii: [f64; 3]) -> PyResult<PyClassInitializer<Ellipsoid>> {
        Ok(PyClassInitializer::from(Shape::checked(ShapeSpec::Ellipsoid { center, radii })?).add_subclass(Ellipsoid))
    }
}

/// An axis-aligned box of edge lengths `size` around `center`.
#[pyclass(name = "Box", extends = Shape, frozen, module = "octsolid")]
pub struct Cuboid;

#[pymethods]
impl Cuboid {
    #[new]
    fn new(center: [f64; 3], size: &Bound<'_, PyAny>) -> PyResult<PyClassInitializer<Cuboid>> {
        Ok(PyClassInitializer::from(Shape::checked(ShapeSpec::Box { center, size: vec3_or_scalar(size)? })?)
            .add_subclass(Cuboid))
    }
}

/// A capped cylinder along `axis` (`"x"`, `"y"`, `"z"`), its middle at `center`.
#[pyclass(extends = Shape, frozen, module = "octsolid")]
pub struct Cylinder;

#[pymethods]
impl Cylinder {
    #[new]
    fn new(
        center: [f64; 3],
        axis: &Bound<'_, PyAny>,
        radius: f64,
        height: f64,
    ) -> PyResult<PyClassInitializer<Cylinder>> {
        let axis = axis_of(axis)?;
        Ok(PyClassInitializer::from(Shape::checked(ShapeSpec::Cylinder { center, axis, radius, height })?)
            .add_subclass(Cylinder))
    }
}

/// A capped cone along `axis`, its apex towards `+axis`, the middle of its height at
/// `center` (the base disc of `radius` lies `height / 2` below it).
#[pyclass(extends = Shape, frozen, module = "octsolid")]
pub struct Cone;

#[pymethods]
impl Cone {
    #[new]
    fn new(center: [f64; 3], axis: &Bound<'_, PyAny>, radius: f64, height: f64) -> PyResult<PyClassInitializer<Cone>> {
        let axis = axis_of(axis)?;
        let base = (DVec3::from_array(center) - axis.unit() * (height * 0.5)).to_array();
        Ok(PyClassInitializer::from(Shape::checked(ShapeSpec::Cone { base, axis, radius, height })?).add_subclass(Cone))
    }
}

/// A torus around `axis` through `center`: `radius` to the middle of the tube, `tube`
/// the tube's radius.
#[pyclass(extends = Shape, frozen, module = "octsolid")]
pub struct Torus;

#[pymethods]
impl Torus {
    #[new]
    fn new(center: [f64; 3], axis: &Bound<'_, PyAny>, radius: f64, tube: f64) -> PyResult<PyClassInitializer<Torus>> {
        let axis = axis_of(axis)?;
        Ok(PyClassInitializer::from(Shape::checked(ShapeSpec::Torus { center, axis, radius, tube })?)
            .add_subclass(Torus))
    }
}

/// The points `p` with `normal . p <= offset` (unbounded: voxelize it with a domain).
#[pyclass(extends = Shape, frozen, module = "octsolid")]
pub struct HalfSpace;

#[pymethods]
impl HalfSpace {
    #[new]
    fn new(normal: [f64; 3], offset: f64) -> PyResult<PyClassInitializer<HalfSpace>> {
        Ok(PyClassInitializer::from(Shape::checked(ShapeSpec::HalfSpace { normal, offset })?).add_subclass(HalfSpace))
    }
}

/// `counts` copies of `shape` along x, y and z (a number: along x alone), `step`
/// apart (a vector, or a number along every axis); copy 0 is the shape itself.
#[pyfunction]
pub fn linear_array(shape: &Shape, counts: &Bound<'_, PyAny>, step: &Bound<'_, PyAny>) -> PyResult<Shape> {
    let count = match counts.extract::<u32>() {
        Ok(n) => [n, 1, 1],
        Err(_) => counts.extract()?,
    };
    Shape::checked(ShapeSpec::Array { shape: Box::new(shape.spec.clone()), count, step: vec3_or_scalar(step)? })
}

/// `count` copies of `shape` turned about `axis` through `center`, evenly round the
/// circle (or `step_degrees` apart): a bolt circle.
#[pyfunction]
#[pyo3(signature = (shape, axis, center, count, step_degrees=None))]
pub fn polar_array(
    shape: &Shape,
    axis: &Bound<'_, PyAny>,
    center: [f64; 3],
    #[pyo3(from_py_with = count_arg)] count: u32,
    step_degrees: Option<f64>,
) -> PyResult<Shape> {
    let axis = axis_of(axis)?;
    Shape::checked(ShapeSpec::Polar {
        shape: Box::new(shape.spec.clone()),
        count,
        axis,
        center: Some(center),
        step_degrees,
    })
}
