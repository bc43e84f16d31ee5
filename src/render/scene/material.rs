//! Materials: the Phong coefficients, a colour or texture, a bump map, and Whitted's
//! reflectance, transmittance and index of refraction; emission for area lights.

use glam::DVec3;

use super::texture::{Texture, noise};
use crate::error::{Error, Result};

/// A surface's optical properties.
///
/// Local (Phong) term: `I_c = ka Ia C + sum_i Ii (kd C cos(alpha_i) + ks cos^n(theta_i))`,
/// `C` the colour (or the texture's at the point). Whitted: `I = (1 - kr - kt) I_c +
/// kr I_reflected + kt I_transmitted` (see `render::shade`).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Surface colour (linear RGB), used where there is no texture.
    pub color: DVec3,
    /// Colour texture replacing `color`, if any.
    pub texture: Option<Texture>,
    /// Bump mapping (a shading-only perturbation of the normal), if any.
    pub bump: Option<Bump>,
    /// Ambient coefficient.
    pub ka: f64,
    /// Diffuse (Lambert) coefficient.
    pub kd: f64,
    /// Specular coefficient.
    pub ks: f64,
    /// Specular exponent n.
    pub shininess: f64,
    /// Mirror reflectance `kr` (Whitted's `ks` of the reflected ray).
    pub reflectance: f64,
    /// Transmittance `kt`: the part of the light that passes through (also the
    /// factor a shadow ray keeps when it crosses the solid).
    pub transmittance: f64,
    /// Index of refraction (the surroundings have 1).
    pub ior: f64,
    /// Emitted radiance of a Lambertian emitter (linear RGB, not bounded by 1): the
    /// solid is an area light for radiosity (`render::radiosity`), and shows this
    /// radiance plus its local term under direct illumination.
    pub emission: DVec3,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            color: DVec3::new(0.8, 0.55, 0.3),
            texture: None,
            bump: None,
            ka: 0.15,
            kd: 0.75,
            ks: 0.25,
            shininess: 24.0,
            reflectance: 0.0,
            transmittance: 0.0,
            ior: 1.0,
            emission: DVec3::ZERO,
        }
    }
}

impl Material {
    /// An opaque Phong material of colour `color`.
    #[must_use]
    pub fn phong(color: DVec3, ka: f64, kd: f64, ks: f64, shininess: f64) -> Self {
        Material { color, ka, kd, ks, shininess, ..Material::default() }
    }

    /// Fails unless every coefficient is finite and in range: `ka, kd, ks, kr, kt` in
    /// `[0, 1]`, `kr + kt <= 1`, `ior > 0`, `shininess >= 0`.
    pub fn check(&self) -> Result<()> {
        let unit = [("ka", self.ka), ("kd", self.kd), ("ks", self.ks)]
            .into_iter()
            .chain([("reflectance", self.reflectance), ("transmittance", self.transmittance)]);
        for (what, k) in unit {
            if !(0.0..=1.0).contains(&k) {
                return Err(Error::invalid(what, format!("{k} is outside [0, 1]")));
            }
        }
        if self.reflectance + self.transmittance > 1.0 {
            return Err(Error::invalid("material", "reflectance + transmittance exceeds 1"));
        }
        if !(self.ior.is_finite() && self.ior > 0.0) {
            return Err(Error::invalid("ior", format!("{} must be a finite positive number", self.ior)));
        }
        if !(self.emission.is_finite() && self.emission.min_element() >= 0.0) {
            return Err(Error::invalid("emission", format!("{} must be finite and not negative", self.emission)));
        }
        if !(self.shininess.is_finite() && self.shininess >= 0.0 && self.color.is_finite()) {
            return Err(Error::invalid("material", "shininess and colour must be finite"));
        }
        if let Some(b) = self.bump
            && !(b.amplitude.is_finite() && b.amplitude >= 0.0 && b.scale.is_finite() && b.scale > 0.0)
        {
            return Err(Error::invalid("bump", "amplitude must be finite and not negative, scale positive"));
        }
        Ok(())
    }

    /// The diffuse reflectance radiosity uses: `color` times `kd` (each component at
    /// most 1 for a checked material).
    #[must_use]
    pub fn diffuse_reflectance(&self) -> DVec3 {
        self.color * self.kd
    }

    /// The surface colour at `p`: the texture's, else the flat colour.
    #[must_use]
    pub fn color_at(&self, p: DVec3) -> DVec3 {
        self.texture.as_ref().map_or(self.color, |t| t.color(p))
    }
}

/// Bump mapping: the normal tilted by the gradient of a noise height field,
/// `n' = normalize(n - a (grad h - (grad h . n) n))`, `h(p) = noise(p / scale)`, the
/// gradient by central differences. Shading only: the silhouette stays smooth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bump {
    /// Strength `a` (height in units of `scale`).
    pub amplitude: f64,
    /// Feature size of the noise.
    pub scale: f64,
}

impl Bump {
    /// The perturbed unit normal at `p` for the unit normal `n`.
    #[must_use]
    pub fn perturb(&self, p: DVec3, n: DVec3) -> DVec3 {
        let e = 1e-3;
        let h = |q: DVec3| noise(q / self.scale);
        let g = DVec3::new(
            h(p + DVec3::X * e * self.scale) - h(p - DVec3::X * e * self.scale),
            h(p + DVec3::Y * e * self.scale) - h(p - DVec3::Y * e * self.scale),
            h(p + DVec3::Z * e * self.scale) - h(p - DVec3::Z * e * self.scale),
        ) / (2.0 * e);
        (n - (g - n * g.dot(n)) * self.amplitude).try_normalize().unwrap_or(n)
    }
}
