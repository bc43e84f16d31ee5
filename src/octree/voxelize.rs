//! Adaptive top-down voxelization of any [`Shape`] into a canonical linear octree.
//!
//! Algorithm: classify the root box; `Inside` emits the node whole, `Outside` drops it,
//! `Boundary` recurses into the eight children in Morton order; a voxel is decided by
//! its centre ([`Shape::contains`]). Work and output are proportional to the surface,
//! not the volume. The walk itself (Morton order, the merge of eight full children,
//! the parallel top levels, progress, the budget check) is the [`super::driver`]'s; a
//! shape carries no state down the tree.
//!
//! A CSG tree ([`Shape::as_csg`]) is voxelized pruned instead ([`PrunedCsg`]): each
//! node carries down the residual of the tree its parent's box left (the subtrees
//! still undecided there, n-ary unions and intersections culled to the children
//! whose bounds meet the box), reduces it for its own box, and decides its voxels by
//! the residual. A node then costs what the few primitives near it cost, not the
//! whole tree, and the voxels are the same (see [`PrunedCsg`] for why), so the keys
//! are the same as the unpruned walk's.
//!
//! Offset, shell and round nodes ([`crate::shape::Morphed`]) are made on a lattice,
//! not decided point by point: a shape that still holds one is refused (resolve it
//! first, `surface::resolve_offsets`).
//!
//! Departure: the pruned walk classifies the box of a node's voxel *centres*, half a
//! voxel inside its cube, not the cube. Voxels are decided by their centres, so a
//! class for that box decides the node's voxels exactly as well (the soundness
//! contract covers any box), and a face lying on voxel boundaries (a plate whose
//! faces are on the lattice) is then half a voxel from every box, decided at the
//! coarsest level that fits, instead of a sliver of `Boundary` down to the voxels on
//! each side of it.

use super::domain::Domain;
use super::driver::{CellSink, Cells, Decision, Plan, VoxelizeOptions, Voxelizer};
use super::linear::LinearOctree;
use super::node::NodeKey;
use crate::aabb::Aabb;
use crate::error::Result;
use crate::morton;
use crate::shape::{Class, PrunedCsg, Reduced, Residual, Shape, has_morphed, unresolved};

/// Estimated peak bytes to voxelize `shape` in `domain`: nodes near the surface,
/// taken as twice the area of the shape's box (clipped to the domain) in voxel faces,
/// at 8 bytes a node, doubled for the per-task buffers joined at the end.
#[must_use]
pub fn estimate_bytes(shape: &dyn Shape, domain: &Domain) -> u64 {
    bytes_for_faces(shape_faces(shape, domain))
}

/// Estimated peak bytes to voxelize one cell at `level` of a cell-by-cell
/// voxelization: [`estimate_bytes`] with the area capped at the cell's own box.
#[must_use]
pub fn estimate_cell_bytes(shape: &dyn Shape, domain: &Domain, level: u8) -> u64 {
    let cell_edge = f64::from(domain.resolution() >> level);
    bytes_for_faces(shape_faces(shape, domain).min(6.0 * cell_edge * cell_edge))
}

/// The area of the shape's box clipped to the domain, in voxel faces.
fn shape_faces(shape: &dyn Shape, domain: &Domain) -> f64 {
    let domain_box = domain.aabb();
    let area = match shape.bounds() {
        Some(b) => b.intersection(&domain_box).map_or(0.0, |b| b.area()),
        None => domain_box.area(),
    };
    area / domain.voxel_size().powi(2)
}

/// Nodes near a surface of `faces` voxel faces (two a face), at 8 bytes a node,
/// doubled for the per-task buffers joined at the end.
fn bytes_for_faces(faces: f64) -> u64 {
    ((2.0 * faces * 8.0 * 2.0).min(u64::MAX as f64) as u64).saturating_add(4096)
}

/// Voxelizes `shape` into the canonical linear octree of `domain`.
///
/// Refuses (before any work) when [`estimate_bytes`] exceeds `options.budget`, and
/// a shape holding an offset, shell or round node not yet resolved.
pub fn voxelize(shape: &dyn Shape, domain: Domain, options: &VoxelizeOptions) -> Result<LinearOctree> {
    if has_morphed(shape) {
        return Err(unresolved());
    }
    let plan = Plan::new("voxelizing", estimate_bytes(shape, &domain), domain, options)?;
    match shape.as_csg() {
        Some(tree) => {
            let pruned = PrunedCsg::new(tree);
            let root = pruned.root();
            Ok(plan.run(&PrunedVoxelizer { pruned, domain }, root)?.0)
        }
        None => Ok(plan.run(&ShapeVoxelizer { shape, domain }, ())?.0),
    }
}

