//! Our second contender: the 64-tree ([`Tree64`], 4x4x4 nodes) and its mirrored walk,
//! with the traversal octree's hits bit for bit (issue 41).
//!
//! Bytes counted: the 64-tree (8 bytes a node of the lowest level, 24 above, plus the
//! struct), which is all its walk reads; the linear octree it is built from is not
//! counted.

use super::contender::{Contender, SurfaceHit};
use octsolid::Ray;
use octsolid::octree::LinearOctree;
use octsolid::render::{Hit, Tree64};

impl Contender for Tree64 {
    type Input = LinearOctree;

    fn build(input: &LinearOctree) -> Self {
        Tree64::new(input)
    }

    fn bytes(&self) -> usize {
        Tree64::bytes(self)
    }

    fn node_count(&self) -> usize {
        Tree64::node_count(self)
    }

    fn surface(&self, hit: Hit, ray: &Ray) -> SurfaceHit {
        SurfaceHit { t: hit.t, normal: hit.normal(ray.dir) }
    }
}
