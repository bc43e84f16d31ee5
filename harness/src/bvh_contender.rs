//! The `bvh` crate's binary SAH BVH over a triangle mesh, in `f64` (the width of our
//! octree walk), built in parallel (`build_par`, rayon).
//!
//! Queries use the crate's own pieces: the closest hit walks
//! `nearest_traverse_iterator` (best first: leaves come out in increasing order of their
//! box's entry distance) and stops once a leaf's box starts beyond the closest
//! triangle hit found so far; triangles are tested with the crate's Moller-Trumbore
//! `Ray::intersects_triangle`, which culls back faces (meshes here are outward-wound, and
//! every ray starts outside the solid). Shadow rays stop at the first triangle hit
//! before `t_max` along `traverse_iterator`. The crate has no "closest hit with a
//! shrinking `t_max`" query of its own.
//!
//! Bytes counted: the node array and the shape array (three `f64` points and the node
//! index a triangle), each at its capacity.

use bvh::aabb::{Aabb, Bounded};
use bvh::bounding_hierarchy::{BHShape, BoundingHierarchy};
use bvh::bvh::{Bvh, BvhNode};
use bvh::ray::Ray as BvhRay;
use glam::DVec3;
use nalgebra::{Point3, Vector3};

use octsolid::{Ray, RayCast};

use super::contender::{Contender, SurfaceHit};
use octsolid::mesh::TriangleMesh;

/// One triangle as a shape of the `bvh` crate.
#[derive(Clone, Copy, Debug)]
pub struct BvhTriangle {
    corners: [Point3<f64>; 3],
    node_index: usize,
}

impl Bounded<f64, 3> for BvhTriangle {
    fn aabb(&self) -> Aabb<f64, 3> {
        let [a, b, c] = self.corners;
        Aabb::with_bounds(a, a).grow(&b).grow(&c)
    }
}

impl BHShape<f64, 3> for BvhTriangle {
    fn set_bh_node_index(&mut self, index: usize) {
        self.node_index = index;
    }

    fn bh_node_index(&self) -> usize {
        self.node_index
    }
}

/// A BVH of the `bvh` crate and its triangles.
pub struct BvhCrateBvh {
    bvh: Bvh<f64, 3>,
    triangles: Vec<BvhTriangle>,
}

/// The crate's ray for `ray`.
fn to_bvh(ray: &Ray) -> BvhRay<f64, 3> {
    let (o, d) = (ray.origin, ray.dir);
    BvhRay::new(Point3::new(o.x, o.y, o.z), Vector3::new(d.x, d.y, d.z))
}

impl Contender for BvhCrateBvh {
    type Input = TriangleMesh;

    fn build(mesh: &TriangleMesh) -> Self {
        let corner = |i: u32| {
            let v = mesh.vertices[i as usize];
            Point3::new(v.x, v.y, v.z)
        };
        let mut triangles: Vec<BvhTriangle> = mesh
            .triangles
            .iter()
            .map(|t| BvhTriangle { corners: [corner(t[0]), corner(t[1]), corner(t[2])], node_index: 0 })
            .collect();
        let bvh = Bvh::build_par(&mut triangles);
        BvhCrateBvh { bvh, triangles }
    }

    fn bytes(&self) -> usize {
        std::mem::size_of::<Self>()
            + self.bvh.nodes.capacity() * std::mem::size_of::<BvhNode<f64, 3>>()
            + self.triangles.capacity() * std::mem::size_of::<BvhTriangle>()
    }

    fn node_count(&self) -> usize {
        self.bvh.nodes.len()
    }

    fn surface(&self, hit: SurfaceHit, _ray: &Ray) -> SurfaceHit {
        hit
    }
}

impl RayCast for BvhCrateBvh {
    type Hit = SurfaceHit;

    fn hit(&self, ray: &Ray) -> Option<SurfaceHit> {
        let r = to_bvh(ray);
        let mut best: Option<(f64, &BvhTriangle)> = None;
        for tri in self.bvh.nearest_traverse_iterator(&r, &self.triangles) {
            let limit = best.map_or(ray.t_max, |b| b.0);
            // Leaves come in increasing order of box entry: none after this one can be nearer.
            if r.intersection_slice_for_aabb(&tri.aabb()).is_some_and(|(enter, _)| enter > limit) {
                break;
            }
            let [a, b, c] = &tri.corners;
            let t = r.intersects_triangle(a, b, c).distance;
            if t < limit {
                best = Some((t, tri));
            }
        }
        let (t, tri) = best?;
        let [a, b, c] = tri.corners;
        let n = (b - a).cross(&(c - a)).normalize();
        let n = DVec3::new(n.x, n.y, n.z);
        Some(SurfaceHit { t, normal: if n.dot(ray.dir) > 0.0 { -n } else { n } })
    }

    fn occluded(&self, ray: &Ray) -> bool {
        let r = to_bvh(ray);
        self.bvh.traverse_iterator(&r, &self.triangles).any(|tri| {
            let [a, b, c] = &tri.corners;
            r.intersects_triangle(a, b, c).distance < ray.t_max
        })
    }
}