/// Voxelizes `shape` in `domain` cell by cell: the cells of `cells` that hold voxels
/// go to `sink` in Morton order, each as soon as it is done, with exactly the keys
/// [`voxelize`] gives in the cell (a full cell as [`super::CellNodes::Full`]).
///
/// Refuses (before any work) when [`estimate_cell_bytes`] exceeds `options.budget`;
/// fails with the sink's first error.
pub fn voxelize_cells(
    shape: &dyn Shape,
    domain: Domain,
    options: &VoxelizeOptions,
    cells: &Cells,
    sink: &mut dyn CellSink,
) -> Result<()> {
    check_level(cells, &domain)?;
    if has_morphed(shape) {
        return Err(unresolved());
    }
    let estimate = estimate_cell_bytes(shape, &domain, cells.level);
    let plan = Plan::new("voxelizing a cell", estimate, domain, options)?;
    match shape.as_csg() {
        Some(tree) => {
            let pruned = PrunedCsg::new(tree);
            let root = pruned.root();
            plan.run_cells(&PrunedVoxelizer { pruned, domain }, root, cells, sink)
        }
        None => plan.run_cells(&ShapeVoxelizer { shape, domain }, (), cells, sink),
    }
}

/// Refuses cells below the voxels or a range beyond the last cell.
pub(crate) fn check_level(cells: &Cells, domain: &Domain) -> Result<()> {
    if cells.level > domain.depth() {
        return Err(crate::Error::invalid(
            "cell level",
            format!("{} is below the voxels of depth {}", cells.level, domain.depth()),
        ));
    }
    let count = Cells::count(cells.level);
    if cells.range.start > cells.range.end || cells.range.end > count {
        return Err(crate::Error::invalid(
            "cells",
            format!(
                "{}..{} is not a range of the {count} cells at level {}",
                cells.range.start, cells.range.end, cells.level
            ),
        ));
    }
    Ok(())
}

/// A shape's decisions: its classification of node boxes, voxels by their centre.
struct ShapeVoxelizer<'a> {
    shape: &'a dyn Shape,
    domain: Domain,
}

impl Voxelizer for ShapeVoxelizer<'_> {
    type Node = ();
    type Counters = ();

    // Inlined into the driver's walk: a shape decides a node in a few instructions,
    // and the call was 5% of a sphere's voxelization (callgrind, `octsolid shape
    // sphere --depth 9` on one thread: 853 M instructions called, 798 M inlined).
    #[inline(always)]
    fn decide(&self, key: NodeKey, _: (), _: &mut ()) -> Decision<()> {
        let min = morton::decode(key.start());
        // Step 1: a voxel is decided by its centre.
        if key.k() == 0 {
            return if self.shape.contains(self.domain.voxel_center(min)) { Decision::Full } else { Decision::Empty };
        }
        // Step 2: classify the node's box; recurse where the shape is not sure.
        match self.shape.classify(&self.domain.cube_box(min, 1 << key.k())) {
            Class::Inside => Decision::Full,
            Class::Outside => Decision::Empty,
            Class::Boundary => Decision::Split([(); 8]),
        }
    }
}

/// A CSG tree's decisions: each node reduces the residual its parent handed down.
struct PrunedVoxelizer {
    pruned: PrunedCsg,
    domain: Domain,
}

impl Voxelizer for PrunedVoxelizer {
    type Node = Residual;
    type Counters = ();

    fn decide(&self, key: NodeKey, residual: Residual, _: &mut ()) -> Decision<Residual> {
        let min = morton::decode(key.start());
        // Step 1: a voxel is decided by its centre, by the residual of its parent's box.
        if key.k() == 0 {
            let inside = self.pruned.contains(&residual, self.domain.voxel_center(min));
            return if inside { Decision::Full } else { Decision::Empty };
        }
        // Step 2: reduce the residual for the box of the node's voxel centres (its first
        // and last centre, computed as the voxels' own: the lattice is monotone, so it
        // holds every centre); recurse where it is undecided, deciding the voxels of a
        // 2-voxel node at once.
        let last = min.map(|c| c + (1 << key.k()) - 1);
        let centres = Aabb { min: self.domain.voxel_center(min), max: self.domain.voxel_center(last) };
        let residual = match self.pruned.reduce(&residual, &centres) {
            Reduced::Inside => return Decision::Full,
            Reduced::Outside => return Decision::Empty,
            Reduced::Same => residual,
            Reduced::Smaller(smaller) => smaller,
        };
        if key.k() == 1 {
            // Child i of a node lies at its corner plus bits (0, 1, 2) of i (Morton order).
            let mut full = 0u8;
            for i in 0..8u32 {
                let voxel = [min[0] + (i & 1), min[1] + (i >> 1 & 1), min[2] + (i >> 2)];
                full |= u8::from(self.pruned.contains(&residual, self.domain.voxel_center(voxel))) << i;
            }
            return Decision::Children(full);
        }
        Decision::Split(std::array::from_fn(|_| residual.clone()))
    }
}
