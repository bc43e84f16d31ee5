//! Lights: points and directions, with a colour that includes the intensity.

use glam::DVec3;

use crate::ray::Ray;

/// A light with a colour (linear RGB, intensity included).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Light {
    /// Light from a point, falling on everything it sees.
    Point {
        /// Position.
        position: DVec3,
        /// Colour and intensity.
        color: DVec3,
    },
    /// Light from a direction (the sun): `direction` points from the light.
    Directional {
        /// Direction the light travels.
        direction: DVec3,
        /// Colour and intensity.
        color: DVec3,
    },
}

impl Light {
    /// The shadow ray from `p` to the light: unit direction towards it, `t_max` the
    /// distance to it (infinite for a directional light).
    #[must_use]
    pub fn shadow_ray(&self, p: DVec3) -> Ray {
        match *self {
            Light::Point { position, .. } => {
                let v = position - p;
                let d = v.length();
                Ray::segment(p, v / d, d)
            }
            Light::Directional { direction, .. } => Ray::new(p, -direction.normalize()),
        }
    }

    /// Unit vector from `p` towards the light.
    #[must_use]
    pub fn direction_from(&self, p: DVec3) -> DVec3 {
        self.shadow_ray(p).dir
    }

    /// The light's colour.
    #[must_use]
    pub fn color(&self) -> DVec3 {
        match *self {
            Light::Point { color, .. } | Light::Directional { color, .. } => color,
        }
    }
}
