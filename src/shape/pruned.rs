//! Pruned CSG classification: a CSG tree reduced to what still matters in a box.
//!
//! Classifying a box with [`Csg::classify`] asks every leaf of the tree, so voxelizing
//! a plate minus 400 holes asks 401 shapes at every node of the octree. But a subtree
//! decided `Inside` or `Outside` for a box is decided for every box inside it, and a
//! hole far from the box cannot matter there. [`PrunedCsg`] keeps a *residual* tree
//! for each box: the original tree with every decided subtree replaced by its constant
//! and the constants folded away. A walk hands each box's residual to its sub-boxes,
//! so going down the octree the tree shrinks to the few leaves near the node.
//!
//! Steps:
//! 1. **Flatten** ([`PrunedCsg::new`]): nested unions become one n-ary union
//!    (likewise intersections and symmetric differences, which are associative), a
//!    difference `a - b - c` becomes `a & !b & !c`, `!!a` becomes `a`, and a pattern
//!    ([`CsgNode::Placed`]) the union of its copies: each leaf of its child once a
//!    placement, the leaf under the chain of placements of the patterns above it
//!    (outermost first, mapping points and boxes in as the nested copies do, hence
//!    with their bits). Leaves keep their bounds ([`Shape::bounds`], through their
//!    placements) widened by a relative `1e-9` so rounding can never cull a leaf that
//!    reaches the box.
//! 2. **Reduce** ([`PrunedCsg::reduce`]): a leaf whose bounds miss the box is
//!    `Outside` without asking it, else its [`Shape::classify`]; an n-ary union drops
//!    its `Outside` children and is `Inside` as soon as one child is (intersection the
//!    dual; symmetric difference drops `Outside` children and flips its parity for each
//!    `Inside` one); a node left with one child becomes that child. Only children still
//!    in the residual are visited, so the list an n-ary node scans is the one its
//!    parent box left: the octree descent itself is the spatial index over the
//!    children's bounds (the children meeting a box are found among those meeting its
//!    parent, about an eighth of them a level), and a residual that did not change is
//!    shared, not copied.
//! 3. **Decide points** ([`PrunedCsg::contains`]): the residual's boolean at a point of
//!    its box.
//!
//! Equivalence: the leaves are conservative ([`Shape`]'s soundness contract), so a
//! constant put in for a subtree over a box is that subtree's membership at every
//! point of the box, and the residual decides every point of its box as the whole tree
//! does. Voxelizing by residuals therefore gives the same voxels, hence (the canonical
//! form being unique) the same keys, as the unpruned walk, while the classes of
//! intermediate boxes may be more decided than [`Csg::classify`]'s (the bounds test),
//! which only saves work.
//!
//! Departure: no bounds hierarchy over an n-ary node's children is built up front (a
//! BVH would answer the first query in `O(log n)`); the descent's own culling costs
//! `O(children meeting the parent's box)` a node, which is the same order after the
//! top levels and needs no build. Limits: a leaf is whatever is not a [`Csg`] (a
//! transformed tree is one: a placed node of one placement), and the table holds one
//! leaf a copy: a pattern whose copies would make more than [`MAX_LEAVES`] leaves
//! (100,000 copies of a union of 20 shapes) is flattened one leaf a copy, its child
//! classified as a whole, so the table holds at most about [`super::MAX_COPIES`] times
//! the patterns written past that size. A tree nested
//! deeper than [`MAX_RECURSION`] (only the library's API builds one) is not flattened:
//! it is one leaf, classified as a whole by [`Csg`]'s own fold.

use std::sync::Arc;

use glam::DVec3;

use super::csg::{Csg, CsgNode, MAX_RECURSION};
use super::{Class, Placement, Shape};
use crate::aabb::Aabb;

/// A CSG tree reduced for a box; leaves index [`PrunedCsg`]'s leaf table. Cheap to
/// clone: a leaf (or its complement, the commonest residual deep in the octree) is
/// two words with no reference count, so the walk's threads share no counter for it;
/// inner nodes are shared.
#[derive(Clone, Debug)]
pub enum Residual {
    /// The leaf of this index, or its complement.
    Leaf {
        /// Index into the leaf table.
        index: u32,
        /// Whether the points are those not in the leaf.
        complement: bool,
    },
    /// Points not in the child (not a leaf).
    Not(Arc<Residual>),
    /// Points in any child (at least two).
    Union(Arc<[Residual]>),
    /// Points in every child (at least two).
    Intersection(Arc<[Residual]>),
    /// Points in an odd number of children (at least two).
    Xor(Arc<[Residual]>),
}

