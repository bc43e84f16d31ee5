//! Camera placement from what a user says: named views, orbit angles, and framing
//! that fills the picture with the object's silhouette.
//!
//! Views are given in a z-up frame and turned with the world for other up axes, as
//! [`Camera::default_view`] does: `front` looks from -y towards +y (the eye on the -y
//! side, OpenSCAD's front), `right` from +x, `top` from +z, `iso` from `(1, -1, 1)`.
//! Orbit angles: azimuth 0 is `front`, positive azimuths turn the eye towards `right`
//! (counter-clockwise seen from above); elevation is the angle above the horizon,
//! so the eye direction is `(sin a cos e, -cos a cos e, sin e)`.
//!
//! Framing ([`Camera::frame_points`]): the box-corner framing of [`Camera::frame`]
//! leaves a round object small (its box's corners stick out of its silhouette), so
//! this frames a point set instead — for a solid, the corners of its nodes coarsened
//! to at most 64 a side ([`silhouette_points`]), which hold the solid's silhouette to
//! within 1/64 of its size. The target is moved across the view to the middle of the
//! points' projected extent, then the eye is put at the nearest distance where every
//! point projects inside the picture, plus a 4% margin; two rounds, since moving the
//! target changes the perspective.

use glam::DVec3;

use super::camera::{Camera, DEFAULT_VIEW, Projection, turned_to_up};
use crate::octree::{CoarsenRule, LinearOctree};
use crate::shape::Axis;

/// A named viewing direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NamedView {
    /// From -y (z-up frame).
    Front,
    /// From +y.
    Back,
    /// From -x.
    Left,
    /// From +x.
    Right,
    /// From +z, looking down.
    Top,
    /// From -z, looking up.
    Bottom,
    /// From `(1, -1, 1)`.
    Iso,
}

impl std::str::FromStr for NamedView {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        Ok(match s.to_ascii_lowercase().as_str() {
            "front" => NamedView::Front,
            "back" => NamedView::Back,
            "left" => NamedView::Left,
            "right" => NamedView::Right,
            "top" => NamedView::Top,
            "bottom" => NamedView::Bottom,
            "iso" => NamedView::Iso,
            _ => return Err(format!("unknown view {s:?}; expected front, back, left, right, top, bottom or iso")),
        })
    }
}

impl std::fmt::Display for NamedView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl NamedView {
    /// Every value, in the order `--help` lists them.
    pub const ALL: [NamedView; 7] = [
        NamedView::Front,
        NamedView::Back,
        NamedView::Left,
        NamedView::Right,
        NamedView::Top,
        NamedView::Bottom,
        NamedView::Iso,
    ];

    /// The view's name (`FromStr` takes it in any case).
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            NamedView::Front => "front",
            NamedView::Back => "back",
            NamedView::Left => "left",
            NamedView::Right => "right",
            NamedView::Top => "top",
            NamedView::Bottom => "bottom",
            NamedView::Iso => "iso",
        }
    }

    /// The direction from the target towards the eye in a world whose up is `up`.
    #[must_use]
    pub fn direction(self, up: Axis) -> DVec3 {
        let v = match self {
            NamedView::Front => -DVec3::Y,
            NamedView::Back => DVec3::Y,
            NamedView::Left => -DVec3::X,
            NamedView::Right => DVec3::X,
            NamedView::Top => DVec3::Z,
            NamedView::Bottom => -DVec3::Z,
            NamedView::Iso => DVec3::new(1.0, -1.0, 1.0).normalize(),
        };
        turned_to_up(v, up)
    }
}

/// The azimuth and elevation (degrees) of [`DEFAULT_VIEW`].
#[must_use]
pub fn default_orbit() -> (f64, f64) {
    let v = DEFAULT_VIEW.normalize();
    (v.x.atan2(-v.y).to_degrees(), v.z.asin().to_degrees())
}

/// The direction from the target towards the eye at `azimuth` and `elevation`
/// degrees (see the module doc) in a world whose up is `up`.
#[must_use]
pub fn orbit_direction(azimuth: f64, elevation: f64, up: Axis) -> DVec3 {
    let (a, e) = (azimuth.to_radians(), elevation.to_radians());
    turned_to_up(DVec3::new(a.sin() * e.cos(), -a.cos() * e.cos(), e.sin()), up)
}

