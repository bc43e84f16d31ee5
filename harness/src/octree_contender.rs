//! Our contender: the traversal octree ([`Traversal`]) and its exact ray walk.
//!
//! Bytes counted: the traversal octree (8 bytes an inner node plus the struct), which is
//! all the walk reads; the linear octree it is built from is not counted.

use super::contender::{Contender, SurfaceHit};
use octsolid::Ray;
use octsolid::octree::LinearOctree;
use octsolid::render::{Hit, Traversal};

impl Contender for Traversal {
    type Input = LinearOctree;

    fn build(input: &LinearOctree) -> Self {
        Traversal::new(input)
    }

    fn bytes(&self) -> usize {
        Traversal::bytes(self)
    }

    fn node_count(&self) -> usize {
        Traversal::node_count(self)
    }

    fn surface(&self, hit: Hit, ray: &Ray) -> SurfaceHit {
        SurfaceHit { t: hit.t, normal: hit.normal(ray.dir) }
    }
}
