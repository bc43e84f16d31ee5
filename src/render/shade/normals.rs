//! Shading normals. [`Normals::Axis`] is the entered face's axis normal;
//! [`Normals::Smooth`] the source shape's normal where there is one (within two voxels
//! of the hit), else the solid's surface data's (`scene::CrossingNormals`, a file's
//! crossings), else (and always with [`Normals::Octree`]) the octree's occupancy
//! gradient (`scene::NormalField`); a smooth normal falls back to the axis normal
//! where it would face away from the viewer. A material's bump map then tilts it.

use glam::DVec3;

use crate::ray::Ray;
use crate::render::scene::{Scene, SceneHit, SceneSolid};
use crate::render::trace::Hit;

/// Which normal shades a surface. Scene files write it in snake case (`normals =
/// "smooth"`). The default is [`Normals::Smooth`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Normals {
    /// The entered voxel face's axis normal (exact for the voxel solid; curved
    /// surfaces show the voxel staircase as rings).
    Axis,
    /// The source shape's normal where the solid was voxelized from a shape that
    /// knows its surface ([`crate::shape::Shape::surface`]) and the hit lies within
    /// two voxels of that surface; else the normals of the solid's surface data (a
    /// file's crossings, [`crate::render::SceneSolid::set_surface`]); else the octree's
    /// estimate. The default.
    #[default]
    Smooth,
    /// Estimated from the octree's occupancy around the hit (`scene::NormalField`).
    Octree,
}

impl Normals {
    /// Every value, in the order `--help` lists them.
    pub const ALL: [Normals; 3] = [Normals::Axis, Normals::Smooth, Normals::Octree];

    /// The value's one spelling (the command line's, a scene file's, `Display`'s).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Normals::Axis => "axis",
            Normals::Smooth => "smooth",
            Normals::Octree => "octree",
        }
    }
}

crate::spelling::spelled!(Normals);

/// The smooth surface at the surface point `p` of `solid` under the normals `mode`:
/// the outward normal and the point where textures are looked up. With
/// [`Normals::Smooth`] and a source shape whose surface lies within two voxels of `p`:
/// the shape's normal, and `p` moved onto that surface (`p - d n`), so pictures do not
/// follow the voxel staircase. Else the octree's estimate (`None` without a gradient,
/// and always with [`Normals::Axis`]) at `p` itself.
#[must_use]
pub fn smooth_at(solid: &SceneSolid, p: DVec3, mode: Normals) -> (Option<DVec3>, DVec3) {
    if mode == Normals::Axis {
        return (None, p);
    }
    if mode == Normals::Smooth {
        if let Some(s) = solid.shape_surface(p) {
            return (Some(s.normal), p - s.normal * s.distance);
        }
        if let Some(n) = solid.crossing_normal(p) {
            return (Some(n), p);
        }
    }
    (solid.estimated_normal(p), p)
}

/// The axis of the hit's face that is the solid's boundary. A ray that enters a voxel
/// through an edge or a corner crosses several voxel planes at once, and the walk
/// names the lowest axis ([`Hit::axis`]); where the voxel across that face is full (a
/// ray meeting a floor exactly on the edge between two of its voxels is "entering"
/// the floor through the wall between them), the face that shades is another of the
/// planes crossed, one with an empty voxel across it: the face the ray can see.
/// `p` is the hit point. Only edge and corner hits pay the voxel lookups.
fn boundary_axis(solid: &SceneSolid, hit: &Hit, dir: DVec3, p: DVec3) -> Option<usize> {
    let a = usize::from(hit.axis?);
    let domain = solid.tree.domain();
    let q = (p - domain.min()) * domain.voxels_per_unit();
    let v = hit.voxel;
    // The plane on axis `b` the ray enters voxel `v` through, when `p` lies on it.
    let on_entry_plane = |b: usize| {
        let plane = if dir[b] > 0.0 { f64::from(v[b]) } else { f64::from(v[b]) + 1.0 };
        dir[b] != 0.0 && (q[b] - plane).abs() < 1e-7
    };
    let others = [(a + 1) % 3, (a + 2) % 3];
    if !others.iter().any(|&b| on_entry_plane(b)) {
        return Some(a);
    }
    // Whether the voxel across the entry face on axis `b` is full (outside the domain:
    // empty).
    let across_is_full = |b: usize| {
        let mut c = v;
        if dir[b] > 0.0 {
            if c[b] == 0 {
                return false;
            }
            c[b] -= 1;
        } else {
            c[b] += 1;
            if c[b] >= domain.resolution() {
                return false;
            }
        }
        solid.tree.contains_voxel(c)
    };
    if !across_is_full(a) {
        return Some(a);
    }
    Some(others.into_iter().find(|&b| on_entry_plane(b) && !across_is_full(b)).unwrap_or(a))
}

