//! CSG trees of shapes, built with the operators `|` `&` `-` `^` `!`.
//!
//! A tree classifies a box from its children's classes by the Inside / Outside /
//! Boundary algebra (union: Inside if either is, Outside if both are; intersection the
//! dual; difference `a & !b`; complement swaps Inside and Outside), and decides a point
//! by the boolean of its children. Since every leaf is conservative, so is the tree,
//! and voxelizing the tree gives exactly the CSG of the voxelized leaves.

use std::ops::{BitAnd, BitOr, BitXor, Not, Sub};
use std::sync::Arc;

use glam::DVec3;

use super::bounds::both;
use super::{
    Class, Cone, Cuboid, Cylinder, DisplacedSphere, Ellipsoid, HalfSpace, Menger, Shape, Sphere, Surface, Torus,
    Transformed,
};
use crate::aabb::Aabb;

/// A node of a CSG tree.
pub enum CsgNode {
    /// A primitive (any shape, including user types).
    Leaf(Arc<dyn Shape>),
    /// Points in either.
    Union(Csg, Csg),
    /// Points in both.
    Intersection(Csg, Csg),
    /// Points in the first and not the second.
    Difference(Csg, Csg),
    /// Points in exactly one.
    SymmetricDifference(Csg, Csg),
    /// Points not in the child.
    Complement(Csg),
}

/// A CSG tree of shapes; cheap to clone (shared nodes).
#[derive(Clone)]
pub struct Csg(Arc<CsgNode>);

impl std::fmt::Debug for Csg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &*self.0 {
            CsgNode::Leaf(_) => write!(f, "Leaf"),
            CsgNode::Union(a, b) => write!(f, "({a:?} | {b:?})"),
            CsgNode::Intersection(a, b) => write!(f, "({a:?} & {b:?})"),
            CsgNode::Difference(a, b) => write!(f, "({a:?} - {b:?})"),
            CsgNode::SymmetricDifference(a, b) => write!(f, "({a:?} ^ {b:?})"),
            CsgNode::Complement(a) => write!(f, "!{a:?}"),
        }
    }
}

impl Csg {
    /// A tree of one shape.
    #[must_use]
    pub fn leaf(shape: impl Shape + 'static) -> Csg {
        Csg(Arc::new(CsgNode::Leaf(Arc::new(shape))))
    }

    /// The root node.
    #[must_use]
    pub fn node(&self) -> &CsgNode {
        &self.0
    }

    fn make(node: CsgNode) -> Csg {
        Csg(Arc::new(node))
    }
}

impl Shape for Csg {
    fn classify(&self, b: &Aabb) -> Class {
        match &*self.0 {
            CsgNode::Leaf(s) => s.classify(b),
            CsgNode::Union(x, y) => both(x.classify(b).complement(), y.classify(b).complement()).complement(),
            CsgNode::Intersection(x, y) => both(x.classify(b), y.classify(b)),
            CsgNode::Difference(x, y) => match x.classify(b) {
                Class::Outside => Class::Outside,
                cx => both(cx, y.classify(b).complement()),
            },
            CsgNode::SymmetricDifference(x, y) => match (x.classify(b), y.classify(b)) {
                (Class::Boundary, _) | (_, Class::Boundary) => Class::Boundary,
                (cx, cy) if cx == cy => Class::Outside,
                _ => Class::Inside,
            },
            CsgNode::Complement(x) => x.classify(b).complement(),
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        match &*self.0 {
            CsgNode::Leaf(s) => s.contains(p),
            CsgNode::Union(x, y) => x.contains(p) || y.contains(p),
            CsgNode::Intersection(x, y) => x.contains(p) && y.contains(p),
            CsgNode::Difference(x, y) => x.contains(p) && !y.contains(p),
            CsgNode::SymmetricDifference(x, y) => x.contains(p) != y.contains(p),
            CsgNode::Complement(x) => !x.contains(p),
        }
    }

    /// Leaves' surfaces combined as distance bounds (see [`Surface`]); `None` when a
    /// leaf cannot tell.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        Some(match &*self.0 {
            CsgNode::Leaf(s) => s.surface(p)?,
            CsgNode::Union(x, y) => x.surface(p)?.union(y.surface(p)?),
            CsgNode::Intersection(x, y) => x.surface(p)?.intersection(y.surface(p)?),
            CsgNode::Difference(x, y) => x.surface(p)?.intersection(y.surface(p)?.flipped()),
            CsgNode::SymmetricDifference(x, y) => {
                let (a, b) = (x.surface(p)?, y.surface(p)?);
                a.intersection(b.flipped()).union(b.intersection(a.flipped()))
            }
            CsgNode::Complement(x) => x.surface(p)?.flipped(),
        })
    }

    fn bounds(&self) -> Option<Aabb> {
        match &*self.0 {
            CsgNode::Leaf(s) => s.bounds(),
            CsgNode::Union(x, y) | CsgNode::SymmetricDifference(x, y) => Some(x.bounds()?.union(&y.bounds()?)),
            CsgNode::Intersection(x, y) => match (x.bounds(), y.bounds()) {
                (Some(a), Some(b)) => Some(a.intersection(&b).unwrap_or(Aabb { min: a.min, max: a.min })),
                (a, b) => a.or(b),
            },
            CsgNode::Difference(x, _) => x.bounds(),
            CsgNode::Complement(_) => None,
        }
    }

    fn as_csg(&self) -> Option<&Csg> {
        Some(self)
    }
}