/// What a residual becomes in a box.
#[derive(Debug)]
pub enum Reduced {
    /// Every point of the box is in the solid.
    Inside,
    /// No point of the box is in the solid.
    Outside,
    /// Undecided, and nothing of the residual could be dropped.
    Same,
    /// Undecided: the smaller residual that decides the box's points.
    Smaller(Residual),
}

/// The most leaves a pattern is flattened into: past it, each copy of the pattern's
/// child is one leaf (see the module doc).
pub const MAX_LEAVES: u64 = 1 << 20;

/// A CSG tree flattened for pruned classification (see the module doc).
pub struct PrunedCsg {
    leaves: Vec<(Arc<dyn Shape>, Option<Aabb>)>,
    root: Residual,
}

impl std::fmt::Debug for PrunedCsg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "PrunedCsg {{ {} leaves, root {:?} }}", self.leaves.len(), self.root)
    }
}

/// The n-ary operators.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Nary {
    Union,
    Intersection,
    Xor,
}

impl PrunedCsg {
    /// Flattens `tree` (step 1 of the module doc).
    #[must_use]
    pub fn new(tree: &Csg) -> PrunedCsg {
        let mut pruned = PrunedCsg { leaves: Vec::new(), root: Residual::Leaf { index: 0, complement: false } };
        match pruned.flatten(tree, &[], 0) {
            Some(root) => pruned.root = root,
            None => {
                // Too deep to flatten by recursion: the whole tree is one leaf.
                pruned.leaves = vec![(Arc::new(tree.clone()), tree.bounds().map(widened))];
            }
        }
        pruned
    }

    /// The whole tree as a residual: where a walk starts.
    #[must_use]
    pub fn root(&self) -> Residual {
        self.root.clone()
    }

    /// Number of leaves.
    #[must_use]
    pub fn leaf_count(&self) -> usize {
        self.leaves.len()
    }

    /// The residual of `tree` under the placements `chain` (outermost first), its
    /// leaves added to the table; `None` past [`MAX_RECURSION`] nodes deep.
    fn flatten(&mut self, tree: &Csg, chain: &[Placement], depth: u32) -> Option<Residual> {
        if depth > MAX_RECURSION {
            return None;
        }
        Some(match tree.node() {
            CsgNode::Leaf(shape) => self.leaf(shape, chain),
            CsgNode::Union(children) => self.nary(Nary::Union, children, chain, depth)?,
            CsgNode::Intersection(children) => self.nary(Nary::Intersection, children, chain, depth)?,
            CsgNode::SymmetricDifference(children) => self.nary(Nary::Xor, children, chain, depth)?,
            CsgNode::Difference(children) => {
                let mut parts = Vec::new();
                for (i, child) in children.iter().enumerate() {
                    let part = self.flatten(child, chain, depth + 1)?;
                    splice(Nary::Intersection, if i == 0 { part } else { not(part) }, &mut parts);
                }
                make(Nary::Intersection, parts)
            }
            CsgNode::Complement(a) => not(self.flatten(a, chain, depth + 1)?),
            CsgNode::Placed(child, placements) if tree.instances() > MAX_LEAVES && child.instances() > 1 => {
                // Too many leaves to make one by one: each copy's child is one leaf.
                let child: Arc<dyn Shape> = Arc::new(child.clone());
                let mut parts = Vec::new();
                let mut inner = chain.to_vec();
                for placement in placements.iter() {
                    if *placement != Placement::Identity {
                        inner.push(placement.clone());
                    }
                    parts.push(self.leaf(&child, &inner));
                    inner.truncate(chain.len());
                }
                make(Nary::Union, parts)
            }
            CsgNode::Placed(child, placements) => {
                let mut parts = Vec::new();
                let mut inner = chain.to_vec();
                for placement in placements.iter() {
                    if *placement != Placement::Identity {
                        inner.push(placement.clone());
                    }
                    let part = self.flatten(child, &inner, depth + 1)?;
                    splice(Nary::Union, part, &mut parts);
                    inner.truncate(chain.len());
                }
                make(Nary::Union, parts)
            }
        })
    }

    /// `shape` under the placements `chain`, added to the leaf table.
    fn leaf(&mut self, shape: &Arc<dyn Shape>, chain: &[Placement]) -> Residual {
        let shape = if chain.is_empty() {
            shape.clone()
        } else {
            Arc::new(PlacedLeaf { shape: shape.clone(), chain: chain.into() })
        };
        let index = u32::try_from(self.leaves.len()).expect("fewer than 2^32 leaves");
        let bounds = shape.bounds().map(widened);
        self.leaves.push((shape, bounds));
        Residual::Leaf { index, complement: false }
    }

