//! Shape specifications: a CSG tree of shapes written as data, and the one place a
//! shape is built by its kind.
//!
//! A [`ShapeSpec`] is what a scene file writes after `shape =` (`docs/SCENES.md`): one
//! key naming the kind, in snake case, holding the kind's fields, e.g.
//! `{ sphere = { center = [0, 0, 0], radius = 1 } }`, or a list for the set operations,
//! `{ difference = [a, b, c] }`. Unknown kinds and fields are deserialization errors,
//! which the scene loader reports with file, line and column. The CLI's
//! `octsolid shape KIND --radius ...` flags become a spec too, so both build shapes by
//! [`ShapeSpec::build`] and get the same checks and the same bits.
//!
//! Building checks what the shapes' constructors check (finite values, positive sizes)
//! and that every set operation has an operand; a `transform` applies `scale`, then the
//! rotation of `rotate_degrees` about `rotate_axis` (both or neither), then `translate`
//! ([`TransformSpec`], which a scene's `mesh` and `oct` solids take too).
//!
//! Reading checks too: deserializing a node builds it (a primitive by its constructor,
//! a set operation's operand count, a transform's map) and refuses it with the
//! constructor's message, so a scene's negative radius is an error of the reader, at
//! the place of the node that holds it (the deserializer's span of that node), like a
//! misspelt kind. This is done by a visitor of the node's table that hands it to the
//! derived deserializer (of a private twin, see `shape_spec!`) and checks the result
//! before returning, inside the reader's call for that node.
//!
//! Three nodes are patterns ([`super::linear_array`], [`super::polar_array`],
//! [`super::mirrored`]): `{ array = { shape = ..., count = [20, 20, 1], step = [10, 10,
//! 0] } }`, `{ polar = { shape = ..., count = 6, axis = "z", center = [0, 0, 0] } }`
//! (`step_degrees` defaults to `360 / count`) and `{ mirror = { shape = ..., normal =
//! [1, 0, 0], point = [0, 0, 0] } }`; their counts and planes are checked as they are
//! read, the counts multiplied by those of the patterns inside them (at most
//! [`super::MAX_COPIES`] copies of any leaf in all, [`Csg::copies`]).
//!
//! Nesting: a spec is at most [`MAX_NESTING`] nodes deep. Reading counts the nodes open
//! on the thread and refuses the first one past it before reading what it holds, so
//! neither the reader nor the build recurses deeper; [`ShapeSpec::build_with`] counts a
//! spec made in code (without recursion) before building it. Dropping, cloning or
//! printing a spec made in code deeper than that still recurses.
//!
//! Three nodes are made of profiles and hulls: `{ extrude = { profile = ..., height =
//! H } }` (with `axis`, `center`, `twist`, `scale`; [`super::Extrude`]), `{ revolve = {
//! profile = ..., axis = "z" } }` (with `angle`; [`super::Revolve`]), whose `profile`
//! is a [`ProfileSpec`] built (and so checked) as the node is read, and `{ hull =
//! [shape, ...] }` ([`super::Hull`], built with its default tolerance).
//!
//! Three nodes are offsets, not pointwise shapes ([`super::Morphed`], resolved on the
//! lattice of the solid they are voxelized into): `{ offset = { solid = SHAPE, by = D
//! } }` (or `voxels = N`), `{ shell = { solid = SHAPE, thickness = T, outward = false }
//! }` and `{ round = { solid = SHAPE, radius = R, convex = true, concave = true } }`;
//! their distances are checked as they are read.
//!
//! Two leaves name files, `{ mesh = "part.obj" }` (a closed triangle mesh) and
//! `{ oct = "part.oct" }` (a stored octree). The shape layer knows no mesh or octree:
//! [`ShapeSpec::build_with`] asks a [`FileLeaves`] (the scene loader) for their shapes;
//! [`ShapeSpec::build`] refuses them.
//!
//! [`ShapeSpec::volume`] is the exact volume where there is a closed form: each
//! primitive's formula (the Menger sponge's `size^3 (20/27)^level` included; an
//! extrusion's of a profile without set operations, [`super::Extrude::volume`]), and a
//! transform's inner volume times `|det M|` of its linear part. Half-spaces and
//! complements are unbounded, a displaced sphere and the set operations have none.

use std::path::{Path, PathBuf};

use glam::{DAffine3, DQuat, DVec3};
use serde::Deserialize;
use serde::de::{self, Deserializer, IgnoredAny, MapAccess, Visitor};

use super::pattern::{check_linear, check_mirror, check_mirror_copies, check_polar};
use super::{
    Axis, Cone, Csg, Cuboid, Cylinder, DisplacedSphere, Distance, Ellipsoid, Extrude, HalfSpace, Hull, HullOptions,
    Menger, Morphology, ProfileSpec, Revolve, Sphere, Torus, Transformed, linear_array, mirrored, morphed, polar_array,
};
use crate::error::{Error, Result};

