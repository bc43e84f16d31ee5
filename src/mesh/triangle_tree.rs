//! Whether any triangle of a mesh meets a box: a bounding-box hierarchy over the
//! triangles, for queries that stop at the first triangle found.
//!
//! Build: the triangles are split at the median centroid along the longest axis of
//! their centroids (as the winding number's hierarchy in `winding.rs`), down to leaves
//! of at most [`LEAF_SIZE`]; each node stores the box of its triangles, O(n log n).
//! Query [`TriangleTree::meets`]: descend the nodes whose box meets the closed query
//! box; at a leaf, a triangle's own box first, then the separating-axis test of
//! `tri_box.rs`, which is conservative (the box grown by a relative hair), so a
//! triangle that meets the box is never missed; one that misses it by less than the
//! hair may be reported. Box comparisons are exact. A box far from the surface is
//! rejected near the root; one the surface crosses stops at the first triangle found.
//! Query [`TriangleTree::for_each_near`]: every triangle whose own box meets the query
//! box, by its index in the mesh (the candidates an exact test then decides, as the
//! crossings of a short segment in `surface`'s Hermite data of a mesh).

use glam::DVec3;

use super::TriangleMesh;
use super::tri_box::triangle_box_overlap;
use crate::aabb::Aabb;

/// Most triangles in a leaf.
const LEAF_SIZE: usize = 4;

/// One node: the box of its triangles; a leaf holds `count > 0` triangles from
/// `first`, an inner node has its first child next and its second at `second`.
#[derive(Clone, Copy, Debug)]
struct Node {
    bounds: Aabb,
    first: u32,
    count: u32,
    second: u32,
}

/// A bounding-box hierarchy over a mesh's triangles (see the module doc).
#[derive(Clone, Debug)]
pub(crate) struct TriangleTree {
    /// Each triangle's corners, in the order of the leaves.
    corners: Vec<[DVec3; 3]>,
    /// Each triangle's box, in the same order.
    boxes: Vec<Aabb>,
    /// Each triangle's index in the mesh, in the same order.
    indices: Vec<u32>,
    /// The nodes, depth first, the root first.
    nodes: Vec<Node>,
}

impl TriangleTree {
    /// The hierarchy over the triangles of `mesh` (which has at least one).
    pub(crate) fn new(mesh: &TriangleMesh) -> Self {
        let mut items: Vec<Item> = (0..mesh.triangles.len())
            .map(|t| {
                let c = mesh.corners(t);
                Item { centroid: (c[0] + c[1] + c[2]) / 3.0, corners: c, index: t as u32 }
            })
            .collect();
        let mut nodes = Vec::with_capacity(2 * items.len() / LEAF_SIZE + 1);
        build(&mut items, 0, &mut nodes);
        let corners: Vec<[DVec3; 3]> = items.iter().map(|item| item.corners).collect();
        let indices = items.iter().map(|item| item.index).collect();
        let boxes = corners.iter().map(|c| Aabb::from_points(*c).expect("three corners")).collect();
        TriangleTree { corners, boxes, indices, nodes }
    }

    /// Calls `visit` with the mesh index of every triangle whose bounding box meets the
    /// closed box `b` (exact box comparisons; no triangle test).
    pub(crate) fn for_each_near(&self, b: &Aabb, mut visit: impl FnMut(u32)) {
        self.find_in_leaves(b, |t| {
            visit(self.indices[t]);
            false
        });
    }

    /// Whether some triangle meets the closed box `b` (conservative, see the module doc).
    pub(crate) fn meets(&self, b: &Aabb) -> bool {
        let (center, half) = (b.center(), b.size() * 0.5);
        self.find_in_leaves(b, |t| triangle_box_overlap(&self.corners[t], center, half))
    }