    /// The n-ary node of `op` over `children`, the children's own `op` nodes spliced in.
    fn nary(&mut self, op: Nary, children: &[Csg], chain: &[Placement], depth: u32) -> Option<Residual> {
        let mut parts = Vec::new();
        // A left fold of shared operands nests on the left: walk down it without recursion.
        let mut pending: Vec<&Csg> = Vec::new();
        let mut left = children;
        loop {
            pending.extend(left[1..].iter().rev());
            match same_op(op, &left[0]) {
                Some(inner) => left = inner,
                None => {
                    pending.push(&left[0]);
                    break;
                }
            }
        }
        for operand in pending.into_iter().rev() {
            let part = self.flatten(operand, chain, depth + 1)?;
            splice(op, part, &mut parts);
        }
        Some(make(op, parts))
    }

    /// Step 2 of the module doc: `residual` reduced for the closed box `b`.
    #[must_use]
    pub fn reduce(&self, residual: &Residual, b: &Aabb) -> Reduced {
        match residual {
            Residual::Leaf { index, complement } => match (self.classify_leaf(*index, b), complement) {
                (Class::Inside, false) | (Class::Outside, true) => Reduced::Inside,
                (Class::Outside, false) | (Class::Inside, true) => Reduced::Outside,
                (Class::Boundary, _) => Reduced::Same,
            },
            Residual::Not(a) => match self.reduce(a, b) {
                Reduced::Inside => Reduced::Outside,
                Reduced::Outside => Reduced::Inside,
                Reduced::Same => Reduced::Same,
                Reduced::Smaller(r) => Reduced::Smaller(not(r)),
            },
            Residual::Union(parts) => self.reduce_nary(Nary::Union, parts, b),
            Residual::Intersection(parts) => self.reduce_nary(Nary::Intersection, parts, b),
            Residual::Xor(parts) => self.reduce_nary(Nary::Xor, parts, b),
        }
    }

    fn reduce_nary(&self, op: Nary, parts: &[Residual], b: &Aabb) -> Reduced {
        // The constant that decides the node (union: Inside; intersection: Outside) and
        // the one a child drops out with; a symmetric difference drops both, counting
        // Inside children as flips of its parity.
        let (decides, drops) = match op {
            Nary::Union => (Some(Class::Inside), Class::Outside),
            Nary::Intersection => (Some(Class::Outside), Class::Inside),
            Nary::Xor => (None, Class::Outside),
        };
        // `kept` is allocated at the first change only: an unchanged node is shared.
        let mut kept: Option<Vec<Residual>> = None;
        let mut flipped = false;
        for (i, part) in parts.iter().enumerate() {
            let reduced = self.reduce(part, b);
            let class = match reduced {
                Reduced::Inside => Some(Class::Inside),
                Reduced::Outside => Some(Class::Outside),
                Reduced::Same | Reduced::Smaller(_) => None,
            };
            if class.is_some() && class == decides {
                return if class == Some(Class::Inside) { Reduced::Inside } else { Reduced::Outside };
            }
            match reduced {
                Reduced::Same => {
                    if let Some(kept) = &mut kept {
                        kept.push(part.clone());
                    }
                }
                Reduced::Smaller(r) => kept.get_or_insert_with(|| parts[..i].to_vec()).push(r),
                Reduced::Inside | Reduced::Outside => {
                    // Dropped (a symmetric difference's Inside child flips its parity).
                    flipped ^= class != Some(drops);
                    kept.get_or_insert_with(|| parts[..i].to_vec());
                }
            }
        }
        let Some(mut kept) = kept else {
            return Reduced::Same;
        };
        let empty = match op {
            Nary::Union | Nary::Xor => Reduced::Outside,
            Nary::Intersection => Reduced::Inside,
        };
        let residual = match kept.len() {
            0 => return if flipped { complement(empty) } else { empty },
            1 => kept.pop().expect("one part"),
            _ => make(op, kept),
        };
        Reduced::Smaller(if flipped { not(residual) } else { residual })
    }

    /// A leaf's class: `Outside` without asking it when its bounds miss the box.
    #[inline]
    fn classify_leaf(&self, i: u32, b: &Aabb) -> Class {
        let (shape, bounds) = &self.leaves[i as usize];
        match bounds {
            Some(s) if b.max.cmplt(s.min).any() || b.min.cmpgt(s.max).any() => Class::Outside,
            _ => shape.classify(b),
        }
    }