macro_rules! csg_operators {
    ($($ty:ty),* $(,)?) => {$(
        impl<R: Into<Csg>> BitOr<R> for $ty {
            type Output = Csg;
            fn bitor(self, rhs: R) -> Csg {
                Csg::make(CsgNode::Union(self.into(), rhs.into()))
            }
        }
        impl<R: Into<Csg>> BitAnd<R> for $ty {
            type Output = Csg;
            fn bitand(self, rhs: R) -> Csg {
                Csg::make(CsgNode::Intersection(self.into(), rhs.into()))
            }
        }
        impl<R: Into<Csg>> Sub<R> for $ty {
            type Output = Csg;
            fn sub(self, rhs: R) -> Csg {
                Csg::make(CsgNode::Difference(self.into(), rhs.into()))
            }
        }
        impl<R: Into<Csg>> BitXor<R> for $ty {
            type Output = Csg;
            fn bitxor(self, rhs: R) -> Csg {
                Csg::make(CsgNode::SymmetricDifference(self.into(), rhs.into()))
            }
        }
        impl Not for $ty {
            type Output = Csg;
            fn not(self) -> Csg {
                Csg::make(CsgNode::Complement(self.into()))
            }
        }
    )*};
}

macro_rules! leaf_conversions {
    ($($ty:ty),* $(,)?) => {$(
        impl From<$ty> for Csg {
            fn from(shape: $ty) -> Csg {
                Csg::leaf(shape)
            }
        }
    )*};
}

leaf_conversions!(Sphere, Ellipsoid, Cuboid, Cylinder, Cone, Torus, HalfSpace, Menger, DisplacedSphere);
csg_operators!(Csg, Sphere, Ellipsoid, Cuboid, Cylinder, Cone, Torus, HalfSpace, Menger, DisplacedSphere);

impl<S: Shape + 'static> From<Transformed<S>> for Csg {
    fn from(shape: Transformed<S>) -> Csg {
        Csg::leaf(shape)
    }
}

impl From<&Csg> for Csg {
    fn from(tree: &Csg) -> Csg {
        tree.clone()
    }
}

csg_operators!(&Csg);

macro_rules! transformed_operators {
    ($($trait:ident $method:ident $node:ident),*) => {$(
        impl<S: Shape + 'static, R: Into<Csg>> $trait<R> for Transformed<S> {
            type Output = Csg;
            fn $method(self, rhs: R) -> Csg {
                Csg::make(CsgNode::$node(self.into(), rhs.into()))
            }
        }
    )*};
}

transformed_operators!(BitOr bitor Union, BitAnd bitand Intersection, Sub sub Difference, BitXor bitxor SymmetricDifference);