/// The geometric and the shading normal at a hit of the ray direction `dir`, both unit
/// and facing the ray (for a hit with no face, the origin inside: `-dir`), from the
/// raw smooth estimate `smooth` (outward; `None` with axis normals). The geometric
/// normal is that of the boundary face the ray enters ([`boundary_axis`]).
#[must_use]
fn normals_at(solid: &SceneSolid, hit: &Hit, dir: DVec3, p: DVec3, smooth: Option<DVec3>) -> (DVec3, DVec3) {
    let geometric = match boundary_axis(solid, hit, dir, p) {
        Some(a) => {
            let mut n = DVec3::ZERO;
            n[a] = -dir[a].signum();
            n
        }
        None => -dir,
    };
    let shading = smooth.filter(|n| n.dot(dir) < 0.0).unwrap_or(geometric);
    let shading = match &solid.material.bump {
        Some(bump) => bump.perturb(p, shading),
        None => shading,
    };
    (geometric, shading)
}

/// A shaded point: where a ray of direction `dir` hit solid `solid`, with the
/// geometric and shading normals of `normals_at`.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// Index of the solid.
    pub solid: usize,
    /// The point.
    pub p: DVec3,
    /// Unit direction of the arriving ray.
    pub dir: DVec3,
    /// The face's axis normal, facing the ray.
    pub geometric: DVec3,
    /// The normal that shades.
    pub normal: DVec3,
    /// The smooth estimate of the outward normal, when smooth normals are on.
    pub smooth: Option<DVec3>,
    /// Where the material's texture is looked up ([`smooth_at`]).
    pub texture_at: DVec3,
    /// Whether `texture_at` lies on the source shape's surface (else it is the point
    /// on the voxel face, up to half a voxel diagonal off the smooth surface).
    pub on_shape: bool,
}

impl SurfacePoint {
    /// The point where `ray` (unit direction) hits `sh`.
    #[must_use]
    pub fn new(scene: &Scene, ray: &Ray, sh: &SceneHit, mode: Normals) -> Self {
        let (p, dir) = (ray.at(sh.hit.t), ray.dir);
        let solid = &scene.solids[sh.solid];
        let (smooth, texture_at) = smooth_at(solid, p, mode);
        let (geometric, normal) = normals_at(solid, &sh.hit, dir, p, smooth);
        let on_shape = texture_at != p;
        SurfacePoint { solid: sh.solid, p, dir, geometric, normal, smooth, texture_at, on_shape }
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::octree::{Domain, VoxelizeOptions, voxelize};
    use crate::ray::RayCast;
    use crate::render::ShadeOptions;
    use crate::render::scene::Material;
    use crate::shape::Sphere;
    use crate::test_util::Rng;

    /// The angles in degrees between the default shading normal and the sphere's own,
    /// `(p - c) / |p - c|`, at the hits of rays from all around aimed near the centre,
    /// for the hits where the sphere's normal faces the ray (others take the axis
    /// normal by design), sorted.
    fn angles_at_hits(scene: &Scene, center: DVec3) -> Vec<f64> {
        let mode = ShadeOptions::default().normals;
        let mut rng = Rng(8);
        let mut angles = Vec::new();
        while angles.len() < 10_000 {
            let dir = rng.vec(-1.0, 1.0);
            if !(0.1..1.0).contains(&dir.length()) {
                continue;
            }
            let ray = Ray::new(center - dir.normalize() * 3.0 + rng.vec(-0.4, 0.4), dir.normalize());
            let Some(sh) = scene.hit(&ray) else { continue };
            let s = SurfacePoint::new(scene, &ray, &sh, mode);
            let want = (s.p - center).normalize();
            if want.dot(ray.dir) < -0.2 {
                angles.push(s.normal.angle_between(want).to_degrees());
            }
        }
        angles.sort_by(f64::total_cmp);
        angles
    }

    #[test]
    fn the_default_shading_normal_of_a_sphere_is_the_spheres() {
        let center = DVec3::new(0.013, -0.021, 0.007);
        let sphere = Sphere::new(center, 0.8).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 9).unwrap();
        let tree = voxelize(&sphere, domain, &VoxelizeOptions::default()).unwrap();
        // Voxelized from the shape: the shape's own normal at the hit, to rounding.
        let mut shaped = Scene::new();
        shaped.add_shaped("sphere", tree.clone(), Material::default(), Arc::new(sphere));
        let angles = angles_at_hits(&shaped, center);
        assert!(angles[angles.len() - 1] < 1e-5, "worst {} degrees", angles[angles.len() - 1]);
        // The octree alone: its estimate, within a few degrees (see scene::normal_field).
        let mut bare = Scene::new();
        bare.add("sphere", tree, Material::default());
        let angles = angles_at_hits(&bare, center);
        let (median, p95) = (angles[angles.len() / 2], angles[angles.len() * 95 / 100]);
        assert!(median < 0.8 && p95 < 3.0, "median {median}, 95% {p95} degrees");
    }