/// Defines [`ShapeSpec`] and, from the same variants, the private `Derived`, whose
/// derived deserializer (`serde(remote = "ShapeSpec")`, an inherent function of
/// `Derived` that makes a `ShapeSpec`) is what the checking [`Deserialize`] impl of
/// `ShapeSpec` calls for a node's table. One list of variants; no derived deserializer
/// that skips the checks is public (`remote = "Self"` would make it an inherent
/// `ShapeSpec::deserialize`).
macro_rules! shape_spec {
    ($(#[$attr:meta])* pub enum ShapeSpec { $($variants:tt)* }) => {
        $(#[$attr])*
        pub enum ShapeSpec { $($variants)* }

        #[derive(Deserialize)]
        #[serde(remote = "ShapeSpec", rename_all = "snake_case", deny_unknown_fields)]
        #[allow(dead_code)] // only its generated function is used
        enum Derived { $($variants)* }
    };
}

shape_spec! {
/// A shape CSG tree as data (see the module doc); [`ShapeSpec::build`] makes the [`Csg`].
#[derive(Clone, Debug, PartialEq)]
pub enum ShapeSpec {
    /// A ball.
    Sphere {
        /// Centre.
        center: [f64; 3],
        /// Radius.
        radius: f64,
    },
    /// An axis-aligned ellipsoid.
    Ellipsoid {
        /// Centre.
        center: [f64; 3],
        /// Semi-axes along x, y and z.
        radii: [f64; 3],
    },
    /// An axis-aligned box.
    Box {
        /// Centre.
        center: [f64; 3],
        /// Edge lengths.
        size: [f64; 3],
    },
    /// A capped cylinder.
    Cylinder {
        /// Centre (the middle of the axis).
        center: [f64; 3],
        /// The axis it runs along.
        axis: Axis,
        /// Radius.
        radius: f64,
        /// Length along the axis.
        height: f64,
    },
    /// A capped cone, its apex towards `+axis`.
    Cone {
        /// Centre of the base disc.
        base: [f64; 3],
        /// The axis from the base to the apex.
        axis: Axis,
        /// Radius of the base.
        radius: f64,
        /// Base to apex.
        height: f64,
    },
    /// A torus around an axis.
    Torus {
        /// Centre.
        center: [f64; 3],
        /// The axis it turns around.
        axis: Axis,
        /// Centre to the middle of the tube.
        radius: f64,
        /// Radius of the tube.
        tube: f64,
    },
    /// The points `p` with `normal . p <= offset`.
    HalfSpace {
        /// Outward normal (need not be unit).
        normal: [f64; 3],
        /// The plane's offset along the normal.
        offset: f64,
    },
    /// The Menger sponge in a cube.
    Menger {
        /// Centre of the cube.
        center: [f64; 3],
        /// Edge of the cube.
        size: f64,
        /// Recursion level (at most 30).
        level: u32,
    },
    /// A sphere of radius `R + A sin(k x) sin(k y) sin(k z)` over unit directions.
    DisplacedSphere {
        /// Centre.
        center: [f64; 3],
        /// Mean radius `R`.
        radius: f64,
        /// Amplitude `A` of the bumps.
        amplitude: f64,
        /// Frequency `k` of the bumps.
        frequency: f64,
    },
    /// Points in any operand.
    Union(Vec<ShapeSpec>),
    /// Points in every operand.
    Intersection(Vec<ShapeSpec>),
    /// Points in the first operand and no other.
    Difference(Vec<ShapeSpec>),
    /// Points in an odd number of the operands.
    Xor(Vec<ShapeSpec>),
    /// Points not in the shape.
    Complement(Box<ShapeSpec>),
    /// Copies of a shape on a grid ([`super::linear_array`]): `count` copies along x,
    /// y and z, `step` apart.
    Array {
        /// The shape copied; copy `[0, 0, 0]` is where it is.
        shape: Box<ShapeSpec>,
        /// Copies along x, y and z (each at least 1).
        count: [u32; 3],
        /// The offset between neighbouring copies along x, y and z.
        step: [f64; 3],
    },
    /// Copies of a shape turned about an axis ([`super::polar_array`]): a bolt circle.
    Polar {
        /// The shape copied; copy 0 is where it is.
        shape: Box<ShapeSpec>,
        /// Number of copies.
        count: u32,
        /// The axis turned about (through `center`).
        axis: Axis,
        /// A point of the axis (default the origin).
        center: Option<[f64; 3]>,
        /// The turn between neighbouring copies in degrees (default `360 / count`).
        step_degrees: Option<f64>,
    },
    /// A shape and its mirror image in a plane ([`super::mirrored`]).
    Mirror {
        /// The shape mirrored.
        shape: Box<ShapeSpec>,
        /// The plane's normal (need not be unit).
        normal: [f64; 3],
        /// A point of the plane (default the origin).
        point: Option<[f64; 3]>,
    },
    /// A closed triangle mesh read from a file (OBJ, STL, PLY), built by a [`FileLeaves`].
    Mesh(PathBuf),
    /// A solid read from an `.oct` file, built by a [`FileLeaves`].
    Oct(PathBuf),
    /// A shape scaled, then rotated, then translated.
    Transform {
        /// The shape moved.
        shape: Box<ShapeSpec>,
        /// Scale factors along x, y and z (default 1).
        scale: Option<[f64; 3]>,
        /// The rotation's axis (with `rotate_degrees`; need not be unit).
        rotate_axis: Option<[f64; 3]>,
        /// The rotation's angle in degrees (with `rotate_axis`).
        rotate_degrees: Option<f64>,
        /// Translation (default none).
        translate: Option<[f64; 3]>,
    },
    /// A 2D profile swept along an axis ([`super::Extrude`]).
    Extrude {
        /// The profile, in the plane across the axis.
        profile: ProfileSpec,
        /// Length along the axis.
        height: f64,
        /// The axis swept along (default z).
        axis: Option<Axis>,
        /// Centred on the plane `w = 0` instead of standing on it (default false).
        center: Option<bool>,
        /// Degrees turned over the height, clockwise seen from `+axis` (default 0).
        twist: Option<f64>,
        /// The top's scale, one number or one a profile axis (default 1).
        scale: Option<ScaleSpec>,
    },
    /// A profile in the `(r, z)` half-plane turned about an axis ([`super::Revolve`]).
    Revolve {
        /// The profile, `r >= 0`.
        profile: ProfileSpec,
        /// The axis turned about, through the origin (default z).
        axis: Option<Axis>,
        /// Degrees turned, in `(0, 360]` (default 360).
        angle: Option<f64>,
    },
    /// The convex hull of shapes ([`super::Hull`]).
    Hull(Vec<ShapeSpec>),
    /// A solid grown or shrunk by a ball ([`super::offset`]): `by` world units or
    /// `voxels` voxels (one of them), positive grows.
    Offset {
        /// The solid offset.
        solid: Box<ShapeSpec>,
        /// The distance in world units.
        by: Option<f64>,
        /// The distance in voxels of the solid's lattice.
        voxels: Option<f64>,
    },
    /// The wall of a solid ([`super::shell`]).
    Shell {
        /// The solid hollowed.
        solid: Box<ShapeSpec>,
        /// The wall's thickness in world units.
        thickness: f64,
        /// The wall outside the surface instead of inside (default false).
        outward: Option<bool>,
    },
    /// A solid with its edges rounded ([`super::round`]).
    Round {
        /// The solid rounded.
        solid: Box<ShapeSpec>,
        /// The rounding radius in world units.
        radius: f64,
        /// Round the convex edges (default true).
        convex: Option<bool>,
        /// Round the concave edges (default true).
        concave: Option<bool>,
    },
}
}

/// An extrusion's top scale: one factor, or one a profile axis.
#[derive(Clone, Copy, Debug, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum ScaleSpec {
    /// The same factor along both profile axes.
    Uniform(f64),
    /// Factors along the profile's x and y.
    Axes([f64; 2]),
}

impl ScaleSpec {
    /// The factors along the profile's x and y.
    #[must_use]
    pub fn factors(self) -> glam::DVec2 {
        match self {
            ScaleSpec::Uniform(s) => glam::DVec2::splat(s),
            ScaleSpec::Axes(s) => glam::DVec2::from_array(s),
        }
    }
}

/// A `[x, y, z]` of a spec as a vector.
fn v(a: [f64; 3]) -> DVec3 {
    DVec3::from_array(a)
}

/// An optional point, the origin when absent.
fn origin(p: Option<[f64; 3]>) -> DVec3 {
    p.map_or(DVec3::ZERO, v)
}

/// An affine map as data: `scale`, then the rotation of `rotate_degrees` about
/// `rotate_axis` (both or neither), then `translate`; every part optional.
#[derive(Clone, Copy, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransformSpec {
    /// Scale factors along x, y and z (default 1).
    pub scale: Option<[f64; 3]>,
    /// The rotation's axis (with `rotate_degrees`; need not be unit).
    pub rotate_axis: Option<[f64; 3]>,
    /// The rotation's angle in degrees (with `rotate_axis`).
    pub rotate_degrees: Option<f64>,
    /// Translation (default none).
    pub translate: Option<[f64; 3]>,
}

