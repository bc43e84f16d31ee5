//! Scenes: what a picture shows. Solids ([`SceneSolid`]: a linear octree, its
//! traversal octree, its material, the shape it came from and the caches rays fill:
//! the 64-tree for the kinds of rays routed to it (`cast`), the complement's traversal for rays
//! inside, the octree's normal estimate), their materials and textures, lights, ambient
//! light and background. A ray is cast for a purpose ([`Cast`]), which picks the
//! structure each solid walks it through.

mod cast;
mod crossing_normals;
mod default_scene;
mod gradient;
mod light;
mod material;
mod normal_field;
mod occupancy;
mod section;
mod texture;
mod thread_cache;

use cast::LazyTree64;
pub use cast::{Cast, Walker};
use crossing_normals::CrossingNormals;
pub use light::Light;
pub use material::{Bump, Material};
pub(crate) use normal_field::NormalField;
pub use section::Section;
pub use texture::{Mapping, Texture};

use std::sync::{Arc, OnceLock};

use glam::DVec3;

use super::trace::{Hit, PACKET, Traversal};
use crate::aabb::Aabb;
use crate::octree::LinearOctree;
use crate::ray::{Ray, RayCast};
use crate::shape::{Axis, Shape, Surface};
use crate::surface::HermiteData;

/// One solid of a scene with its material and traversal structure.
#[derive(Clone, Debug)]
pub struct SceneSolid {
    /// A name for messages.
    pub name: String,
    /// The solid.
    pub tree: LinearOctree,
    /// Its traversal octree.
    pub traversal: Traversal,
    /// Its material.
    pub material: Material,
    /// Its 64-tree, built on first use by the kinds of rays routed to it (`cast`).
    tree64: LazyTree64,
    /// The complement's traversal octree, built on first use: rays inside the solid
    /// (refraction) leave it where they enter the complement.
    interior: OnceLock<Traversal>,
    /// Its smooth normals, estimated where rays ask for them.
    normals: NormalField,
    /// The shape it was voxelized from, when it came from one.
    source: Option<Source>,
    /// Its surface data, when it has some (a file's crossings).
    crossings: Option<CrossingNormals>,
}

/// A solid's source shape (shapes need not be `Debug`).
#[derive(Clone)]
struct Source(Arc<dyn Shape>);

impl std::fmt::Debug for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Source(shape)")
    }
}

impl SceneSolid {
    /// The structure that walks rays cast for `cast` through this solid (see
    /// [`Cast`]; the 64-tree is built on the first ray that takes it).
    #[must_use]
    pub fn walker(&self, cast: Cast) -> Walker<'_> {
        if cast.takes_tree64() { Walker::Tree64(self.tree64.get(&self.tree)) } else { Walker::Octree(&self.traversal) }
    }

    /// Where `ray`, starting inside the solid, leaves it: the hit of the first empty
    /// voxel it enters (`axis` its face). `None` when it leaves through the domain's
    /// boundary first.
    #[must_use]
    pub fn exit(&self, ray: &Ray) -> Option<Hit> {
        self.interior.get_or_init(|| Traversal::new(&self.tree.complement())).hit(ray)
    }

    /// The source shape's surface seen from `p` when it lies within two voxels of
    /// `p` (smooth normals come from it there).
    pub(crate) fn shape_surface(&self, p: DVec3) -> Option<Surface> {
        let s = self.source.as_ref()?.0.surface(p)?;
        (s.distance.abs() <= 2.0 * self.tree.domain().voxel_size()).then_some(s)
    }

    /// Gives the solid its surface data (the crossings of its boundary faces, as an
    /// `.oct` file carries them, [`crate::SolidFile::surface`]): smooth normals then
    /// come from them where the solid has no source shape. Empty data changes nothing.
    pub fn set_surface(&mut self, surface: HermiteData) {
        self.crossings = (!surface.is_empty()).then(|| CrossingNormals::new(surface));
    }

    /// The normal of the solid's surface data at the surface point `p`, `None`
    /// without data near `p`.
    pub(crate) fn crossing_normal(&self, p: DVec3) -> Option<DVec3> {
        self.crossings.as_ref()?.normal(self.tree.domain(), p)
    }

    /// The shape it was voxelized from, when it came from one.
    pub(crate) fn shape(&self) -> Option<&dyn Shape> {
        self.source.as_ref().map(|s| &*s.0)
    }

    /// The octree's estimate of the outward normal at the surface point `p`, `None`
    /// where the occupancy has no gradient.
    pub(crate) fn estimated_normal(&self, p: DVec3) -> Option<DVec3> {
        self.normals.normal(&self.tree, p)
    }
}

