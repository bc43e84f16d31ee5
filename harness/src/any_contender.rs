//! A contender chosen at run time by its [`ContenderKind`]: the section of issue 41's
//! rays and `walk_one` build one from its name and trace ray sets through it without
//! knowing its type. A new structure joins by a [`ContenderKind`] variant (its label and
//! [`ContenderKind::slug`]) and one arm in [`build_contender`].

use octsolid::mesh::TriangleMesh;
use octsolid::octree::LinearOctree;
use octsolid::render::{Traversal, Tree64};

use super::bvh_contender::BvhCrateBvh;
use super::contender::Contender;
#[cfg(feature = "embree")]
use super::embree_contender::{self, EmbreeBvh, EmbreePackets};
use super::matrix::ContenderKind;
use super::obvhs_contender::ObvhsBvh;
use super::rays::RaySet;

/// A built contender, its type erased.
pub trait Traced: Send + Sync {
    /// Traces `rays` in the current rayon pool; the number that hit (closest hits, or
    /// occluded shadow rays). See [`Contender::trace`].
    fn trace_set(&self, rays: &RaySet) -> u64;

    /// Bytes of the structure ([`Contender::bytes`]).
    fn structure_bytes(&self) -> usize;
}

impl<C: Contender> Traced for C {
    fn trace_set(&self, rays: &RaySet) -> u64 {
        self.trace(rays)
    }

    fn structure_bytes(&self) -> usize {
        self.bytes()
    }
}

/// What contenders are built from: the solid, its boundary faces, the source mesh.
#[derive(Clone, Copy)]
pub struct Inputs<'a> {
    /// The solid (the octree contenders).
    pub tree: &'a LinearOctree,
    /// Its boundary faces (`mesh::boundary_mesh`), for the BVHs over them.
    pub faces: &'a TriangleMesh,
    /// The mesh it was voxelized from, if any.
    pub mesh: Option<&'a TriangleMesh>,
}

/// Builds contender `kind` (in the current rayon pool), or says why it cannot be built
/// in this binary (Embree's without the `embree` feature or without a device, an
/// original-mesh contender without a mesh).
pub fn build_contender(kind: ContenderKind, inputs: Inputs<'_>) -> Result<Box<dyn Traced>, String> {
    let mesh = || inputs.mesh.ok_or_else(|| format!("{}: the solid has no source mesh", kind.label()));
    #[cfg(feature = "embree")]
    let embree = |m: &TriangleMesh, packets: bool| -> Result<Box<dyn Traced>, String> {
        embree_contender::available().clone()?;
        let bvh = EmbreeBvh::try_build(m)?;
        Ok(if packets { Box::new(EmbreePackets(bvh)) } else { Box::new(bvh) })
    };
    match kind {
        ContenderKind::Octree => Ok(Box::new(Traversal::build(inputs.tree))),
        ContenderKind::Tree64 => Ok(Box::new(Tree64::build(inputs.tree))),
        ContenderKind::ObvhsFaces => Ok(Box::new(ObvhsBvh::build(inputs.faces))),
        ContenderKind::BvhFaces => Ok(Box::new(BvhCrateBvh::build(inputs.faces))),
        ContenderKind::ObvhsMesh => Ok(Box::new(ObvhsBvh::build(mesh()?))),
        ContenderKind::BvhMesh => Ok(Box::new(BvhCrateBvh::build(mesh()?))),
        #[cfg(feature = "embree")]
        ContenderKind::EmbreeFaces => embree(inputs.faces, false),
        #[cfg(feature = "embree")]
        ContenderKind::EmbreePacketsFaces => embree(inputs.faces, true),
        #[cfg(feature = "embree")]
        ContenderKind::EmbreeMesh => embree(mesh()?, false),
        #[cfg(feature = "embree")]
        ContenderKind::EmbreePacketsMesh => embree(mesh()?, true),
        #[cfg(not(feature = "embree"))]
        ContenderKind::EmbreeFaces
        | ContenderKind::EmbreePacketsFaces
        | ContenderKind::EmbreeMesh
        | ContenderKind::EmbreePacketsMesh => {
            Err(format!("{} needs the harness's `embree` feature (--features embree)", kind.label()))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rays::RayKind;
    use crate::secondary_rays::{SEED, secondary_rays};
    use glam::DVec3;
    use octsolid::mesh::{BoundaryOptions, boundary_mesh};
    use octsolid::octree::{Domain, VoxelizeOptions, voxelize};
    use octsolid::shape::Menger;
    use octsolid::{Aabb, RayCast};

    #[test]
    fn contenders_by_name_answer_the_secondary_rays_as_the_octree_does() {
        // A level-2 Menger sponge at depth 6 (holes, so bounce and shadow rays hit it
        // again): its boundary faces are the octree's surface, so every contender
        // over them must find the octree's hits (an f32 BVH may slip through an edge
        // now and then: at most 1 ray in 200).
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 6).unwrap();
        let tree = voxelize(&Menger::new(DVec3::ZERO, 1.8, 2).unwrap(), domain, &VoxelizeOptions::default()).unwrap();
        let faces = boundary_mesh(&tree, &BoundaryOptions::default());
        let octree = Traversal::new(&tree);
        let rays = secondary_rays(&octree, &Aabb::new(DVec3::splat(-0.9), DVec3::splat(0.9)), 256, SEED);
        let inputs = Inputs { tree: &tree, faces: &faces, mesh: None };
        let mut kinds = vec![ContenderKind::Octree, ContenderKind::Tree64, ContenderKind::ObvhsFaces];
        if cfg!(feature = "embree") {
            kinds.push(ContenderKind::EmbreeFaces);
        }
        for set in rays.sets() {
            let any = set.kind == RayKind::Shadow;
            let expected =
                set.rays.iter().filter(|r| if any { octree.occluded(r) } else { octree.hit(r).is_some() }).count()
                    as u64;
            assert!(expected > 0, "{}: nothing hit", set.kind.name());
            for &kind in &kinds {
                let c = build_contender(kind, inputs).unwrap();
                let got = c.trace_set(set);
                assert!(
                    got.abs_diff(expected) * 200 <= expected,
                    "{} {}: {got} against {expected}",
                    kind.slug(),
                    set.kind.name()
                );
            }
        }
        let no_mesh = build_contender(ContenderKind::ObvhsMesh, inputs).err().unwrap();
        assert!(no_mesh.contains("no source mesh"), "{no_mesh}");
        assert_eq!(ContenderKind::from_slug("embree-mesh"), Some(ContenderKind::EmbreeMesh));
        assert!(ContenderKind::ALL.iter().all(|&k| ContenderKind::from_slug(k.slug()) == Some(k)));
    }
}