impl TransformSpec {
    /// The map `translate * rotate * scale`, refused unless it is finite and
    /// invertible, and when only one of `rotate_axis` and `rotate_degrees` is given.
    pub fn map(&self) -> Result<DAffine3> {
        let scale = DAffine3::from_scale(self.scale.map_or(DVec3::ONE, v));
        let rotate = match (self.rotate_axis, self.rotate_degrees) {
            (Some(a), Some(deg)) => {
                let a = v(a).try_normalize().ok_or_else(|| Error::invalid("rotate_axis", "must be non-zero"))?;
                DAffine3::from_quat(DQuat::from_axis_angle(a, deg.to_radians()))
            }
            (None, None) => DAffine3::IDENTITY,
            _ => return Err(Error::invalid("transform", "give rotate_axis and rotate_degrees together")),
        };
        let map = DAffine3::from_translation(self.translate.map_or(DVec3::ZERO, v)) * rotate * scale;
        super::check_invertible(&map)?;
        Ok(map)
    }
}

/// What builds the leaves of a spec that name files: the scene loader, which reads
/// them relative to its folder.
pub trait FileLeaves {
    /// The shape of the closed mesh in `file` (`{ mesh = "file" }`).
    fn mesh(&self, file: &Path) -> Result<Csg>;
    /// The shape of the octree in `file` (`{ oct = "file" }`).
    fn oct(&self, file: &Path) -> Result<Csg>;
}

