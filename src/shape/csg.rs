//! CSG trees of shapes, built with the operators `|` `&` `-` `^` `!` and by patterns.
//!
//! A tree classifies a box from its children's classes by the Inside / Outside /
//! Boundary algebra (union: Inside if either is, Outside if both are; intersection the
//! dual; difference `a & !b`; complement swaps Inside and Outside), and decides a point
//! by the boolean of its children. Since every leaf is conservative, so is the tree,
//! and voxelizing the tree gives exactly the CSG of the voxelized leaves.
//!
//! Nodes are n-ary: `a | b | c` is one union of three children (an operator whose
//! left operand is the same operation, held nowhere else, takes the right operand as
//! one more child), evaluated as the left fold `(a | b) | c` it was written as, so the
//! bits are those of the binary tree. A difference is its first child minus each of the
//! others in turn. A [`CsgNode::Placed`] node is the union of one child under many
//! [`Placement`]s (a pattern's copies, a `transform`): the child is shared, not copied.
//!
//! Bounds on the work: [`Csg::copies`] is the most copies any leaf is made into (the
//! product of the placement counts of the nodes above it), at most [`MAX_COPIES`]
//! (refused by [`Csg::placed`] with the count). A tree no higher than
//! [`MAX_RECURSION`] is evaluated by recursion; a higher one (only the library's API
//! builds one, e.g. `a | (b & (c | ...))` alternating a million times) by the same
//! fold with its stack on the heap. Dropping and printing a tree never recurse.

use std::ops::{BitAnd, BitOr, BitXor, Not, Sub};
use std::sync::{Arc, OnceLock};

use glam::DVec3;

use super::bounds::both;
use super::pattern::MAX_COPIES;
use super::{
    Class, Cone, Cuboid, Cylinder, DisplacedSphere, Ellipsoid, Extrude, HalfSpace, Menger, Placement, Revolve, Shape,
    Sphere, Surface, Torus, Transformed,
};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// The highest tree evaluated by recursion; a higher one is folded with its stack on
/// the heap (see the module doc).
pub const MAX_RECURSION: u32 = 256;

/// A node of a CSG tree. Every list of children holds at least two.
pub enum CsgNode {
    /// A primitive (any shape, including user types).
    Leaf(Arc<dyn Shape>),
    /// Points in any child.
    Union(Vec<Csg>),
    /// Points in every child.
    Intersection(Vec<Csg>),
    /// Points in the first child and no other.
    Difference(Vec<Csg>),
    /// Points in an odd number of the children (the left fold of binary `^`).
    SymmetricDifference(Vec<Csg>),
    /// Points not in the child.
    Complement(Csg),
    /// Points in the child under any of the placements (at least one): a pattern.
    Placed(Csg, Arc<[Placement]>),
}

/// A node with what is known of the tree below it.
struct Node {
    node: CsgNode,
    /// [`Csg::copies`].
    copies: u64,
    /// Edges on the longest path down to a leaf.
    height: u32,
    /// [`Csg::instances`].
    instances: u64,
}

/// A CSG tree of shapes; cheap to clone (shared nodes).
#[derive(Clone)]
pub struct Csg(Arc<Node>);

/// The n-ary operations.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Op {
    Union,
    Intersection,
    Difference,
    Xor,
}

impl Op {
    fn node(self, children: Vec<Csg>) -> CsgNode {
        match self {
            Op::Union => CsgNode::Union(children),
            Op::Intersection => CsgNode::Intersection(children),
            Op::Difference => CsgNode::Difference(children),
            Op::Xor => CsgNode::SymmetricDifference(children),
        }
    }

    fn symbol(self) -> &'static str {
        match self {
            Op::Union => " | ",
            Op::Intersection => " & ",
            Op::Difference => " - ",
            Op::Xor => " ^ ",
        }
    }
}

impl CsgNode {
    /// The operation and children of an n-ary node.
    fn nary(&self) -> Option<(Op, &[Csg])> {
        match self {
            CsgNode::Union(c) => Some((Op::Union, c)),
            CsgNode::Intersection(c) => Some((Op::Intersection, c)),
            CsgNode::Difference(c) => Some((Op::Difference, c)),
            CsgNode::SymmetricDifference(c) => Some((Op::Xor, c)),
            CsgNode::Leaf(_) | CsgNode::Complement(_) | CsgNode::Placed(..) => None,
        }
    }

