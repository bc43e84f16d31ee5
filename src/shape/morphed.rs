//! Offset, shell and round nodes of a CSG tree: a shape grown or shrunk by a ball,
//! hollowed to a wall, or with its edges rounded, written `round(shell(part, 2.0),
//! 0.5)`.
//!
//! These are not pointwise shapes: an offset is the set of points within a distance of
//! the whole child, which no question about one point of the child answers. A
//! [`Morphed`] node is therefore resolved on the lattice it is voxelized into
//! (`surface::resolve_offsets`): its child is voxelized there, the operation applied
//! by the exact band distance (`LinearOctree::offset`, `shell`, `round`, measured to the
//! child's true surface through its crossings), and the node replaced by that octree,
//! which then combines with the rest of the tree as any solid does. The voxelizer
//! refuses a tree that still holds one, so no solid is made from the estimate below.
//!
//! The definitions are those of `octree::offset` (in voxels there, in world units
//! here unless [`Distance::Voxels`]): offset by `D > 0` the points nearer than `D`,
//! by `D < 0` the points at least `|D|` inside; shell of thickness `T` the solid minus
//! its offset by `-T` (outward: its offset by `T` minus the solid); round by `R` the
//! opening (convex edges), then the closing (concave edges).
//!
//! Before resolution a node answers point and box questions from its child's signed
//! distance ([`Shape::surface`]: exact for primitives, a first-order estimate
//! otherwise), which is what smooth shading asks of it: an offset moves the child's
//! surface by `D`; a shell is the slab `-T < d <= 0` (`0 < d <= T` outward), its
//! distance `max(d, -T - d)`; a round answers as its child. Boxes are classified only
//! by the node's bounds (outside them `Outside`, else `Boundary`).

use glam::DVec3;

use super::{Class, Csg, CsgNode, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// A length given in world units or in voxels of the lattice the node is resolved on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Distance {
    /// World units.
    World(f64),
    /// Voxels of the lattice.
    Voxels(f64),
}

impl Distance {
    /// The length in voxels, `voxels_per_unit` of them a world unit (multiplied, as
    /// the commands do, so a node's distance is theirs to the bit).
    #[must_use]
    pub fn in_voxels(self, voxels_per_unit: f64) -> f64 {
        match self {
            Distance::World(d) => d * voxels_per_unit,
            Distance::Voxels(n) => n,
        }
    }

    /// The length in world units where it is one (`None` for voxels).
    #[must_use]
    pub fn world(self) -> Option<f64> {
        match self {
            Distance::World(d) => Some(d),
            Distance::Voxels(_) => None,
        }
    }

    fn value(self) -> f64 {
        match self {
            Distance::World(d) | Distance::Voxels(d) => d,
        }
    }
}

/// The operation of a [`Morphed`] node (see the module doc).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Morphology {
    /// Grown (`by > 0`) or shrunk (`by < 0`) by a ball.
    Offset {
        /// The ball's radius, signed.
        by: Distance,
    },
    /// The wall of `thickness` inside the surface, or outside it when `outward`.
    Shell {
        /// The wall's thickness, positive.
        thickness: Distance,
        /// The wall outside the surface.
        outward: bool,
    },
    /// Convex edges (an opening) and concave edges (a closing) rounded by a ball.
    Round {
        /// The ball's radius, positive.
        radius: Distance,
        /// Round the convex edges.
        convex: bool,
        /// Round the concave edges.
        concave: bool,
    },
}

impl Morphology {
    /// Fails when a distance is not finite, a thickness or radius not positive, or a
    /// round rounds neither kind of edge.
    pub fn check(&self) -> Result<()> {
        let (what, d, positive) = match *self {
            Morphology::Offset { by } => ("offset distance", by, false),
            Morphology::Shell { thickness, .. } => ("shell thickness", thickness, true),
            Morphology::Round { radius, convex, concave } => {
                if !convex && !concave {
                    return Err(Error::invalid("round", "round convex edges, concave edges or both"));
                }
                ("round radius", radius, true)
            }
        };
        let v = d.value();
        if !v.is_finite() || (positive && v <= 0.0) {
            let want = if positive { "a finite positive number" } else { "a finite number" };
            return Err(Error::invalid(what, format!("{} is not {want}", crate::error::Number(v))));
        }
        Ok(())
    }

    /// How far the result reaches beyond the child, in world units (`None` for a
    /// distance in voxels, known only on a lattice).
    fn reach(&self) -> Option<f64> {
        match *self {
            Morphology::Offset { by } => Some(by.world()?.max(0.0)),
            Morphology::Shell { thickness, outward: true } => thickness.world(),
            // The opening lies in the solid, the closing in its convex hull.
            Morphology::Shell { outward: false, .. } | Morphology::Round { .. } => Some(0.0),
        }
    }
}

/// The lattice [`Shape::bounds`] of a node whose distance is in voxels assumes: this
/// many voxels across its child's largest extent (a domain's bounds around it are
/// then a guess; the node is cut by the domain it is resolved in).
pub const VOXELS_ACROSS: f64 = 256.0;