/// The [`FileLeaves`] of [`ShapeSpec::build`]: none; a file leaf is refused.
struct NoFiles;

impl FileLeaves for NoFiles {
    fn mesh(&self, file: &Path) -> Result<Csg> {
        Err(no_file_leaves("mesh", file))
    }
    fn oct(&self, file: &Path) -> Result<Csg> {
        Err(no_file_leaves("oct", file))
    }
}

fn no_file_leaves(kind: &str, file: &Path) -> Error {
    Error::invalid(
        "shape",
        format!("{kind} leaf {}: files are read by a scene (ShapeSpec::build_with)", file.display()),
    )
}

impl ShapeSpec {
    /// The CSG tree this spec describes; errors name the refused value (a negative
    /// radius, a set operation without operands, a rotation axis of zero length). A
    /// `mesh` or `oct` leaf is refused: see [`ShapeSpec::build_with`].
    pub fn build(&self) -> Result<Csg> {
        self.build_with(&NoFiles)
    }

    /// [`ShapeSpec::build`] with the leaves that name files built by `files`; fails,
    /// before building anything, for a spec nested deeper than [`MAX_NESTING`].
    pub fn build_with(&self, files: &dyn FileLeaves) -> Result<Csg> {
        let nesting = self.nesting();
        if nesting > MAX_NESTING {
            return Err(too_deep(nesting));
        }
        self.build_nested(files)
    }

    /// [`ShapeSpec::build_with`] of a spec known to nest at most [`MAX_NESTING`] deep.
    fn build_nested(&self, files: &dyn FileLeaves) -> Result<Csg> {
        Ok(match self {
            ShapeSpec::Union(parts) => fold(parts, files, |a, b| a | b)?,
            ShapeSpec::Intersection(parts) => fold(parts, files, |a, b| a & b)?,
            ShapeSpec::Difference(parts) => fold(parts, files, |a, b| a - b)?,
            ShapeSpec::Xor(parts) => fold(parts, files, |a, b| a ^ b)?,
            ShapeSpec::Complement(inner) => !inner.build_nested(files)?,
            ShapeSpec::Array { shape, count, step } => linear_array(shape.build_nested(files)?, *count, v(*step))?,
            ShapeSpec::Polar { shape, count, axis, center, step_degrees } => {
                polar_array(shape.build_nested(files)?, *axis, origin(*center), *count, *step_degrees)?
            }
            ShapeSpec::Mirror { shape, normal, point } => {
                mirrored(shape.build_nested(files)?, v(*normal), origin(*point))?
            }
            ShapeSpec::Transform { shape, .. } => {
                Transformed::new(shape.build_nested(files)?, self.transform()?)?.into()
            }
            ShapeSpec::Mesh(file) => files.mesh(file)?,
            ShapeSpec::Oct(file) => files.oct(file)?,
            ShapeSpec::Hull(parts) => {
                let parts = parts.iter().map(|p| p.build_nested(files)).collect::<Result<Vec<_>>>()?;
                Hull::new(&parts, HullOptions::default())?.into()
            }
            ShapeSpec::Offset { solid, .. } | ShapeSpec::Shell { solid, .. } | ShapeSpec::Round { solid, .. } => {
                morphed(solid.build_nested(files)?, self.morphology()?)
            }
            primitive => primitive.primitive()?,
        })
    }