    fn children(&self) -> &[Csg] {
        match self {
            CsgNode::Leaf(_) => &[],
            CsgNode::Union(c) | CsgNode::Intersection(c) | CsgNode::Difference(c) | CsgNode::SymmetricDifference(c) => {
                c
            }
            CsgNode::Complement(c) | CsgNode::Placed(c, _) => std::slice::from_ref(c),
        }
    }
}

impl Csg {
    /// A tree of one shape (the tree itself when the shape is a tree).
    #[must_use]
    pub fn leaf(shape: impl Shape + 'static) -> Csg {
        match shape.as_csg() {
            Some(tree) => tree.clone(),
            None => Csg::make(CsgNode::Leaf(Arc::new(shape))),
        }
    }

    /// The union of `child` under each of `placements`; fails for no placements and
    /// when the copies would pass [`MAX_COPIES`] ([`Csg::copies`]).
    pub fn placed(child: Csg, placements: Vec<Placement>) -> Result<Csg> {
        let n = placements.len() as u64;
        let total = n.saturating_mul(child.copies());
        if !(1..=MAX_COPIES).contains(&total) {
            return Err(Error::invalid(
                "pattern",
                format!(
                    "{n} placements of a tree of {} copies make {total} copies; patterns make 1 to {MAX_COPIES} \
                     copies in all, nested ones multiplied",
                    child.copies()
                ),
            ));
        }
        Ok(Csg::make(CsgNode::Placed(child, placements.into())))
    }

    /// The root node.
    #[must_use]
    pub fn node(&self) -> &CsgNode {
        &self.0.node
    }

    /// The most copies any leaf of the tree is made into: the product of the numbers
    /// of placements of the [`CsgNode::Placed`] nodes above it (1 without patterns).
    #[must_use]
    pub fn copies(&self) -> u64 {
        self.0.copies
    }

    /// The leaves of the tree with every pattern's copies made one by one: what
    /// [`super::PrunedCsg`] would flatten it into.
    #[must_use]
    pub fn instances(&self) -> u64 {
        self.0.instances
    }

    /// Edges on the longest path from the root to a leaf.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.0.height
    }

    fn make(node: CsgNode) -> Csg {
        let children = node.children();
        let mut copies = children.iter().map(Csg::copies).max().unwrap_or(1);
        if let CsgNode::Placed(_, placements) = &node {
            copies = copies.saturating_mul(placements.len() as u64);
        }
        let height = children.iter().map(|c| c.height().saturating_add(1)).max().unwrap_or(0);
        let mut instances = children.iter().fold(0u64, |n, c| n.saturating_add(c.instances())).max(1);
        if let CsgNode::Placed(_, placements) = &node {
            instances = instances.saturating_mul(placements.len() as u64);
        }
        Csg(Arc::new(Node { node, copies, height, instances }))
    }

    /// `self op rhs`: `rhs` joins `self`'s children when `self` is an `op` node held
    /// nowhere else (a left fold builds one node), else a new node of the two.
    fn join(mut self, op: Op, rhs: Csg) -> Csg {
        if let Some(node) = Arc::get_mut(&mut self.0) {
            let children = match (&mut node.node, op) {
                (CsgNode::Union(c), Op::Union)
                | (CsgNode::Intersection(c), Op::Intersection)
                | (CsgNode::Difference(c), Op::Difference)
                | (CsgNode::SymmetricDifference(c), Op::Xor) => Some(c),
                _ => None,
            };
            if let Some(children) = children {
                node.copies = node.copies.max(rhs.copies());
                node.height = node.height.max(rhs.height().saturating_add(1));
                node.instances = node.instances.saturating_add(rhs.instances());
                children.push(rhs);
                return self;
            }
        }
        Csg::make(op.node(vec![self, rhs]))
    }

    /// The answer to `query` at `at` (see the module doc for the two ways).
    fn ask<Q: Query>(&self, query: &Q, at: Q::At) -> Q::Out {
        if self.height() <= MAX_RECURSION { recurse(query, self, at) } else { fold_on_heap(query, self, at) }
    }
}

/// One question asked of a tree: a leaf's answer at `At` (a point, a box, nothing),
/// how a placement maps `At` into its copy and the answer back out, and how answers
/// combine by the n-ary operations, left to right.
trait Query {
    type At: Copy;
    type Out: Copy;
    fn leaf(&self, shape: &dyn Shape, at: Self::At) -> Self::Out;
    fn enter(&self, placement: &Placement, at: Self::At) -> Self::At;
    fn leave(&self, placement: &Placement, out: Self::Out) -> Self::Out;
    /// `acc op next`.
    fn combine(&self, op: Op, acc: Self::Out, next: Self::Out) -> Self::Out;
    /// Whether `acc op ...` is `acc` whatever follows.
    fn decided(&self, op: Op, acc: Self::Out) -> bool;
    fn complement(&self, out: Self::Out) -> Self::Out;
}