    /// Walks the nodes whose bounds meet `b` and asks `found` about each leaf triangle
    /// (by its place in the tree's order) whose box meets `b`, until it says yes;
    /// whether it did.
    fn find_in_leaves(&self, b: &Aabb, mut found: impl FnMut(usize) -> bool) -> bool {
        let mut stack = [0u32; 64];
        let mut top = 1;
        while top > 0 {
            top -= 1;
            let index = stack[top];
            let node = &self.nodes[index as usize];
            if !overlaps(&node.bounds, b) {
                continue;
            }
            if node.count > 0 {
                let range = node.first as usize..(node.first + node.count) as usize;
                if range.into_iter().any(|t| overlaps(&self.boxes[t], b) && found(t)) {
                    return true;
                }
            } else {
                stack[top] = index + 1;
                stack[top + 1] = node.second;
                top += 2;
            }
        }
        false
    }
}

/// Whether two closed boxes share a point.
#[inline]
fn overlaps(a: &Aabb, b: &Aabb) -> bool {
    a.min.cmple(b.max).all() && a.max.cmpge(b.min).all()
}

/// A triangle while the hierarchy is built: its centroid, corners and mesh index.
struct Item {
    centroid: DVec3,
    corners: [DVec3; 3],
    index: u32,
}

/// Appends the nodes over `items` (offset `first` in the final order) to `nodes`, the
/// subtree's root first; returns the root's index.
fn build(items: &mut [Item], first: usize, nodes: &mut Vec<Node>) -> u32 {
    let at = nodes.len() as u32;
    let bounds = Aabb::from_points(items.iter().flat_map(|item| item.corners)).expect("a node has triangles");
    nodes.push(Node { bounds, first: first as u32, count: items.len() as u32, second: 0 });
    if items.len() <= LEAF_SIZE {
        return at;
    }
    let centroids = Aabb::from_points(items.iter().map(|item| item.centroid)).expect("a node has triangles");
    let axis = centroids.size().max_position();
    let mid = items.len() / 2;
    items.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    let (left, right) = items.split_at_mut(mid);
    build(left, first, nodes);
    let second = build(right, first + mid, nodes);
    nodes[at as usize].count = 0;
    nodes[at as usize].second = second;
    at
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate::icosphere;
    use crate::test_util::Rng;

    #[test]
    fn meets_agrees_with_testing_every_triangle() {
        let mesh = icosphere(DVec3::new(0.1, -0.2, 0.05), 1.0, 3);
        let tree = TriangleTree::new(&mesh);
        let mut rng = Rng(7);
        let (mut met, mut missed) = (0, 0);
        for _ in 0..4000 {
            let b = Aabb::from_center_half(rng.vec(-1.3, 1.3), rng.vec(0.005, 0.3));
            // The oracle: the same separating-axis test on every triangle.
            let want =
                (0..mesh.triangles.len()).any(|t| triangle_box_overlap(&mesh.corners(t), b.center(), b.size() * 0.5));
            assert_eq!(tree.meets(&b), want, "{b:?}");
            if want { met += 1 } else { missed += 1 }
        }
        assert!(met > 500 && missed > 500, "{met} met, {missed} missed");
    }

    #[test]
    fn for_each_near_finds_exactly_the_triangles_whose_boxes_meet() {
        let mesh = icosphere(DVec3::new(0.1, -0.2, 0.05), 1.0, 3);
        let tree = TriangleTree::new(&mesh);
        let mut rng = Rng(11);
        let mut found_some = 0;
        for _ in 0..2000 {
            let b = Aabb::from_center_half(rng.vec(-1.3, 1.3), rng.vec(0.0, 0.2));
            let mut got = Vec::new();
            tree.for_each_near(&b, |t| got.push(t));
            got.sort_unstable();
            // The oracle: every triangle's box against the query box.
            let want: Vec<u32> = (0..mesh.triangles.len() as u32)
                .filter(|&t| overlaps(&Aabb::from_points(mesh.corners(t as usize)).unwrap(), &b))
                .collect();
            assert_eq!(got, want, "{b:?}");
            found_some += usize::from(!want.is_empty());
        }
        assert!(found_some > 300, "{found_some} boxes met triangles");
    }
}
