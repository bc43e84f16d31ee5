//! Offset, shell and round nodes resolved on a lattice: a CSG tree's [`Morphed`]
//! nodes replaced by the solids they make there, so the tree voxelizes like any other.
//!
//! [`resolve_offsets`] walks the tree; at each offset node it voxelizes the node's child
//! on the lattice, takes the child's crossings from its shape
//! ([`HermiteData::from_shape`]), applies the operation along that true surface
//! ([`offset_with_surface`], [`shell_with_surface`], [`round_with_surface`], what the
//! `offset`, `shell` and `round` commands do to a solid file with surface data), and
//! puts the result in the node's place as an octree leaf that keeps the result's
//! crossings ([`SurfacedOctree`]). An offset node directly inside another (`round(
//! shell(part, 2), 0.5)`) hands its octree and crossings on without a voxelization
//! between, so the nesting is the commands run one after the other, voxel for voxel.
//!
//! The lattice: the domain given, for nodes outside any pattern or transform. Below a
//! [`CsgNode::Placed`] node (a pattern's copies, a transform) a node lives in its own
//! frame: it is resolved once, on a lattice of the domain's voxel size whose planes lie
//! on multiples of it around the node's bounds (`Domain::on_grid`), and its copies
//! are resampled from that one solid when the tree is voxelized. Distances are in the
//! node's frame, as OpenSCAD's `offset` inside a `scale`.
//!
//! [`SurfacedOctree`] answers [`Shape::surface`] from its crossings: the tangent plane
//! of the nearest crossing among the boundary faces of the point's voxel and its six
//! neighbours, so crossings taken again from the resolved tree (`export`, a
//! scene's `.oct` with its surface section, an offset of an offset) are the ones the
//! operation made on the faces it made, and a union or difference of them with shapes
//! keeps both sides' surfaces.

use std::sync::Arc;

use glam::{DAffine3, DVec3, I64Vec3};

use super::hermite::HermiteData;
use super::offset::{offset_with_surface, round_with_surface, shell_with_surface};
use crate::aabb::Aabb;
use crate::error::{Error, Result};
use crate::morton;
use crate::octree::{Domain, LinearOctree, OctreeShape, OffsetOptions, VoxelizeOptions, voxelize};
use crate::shape::{Class, Csg, CsgNode, MAX_RECURSION, Morphed, Morphology, Shape, Surface, has_morphed};

/// `shape` with every offset, shell and round node replaced by its solid on the
/// lattice of `domain` (see the module doc); the tree itself when it holds none.
///
/// # Errors
/// An operation's refused distance, a voxelization's or an offset's budget, an
/// unbounded child below a pattern, a tree higher than [`MAX_RECURSION`] holding an
/// offset node.
pub fn resolve_offsets(shape: &Csg, domain: Domain, options: &VoxelizeOptions) -> Result<Csg> {
    if !has_morphed(shape) {
        return Ok(shape.clone());
    }
    if shape.height() > MAX_RECURSION {
        return Err(Error::invalid(
            "shape",
            format!("a tree {} high holding offset nodes; at most {MAX_RECURSION}", shape.height()),
        ));
    }
    resolve(shape, Lattice::Domain(domain), options)
}

/// Where an offset node is resolved.
#[derive(Clone, Copy)]
enum Lattice {
    /// On this domain's voxels.
    Domain(Domain),
    /// In a node's own frame, on voxel planes at the multiples of this size.
    Local(f64),
}

impl Lattice {
    fn voxel_size(self) -> f64 {
        match self {
            Lattice::Domain(d) => d.voxel_size(),
            Lattice::Local(v) => v,
        }
    }
}

/// [`resolve_offsets`] of a subtree on `lattice` (recursion bounded by the tree's height).
fn resolve(tree: &Csg, lattice: Lattice, options: &VoxelizeOptions) -> Result<Csg> {
    if !has_morphed(tree) {
        return Ok(tree.clone());
    }
    let each = |c: &[Csg]| c.iter().map(|c| resolve(c, lattice, options)).collect::<Result<Vec<_>>>();
    let fold = |c: &[Csg], op: fn(Csg, Csg) -> Csg| -> Result<Csg> {
        let parts = each(c)?;
        Ok(parts.into_iter().reduce(op).expect("an n-ary node has children"))
    };
    Ok(match tree.node() {
        CsgNode::Leaf(leaf) => match leaf.as_morphed() {
            Some(node) => {
                let (solid, data) = evaluate(node, lattice, options)?;
                Csg::leaf(SurfacedOctree::new(solid, data))
            }
            None => tree.clone(),
        },
        CsgNode::Union(c) => fold(c, |a, b| a | b)?,
        CsgNode::Intersection(c) => fold(c, |a, b| a & b)?,
        CsgNode::Difference(c) => fold(c, |a, b| a - b)?,
        CsgNode::SymmetricDifference(c) => fold(c, |a, b| a ^ b)?,
        CsgNode::Complement(c) => !resolve(c, lattice, options)?,
        CsgNode::Placed(c, placements) => {
            Csg::placed(resolve(c, Lattice::Local(lattice.voxel_size()), options)?, placements.to_vec())?
        }
    })
}

