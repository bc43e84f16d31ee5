//! What a ray is cast for, and so which of a solid's two ray structures walks it: the
//! traversal octree ([`Traversal`], built with the solid) or the 64-tree ([`Tree64`],
//! 4x4x4 nodes, built on the first ray that asks for it). Both find the same hits bit
//! for bit (`trace::tree64`), so the choice changes speed only, never a picture.
//!
//! The choice (issue 41: the 64-tree where it is measured at least 5% faster): none
//! today. On the bunny at depth 10, one thread (`walk_one`), the 64-tree takes 0.91x
//! to 0.94x the octree's time on bounce rays leaving the surface and 0.89x on shadow
//! rays starting at it, but 1.06x on shadow rays starting a few voxels off it and
//! 1.25x on primary rays; in whole workloads, with every bounce and shadow ray routed
//! to it (A/B in one sitting, both cores, CPU time, identical pictures and `.rad`
//! files), the Whitted classic took 1.15x the octree's CPU time (1.12x without
//! shadows) and the turned Cornell box's radiosity 1.05x (BENCHMARKS.md, "Ray traversal
//! and visibility"). So every kind walks the octree, and [`Cast::takes_tree64`] is the one
//! switch to turn when a faster 64-tree walk is measured ahead. Rays walking the inside
//! of a solid (refraction, [`super::SceneSolid::exit`]) walk the complement's octree.

use std::sync::OnceLock;

use crate::octree::LinearOctree;
use crate::ray::{Ray, RayCast};
use crate::render::trace::{Hit, Traversal, Tree64};

/// What a ray is cast for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cast {
    /// Camera rays: coherent, from outside the solids.
    Primary,
    /// Rays leaving a surface for the closest hit or a point in view: Whitted's
    /// reflected and refracted rays, radiosity's form factor visibility.
    Bounce,
    /// Rays from a surface point to a light, any hit.
    Shadow,
}

impl Cast {
    /// Whether the 64-tree walks rays of this kind: none measured faster in whole
    /// workloads yet (see the module doc).
    #[must_use]
    pub const fn takes_tree64(self) -> bool {
        match self {
            Cast::Primary | Cast::Bounce | Cast::Shadow => false,
        }
    }
}

/// The structure one solid walks a ray through: its traversal octree or its 64-tree.
#[derive(Clone, Copy, Debug)]
pub enum Walker<'a> {
    /// The traversal octree.
    Octree(&'a Traversal),
    /// The 64-tree.
    Tree64(&'a Tree64),
}

impl RayCast for Walker<'_> {
    type Hit = Hit;

    #[inline]
    fn hit(&self, ray: &Ray) -> Option<Hit> {
        match self {
            Walker::Octree(t) => t.hit(ray),
            Walker::Tree64(t) => t.hit(ray),
        }
    }

    #[inline]
    fn occluded(&self, ray: &Ray) -> bool {
        match self {
            Walker::Octree(t) => t.occluded(ray),
            Walker::Tree64(t) => t.occluded(ray),
        }
    }
}

/// A solid's 64-tree, built once on first use (threads asking meanwhile wait for it).
#[derive(Clone, Debug, Default)]
pub(super) struct LazyTree64(OnceLock<Tree64>);

impl LazyTree64 {
    /// The 64-tree of `tree`, built now if it is not yet.
    pub fn get(&self, tree: &LinearOctree) -> &Tree64 {
        self.0.get_or_init(|| Tree64::new(tree))
    }
}

#[cfg(test)]
mod tests {
    use glam::DVec3;

    use super::*;
    use crate::octree::{Domain, VoxelizeOptions, voxelize};
    use crate::render::scene::{Material, Scene};
    use crate::samples::classic_csg;
    use crate::shape::Menger;
    use crate::test_util::Rng;

    /// A scene cast any way finds the hits of the traversal octree's walk (itself
    /// checked against brute force in `trace`), bit for bit: two solids (the classic
    /// part at an even depth, a Menger sponge at an odd one, overlapping), rays from
    /// everywhere in and around them, unbounded and ending inside.
    #[test]
    fn every_cast_finds_the_octree_walks_hits() {
        let mut scene = Scene::new();
        let part = Domain::new(DVec3::splat(-1.1), 2.2, 6).unwrap();
        scene.add("part", voxelize(&classic_csg(), part, &VoxelizeOptions::default()).unwrap(), Material::default());
        let sponge = Domain::new(DVec3::new(-0.5, -2.0, -1.0), 2.5, 7).unwrap();
        let menger = Menger::new(DVec3::new(0.5, -0.8, 0.2), 2.0, 3).unwrap();
        scene.add("sponge", voxelize(&menger, sponge, &VoxelizeOptions::default()).unwrap(), Material::default());
        let lazy: Vec<LazyTree64> = scene.solids.iter().map(|_| LazyTree64::default()).collect();
        let mut rng = Rng(0x41_64_7e_e5);
        let (mut hits, mut blocked) = (0, 0);
        for i in 0..4000 {
            let origin = rng.vec(-2.5, 2.5);
            let dir = (rng.vec(-1.0, 1.0) + DVec3::new(1e-9, 0.0, 0.0)).normalize();
            let t_max = if i % 2 == 0 { f64::INFINITY } else { rng.range(0.0, 4.0) };
            let ray = Ray::segment(origin, dir, t_max);
            let octree: Option<(usize, Hit)> = scene
                .solids
                .iter()
                .enumerate()
                .filter_map(|(k, s)| s.traversal.hit(&ray).map(|h| (k, h)))
                .min_by(|a, b| a.1.t.total_cmp(&b.1.t).then(a.0.cmp(&b.0)));
            let any = scene.solids.iter().any(|s| s.traversal.occluded(&ray));
            for cast in [Cast::Primary, Cast::Bounce, Cast::Shadow] {
                let got = scene.hit_as(&ray, cast).map(|h| (h.solid, h.hit));
                assert_eq!(got, octree, "{cast:?} {ray:?}");
                assert_eq!(scene.occluded_as(&ray, cast), any, "{cast:?} {ray:?}");
            }
            // Through each solid's lazily built 64-tree, as a routed kind walks.
            for (k, (s, lazy)) in scene.solids.iter().zip(&lazy).enumerate() {
                let walker = Walker::Tree64(lazy.get(&s.tree));
                assert_eq!(walker.hit(&ray), s.traversal.hit(&ray), "solid {k} {ray:?}");
                assert_eq!(walker.occluded(&ray), s.traversal.occluded(&ray), "solid {k} {ray:?}");
            }
            hits += usize::from(octree.is_some());
            blocked += usize::from(any);
        }
        assert!(hits > 400 && blocked > 400 && hits < 3600, "{hits} hits, {blocked} blocked of 4000");
    }
}