    /// The shape of a primitive leaf.
    ///
    /// # Panics
    /// When `self` is a set operation, a transform or a file leaf.
    fn primitive(&self) -> Result<Csg> {
        Ok(match self {
            ShapeSpec::Sphere { center, radius } => Sphere::new(v(*center), *radius)?.into(),
            ShapeSpec::Ellipsoid { center, radii } => Ellipsoid::new(v(*center), v(*radii))?.into(),
            ShapeSpec::Box { center, size } => Cuboid::new(v(*center), v(*size))?.into(),
            ShapeSpec::Cylinder { center, axis, radius, height } => {
                Cylinder::new(v(*center), *axis, *radius, *height)?.into()
            }
            ShapeSpec::Cone { base, axis, radius, height } => Cone::new(v(*base), *axis, *radius, *height)?.into(),
            ShapeSpec::Torus { center, axis, radius, tube } => Torus::new(v(*center), *axis, *radius, *tube)?.into(),
            ShapeSpec::HalfSpace { normal, offset } => HalfSpace::new(v(*normal), *offset)?.into(),
            ShapeSpec::Menger { center, size, level } => Menger::new(v(*center), *size, *level)?.into(),
            ShapeSpec::DisplacedSphere { center, radius, amplitude, frequency } => {
                DisplacedSphere::new(v(*center), *radius, *amplitude, *frequency)?.into()
            }
            ShapeSpec::Extrude { .. } => self.extrude()?.into(),
            ShapeSpec::Revolve { profile, axis, angle } => {
                Revolve::new(profile.build()?, axis.unwrap_or(Axis::Z), angle.unwrap_or(360.0))?.into()
            }
            other => unreachable!("{other:?} is not a primitive"),
        })
    }

    /// The shape of an `extrude` node.
    ///
    /// # Panics
    /// When `self` is another kind.
    fn extrude(&self) -> Result<Extrude> {
        let ShapeSpec::Extrude { profile, height, axis, center, twist, scale } = self else {
            unreachable!("{self:?} is not an extrusion")
        };
        Extrude::new(
            profile.build()?,
            axis.unwrap_or(Axis::Z),
            *height,
            center.unwrap_or(false),
            twist.unwrap_or(0.0),
            scale.map_or(glam::DVec2::ONE, ScaleSpec::factors),
        )
    }

    /// The operation of an `offset`, `shell` or `round` node, checked.
    ///
    /// # Panics
    /// When `self` is another kind.
    fn morphology(&self) -> Result<Morphology> {
        let operation = match *self {
            ShapeSpec::Offset { by, voxels, .. } => Morphology::Offset {
                by: match (by, voxels) {
                    (Some(d), None) => Distance::World(d),
                    (None, Some(n)) => Distance::Voxels(n),
                    _ => return Err(Error::invalid("offset", "give one of by (world units) or voxels")),
                },
            },
            ShapeSpec::Shell { thickness, outward, .. } => {
                Morphology::Shell { thickness: Distance::World(thickness), outward: outward.unwrap_or(false) }
            }
            ShapeSpec::Round { radius, convex, concave, .. } => Morphology::Round {
                radius: Distance::World(radius),
                convex: convex.unwrap_or(true),
                concave: concave.unwrap_or(true),
            },
            ref other => unreachable!("{other:?} is not an offset, shell or round"),
        };
        operation.check()?;
        Ok(operation)
    }

    /// Checks this node alone (its children were checked when they were read): a
    /// primitive builds, a set operation has an operand, a transform's map is valid.
    fn check_node(&self) -> Result<()> {
        match self {
            ShapeSpec::Union(parts)
            | ShapeSpec::Intersection(parts)
            | ShapeSpec::Difference(parts)
            | ShapeSpec::Xor(parts)
            | ShapeSpec::Hull(parts)
                if parts.is_empty() =>
            {
                Err(no_operands())
            }
            ShapeSpec::Transform { .. } => self.transform().map(drop),
            ShapeSpec::Offset { .. } | ShapeSpec::Shell { .. } | ShapeSpec::Round { .. } => self.morphology().map(drop),
            ShapeSpec::Array { shape, count, step } => check_linear(*count, v(*step), shape.copies()),
            ShapeSpec::Polar { shape, count, center, step_degrees, .. } => {
                check_polar(origin(*center), *count, *step_degrees, shape.copies()).map(drop)
            }
            ShapeSpec::Mirror { shape, normal, point } => {
                check_mirror(v(*normal), origin(*point))?;
                check_mirror_copies(shape.copies())
            }
            ShapeSpec::Union(_)
            | ShapeSpec::Intersection(_)
            | ShapeSpec::Difference(_)
            | ShapeSpec::Xor(_)
            | ShapeSpec::Complement(_)
            | ShapeSpec::Hull(_)
            | ShapeSpec::Mesh(_)
            | ShapeSpec::Oct(_) => Ok(()),
            primitive => primitive.primitive().map(drop),
        }
    }

