//! Whether any triangle of a mesh meets a box: a bounding-box hierarchy over the
//! triangles, for queries that stop at the first triangle found.
//!
//! Build: the triangles are split at the median centroid along the longest axis of
//! their centroids (as the winding number's hierarchy in `winding.rs`), down to leaves
//! of at most [`LEAF_SIZE`]; each node stores the box of its triangles (a leaf's from
//! its corners, an inner node's the union of its children's), O(n log n). The nodes
//! lie depth first; a subtree's node count follows from its triangle count alone
//! ([`node_count`]), so both halves of a large node are built at once, each into its
//! own part of the node array (the same array as one after the other).
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

/// Fewest triangles in a node whose halves are built in parallel.
const PARALLEL_SIZE: usize = 4096;

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
        let placeholder = Node { bounds: Aabb { min: DVec3::ZERO, max: DVec3::ZERO }, first: 0, count: 0, second: 0 };
        let mut nodes = vec![placeholder; node_count(items.len())];
        build(&mut items, 0, &mut nodes, 0);
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

/// How many nodes the hierarchy over `n > 0` triangles has.
fn node_count(n: usize) -> usize {
    // (count(m), count(m + 1)) from (count(m / 2), count(m / 2 + 1)): the halves of m and
    // of m + 1 are m / 2 and m / 2 + 1 triangles, in the pairs below.
    fn pair(m: usize) -> (usize, usize) {
        if m <= 2 * LEAF_SIZE {
            return (direct(m), direct(m + 1));
        }
        let (h, h1) = pair(m / 2);
        if m.is_multiple_of(2) { (1 + 2 * h, 1 + h + h1) } else { (1 + h + h1, 1 + 2 * h1) }
    }
    fn direct(m: usize) -> usize {
        if m <= LEAF_SIZE { 1 } else { 1 + direct(m / 2) + direct(m - m / 2) }
    }
    pair(n).0
}

/// Writes the nodes over `items` (offset `first` in the final order) into `nodes`
/// (exactly [`node_count`] of them, the subtree's root first; `at` is the index of
/// `nodes[0]` in the whole array).
fn build(items: &mut [Item], first: usize, nodes: &mut [Node], at: usize) {
    debug_assert_eq!(nodes.len(), node_count(items.len()));
    if items.len() <= LEAF_SIZE {
        let bounds = Aabb::from_points(items.iter().flat_map(|item| item.corners)).expect("a node has triangles");
        nodes[0] = Node { bounds, first: first as u32, count: items.len() as u32, second: 0 };
        return;
    }
    let centroids = Aabb::from_points(items.iter().map(|item| item.centroid)).expect("a node has triangles");
    let axis = centroids.size().max_position();
    let (n, mid) = (items.len(), items.len() / 2);
    items.select_nth_unstable_by(mid, |a, b| a.centroid[axis].total_cmp(&b.centroid[axis]));
    let (left, right) = items.split_at_mut(mid);
    let (root, below) = nodes.split_first_mut().expect("a node");
    let (left_nodes, right_nodes) = below.split_at_mut(node_count(mid));
    let second = at + 1 + left_nodes.len();
    if n >= PARALLEL_SIZE {
        rayon::join(|| build(left, first, left_nodes, at + 1), || build(right, first + mid, right_nodes, second));
    } else {
        build(left, first, left_nodes, at + 1);
        build(right, first + mid, right_nodes, second);
    }
    let bounds = left_nodes[0].bounds.union(&right_nodes[0].bounds);
    *root = Node { bounds, first: first as u32, count: 0, second: second as u32 };
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

    /// The triangles (by their place in the tree's order) under node `i`, checking on
    /// the way that each node's box is exactly its triangles' box.
    fn check_node(tree: &TriangleTree, i: usize) -> std::ops::Range<usize> {
        let node = tree.nodes[i];
        let range = if node.count > 0 {
            node.first as usize..(node.first + node.count) as usize
        } else {
            let (left, right) = (check_node(tree, i + 1), check_node(tree, node.second as usize));
            assert_eq!(left.end, right.start, "node {i}'s halves follow each other");
            left.start..right.end
        };
        let want = Aabb::from_points(tree.corners[range.clone()].iter().flatten().copied()).unwrap();
        assert_eq!((node.bounds.min, node.bounds.max), (want.min, want.max), "node {i}");
        range
    }

    #[test]
    fn every_node_bounds_exactly_its_triangles_built_in_parallel_or_not() {
        // 20,480 triangles: the top nodes' halves are built in parallel.
        let mesh = icosphere(DVec3::new(0.1, -0.2, 0.05), 1.0, 5);
        assert!(mesh.triangles.len() > 4 * PARALLEL_SIZE);
        let tree = TriangleTree::new(&mesh);
        assert_eq!(check_node(&tree, 0), 0..mesh.triangles.len());
        assert_eq!(tree.nodes.len(), node_count(mesh.triangles.len()));
        let mut indices = tree.indices.clone();
        indices.sort_unstable();
        assert!(indices.iter().enumerate().all(|(i, &t)| i == t as usize), "every triangle once");
        for (i, &t) in tree.indices.iter().enumerate() {
            assert_eq!(tree.corners[i], mesh.corners(t as usize));
        }
    }

    #[test]
    fn node_count_is_the_count_of_the_median_splits() {
        fn splits(n: usize) -> usize {
            if n <= LEAF_SIZE { 1 } else { 1 + splits(n / 2) + splits(n - n / 2) }
        }
        for n in (1..3000).chain([4095, 4096, 4097, 65_535, 65_536, 100_003, 1 << 20]) {
            assert_eq!(node_count(n), splits(n), "{n}");
        }
    }
}