/// Light already worked out on the solids' surfaces, view-independent (a radiosity
/// solution, `render::radiosity`): where a scene has one, the shading stage shows it
/// in place of the local Phong term, and mirrors and glass still trace on top of it.
pub trait Illumination: Send + Sync + std::fmt::Debug {
    /// The outgoing radiance (linear RGB) at the surface point `p` of solid `solid`,
    /// on the voxel face of outward unit axis normal `face`; `None` where it knows
    /// none.
    fn radiance(&self, solid: usize, p: DVec3, face: DVec3) -> Option<DVec3>;
}

/// Everything a picture shows (the camera is separate).
#[derive(Clone, Debug)]
pub struct Scene {
    /// The solids.
    pub solids: Vec<SceneSolid>,
    /// The lights.
    pub lights: Vec<Light>,
    /// Ambient light intensity `Ia` (linear RGB).
    pub ambient: DVec3,
    /// Colour where rays hit nothing (linear RGB).
    pub background: DVec3,
    /// Precomputed diffuse light shown in place of the local term (radiosity), if any.
    pub illumination: Option<Arc<dyn Illumination>>,
}

/// What a primary ray sees: the solid, and the hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SceneHit {
    /// Index of the solid.
    pub solid: usize,
    /// The hit in that solid.
    pub hit: Hit,
}

impl Scene {
    /// An empty scene with no lights.
    #[must_use]
    pub fn new() -> Self {
        Scene {
            solids: Vec::new(),
            lights: Vec::new(),
            ambient: DVec3::splat(1.0),
            background: DVec3::new(0.92, 0.93, 0.95),
            illumination: None,
        }
    }

    /// A scene of the one solid `tree`, as `octsolid render solid.oct` shows it: the
    /// default material, [`Scene::default_lights`] around its bounds (no light for an
    /// empty solid), the default ambient light and background. Smooth normals come from
    /// the octree's estimate (there is no shape; use [`Scene::add_shaped`] for one).
    #[must_use]
    pub fn from_solid(tree: LinearOctree) -> Self {
        let mut scene = Scene::new();
        scene.lights = tree.bounds().map(|b| Scene::default_lights(&b)).unwrap_or_default();
        scene.add("solid", tree, Material::default());
        scene
    }

    /// Adds a solid (its traversal octree is built here).
    pub fn add(&mut self, name: impl Into<String>, tree: LinearOctree, material: Material) {
        let traversal = Traversal::new(&tree);
        self.solids.push(SceneSolid {
            name: name.into(),
            tree,
            traversal,
            material,
            tree64: LazyTree64::default(),
            interior: OnceLock::new(),
            normals: NormalField::new(),
            source: None,
            crossings: None,
        });
    }

    /// Adds a solid voxelized from `shape`, whose surface gives its smooth normals.
    pub fn add_shaped(
        &mut self,
        name: impl Into<String>,
        tree: LinearOctree,
        material: Material,
        shape: Arc<dyn Shape>,
    ) {
        self.add(name, tree, material);
        self.solids.last_mut().expect("just added").source = Some(Source(shape));
    }

    /// A section view: every solid cut to its part at or below `at` along `axis` (the
    /// plane snapped to the nearest plane of each solid's voxel lattice), so the cut
    /// face shows as a filled cap; ambient light and background unchanged, the lights
    /// too, and when none of them reaches the cap's side one more that does; no
    /// precomputed illumination (a radiosity solution is of the whole solids).
    /// Smooth normals still come from a solid's shape or surface data near its surface, and from the
    /// cut octree's estimate (the plane's exact normal on the flat cap) elsewhere.
    #[must_use]
    pub fn sectioned(&self, axis: Axis, at: f64) -> Scene {
        let solids = self
            .solids
            .iter()
            .map(|s| {
                let d = s.tree.domain();
                let voxels = ((at - d.min()[axis.index()]) * d.voxels_per_unit()).round();
                let plane = voxels.clamp(0.0, f64::from(d.resolution())) as u32;
                let tree = s.tree.below_plane(axis, plane);
                SceneSolid {
                    name: s.name.clone(),
                    traversal: Traversal::new(&tree),
                    tree,
                    material: s.material.clone(),
                    tree64: LazyTree64::default(),
                    interior: OnceLock::new(),
                    normals: NormalField::new(),
                    source: s.source.clone(),
                    crossings: s.crossings.clone(),
                }
            })
            .collect();
        // The cap faces +axis: when no light reaches that side (the scene's lights
        // lit the part from where the cut took it away), one comes from the cap's
        // side, a little from the side so the cut's steps show.
        let cap = axis.unit();
        let reaches_cap = |light: &Light| match *light {
            Light::Point { position, .. } => position[axis.index()] > at,
            Light::Directional { direction, .. } => direction.dot(cap) < 0.0,
        };
        let mut lights = self.lights.clone();
        if !lights.iter().any(reaches_cap) {
            let side = DVec3::new(cap.y + cap.z, cap.z + cap.x, cap.x + cap.y) * 0.35;
            lights.push(Light::Directional { direction: -(cap + side), color: DVec3::splat(0.7) });
        }
        // A light solution belongs to the whole solids: the cut scene has none.
        Scene { solids, lights, ambient: self.ambient, background: self.background, illumination: None }
    }