    /// The exact volume where there is a closed form (see the module doc); `None`
    /// where there is none and for a spec that does not build.
    #[must_use]
    pub fn volume(&self) -> Option<f64> {
        match self {
            ShapeSpec::Sphere { center, radius } => Some(Sphere::new(v(*center), *radius).ok()?.volume()),
            ShapeSpec::Ellipsoid { center, radii } => Some(Ellipsoid::new(v(*center), v(*radii)).ok()?.volume()),
            ShapeSpec::Box { center, size } => Some(Cuboid::new(v(*center), v(*size)).ok()?.volume()),
            ShapeSpec::Cylinder { center, axis, radius, height } => {
                Some(Cylinder::new(v(*center), *axis, *radius, *height).ok()?.volume())
            }
            ShapeSpec::Cone { base, axis, radius, height } => {
                Some(Cone::new(v(*base), *axis, *radius, *height).ok()?.volume())
            }
            ShapeSpec::Torus { center, axis, radius, tube } => {
                Some(Torus::new(v(*center), *axis, *radius, *tube).ok()?.volume())
            }
            ShapeSpec::Menger { center, size, level } => Some(Menger::new(v(*center), *size, *level).ok()?.volume()),
            // The volume of an affine image is |det| of the linear part times the volume.
            ShapeSpec::Transform { shape, .. } => {
                Some(shape.volume()? * self.transform().ok()?.matrix3.determinant().abs())
            }
            ShapeSpec::Extrude { profile, .. } if profile.has_exact_area() => Some(self.extrude().ok()?.volume()),
            ShapeSpec::HalfSpace { .. }
            | ShapeSpec::Extrude { .. }
            | ShapeSpec::Revolve { .. }
            | ShapeSpec::Hull(_)
            | ShapeSpec::DisplacedSphere { .. }
            | ShapeSpec::Union(_)
            | ShapeSpec::Intersection(_)
            | ShapeSpec::Difference(_)
            | ShapeSpec::Xor(_)
            | ShapeSpec::Complement(_)
            | ShapeSpec::Array { .. }
            | ShapeSpec::Polar { .. }
            | ShapeSpec::Mirror { .. }
            | ShapeSpec::Mesh(_)
            | ShapeSpec::Oct(_)
            | ShapeSpec::Offset { .. }
            | ShapeSpec::Shell { .. }
            | ShapeSpec::Round { .. } => None,
        }
    }

    /// The operands of a set operation, the shape of a pattern, a transform or a
    /// complement; none for a leaf.
    fn children(&self) -> &[ShapeSpec] {
        match self {
            ShapeSpec::Union(parts)
            | ShapeSpec::Intersection(parts)
            | ShapeSpec::Difference(parts)
            | ShapeSpec::Xor(parts)
            | ShapeSpec::Hull(parts) => parts,
            ShapeSpec::Complement(shape)
            | ShapeSpec::Array { shape, .. }
            | ShapeSpec::Polar { shape, .. }
            | ShapeSpec::Mirror { shape, .. }
            | ShapeSpec::Transform { shape, .. } => std::slice::from_ref(shape),
            ShapeSpec::Offset { solid, .. } | ShapeSpec::Shell { solid, .. } | ShapeSpec::Round { solid, .. } => {
                std::slice::from_ref(solid)
            }
            _ => &[],
        }
    }

    /// Nodes on the longest path from this one to a leaf (1 for a leaf), counted
    /// without recursion.
    fn nesting(&self) -> usize {
        let mut deepest = 0;
        let mut pending = vec![(self, 1)];
        while let Some((node, depth)) = pending.pop() {
            deepest = deepest.max(depth);
            pending.extend(node.children().iter().map(|c| (c, depth + 1)));
        }
        deepest
    }

    /// The most copies the patterns make of any leaf ([`Csg::copies`] of the tree
    /// built); called on specs read, which nest at most [`MAX_NESTING`] deep.
    fn copies(&self) -> u64 {
        let inner = self.children().iter().map(ShapeSpec::copies).max().unwrap_or(1);
        let count = match self {
            ShapeSpec::Array { count, .. } => count.iter().map(|&n| u64::from(n)).product(),
            ShapeSpec::Polar { count, .. } => u64::from(*count),
            ShapeSpec::Mirror { .. } => 2,
            _ => 1,
        };
        count.saturating_mul(inner)
    }

    /// The map of a `transform` ([`TransformSpec::map`]); the identity for any other kind.
    fn transform(&self) -> Result<DAffine3> {
        let ShapeSpec::Transform { scale, rotate_axis, rotate_degrees, translate, .. } = self else {
            return Ok(DAffine3::IDENTITY);
        };
        TransformSpec {
            scale: *scale,
            rotate_axis: *rotate_axis,
            rotate_degrees: *rotate_degrees,
            translate: *translate,
        }
        .map()
    }
}