/// A camera up vector that is not parallel to `view`: `up`, or, looking straight
/// along it (top and bottom views), the frame's "forward" (+y turned with the world)
/// so that the picture keeps front at the bottom.
#[must_use]
pub fn up_for(view: DVec3, up: DVec3, up_axis: Axis) -> DVec3 {
    if view.normalize().cross(up.normalize()).length() > 1e-6 { up } else { turned_to_up(DVec3::Y, up_axis) }
}

/// The corners of `tree`'s nodes coarsened (by [`CoarsenRule::Any`]) to at most 64
/// voxels a side: points whose hull holds the solid and whose silhouette is the
/// solid's to within 1/64 of the domain (see the module doc).
#[must_use]
pub fn silhouette_points(tree: &LinearOctree) -> Vec<DVec3> {
    let coarse =
        if tree.depth() > 6 { tree.coarsen(6, CoarsenRule::Any).expect("coarser depth") } else { tree.clone() };
    let d = coarse.domain();
    coarse
        .nodes()
        .flat_map(|n| {
            (0..8).map(move |i| {
                let corner = [0, 1, 2].map(|a| n.min[a] + if i >> a & 1 == 1 { n.size } else { 0 });
                d.lattice_point(corner)
            })
        })
        .collect()
}

impl Camera {
    /// A camera looking along `-view` with `up` that fills a picture of `aspect` =
    /// width / height with `points` (see the module doc): perspective with `fov_y`
    /// degrees, or orthographic when `fov_y` is `None`. `None` for an empty set.
    #[must_use]
    pub fn frame_points(points: &[DVec3], view: DVec3, up: DVec3, aspect: f64, fov_y: Option<f64>) -> Option<Camera> {
        if points.is_empty() {
            return None;
        }
        let w = view.normalize();
        let right = (-w).cross(up).normalize();
        let true_up = right.cross(-w);
        let extent = |dir: DVec3| {
            points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p.dot(dir)), hi.max(p.dot(dir))))
        };
        let centre = |dir: DVec3| {
            let (lo, hi) = extent(dir);
            (lo + hi) * 0.5
        };
        let mut target = right * centre(right) + true_up * centre(true_up) + w * centre(w);
        let margin = 1.04;
        let Some(fov_y) = fov_y else {
            let (half_w, half_h) = (extent(right), extent(true_up));
            let height = ((half_w.1 - half_w.0) / aspect).max(half_h.1 - half_h.0).max(1e-12) * margin;
            let depth = extent(w);
            let eye = target + w * (depth.1 - centre(w) + height);
            return Some(Camera { eye, target, up, projection: Projection::Orthographic { height } });
        };
        let ty = (fov_y.to_radians() * 0.5).tan();
        let tx = ty * aspect;
        // A point p (from the target) at eye distance D has depth D - p.w, so it fits
        // when D >= p.w + |p.right| / tx and D >= p.w + |p.up| / ty.
        let fit = |target: DVec3| {
            let need = |p: DVec3| {
                let p = p - target;
                p.dot(w) + (p.dot(right).abs() / tx).max(p.dot(true_up).abs() / ty)
            };
            points.iter().map(|&p| need(p)).fold(f64::MIN_POSITIVE, f64::max) * margin
        };
        for _ in 0..2 {
            let distance = fit(target);
            // Centre the projected extent: the image x of p is p.right / ((D - p.w) tx).
            let eye = target + w * distance;
            let projected = |dir: DVec3, t: f64| {
                points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), &p| {
                    let v = p - eye;
                    let x = v.dot(dir) / ((-v.dot(w)).max(1e-12) * t);
                    (lo.min(x), hi.max(x))
                })
            };
            let ((x0, x1), (y0, y1)) = (projected(right, tx), projected(true_up, ty));
            target += (right * ((x0 + x1) * 0.5 * tx) + true_up * ((y0 + y1) * 0.5 * ty)) * distance;
        }
        let distance = fit(target);
        Some(Camera { eye: target + w * distance, target, up, projection: Projection::Perspective { fov_y } })
    }
}