/// The left fold of `op` over `outs` (at least one), stopping once decided.
fn fold<Q: Query>(query: &Q, op: Op, mut outs: impl Iterator<Item = Q::Out>) -> Q::Out {
    let mut acc = outs.next().expect("a node has children");
    while !query.decided(op, acc) {
        let Some(next) = outs.next() else { break };
        acc = query.combine(op, acc, next);
    }
    acc
}

fn recurse<Q: Query>(query: &Q, tree: &Csg, at: Q::At) -> Q::Out {
    match tree.node() {
        CsgNode::Leaf(shape) => query.leaf(&**shape, at),
        CsgNode::Complement(child) => query.complement(recurse(query, child, at)),
        CsgNode::Placed(child, placements) => {
            fold(query, Op::Union, placements.iter().map(|p| query.leave(p, recurse(query, child, query.enter(p, at)))))
        }
        node => {
            let (op, children) = node.nary().expect("an n-ary node");
            fold(query, op, children.iter().map(|c| recurse(query, c, at)))
        }
    }
}

/// [`recurse`] with its stack on the heap: one frame a node on the current path,
/// holding the answer folded so far and the next child to ask.
fn fold_on_heap<Q: Query>(query: &Q, root: &Csg, at: Q::At) -> Q::Out {
    struct Frame<'a, Q: Query> {
        tree: &'a Csg,
        at: Q::At,
        next: usize,
        acc: Option<Q::Out>,
    }
    let mut stack: Vec<Frame<'_, Q>> = vec![Frame { tree: root, at, next: 0, acc: None }];
    let mut finished: Option<Q::Out> = None;
    loop {
        let top = stack.last_mut().expect("the root's frame is popped last");
        let node = top.tree.node();
        let op = match node {
            CsgNode::Placed(..) | CsgNode::Leaf(_) | CsgNode::Complement(_) => Op::Union,
            node => node.nary().expect("an n-ary node").0,
        };
        if let Some(out) = finished.take() {
            let out = match node {
                CsgNode::Placed(_, placements) => query.leave(&placements[top.next - 1], out),
                _ => out,
            };
            top.acc = Some(match top.acc {
                None => out,
                Some(acc) => query.combine(op, acc, out),
            });
        }
        let open = top.acc.is_none_or(|acc| !query.decided(op, acc));
        let child = match node {
            CsgNode::Leaf(_) => None,
            CsgNode::Complement(child) => (top.next == 0).then_some((child, top.at)),
            CsgNode::Placed(child, placements) => {
                placements.get(top.next).filter(|_| open).map(|p| (child, query.enter(p, top.at)))
            }
            node => node.children().get(top.next).filter(|_| open).map(|c| (c, top.at)),
        };
        if let Some((tree, at)) = child {
            top.next += 1;
            stack.push(Frame { tree, at, next: 0, acc: None });
            continue;
        }
        let out = match node {
            CsgNode::Leaf(shape) => query.leaf(&**shape, top.at),
            CsgNode::Complement(_) => query.complement(top.acc.expect("the child's answer")),
            _ => top.acc.expect("a node has children"),
        };
        stack.pop();
        if stack.is_empty() {
            return out;
        }
        finished = Some(out);
    }
}

/// [`Shape::contains`].
struct Contains;

impl Query for Contains {
    type At = DVec3;
    type Out = bool;
    fn leaf(&self, shape: &dyn Shape, p: DVec3) -> bool {
        shape.contains(p)
    }
    fn enter(&self, placement: &Placement, p: DVec3) -> DVec3 {
        placement.local_point(p)
    }
    fn leave(&self, _: &Placement, out: bool) -> bool {
        out
    }
    fn combine(&self, op: Op, acc: bool, next: bool) -> bool {
        match op {
            Op::Union => acc || next,
            Op::Intersection => acc && next,
            Op::Difference => acc && !next,
            Op::Xor => acc != next,
        }
    }
    fn decided(&self, op: Op, acc: bool) -> bool {
        match op {
            Op::Union => acc,
            Op::Intersection | Op::Difference => !acc,
            Op::Xor => false,
        }
    }
    fn complement(&self, out: bool) -> bool {
        !out
    }
}