/// Reading a node checks it (see the module doc): the node's table goes to the derived
/// deserializer, and the node it gives is checked before the reader's call returns.
impl<'de> Deserialize<'de> for ShapeSpec {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        d.deserialize_any(NodeVisitor)
    }
}

/// Reads one node: a table with one key, its kind.
struct NodeVisitor;

impl<'de> Visitor<'de> for NodeVisitor {
    type Value = ShapeSpec;

    fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str("a shape: a table with one key, its kind")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> std::result::Result<ShapeSpec, A::Error> {
        let one_kind = || de::Error::custom("a shape is a table with one key, its kind");
        if map.size_hint() == Some(0) {
            return Err(one_kind());
        }
        let _level = Reading::enter().map_err(de::Error::custom)?;
        let node = Derived::deserialize(de::value::MapAccessDeserializer::new(&mut map))?;
        if map.next_key::<IgnoredAny>()?.is_some() {
            return Err(one_kind());
        }
        node.check_node().map_err(de::Error::custom)?;
        Ok(node)
    }
}

/// The most nodes on a path from a spec's root to a leaf (a leaf in 63 patterns,
/// transforms or operations); a deeper spec is refused, as it is read.
pub const MAX_NESTING: usize = 64;

thread_local! {
    /// The nodes being read on this thread, from the root to the one being read.
    static READING: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// One node being read: counted in [`READING`] while it lives, so that a spec nested
/// deeper than [`MAX_NESTING`] is refused before its reader recurses further.
struct Reading;

impl Reading {
    fn enter() -> Result<Reading> {
        let depth = READING.get() + 1;
        if depth > MAX_NESTING {
            return Err(too_deep(depth));
        }
        READING.set(depth);
        Ok(Reading)
    }
}

impl Drop for Reading {
    fn drop(&mut self) {
        READING.set(READING.get() - 1);
    }
}

fn too_deep(depth: usize) -> Error {
    Error::invalid("shape", format!("shapes nested {depth} deep; at most {MAX_NESTING}"))
}

fn no_operands() -> Error {
    Error::invalid("shape", "a CSG operation needs at least one operand")
}

/// The left fold of `op` over the operands' trees: `((a op b) op c) ...`.
fn fold(parts: &[ShapeSpec], files: &dyn FileLeaves, op: fn(Csg, Csg) -> Csg) -> Result<Csg> {
    let mut it = parts.iter();
    let first = it.next().ok_or_else(no_operands)?;
    it.try_fold(first.build_nested(files)?, |acc, s| Ok(op(acc, s.build_nested(files)?)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::Shape;

    fn spec(toml_text: &str) -> std::result::Result<ShapeSpec, toml::de::Error> {
        #[derive(Deserialize)]
        struct File {
            shape: ShapeSpec,
        }
        toml::from_str::<File>(toml_text).map(|f| f.shape)
    }

    #[test]
    fn scene_syntax_deserializes_to_the_spec() {
        let s = spec(
            "shape = { difference = [\n  { box = { center = [0, 0, 0], size = [2, 2, 2] } },\n  \
             { cylinder = { center = [0, 0, 0], axis = \"Z\", radius = 0.6, height = 3 } },\n] }",
        )
        .unwrap();
        let want = ShapeSpec::Difference(vec![
            ShapeSpec::Box { center: [0.0; 3], size: [2.0; 3] },
            ShapeSpec::Cylinder { center: [0.0; 3], axis: Axis::Z, radius: 0.6, height: 3.0 },
        ]);
        assert_eq!(s, want);
        let e = spec("shape = { cylinder = { center = [0, 0, 0], axis = \"w\", radius = 1, height = 1 } }")
            .unwrap_err()
            .to_string();
        assert!(e.contains("column 51") && e.contains("unknown variant `w`, expected one of `x`, `y`, `z`"), "{e}");
        assert!(spec("shape = { sphere = { center = [0, 0, 0], radius = 1, colour = 2 } }").is_err());
        assert!(spec("shape = { blob = { center = [0, 0, 0] } }").is_err());
    }

    #[test]
    fn volumes_are_the_primitives_and_affine_images_have_det_times_it() {
        let ball = ShapeSpec::Sphere { center: [1.0, 0.0, 0.0], radius: 2.0 };
        assert_eq!(ball.volume(), Some(Sphere::new(DVec3::X, 2.0).unwrap().volume()));
        let stretched = ShapeSpec::Transform {
            shape: Box::new(ball.clone()),
            scale: Some([2.0, 0.5, 3.0]),
            rotate_axis: Some([1.0, 1.0, 0.0]),
            rotate_degrees: Some(30.0),
            translate: Some([5.0, 0.0, 0.0]),
        };
        let want = 3.0 * 32.0 / 3.0 * std::f64::consts::PI;
        assert!((stretched.volume().unwrap() / want - 1.0).abs() < 1e-12, "{:?}", stretched.volume());
        let sponge = ShapeSpec::Menger { center: [0.0; 3], size: 3.0, level: 2 };
        assert_eq!(sponge.volume(), Some(27.0 * (20.0f64 / 27.0).powi(2)));
        assert_eq!(ShapeSpec::Union(vec![ball.clone()]).volume(), None);
        assert_eq!(ShapeSpec::Sphere { center: [0.0; 3], radius: -1.0 }.volume(), None);
    }

    #[test]
    fn building_checks_the_values_and_the_operands() {
        let e = ShapeSpec::Sphere { center: [0.0; 3], radius: -1.0 }.build().unwrap_err().to_string();
        assert!(e.contains("radius"), "{e}");
        let e = ShapeSpec::Union(vec![]).build().unwrap_err().to_string();
        assert!(e.contains("at least one operand"), "{e}");
        let half_turn = ShapeSpec::Transform {
            shape: Box::new(ShapeSpec::Box { center: [1.0, 0.0, 0.0], size: [1.0; 3] }),
            scale: None,
            rotate_axis: Some([0.0, 0.0, 2.0]),
            rotate_degrees: Some(180.0),
            translate: Some([0.0, 0.0, 1.0]),
        };
        let tree = half_turn.build().unwrap();
        assert!(tree.contains(DVec3::new(-1.0, 0.0, 1.0)) && !tree.contains(DVec3::new(1.0, 0.0, 0.0)));
        let lopsided = ShapeSpec::Transform {
            shape: Box::new(ShapeSpec::Sphere { center: [0.0; 3], radius: 1.0 }),
            scale: None,
            rotate_axis: None,
            rotate_degrees: Some(90.0),
            translate: None,
        };
        assert!(lopsided.build().unwrap_err().to_string().contains("together"));
        let xor = ShapeSpec::Xor(vec![
            ShapeSpec::Sphere { center: [0.0; 3], radius: 1.0 },
            ShapeSpec::Sphere { center: [1.0, 0.0, 0.0], radius: 1.0 },
        ]);
        let tree = xor.build().unwrap();
        assert!(tree.contains(DVec3::new(-0.9, 0.0, 0.0)) && !tree.contains(DVec3::new(0.5, 0.0, 0.0)));
    }

    #[test]
    fn offset_nodes_read_with_their_defaults_and_bound_their_grown_solid() {
        let s = spec(
            "shape = { round = { solid = { shell = { solid = { box = { center = [0, 0, 0], size = [2, 2, 2] } }, \
             thickness = 0.5 } }, radius = 0.25, concave = false } }",
        )
        .unwrap();
        let cube = ShapeSpec::Box { center: [0.0; 3], size: [2.0; 3] };
        let shell = ShapeSpec::Shell { solid: Box::new(cube.clone()), thickness: 0.5, outward: None };
        let want = ShapeSpec::Round { solid: Box::new(shell), radius: 0.25, convex: None, concave: Some(false) };
        assert_eq!(s, want);
        assert_eq!(
            want.morphology().unwrap(),
            Morphology::Round { radius: Distance::World(0.25), convex: true, concave: false }
        );
        // Grown by 0.5 the cube's box grows by 0.5; shrunk, a shell or a round stays in it.
        let grown = ShapeSpec::Offset { solid: Box::new(cube.clone()), by: Some(0.5), voxels: None };
        let b = grown.build().unwrap().bounds().unwrap();
        assert_eq!((b.min, b.max), (DVec3::splat(-1.5), DVec3::splat(1.5)));
        let shrunk = ShapeSpec::Offset { solid: Box::new(cube), by: Some(-0.5), voxels: None };
        let b = shrunk.build().unwrap().bounds().unwrap();
        assert_eq!((b.min, b.max), (DVec3::splat(-1.0), DVec3::splat(1.0)));
        assert_eq!(want.build().unwrap().bounds().unwrap().max, DVec3::splat(1.0));
        let e = spec("shape = { offset = { solid = { sphere = { center = [0, 0, 0], radius = 1 } }, by = nan } }")
            .unwrap_err()
            .to_string();
        assert!(e.contains("offset distance") && e.contains("not a finite number"), "{e}");
    }

    #[test]
    fn a_spec_past_the_nesting_is_refused_before_it_is_built() {
        let mut deep = ShapeSpec::Sphere { center: [0.0; 3], radius: 1.0 };
        for _ in 0..MAX_NESTING - 1 {
            deep = ShapeSpec::Complement(Box::new(deep));
        }
        assert!(deep.build().is_ok());
        let deeper = ShapeSpec::Complement(Box::new(deep));
        let e = deeper.build().unwrap_err().to_string();
        assert!(e.contains("nested 65 deep; at most 64"), "{e}");
    }
}