/// The solid of an offset node on `lattice`, and its crossings.
fn evaluate(node: &Morphed, lattice: Lattice, options: &VoxelizeOptions) -> Result<(LinearOctree, HermiteData)> {
    node.operation().check()?;
    let domain = match lattice {
        Lattice::Domain(d) => d,
        Lattice::Local(voxel) => {
            let bounds = node.bounds_with_voxel(voxel).ok_or_else(|| {
                Error::invalid("shape", "an offset node in a pattern or transform needs a bounded solid")
            })?;
            Domain::on_grid(&bounds, voxel, None)?
        }
    };
    let (tree, data) = match node.child().node() {
        CsgNode::Leaf(leaf) if leaf.as_morphed().is_some() => {
            evaluate(leaf.as_morphed().expect("checked"), Lattice::Domain(domain), options)?
        }
        _ => {
            let child = resolve(node.child(), Lattice::Domain(domain), options)?;
            let tree = voxelize(&child, domain, options)?;
            let data = HermiteData::from_shape(&child, &tree);
            (tree, data)
        }
    };
    let per_unit = domain.voxels_per_unit();
    let offset = OffsetOptions { budget: options.budget, progress: options.progress, ..OffsetOptions::default() };
    match node.operation() {
        Morphology::Offset { by } => offset_with_surface(&tree, &data, by.in_voxels(per_unit), &offset),
        Morphology::Shell { thickness, outward } => {
            shell_with_surface(&tree, &data, thickness.in_voxels(per_unit), outward, &offset)
        }
        Morphology::Round { radius, convex, concave } => {
            round_with_surface(&tree, &data, radius.in_voxels(per_unit), convex, concave, &offset)
        }
    }
}

/// A resolved node: an octree where it lies, with its crossings (see the module doc).
pub struct SurfacedOctree {
    octree: OctreeShape<Arc<LinearOctree>>,
    data: HermiteData,
}

impl SurfacedOctree {
    /// `tree` with `data`, the crossings of its boundary faces.
    #[must_use]
    pub fn new(tree: LinearOctree, data: HermiteData) -> SurfacedOctree {
        let octree = OctreeShape::new(Arc::new(tree), DAffine3::IDENTITY).expect("the identity is invertible");
        SurfacedOctree { octree, data }
    }

    /// The octree.
    #[must_use]
    pub fn tree(&self) -> &LinearOctree {
        self.octree.tree()
    }

    /// The crossings of its boundary faces.
    #[must_use]
    pub fn data(&self) -> &HermiteData {
        &self.data
    }
}

impl Shape for SurfacedOctree {
    fn classify(&self, b: &Aabb) -> Class {
        self.octree.classify(b)
    }

    fn contains(&self, p: DVec3) -> bool {
        self.octree.contains(p)
    }

    fn bounds(&self) -> Option<Aabb> {
        self.octree.bounds()
    }

    /// The tangent plane of the nearest crossing on the boundary faces of `p`'s voxel
    /// and its six neighbours (in world units); `None` when none is there.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let domain = self.tree().domain();
        let voxel = domain.voxel_size();
        let at = (p - domain.min()) / voxel;
        let n = i64::from(domain.resolution());
        let c = at.floor().as_i64vec3();
        let faces = self.data.faces();
        let mut best: Option<(f64, Surface)> = None;
        let steps = [[0, 0, 0], [-1, 0, 0], [1, 0, 0], [0, -1, 0], [0, 1, 0], [0, 0, -1], [0, 0, 1]];
        for step in steps {
            let u = c + I64Vec3::from_array(step);
            if u.cmplt(I64Vec3::ZERO).any() || u.cmpge(I64Vec3::splat(n)).any() {
                continue;
            }
            // A voxel's faces are together in the sorted crossings.
            let code = morton::encode(u.x as u32, u.y as u32, u.z as u32);
            let first = faces.partition_point(|(key, _)| key.voxel < code);
            for &(key, crossing) in faces[first..].iter().take_while(|(key, _)| key.voxel == code) {
                let point = crossing.point(key);
                let far = (at - point).length_squared();
                if best.is_some_and(|(d, _)| d <= far) {
                    continue;
                }
                let normal = crossing.normal.as_dvec3();
                best = Some((far, Surface { distance: normal.dot(at - point) * voxel, normal }));
            }
        }
        best.map(|(_, s)| s)
    }
}
