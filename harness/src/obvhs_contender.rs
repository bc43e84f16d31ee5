//! The `obvhs` crate's compressed wide BVH (CWBVH, Ylitie et al. 2017: 8-wide nodes of
//! 80 bytes, built by PLOC with reinsertion) over a triangle mesh, traversed on the CPU
//! with its own SIMD node tests and Moller-Trumbore triangles, in `f32` (the only width
//! the crate offers).
//!
//! Build preset: `BvhBuildParams::medium_build()`, which the crate describes as "around
//! the same build time as embree but with faster traversal". After the build the
//! triangles are stored in the BVH's leaf order (as the crate's own examples do), so a
//! leaf's primitive index is the triangle's index.
//!
//! Bytes counted: the node array, the primitive index array and the reordered triangle
//! array (48 bytes a triangle: three 16-byte `Vec3A`), each at its capacity.

use std::time::Duration;

use glam::Vec3A;
use obvhs::BvhBuildParams;
use obvhs::cwbvh::{CwBvh, builder::build_cwbvh_from_tris, node::CwBvhNode};
use obvhs::ray::{Ray as ObvhsRay, RayHit};
use obvhs::triangle::Triangle;

use octsolid::{Ray, RayCast};

use super::contender::{Contender, SurfaceHit};
use octsolid::mesh::TriangleMesh;

/// A CWBVH of `obvhs` and its triangles in leaf order.
pub struct ObvhsBvh {
    bvh: CwBvh,
    triangles: Vec<Triangle>,
}

/// The `f32` ray of `ray`.
fn to_obvhs(ray: &Ray) -> ObvhsRay {
    ObvhsRay::new(ray.origin.as_vec3a(), ray.dir.as_vec3a(), 0.0, ray.t_max as f32)
}

impl Contender for ObvhsBvh {
    type Input = TriangleMesh;

    fn build(mesh: &TriangleMesh) -> Self {
        let corner = |i: u32| -> Vec3A { mesh.vertices[i as usize].as_vec3a() };
        let triangles: Vec<Triangle> =
            mesh.triangles.iter().map(|t| Triangle { v0: corner(t[0]), v1: corner(t[1]), v2: corner(t[2]) }).collect();
        let bvh = build_cwbvh_from_tris(&triangles, BvhBuildParams::medium_build(), &mut Duration::default());
        let triangles = bvh.primitive_indices.iter().map(|&i| triangles[i as usize]).collect();
        ObvhsBvh { bvh, triangles }
    }

    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.bvh.nodes.capacity() * std::mem::size_of::<CwBvhNode>()
            + self.bvh.primitive_indices.capacity() * std::mem::size_of::<u32>()
            + self.triangles.capacity() * std::mem::size_of::<Triangle>()
    }

    fn node_count(&self) -> usize {
        self.bvh.nodes.len()
    }

    fn surface(&self, hit: SurfaceHit, _ray: &Ray) -> SurfaceHit {
        hit
    }
}

impl RayCast for ObvhsBvh {
    type Hit = SurfaceHit;

    fn hit(&self, ray: &Ray) -> Option<SurfaceHit> {
        let mut hit = RayHit::none();
        if !self.bvh.ray_traverse(to_obvhs(ray), &mut hit, |r, id| self.triangles[id].intersect(r)) {
            return None;
        }
        let n = self.triangles[hit.primitive_id as usize].compute_normal().as_dvec3();
        Some(SurfaceHit { t: f64::from(hit.t), normal: if n.dot(ray.dir) > 0.0 { -n } else { n } })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        !self.bvh.ray_traverse_miss(to_obvhs(ray), |r, id| self.triangles[id].intersect(r))
    }
}
