//! A displaced sphere: the radius varies with direction, so the bumps are real
//! geometry in the solid (texture displacement, voxelized exactly, not shaded).
//!
//! `r(u) = R + A sin(k u_x) sin(k u_y) sin(k u_z)` for the unit direction `u` from the
//! centre; the solid is `|p - c| <= r((p - c) / |p - c|)`, i.e. `g(p) <= 0` with
//! `g(p) = |p - c| - r(u(p))`. Box classification by a Lipschitz bound: over a box of
//! centre `q` and half-diagonal `h` whose points are at least `d` from the centre,
//! `|g(p) - g(q)| <= L h` with `L = 1 + A k sqrt(3) / d` (the bump's gradient on the
//! unit sphere is at most `k sqrt(3)`, and `p -> u(p)` shrinks lengths by `1 / |p - c|`).
//! So `g(q) > L h` is Outside and `g(q) < -L h` Inside; boxes reaching within `R - A`
//! of the centre are Inside when wholly within it. The voxelizer's work stays near the
//! surface.

use glam::DVec3;

use super::bounds::{EPS, finite, positive};
use super::{Class, Shape, Surface};
use crate::aabb::Aabb;
use crate::error::{Error, Result};

/// A sphere with sinusoidal bumps of amplitude `amplitude` and angular frequency `frequency`.
#[derive(Clone, Debug, PartialEq)]
pub struct DisplacedSphere {
    center: DVec3,
    radius: f64,
    amplitude: f64,
    frequency: f64,
}

impl DisplacedSphere {
    /// Fails unless `0 <= amplitude < radius` and every number is finite (`frequency >= 0`).
    pub fn new(center: DVec3, radius: f64, amplitude: f64, frequency: f64) -> Result<Self> {
        let radius = positive("radius", radius)?;
        if !(amplitude.is_finite() && (0.0..radius).contains(&amplitude)) {
            return Err(Error::invalid("amplitude", format!("{amplitude} must lie in [0, radius)")));
        }
        if !(frequency.is_finite() && frequency >= 0.0) {
            return Err(Error::invalid(
                "frequency",
                format!("{} must be finite and not negative", crate::error::Number(frequency)),
            ));
        }
        Ok(DisplacedSphere { center: finite("center", center)?, radius, amplitude, frequency })
    }

    /// The radius towards the unit direction `u`: `R + A sin(k u_x) sin(k u_y) sin(k u_z)`.
    #[must_use]
    pub fn radius_towards(&self, u: DVec3) -> f64 {
        let k = self.frequency;
        self.radius + self.amplitude * (k * u.x).sin() * (k * u.y).sin() * (k * u.z).sin()
    }

    /// `g(p) = |p - c| - r(u(p))`: negative inside.
    fn g(&self, p: DVec3) -> f64 {
        let q = p - self.center;
        let d = q.length();
        if d == 0.0 { -self.radius } else { d - self.radius_towards(q / d) }
    }
}

impl Shape for DisplacedSphere {
    fn classify(&self, b: &Aabb) -> Class {
        let near = (self.center.clamp(b.min, b.max) - self.center).length();
        let far = (b.min - self.center).abs().max((b.max - self.center).abs()).length();
        let margin = EPS * self.radius;
        let (inner, outer) = (self.radius - self.amplitude, self.radius + self.amplitude);
        if far < inner - margin {
            return Class::Inside;
        }
        if near > outer + margin {
            return Class::Outside;
        }
        if near <= 0.5 * inner {
            return Class::Boundary;
        }
        let h = 0.5 * b.size().length();
        let lipschitz = 1.0 + self.amplitude * self.frequency * 3f64.sqrt() / near;
        let g = self.g(b.center());
        if g > lipschitz * h + margin {
            Class::Outside
        } else if g < -lipschitz * h - margin {
            Class::Inside
        } else {
            Class::Boundary
        }
    }

    fn contains(&self, p: DVec3) -> bool {
        self.g(p) <= 0.0
    }

    /// `g` and its gradient `u - (grad_u r - u (u . grad_u r)) / |q|` (first order),
    /// with `u = q / |q|` and `grad_u r = A k (cos(k u_x) sin(k u_y) sin(k u_z), ...)`.
    fn surface(&self, p: DVec3) -> Option<Surface> {
        let q = p - self.center;
        let d = q.length();
        if d == 0.0 {
            return None;
        }
        let u = q / d;
        let k = self.frequency;
        let (s, c) = ((k * u).to_array().map(f64::sin), (k * u).to_array().map(f64::cos));
        let along = DVec3::new(c[0] * s[1] * s[2], s[0] * c[1] * s[2], s[0] * s[1] * c[2]) * (self.amplitude * k);
        Surface::from_field(self.g(p), u - (along - u * u.dot(along)) / d)
    }

    fn bounds(&self) -> Option<Aabb> {
        Some(Aabb::from_center_half(self.center, DVec3::splat(self.radius + self.amplitude)))
    }
}