/// A node of a CSG tree whose solid is its child's after a [`Morphology`]; resolved
/// when voxelized (see the module doc). Made only as a tree's leaf ([`morphed`]), so
/// that a walk of the tree finds it.
#[derive(Clone)]
pub struct Morphed {
    child: Csg,
    operation: Morphology,
}

impl Morphed {
    /// The shape the operation applies to.
    #[must_use]
    pub fn child(&self) -> &Csg {
        &self.child
    }

    /// The operation.
    #[must_use]
    pub fn operation(&self) -> Morphology {
        self.operation
    }

    /// The child's box grown by the node's reach, in world units; with a distance in
    /// voxels, grown by `voxel_size` voxels' worth (`None` when the child is unbounded).
    #[must_use]
    pub fn bounds_with_voxel(&self, voxel_size: f64) -> Option<Aabb> {
        let b = self.child.bounds()?;
        let reach = self.operation.reach().unwrap_or_else(|| match self.operation {
            Morphology::Offset { by } | Morphology::Shell { thickness: by, .. } => by.value().max(0.0) * voxel_size,
            Morphology::Round { .. } => 0.0,
        });
        Some(Aabb::new(b.min - DVec3::splat(reach), b.max + DVec3::splat(reach)))
    }

    /// The child's signed distance at `p` as the estimate of the module doc, `None`
    /// where the child gives none or the distance is in voxels.
    fn estimate(&self, p: DVec3) -> Option<Surface> {
        let s = self.child.surface(p)?;
        Some(match self.operation {
            Morphology::Offset { by } => Surface { distance: s.distance - by.world()?, normal: s.normal },
            Morphology::Shell { thickness, outward } => {
                let t = thickness.world()?;
                // The slab between the surface and its copy moved by -t (or +t).
                let (near, far) = if outward {
                    (s.flipped(), Surface { distance: s.distance - t, ..s })
                } else {
                    (s, Surface { distance: -t - s.distance, normal: -s.normal })
                };
                near.intersection(far)
            }
            Morphology::Round { .. } => s,
        })
    }
}

impl Shape for Morphed {
    fn classify(&self, b: &Aabb) -> Class {
        match self.bounds() {
            Some(own) if own.intersection(b).is_none() => Class::Outside,
            _ => Class::Boundary,
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        match self.estimate(p) {
            Some(s) => s.distance <= 0.0,
            None => self.child.contains(p),
        }
    }

    fn bounds(&self) -> Option<Aabb> {
        // A distance in voxels: on a lattice of VOXELS_ACROSS voxels across the child.
        let b = self.child.bounds()?;
        self.bounds_with_voxel(b.size().max_element() / VOXELS_ACROSS)
    }

    fn surface(&self, p: DVec3) -> Option<Surface> {
        self.estimate(p)
    }

    fn as_morphed(&self) -> Option<&Morphed> {
        Some(self)
    }
}

/// `shape` grown (`by > 0`) or shrunk (`by < 0`) by a ball of radius `|by|` world
/// units; refused (when voxelized or resolved) unless `by` is finite.
#[must_use]
pub fn offset(shape: impl Into<Csg>, by: f64) -> Csg {
    morphed(shape, Morphology::Offset { by: Distance::World(by) })
}

/// The wall `thickness` world units thick inside `shape`'s surface; refused (when
/// voxelized or resolved) unless `thickness` is finite and positive.
#[must_use]
pub fn shell(shape: impl Into<Csg>, thickness: f64) -> Csg {
    morphed(shape, Morphology::Shell { thickness: Distance::World(thickness), outward: false })
}

/// `shape` with every convex and concave edge rounded by `radius` world units; refused
/// (when voxelized or resolved) unless `radius` is finite and positive.
#[must_use]
pub fn round(shape: impl Into<Csg>, radius: f64) -> Csg {
    morphed(shape, Morphology::Round { radius: Distance::World(radius), convex: true, concave: true })
}

/// `shape` after `operation`, as a tree; an operation [`Morphology::check`] refuses is
/// kept and refused when the tree is resolved.
#[must_use]
pub fn morphed(shape: impl Into<Csg>, operation: Morphology) -> Csg {
    Csg::leaf(Morphed { child: shape.into(), operation })
}

/// Whether `shape` holds a [`Morphed`] node not yet resolved (a walk of its tree with
/// the stack on the heap).
#[must_use]
pub fn has_morphed(shape: &dyn Shape) -> bool {
    if shape.as_morphed().is_some() {
        return true;
    }
    let Some(tree) = shape.as_csg() else { return false };
    let mut pending = vec![tree];
    while let Some(node) = pending.pop() {
        match node.node() {
            CsgNode::Leaf(leaf) => {
                if leaf.as_morphed().is_some() {
                    return true;
                }
            }
            CsgNode::Union(c) | CsgNode::Intersection(c) | CsgNode::Difference(c) | CsgNode::SymmetricDifference(c) => {
                pending.extend(c);
            }
            CsgNode::Complement(c) | CsgNode::Placed(c, _) => pending.push(c),
        }
    }
    false
}

/// The refusal of a tree that still holds a [`Morphed`] node.
#[must_use]
pub fn unresolved() -> Error {
    Error::invalid(
        "shape",
        "an offset, shell or round node is made on a lattice: resolve it first (surface::resolve_offsets)",
    )
}