    /// A solid with surface data and no shape (as read from an `.oct` file) shades
    /// with its crossings' normals: at depth 7 within a fraction of a degree of the
    /// sphere's own (median 0.25, worst 0.7), over twice as close as the octree's
    /// estimate (median 0.68); a thin wall's far side does not turn them.
    #[test]
    fn a_solid_with_surface_data_shades_with_its_crossings_normals() {
        let center = DVec3::new(0.013, -0.021, 0.007);
        let sphere = Sphere::new(center, 0.8).unwrap();
        let domain = Domain::new(DVec3::splat(-1.0), 2.0, 7).unwrap();
        let tree = voxelize(&sphere, domain, &VoxelizeOptions::default()).unwrap();
        let mut with_data = Scene::new();
        with_data.add("sphere", tree.clone(), Material::default());
        with_data.solids[0].set_surface(crate::surface::HermiteData::from_shape(&sphere, &tree));
        let angles = angles_at_hits(&with_data, center);
        let (median, worst) = (angles[angles.len() / 2], angles[angles.len() - 1]);
        let mut bare = Scene::new();
        bare.add("sphere", tree, Material::default());
        let estimated = angles_at_hits(&bare, center);
        let estimated_median = estimated[estimated.len() / 2];
        assert!(median < 0.4 && worst < 2.0, "median {median}, worst {worst} degrees");
        assert!(median * 2.0 < estimated_median, "median {median} against the estimate's {estimated_median}");

        // A plate one voxel thick (voxel 1/64): its top shades straight up.
        let plate = crate::shape::Cuboid::new(DVec3::new(0.0, 0.0, 0.004), DVec3::new(1.0, 1.0, 0.01)).unwrap();
        let tree = voxelize(&plate, domain, &VoxelizeOptions::default()).unwrap();
        let mut scene = Scene::new();
        scene.add("plate", tree.clone(), Material::default());
        scene.solids[0].set_surface(crate::surface::HermiteData::from_shape(&plate, &tree));
        let ray = Ray::new(DVec3::new(0.11, 0.07, 1.0), DVec3::NEG_Z);
        let sh = scene.hit(&ray).expect("the plate is hit");
        let s = SurfacePoint::new(&scene, &ray, &sh, Normals::Smooth);
        assert!(s.normal.angle_between(DVec3::Z) < 1e-3, "top normal {}", s.normal);
    }

    /// The bundled Cornell box seen through its own camera at 512x512: its eye lies on
    /// a voxel plane and its floor and the short block's top on others, so rows and
    /// columns of rays meet them exactly on voxel edges, where the walk names the
    /// lowest axis crossed. The face that shades must be one the ray can see: the
    /// voxel across it empty (the walls between the floor's voxels showed as a dark
    /// seam across the block's top and specks along its base, where radiosity found
    /// no patch on them).
    #[test]
    fn the_shaded_face_of_a_hit_on_a_voxel_edge_is_a_boundary_face() {
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/cornell.toml");
        let file = crate::scene_file::read_scene(path, crate::MemoryBudget::default()).unwrap();
        let view = file.camera.view(1.0);
        let (mut edges, mut checked) = (0, 0);
        for row in 0..512 {
            for col in 0..512 {
                let ray = view.ray((f64::from(col) + 0.5) / 256.0 - 1.0, 1.0 - (f64::from(row) + 0.5) / 256.0);
                let Some(sh) = file.scene.hit(&ray) else { continue };
                let solid = &file.scene.solids[sh.solid];
                let s = SurfacePoint::new(&file.scene, &ray, &sh, Normals::Axis);
                let a = (0..3).find(|&a| s.geometric[a] != 0.0).unwrap();
                let mut across = sh.hit.voxel;
                if s.geometric[a] > 0.0 {
                    across[a] += 1;
                } else {
                    across[a] = across[a].wrapping_sub(1);
                }
                let inside = across[a] < solid.tree.domain().resolution();
                assert!(
                    !(inside && solid.tree.contains_voxel(across)),
                    "row {row}, column {col}: a face between full voxels"
                );
                checked += 1;
                edges += usize::from(Some(a as u8) != sh.hit.axis);
            }
        }
        assert!(checked > 200_000 && edges > 50, "{checked} hits, {edges} on voxel edges");
    }
}
