//! Our contender: the traversal octree ([`Traversal`]) and its exact ray walk.
//!
//! Bytes counted: the traversal octree (8 bytes an inner node plus the struct), which is
//! all the walk reads; the linear octree it is built from is not counted.

use super::contender::{Contender, SurfaceHit};
use super::rays::Ray;
use octsolid::octree::LinearOctree;
use octsolid::render::Traversal;

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

    fn closest_hit(&self, ray: &Ray) -> Option<SurfaceHit> {
        self.hit(ray.origin, ray.dir, ray.t_max).map(|h| SurfaceHit { t: h.t, normal: h.normal(ray.dir) })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        Traversal::occluded(self, ray.origin, ray.dir, ray.t_max)
    }
}