/// [`Shape::classify`].
struct Classify;

impl Query for Classify {
    type At = Aabb;
    type Out = Class;
    fn leaf(&self, shape: &dyn Shape, b: Aabb) -> Class {
        shape.classify(&b)
    }
    fn enter(&self, placement: &Placement, b: Aabb) -> Aabb {
        placement.local_box(&b)
    }
    fn leave(&self, _: &Placement, out: Class) -> Class {
        out
    }
    fn combine(&self, op: Op, acc: Class, next: Class) -> Class {
        match op {
            Op::Union => both(acc.complement(), next.complement()).complement(),
            Op::Intersection => both(acc, next),
            Op::Difference => both(acc, next.complement()),
            Op::Xor => match (acc, next) {
                (Class::Boundary, _) | (_, Class::Boundary) => Class::Boundary,
                (a, b) if a == b => Class::Outside,
                _ => Class::Inside,
            },
        }
    }
    fn decided(&self, op: Op, acc: Class) -> bool {
        match op {
            Op::Union => acc == Class::Inside,
            Op::Intersection | Op::Difference => acc == Class::Outside,
            Op::Xor => acc == Class::Boundary,
        }
    }
    fn complement(&self, out: Class) -> Class {
        out.complement()
    }
}

/// [`Shape::surface`]: leaves' surfaces combined as distance bounds, `None` when a
/// leaf cannot tell.
struct SurfaceAt;

impl Query for SurfaceAt {
    type At = DVec3;
    type Out = Option<Surface>;
    fn leaf(&self, shape: &dyn Shape, p: DVec3) -> Option<Surface> {
        shape.surface(p)
    }
    fn enter(&self, placement: &Placement, p: DVec3) -> DVec3 {
        placement.local_point(p)
    }
    fn leave(&self, placement: &Placement, out: Option<Surface>) -> Option<Surface> {
        placement.world_surface(out?)
    }
    fn combine(&self, op: Op, acc: Option<Surface>, next: Option<Surface>) -> Option<Surface> {
        let (a, b) = (acc?, next?);
        Some(match op {
            Op::Union => a.union(b),
            Op::Intersection => a.intersection(b),
            Op::Difference => a.intersection(b.flipped()),
            Op::Xor => a.intersection(b.flipped()).union(b.intersection(a.flipped())),
        })
    }
    fn decided(&self, _: Op, acc: Option<Surface>) -> bool {
        acc.is_none()
    }
    fn complement(&self, out: Option<Surface>) -> Option<Surface> {
        out.map(Surface::flipped)
    }
}

/// [`Shape::support`]: a union's is the farthest of its children's (a pattern's of
/// its copies'); the other operations and complements have none (a cut may remove
/// the farthest point). The answer carries the direction in its frame, to compare.
struct Support;

impl Query for Support {
    type At = DVec3;
    type Out = Option<(DVec3, DVec3)>;
    fn leaf(&self, shape: &dyn Shape, d: DVec3) -> Self::Out {
        Some((shape.support(d)?, d))
    }
    fn enter(&self, placement: &Placement, d: DVec3) -> DVec3 {
        placement.local_direction(d)
    }
    fn leave(&self, placement: &Placement, out: Self::Out) -> Self::Out {
        let (p, d) = out?;
        Some((placement.world_point(p), placement.world_direction(d)))
    }
    fn combine(&self, op: Op, acc: Self::Out, next: Self::Out) -> Self::Out {
        let ((a, d), (b, _)) = (acc?, next?);
        match op {
            Op::Union => Some(if b.dot(d) > a.dot(d) { (b, d) } else { (a, d) }),
            Op::Intersection | Op::Difference | Op::Xor => None,
        }
    }
    fn decided(&self, _: Op, acc: Self::Out) -> bool {
        acc.is_none()
    }
    fn complement(&self, _: Self::Out) -> Self::Out {
        None
    }
}

/// [`Shape::bounds`]: a union's is the union of its children's, an intersection's
/// their intersection (a point when it is empty), a difference's its first child's.
struct Bounds;