    /// Step 3 of the module doc: whether `p` (a point of the box `residual` was
    /// reduced for) is in the solid.
    #[must_use]
    pub fn contains(&self, residual: &Residual, p: DVec3) -> bool {
        match residual {
            Residual::Leaf { index, complement } => self.leaves[*index as usize].0.contains(p) != *complement,
            Residual::Not(a) => !self.contains(a, p),
            Residual::Union(parts) => parts.iter().any(|r| self.contains(r, p)),
            Residual::Intersection(parts) => parts.iter().all(|r| self.contains(r, p)),
            Residual::Xor(parts) => parts.iter().fold(false, |odd, r| odd ^ self.contains(r, p)),
        }
    }
}

/// The children of `tree` when its root is an `op` node.
fn same_op(op: Nary, tree: &Csg) -> Option<&[Csg]> {
    match (op, tree.node()) {
        (Nary::Union, CsgNode::Union(c))
        | (Nary::Intersection, CsgNode::Intersection(c))
        | (Nary::Xor, CsgNode::SymmetricDifference(c)) => Some(c),
        _ => None,
    }
}

/// Appends `part` to the children of an `op` node, splicing in its children when it
/// is an `op` node itself.
fn splice(op: Nary, part: Residual, parts: &mut Vec<Residual>) {
    match (op, &part) {
        (Nary::Union, Residual::Union(inner))
        | (Nary::Intersection, Residual::Intersection(inner))
        | (Nary::Xor, Residual::Xor(inner)) => parts.extend(inner.iter().cloned()),
        _ => parts.push(part),
    }
}

/// The `op` node of `parts` (at least one), the part itself when it is one.
fn make(op: Nary, mut parts: Vec<Residual>) -> Residual {
    if parts.len() == 1 {
        return parts.pop().expect("one part");
    }
    match op {
        Nary::Union => Residual::Union(parts.into()),
        Nary::Intersection => Residual::Intersection(parts.into()),
        Nary::Xor => Residual::Xor(parts.into()),
    }
}

/// `!a`, with `!!a = a`.
fn not(a: Residual) -> Residual {
    match a {
        Residual::Leaf { index, complement } => Residual::Leaf { index, complement: !complement },
        Residual::Not(inner) => (*inner).clone(),
        other => Residual::Not(Arc::new(other)),
    }
}

fn complement(r: Reduced) -> Reduced {
    match r {
        Reduced::Inside => Reduced::Outside,
        Reduced::Outside => Reduced::Inside,
        other => other,
    }
}

/// A leaf of the tree under the placements of the patterns above it, outermost
/// first: it maps points and boxes inward and bounds outward one placement at a time,
/// as the nested copies it stands for do, so it answers with their bits.
struct PlacedLeaf {
    shape: Arc<dyn Shape>,
    chain: Arc<[Placement]>,
}

impl Shape for PlacedLeaf {
    fn classify(&self, b: &Aabb) -> Class {
        self.shape.classify(&self.chain.iter().fold(*b, |b, p| p.local_box(&b)))
    }

    fn contains(&self, p: DVec3) -> bool {
        self.shape.contains(self.chain.iter().fold(p, |p, placement| placement.local_point(p)))
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(self.chain.iter().rev().fold(self.shape.bounds()?, |b, p| p.world_box(&b)))
    }
}