    /// Bounds of all solids, `None` when every solid is empty.
    #[must_use]
    pub fn bounds(&self) -> Option<Aabb> {
        self.solids.iter().filter_map(|s| s.tree.bounds()).reduce(|a, b| a.union(&b))
    }

    /// [`RayCast::hit`] of every ray of a packet, bit for bit, one
    /// [`Traversal::hit_packet`] a solid (fast for a tile of primary rays).
    ///
    /// # Panics
    /// When `rays` and `hits` differ in length.
    pub fn hit_packet(&self, rays: &[Ray], hits: &mut [Option<SceneHit>]) {
        assert_eq!(rays.len(), hits.len(), "a packet's slices differ in length");
        hits.fill(None);
        let mut limited = [Ray::new(DVec3::ZERO, DVec3::ZERO); PACKET];
        let mut found = [None; PACKET];
        for (rays, hits) in rays.chunks(PACKET).zip(hits.chunks_mut(PACKET)) {
            let (limited, found) = (&mut limited[..rays.len()], &mut found[..rays.len()]);
            for (i, s) in self.solids.iter().enumerate() {
                // Each ray only as far as the nearest hit in the solids before.
                for ((limited, ray), best) in limited.iter_mut().zip(rays).zip(hits.iter()) {
                    *limited = ray.until(best.map_or(ray.t_max, |b| b.hit.t));
                }
                s.traversal.hit_packet(limited, found);
                for (best, hit) in hits.iter_mut().zip(found.iter()) {
                    if let Some(hit) = *hit {
                        *best = Some(SceneHit { solid: i, hit });
                    }
                }
            }
        }
    }

    /// Two white lights (a key light from the default view side and a dim fill light
    /// from the other side), for solids rendered without a scene file.
    #[must_use]
    pub fn default_lights(bounds: &Aabb) -> Vec<Light> {
        let c = bounds.center();
        let r = bounds.size().length().max(1e-12);
        vec![
            Light::Point { position: c + DVec3::new(1.2, -1.0, 2.0) * r, color: DVec3::splat(0.85) },
            Light::Directional { direction: DVec3::new(1.0, 0.6, 0.5), color: DVec3::splat(0.25) },
        ]
    }
}

impl Default for Scene {
    fn default() -> Self {
        Scene::new()
    }
}

impl Scene {
    /// The nearest hit over all solids (ties: the first solid) of a ray cast for
    /// `cast`, each solid walked by [`SceneSolid::walker`].
    #[must_use]
    pub fn hit_as(&self, ray: &Ray, cast: Cast) -> Option<SceneHit> {
        let mut best: Option<SceneHit> = None;
        for (i, s) in self.solids.iter().enumerate() {
            let limit = best.map_or(ray.t_max, |b| b.hit.t);
            if let Some(hit) = s.walker(cast).hit(&ray.until(limit)) {
                best = Some(SceneHit { solid: i, hit });
            }
        }
        best
    }

    /// Whether any solid blocks a ray cast for `cast`, each solid walked by
    /// [`SceneSolid::walker`].
    #[must_use]
    pub fn occluded_as(&self, ray: &Ray, cast: Cast) -> bool {
        self.solids.iter().any(|s| s.walker(cast).occluded(ray))
    }
}

/// The nearest hit over all solids (ties: the first solid) as a camera ray's
/// ([`Cast::Primary`]), and whether any solid blocks the ray as a shadow ray's
/// ([`Cast::Shadow`]).
impl RayCast for Scene {
    type Hit = SceneHit;

    fn hit(&self, ray: &Ray) -> Option<SceneHit> {
        self.hit_as(ray, Cast::Primary)
    }

    fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_as(ray, Cast::Shadow)
    }
}
