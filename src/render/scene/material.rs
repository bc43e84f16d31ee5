//! Materials: the Phong coefficients, a colour or texture, a bump map, and Whitted's
//! reflectance, transmittance and index of refraction; emission for area lights.

use glam::DVec3;

use super::texture::{Texture, noise};
use crate::error::{Error, Number, Result, Vector};

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
    pub fn validate(&self) -> Result<()> {
        let unit = [("ka", self.ka), ("kd", self.kd), ("ks", self.ks)]
            .into_iter()
            .chain([("reflectance", self.reflectance), ("transmittance", self.transmittance)]);
        for (what, k) in unit {
            if !(0.0..=1.0).contains(&k) {
                return Err(Error::invalid(what, format!("{} is outside [0, 1]", Number(k))));
            }
        }
        if self.reflectance + self.transmittance > 1.0 {
            return Err(Error::invalid("material", "reflectance + transmittance exceeds 1"));
        }
        if !(self.ior.is_finite() && self.ior > 0.0) {
            return Err(Error::invalid("ior", format!("{} must be a finite positive number", Number(self.ior))));
        }
        if !(self.emission.is_finite() && self.emission.min_element() >= 0.0) {
            return Err(Error::invalid(
                "emission",
                format!("{} must be finite and not negative", Vector(self.emission)),
            ));
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

    /// A MagicaVoxel material (a `.vox` file's `MATL` properties, by their names) of
    /// palette colour `color` (linear RGB), mapped to what Whitted and radiosity can
    /// show. MagicaVoxel's renderer is a path tracer; these are the nearest terms:
    /// - metal (`_type = _metal` with `_weight`, or a `_metal` value): a mirror of that
    ///   reflectance, its colour the palette's;
    /// - glass (`_type = _glass` with `_weight`, or a `_trans` value): that
    ///   transmittance, refracted at index `1 + _ior` (MagicaVoxel stores the index
    ///   less one; `_ri`, where a newer file gives it, is the index itself), plus the
    ///   mirror reflectance of a dielectric face on, `((n - 1) / (n + 1))^2`, within
    ///   what the transmittance leaves;
    /// - emitter (`_type = _emit` with `_weight`, or an `_emit` value, and `_flux`):
    ///   emitted radiance `color * weight * 2^flux`, an area light for radiosity;
    /// - `_rough` and `_spec` set the highlight (`ks = _spec`, `shininess = 2 / r^2 -
    ///   2`, the Phong exponent of a Beckmann roughness `r`, for metals and glass).
    ///
    /// Values that do not parse or are out of range are left at the default; the
    /// result always passes [`Material::validate`].
    #[must_use]
    pub fn from_magicavoxel(color: DVec3, properties: &std::collections::BTreeMap<String, String>) -> Self {
        let number =
            |key: &str| properties.get(key).and_then(|v| v.trim().parse::<f64>().ok()).filter(|v| v.is_finite());
        let unit = |key: &str| number(key).map(|v| v.clamp(0.0, 1.0));
        let kind = properties.get("_type").map(String::as_str).unwrap_or("_diffuse");
        let weight = |of: &str| if kind == of { unit("_weight").unwrap_or(1.0) } else { 0.0 };
        let metal = unit("_metal").unwrap_or(0.0).max(weight("_metal"));
        let glass = unit("_trans").unwrap_or(0.0).max(weight("_glass"));
        let emit = number("_emit").map_or(0.0, |v| v.max(0.0)).max(weight("_emit"));
        let mut m = Material { color, ..Material::default() };
        if metal > 0.0 || glass > 0.0 {
            if let Some(spec) = unit("_spec") {
                m.ks = spec;
            }
            if let Some(rough) = unit("_rough") {
                m.shininess = (2.0 / rough.max(0.02).powi(2) - 2.0).min(1000.0);
            }
        }
        if glass > 0.0 {
            let ior = number("_ri").or_else(|| number("_ior").map(|v| 1.0 + v)).filter(|n| (1.0..=4.0).contains(n));
            m.ior = ior.unwrap_or(1.5);
            m.transmittance = glass;
            let fresnel = ((m.ior - 1.0) / (m.ior + 1.0)).powi(2);
            m.reflectance = fresnel.min(1.0 - glass);
        } else if metal > 0.0 {
            m.reflectance = metal;
        }
        if emit > 0.0 {
            let flux = number("_flux").map_or(0.0, |f| f.clamp(0.0, 16.0));
            m.emission = color * emit * 2f64.powf(flux);
        }
        m
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