/// `b` grown by `1e-9` of its largest extent or coordinate, so that a culling test
/// against it cannot lose a point of the solid to rounding.
fn widened(b: Aabb) -> Aabb {
    let scale = b.size().max_element().max(b.min.abs().max_element()).max(b.max.abs().max_element());
    let m = DVec3::splat(1e-9 * scale + f64::MIN_POSITIVE);
    Aabb { min: b.min - m, max: b.max + m }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::{Axis, Cuboid, Cylinder, Sphere};

    fn leaves_of(r: &Residual) -> usize {
        match r {
            Residual::Leaf { .. } => 1,
            Residual::Not(a) => leaves_of(a),
            Residual::Union(p) | Residual::Intersection(p) | Residual::Xor(p) => p.iter().map(leaves_of).sum(),
        }
    }

    #[test]
    fn a_hole_grid_flattens_to_one_intersection_and_reduces_to_the_holes_near_a_box() {
        let mut plate: Csg = Cuboid::new(DVec3::new(50.0, 50.0, 5.0), DVec3::new(100.0, 100.0, 10.0)).unwrap().into();
        for i in 0..10 {
            for j in 0..10 {
                let c = DVec3::new(5.0 + 10.0 * f64::from(i), 5.0 + 10.0 * f64::from(j), 5.0);
                plate = plate - Cylinder::new(c, Axis::Z, 3.0, 10.0).unwrap();
            }
        }
        let pruned = PrunedCsg::new(&plate);
        assert_eq!(pruned.leaf_count(), 101);
        let root = pruned.root();
        assert!(matches!(&root, Residual::Intersection(p) if p.len() == 101), "{root:?}");
        // A box around one hole's wall, inside the plate: only that hole is left, negated.
        let b = Aabb::new(DVec3::new(7.5, 4.0, 4.0), DVec3::new(8.5, 6.0, 6.0));
        match pruned.reduce(&root, &b) {
            Reduced::Smaller(r) => {
                assert!(matches!(r, Residual::Leaf { complement: true, .. }), "{r:?}");
                assert_eq!(leaves_of(&r), 1);
                // The residual decides points of the box as the whole tree does.
                for p in [DVec3::new(7.9, 5.0, 5.0), DVec3::new(8.1, 5.0, 5.0), DVec3::new(8.0, 4.1, 4.5)] {
                    assert_eq!(pruned.contains(&r, p), plate.contains(p), "{p}");
                }
            }
            other => panic!("{other:?}"),
        }
        // Between holes inside the plate: Inside; above the plate: Outside.
        let between = Aabb::new(DVec3::new(9.0, 9.0, 1.0), DVec3::new(11.0, 11.0, 2.0));
        assert!(matches!(pruned.reduce(&root, &between), Reduced::Inside));
        let above = Aabb::new(DVec3::new(0.0, 0.0, 11.0), DVec3::new(1.0, 1.0, 12.0));
        assert!(matches!(pruned.reduce(&root, &above), Reduced::Outside));
    }

    #[test]
    fn symmetric_differences_count_inside_children_as_flips() {
        let a = Sphere::new(DVec3::ZERO, 2.0).unwrap();
        let b = Sphere::new(DVec3::new(0.5, 0.0, 0.0), 2.0).unwrap();
        let c = Sphere::new(DVec3::new(10.0, 0.0, 0.0), 1.0).unwrap();
        let tree = (a ^ b) ^ c;
        let pruned = PrunedCsg::new(&tree);
        // Deep inside both a and b, far from c: two flips, Outside.
        let core = Aabb::new(DVec3::splat(-0.1), DVec3::splat(0.1));
        assert!(matches!(pruned.reduce(&pruned.root(), &core), Reduced::Outside));
        // Inside a only near b's surface: !b.
        let edge = Aabb::new(DVec3::new(-1.6, -0.1, -0.1), DVec3::new(-1.4, 0.1, 0.1));
        match pruned.reduce(&pruned.root(), &edge) {
            Reduced::Smaller(r) => {
                assert!(matches!(r, Residual::Leaf { complement: true, .. }), "{r:?}");
                for x in [-1.55, -1.45] {
                    let p = DVec3::new(x, 0.0, 0.0);
                    assert_eq!(pruned.contains(&r, p), tree.contains(p), "{p}");
                }
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn a_pattern_past_the_leaves_is_one_leaf_a_copy() {
        let balls = (1..20).fold(Csg::from(Sphere::new(DVec3::ZERO, 0.01).unwrap()), |u, i| {
            u | Sphere::new(DVec3::new(0.05 * f64::from(i), 0.0, 0.0), 0.01).unwrap()
        });
        let grid = crate::shape::linear_array(balls.clone(), [400, 250, 1], DVec3::new(1.0, 1.0, 0.0)).unwrap();
        assert_eq!(grid.instances(), 2_000_000);
        let pruned = PrunedCsg::new(&grid);
        assert_eq!(pruned.leaf_count(), 100_000);
        let small = crate::shape::linear_array(balls, [40, 25, 1], DVec3::new(1.0, 1.0, 0.0)).unwrap();
        assert_eq!(PrunedCsg::new(&small).leaf_count(), 20_000);
        for p in [DVec3::new(399.05, 249.0, 0.0), DVec3::new(399.025, 249.0, 0.0), DVec3::new(7.95, 3.0, 0.0)] {
            assert_eq!(pruned.contains(&pruned.root(), p), grid.contains(p), "{p}");
        }
        assert!(grid.contains(DVec3::new(399.05, 249.0, 0.0)) && !grid.contains(DVec3::new(399.025, 249.0, 0.0)));
    }
}
