//! The scene a solid file is drawn in when no scene file says otherwise, the same for
//! `octsolid render x.oct`, the viewer and [`crate::quick`]: the solid in the default
//! material, lit by [`Scene::default_lights`] around its bounds; in a world whose up is
//! not z, the key light is moved to stand where it stands for z up, above the default
//! view's side of the solid ([`Scene::turn_light_to_up`]). A file of several coloured
//! solids makes its own scene (`io::Solids::scene`), whose key light turns the same
//! way. The framing of a scene's camera for a [`CameraRequest`] is here too
//! ([`Scene::framing`]), since it needs the solids.

use glam::DVec3;

use super::{Light, Material, Scene};
use crate::aabb::Aabb;
use crate::octree::LinearOctree;
use crate::render::film::{Camera, CameraRequest, Framing, Up, silhouette_points};
use crate::shape::Axis;

impl Scene {
    /// The scene of one solid named `name`: the default material and lights, the key
    /// light turned to `up` (see the module doc).
    #[must_use]
    pub fn of_solid(tree: LinearOctree, name: impl Into<String>, up: Up) -> Scene {
        let bounds = tree.bounds();
        let mut scene = Scene::new();
        scene.lights = bounds.map(|b| Scene::default_lights(&b)).unwrap_or_default();
        scene.add(name, tree, Material::default());
        if let Some(bounds) = bounds {
            scene.turn_light_to_up(&bounds, up);
        }
        scene
    }

    /// For an `up` whose axis is not z, moves the first light (the default lights'
    /// key light) to a point light of the default key colour above the default view's
    /// side of `bounds`: the centre plus `(view + 1.5 up) r`, `r` the box's diagonal,
    /// `view` [`Camera::default_view`] of the axis. A scene without lights or with z up
    /// is left as it is.
    pub fn turn_light_to_up(&mut self, bounds: &Aabb, up: Up) {
        if up.axis() == Axis::Z {
            return;
        }
        if let Some(key) = self.lights.first_mut() {
            let (c, r) = (bounds.center(), bounds.size().length());
            let view = Camera::default_view(up.axis());
            *key = Light::Point { position: c + (view + up.vector() * 1.5) * r, color: DVec3::splat(0.85) };
        }
    }

    /// The framing of this scene seen by its file's `camera`: the camera and its up,
    /// and the solids' silhouettes when `request` re-frames it (only then are they
    /// computed).
    #[must_use]
    pub fn framing(&self, camera: Camera, request: &CameraRequest) -> Framing {
        let points = if request.reframes() {
            self.solids.iter().flat_map(|s| silhouette_points(&s.tree)).collect()
        } else {
            Vec::new()
        };
        Framing { points, up: Up::Vector(camera.up), scene_camera: Some(camera) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::octree::Domain;

    fn cube() -> LinearOctree {
        let domain = Domain::new(DVec3::ZERO, 1.0, 2).unwrap();
        LinearOctree::full(domain)
    }

    #[test]
    fn a_solids_key_light_turns_with_up_and_stays_for_z() {
        let z = Scene::of_solid(cube(), "cube", Up::default());
        assert_eq!(z.lights, Scene::default_lights(&cube().bounds().unwrap()));
        let y = Scene::of_solid(cube(), "cube", Up::Axis(Axis::Y));
        let Light::Point { position, .. } = y.lights[0] else { panic!("a point light") };
        let b = cube().bounds().unwrap();
        let expected = b.center() + (Camera::default_view(Axis::Y) + DVec3::Y * 1.5) * b.size().length();
        assert!((position - expected).length() < 1e-12, "{position} vs {expected}");
        assert_eq!(y.lights[1..], z.lights[1..]);
        assert_eq!(y.solids[0].name, "cube");
    }
}