impl Query for Bounds {
    type At = ();
    type Out = Option<Aabb>;
    fn leaf(&self, shape: &dyn Shape, (): ()) -> Option<Aabb> {
        shape.bounds()
    }
    fn enter(&self, _: &Placement, (): ()) {}
    fn leave(&self, placement: &Placement, out: Option<Aabb>) -> Option<Aabb> {
        out.map(|b| placement.world_box(&b))
    }
    fn combine(&self, op: Op, acc: Option<Aabb>, next: Option<Aabb>) -> Option<Aabb> {
        match op {
            Op::Union | Op::Xor => Some(acc?.union(&next?)),
            Op::Intersection => match (acc, next) {
                (Some(a), Some(b)) => Some(a.intersection(&b).unwrap_or(Aabb { min: a.min, max: a.min })),
                (a, b) => a.or(b),
            },
            Op::Difference => acc,
        }
    }
    fn decided(&self, op: Op, acc: Option<Aabb>) -> bool {
        match op {
            Op::Union | Op::Xor => acc.is_none(),
            Op::Intersection => false,
            Op::Difference => true,
        }
    }
    fn complement(&self, _: Option<Aabb>) -> Option<Aabb> {
        None
    }
}

impl Shape for Csg {
    fn classify(&self, b: &Aabb) -> Class {
        self.ask(&Classify, *b)
    }

    fn contains(&self, p: DVec3) -> bool {
        self.ask(&Contains, p)
    }

    /// Leaves' surfaces combined as distance bounds (see [`Surface`]); `None` when a
    /// leaf cannot tell.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        self.ask(&SurfaceAt, p)
    }

    fn bounds(&self) -> Option<Aabb> {
        self.ask(&Bounds, ())
    }

    /// A union's farthest child's support (see `Support`); none for the other
    /// operations.
    fn support(&self, d: DVec3) -> Option<DVec3> {
        self.ask(&Support, d).map(|(p, _)| p)
    }

    fn as_csg(&self) -> Option<&Csg> {
        Some(self)
    }
}

/// A childless node that takes a dropped node's child's place (see [`Csg`]'s `Drop`).
fn placeholder() -> Csg {
    struct Nothing;
    impl Shape for Nothing {
        fn classify(&self, _: &Aabb) -> Class {
            Class::Outside
        }
        fn contains(&self, _: DVec3) -> bool {
            false
        }
        fn bounds(&self) -> Option<Aabb> {
            None
        }
    }
    static NOTHING: OnceLock<Csg> = OnceLock::new();
    NOTHING
        .get_or_init(|| {
            Csg(Arc::new(Node { node: CsgNode::Leaf(Arc::new(Nothing)), copies: 1, height: 0, instances: 1 }))
        })
        .clone()
}

/// Dropping the last reference to a node takes its children first and drops them one
/// by one from a list, so a deep tree is freed without recursion.
impl Drop for Csg {
    fn drop(&mut self) {
        fn take_children(node: &mut CsgNode, into: &mut Vec<Csg>) {
            match node {
                CsgNode::Leaf(_) => {}
                CsgNode::Union(c)
                | CsgNode::Intersection(c)
                | CsgNode::Difference(c)
                | CsgNode::SymmetricDifference(c) => {
                    into.append(c);
                }
                CsgNode::Complement(c) | CsgNode::Placed(c, _) => {
                    if c.node().children().is_empty() {
                        return; // a leaf child: dropping it does not recurse
                    }
                    into.push(std::mem::replace(c, placeholder()));
                }
            }
        }
        let mut pending = Vec::new();
        if let Some(node) = Arc::get_mut(&mut self.0) {
            take_children(&mut node.node, &mut pending);
        }
        while let Some(mut tree) = pending.pop() {
            if let Some(node) = Arc::get_mut(&mut tree.0) {
                take_children(&mut node.node, &mut pending);
            }
        }
    }
}

/// `(a | b | c)`, `!a`, `placed(a; n)` for `n` placements, `Leaf`; written from a list
/// of what is left to print, without recursion.
impl std::fmt::Debug for Csg {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        enum Item<'a> {
            Tree(&'a Csg),
            Text(&'static str),
            Count(usize),
        }
        let mut pending = vec![Item::Tree(self)];
        while let Some(item) = pending.pop() {
            match item {
                Item::Text(s) => f.write_str(s)?,
                Item::Count(n) => write!(f, "; {n})")?,
                Item::Tree(tree) => match tree.node() {
                    CsgNode::Leaf(_) => f.write_str("Leaf")?,
                    CsgNode::Complement(c) => {
                        f.write_str("!")?;
                        pending.push(Item::Tree(c));
                    }
                    CsgNode::Placed(c, placements) => {
                        f.write_str("placed(")?;
                        pending.push(Item::Count(placements.len()));
                        pending.push(Item::Tree(c));
                    }
                    node => {
                        let (op, children) = node.nary().expect("an n-ary node");
                        f.write_str("(")?;
                        pending.push(Item::Text(")"));
                        for (i, c) in children.iter().enumerate().rev() {
                            pending.push(Item::Tree(c));
                            if i > 0 {
                                pending.push(Item::Text(op.symbol()));
                            }
                        }
                    }
                },
            }
        }
        Ok(())
    }
}

