//! A closed triangle mesh as a [`Shape`], so that it takes part in shape CSG before
//! anything is voxelized: `MeshShape::new(&bunny)? - Cylinder::new(..)?`.
//!
//! Points: the ray parity of `parity.rs` (odd crossings of the `+x` ray: inside),
//! exact for a closed mesh; for one that is also consistently oriented outward it is
//! the generalized winding number's `w >= 1/2`, and the mesh solid voxelizer's
//! automatic rule (`InsideRule::Auto` takes parity for a watertight mesh), so the
//! voxels agree with [`super::voxelize_mesh`] wherever a voxel centre is not on the
//! surface.
//!
//! Boxes, conservatively: the surface of a closed mesh is its triangles, so a box that
//! no triangle meets lies wholly on one side and one point decides it (its centre),
//! `Inside` or `Outside`; a box some triangle may meet is `Boundary`. "May meet" is
//! the separating-axis test of `tri_box.rs` through the hierarchy of
//! `triangle_tree.rs`, which can report a triangle that misses the box by a hair but
//! never misses one that meets it; a box outside the mesh's bounds is `Outside`
//! without a query. So the soundness contract of [`Shape`] holds, and voxelizing a
//! `MeshShape` alone gives the same octree as [`super::voxelize_mesh`] (canonical keys
//! of the same voxels).
//!
//! Deviation from the mesh voxelizer: no state is handed down the tree (a [`Shape`] has
//! none), so every boundary voxel is a parity query from scratch instead of a value
//! carried from its parent; slower for large meshes at depth, the same answer.
//!
//! Only closed meshes: [`MeshShape::new`] refuses a mesh that is not watertight
//! (every edge used once in each direction, [`TriangleMesh::is_watertight`]), whose
//! inside parity cannot tell; voxelize such a mesh with the winding rule instead.

use std::ops::{BitAnd, BitOr, BitXor, Not, Sub};

use glam::DVec3;

use super::TriangleMesh;
use super::parity::ParityGrid;
use super::tables::PolygonTables;
use super::triangle_tree::TriangleTree;
use crate::aabb::Aabb;
use crate::error::{Error, Result};
use crate::shape::{Class, Csg, Shape};

/// A closed triangle mesh as a shape (see the module doc).
///
/// ```
/// use octsolid::mesh::generate::cuboid;
/// use octsolid::prelude::*;
///
/// # fn main() -> octsolid::Result<()> {
/// let block = MeshShape::new(&cuboid(DVec3::ZERO, DVec3::splat(2.0)))?;
/// let drilled = block - Cylinder::new(DVec3::ZERO, Axis::Z, 0.5, 3.0)?;
/// // Voxels of 1/16: the block's faces lie on voxel faces.
/// let tree = voxelize(&drilled, Domain::new(DVec3::splat(-2.0), 4.0, 6)?, &Default::default())?;
/// let exact = 8.0 - std::f64::consts::PI * 0.5 * 0.5 * 2.0;
/// assert!((tree.volume() / exact - 1.0).abs() < 0.01);
/// # Ok(())
/// # }
/// ```
#[derive(Clone)]
pub struct MeshShape {
    parity: ParityGrid,
    triangles: TriangleTree,
    bounds: Aabb,
    count: usize,
}

impl MeshShape {
    /// The solid bounded by `mesh`, which must be valid ([`TriangleMesh::validate`]) and
    /// watertight; otherwise an error that counts its open, non-manifold and
    /// misoriented edges.
    pub fn new(mesh: &TriangleMesh) -> Result<Self> {
        mesh.validate()?;
        if !mesh.is_watertight() {
            let r = PolygonTables::new(mesh).report();
            return Err(Error::invalid(
                "mesh",
                format!(
                    "a mesh shape must be closed and consistently oriented, and this one has {} boundary, {} \
                     non-manifold and {} misoriented edges (voxelize it as a mesh solid with the winding rule instead)",
                    r.boundary_edges, r.non_manifold_edges, r.misoriented_edges
                ),
            ));
        }
        Ok(MeshShape {
            parity: ParityGrid::new(mesh),
            triangles: TriangleTree::new(mesh),
            bounds: mesh.bounds(),
            count: mesh.triangles.len(),
        })
    }
}

impl std::fmt::Debug for MeshShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "MeshShape({} triangles in {:?})", self.count, self.bounds)
    }
}

impl Shape for MeshShape {
    fn classify(&self, b: &Aabb) -> Class {
        let apart = b.min.cmpgt(self.bounds.max).any() || b.max.cmplt(self.bounds.min).any();
        if apart {
            return Class::Outside;
        }
        if self.triangles.meets(b) {
            return Class::Boundary;
        }
        if self.contains(b.center()) { Class::Inside } else { Class::Outside }
    }

    fn contains(&self, p: DVec3) -> bool {
        self.parity.crossings(p) % 2 == 1
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(self.bounds)
    }
}

impl From<MeshShape> for Csg {
    fn from(shape: MeshShape) -> Csg {
        Csg::leaf(shape)
    }
}

/// The CSG operators of the shapes (`shape/csg.rs`), for a mesh shape on the left.
macro_rules! mesh_operators {
    ($($trait:ident $method:ident),*) => {$(
        impl<R: Into<Csg>> $trait<R> for MeshShape {
            type Output = Csg;
            fn $method(self, rhs: R) -> Csg {
                Csg::from(self).$method(rhs)
            }
        }
    )*};
}

mesh_operators!(BitOr bitor, BitAnd bitand, Sub sub, BitXor bitxor);

impl Not for MeshShape {
    type Output = Csg;
    fn not(self) -> Csg {
        !Csg::from(self)
    }
}