macro_rules! csg_operators {
    ($($ty:ty),* $(,)?) => {$(
        impl<R: Into<Csg>> BitOr<R> for $ty {
            type Output = Csg;
            fn bitor(self, rhs: R) -> Csg {
                Csg::join(self.into(), Op::Union, rhs.into())
            }
        }
        impl<R: Into<Csg>> BitAnd<R> for $ty {
            type Output = Csg;
            fn bitand(self, rhs: R) -> Csg {
                Csg::join(self.into(), Op::Intersection, rhs.into())
            }
        }
        impl<R: Into<Csg>> Sub<R> for $ty {
            type Output = Csg;
            fn sub(self, rhs: R) -> Csg {
                Csg::join(self.into(), Op::Difference, rhs.into())
            }
        }
        impl<R: Into<Csg>> BitXor<R> for $ty {
            type Output = Csg;
            fn bitxor(self, rhs: R) -> Csg {
                Csg::join(self.into(), Op::Xor, rhs.into())
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

leaf_conversions!(
    Sphere,
    Ellipsoid,
    Cuboid,
    Cylinder,
    Cone,
    Torus,
    HalfSpace,
    Menger,
    DisplacedSphere,
    Extrude,
    Revolve
);
csg_operators!(
    Csg,
    Sphere,
    Ellipsoid,
    Cuboid,
    Cylinder,
    Cone,
    Torus,
    HalfSpace,
    Menger,
    DisplacedSphere,
    Extrude,
    Revolve
);

/// A transformed tree is a [`CsgNode::Placed`] node of one placement, whose leaves a
/// pruning voxelizer sees; any other transformed shape is a leaf.
impl<S: Shape + 'static> From<Transformed<S>> for Csg {
    fn from(shape: Transformed<S>) -> Csg {
        match shape.inner().as_csg() {
            Some(tree) => {
                let placement = Placement::Affine { to_world: shape.to_world(), to_local: shape.to_local() };
                Csg::make(CsgNode::Placed(tree.clone(), Arc::new([placement])))
            }
            None => Csg::leaf(shape),
        }
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
                Csg::join(self.into(), Op::$node, rhs.into())
            }
        }
    )*};
}

transformed_operators!(BitOr bitor Union, BitAnd bitand Intersection, Sub sub Difference, BitXor bitxor Xor);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shape::{linear_array, mirrored};

    fn ball(x: f64) -> Csg {
        Sphere::new(DVec3::new(x, 0.0, 0.0), 0.5).unwrap().into()
    }

    #[test]
    fn a_left_fold_is_one_node_and_a_shared_operand_is_not_changed() {
        let fold = ball(0.0) | ball(1.0) | (ball(2.0) - ball(3.0));
        assert_eq!(format!("{fold:?}"), "(Leaf | Leaf | (Leaf - Leaf))");
        let shared = ball(0.0) - ball(1.0) - ball(2.0);
        let more = &shared - ball(3.0);
        assert_eq!(format!("{shared:?}"), "(Leaf - Leaf - Leaf)");
        assert_eq!(format!("{more:?}"), "((Leaf - Leaf - Leaf) - Leaf)");
        assert_eq!((shared.height(), more.height()), (1, 2));
        // The fold's answers are the binary tree's: inside 0 and 1, not 3.
        assert!(more.contains(DVec3::ZERO) && !more.contains(DVec3::new(1.0, 0.0, 0.0)));
    }

    #[test]
    fn copies_multiply_down_a_path_and_take_the_most_across() {
        let row = linear_array(ball(0.0), [10, 1, 1], DVec3::X).unwrap();
        let pair = mirrored(row.clone(), DVec3::Y, DVec3::ZERO).unwrap();
        assert_eq!((row.copies(), pair.copies()), (10, 20));
        assert_eq!((pair.clone() | row.clone() | ball(5.0)).copies(), 20);
        assert_eq!(format!("{pair:?}"), "placed(placed(Leaf; 10); 2)");
        let e = linear_array(pair, [5001, 1, 1], DVec3::Z).unwrap_err().to_string();
        assert!(e.contains("100020 copies"), "{e}");
    }
}
