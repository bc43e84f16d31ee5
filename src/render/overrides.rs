//! Changes to a picture's options ([`RenderOverrides`]) merged over the options a
//! scene file or the defaults give: the command line's flags, a viewer's query and a
//! scene file's `[image]` table all go through [`RenderOverrides::apply`], so they
//! merge alike.
//!
//! Anti-aliasing merges by kind and numbers: the kind is the overrides' when given;
//! else a depth asks for recursive sampling; else the base's kind when it is not
//! uniform; else a threshold asks for adaptive sampling; else uniform. The threshold
//! and depth are the overrides', else the base's, else [`DEFAULT_AA_THRESHOLD`] and
//! [`DEFAULT_AA_DEPTH`].

use super::pipeline::{AntiAliasing, AntiAliasingKind, DEFAULT_AA_DEPTH, DEFAULT_AA_THRESHOLD, RenderOptions};
use super::shade::Normals;
use super::visibility::Method;

/// What to change in a [`RenderOptions`]: every `None` keeps the base's value.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RenderOverrides {
    /// Image size `[width, height]` in pixels.
    pub size: Option<[u32; 2]>,
    /// Samples a pixel side.
    pub spp: Option<u32>,
    /// How primary visibility is decided.
    pub method: Option<Method>,
    /// Shadow rays on or off.
    pub shadows: Option<bool>,
    /// Shading normals.
    pub normals: Option<Normals>,
    /// Longest chain of reflected and refracted rays.
    pub max_depth: Option<u32>,
    /// Share of a pixel below which a secondary ray is not traced.
    pub cutoff: Option<f64>,
    /// The anti-aliasing kind (see the module doc for what a threshold or depth alone
    /// implies).
    pub aa: Option<AntiAliasingKind>,
    /// Contrast that makes adaptive sampling supersample, recursive sampling split.
    pub aa_threshold: Option<f64>,
    /// Most splits of a pixel's square by recursive sampling.
    pub aa_depth: Option<u32>,
    /// Exposure in stops.
    pub exposure: Option<f64>,
}

impl RenderOverrides {
    /// `base` with these changes (see the module doc for anti-aliasing). The values are
    /// checked where the options are used (the render refuses what is out of range).
    #[must_use]
    pub fn apply(&self, base: RenderOptions) -> RenderOptions {
        let mut options = base;
        if let Some([w, h]) = self.size {
            options.width = w;
            options.height = h;
        }
        options.spp = self.spp.unwrap_or(options.spp);
        options.method = self.method.unwrap_or(options.method);
        let shade = &mut options.shade;
        shade.shadows = self.shadows.unwrap_or(shade.shadows);
        shade.normals = self.normals.unwrap_or(shade.normals);
        shade.max_depth = self.max_depth.unwrap_or(shade.max_depth);
        shade.cutoff = self.cutoff.unwrap_or(shade.cutoff);
        options.aa = self.anti_aliasing(base.aa);
        options.exposure = self.exposure.unwrap_or(options.exposure);
        options
    }

    /// The aspect (width / height) of the picture these overrides give over `base`.
    #[must_use]
    pub fn aspect(&self, base: &RenderOptions) -> f64 {
        let [w, h] = self.size.unwrap_or([base.width, base.height]);
        f64::from(w) / f64::from(h.max(1))
    }

    /// The anti-aliasing over `base`'s (see the module doc).
    fn anti_aliasing(&self, base: AntiAliasing) -> AntiAliasing {
        let (base_threshold, base_depth) = match base {
            AntiAliasing::Uniform => (None, None),
            AntiAliasing::Adaptive { threshold } => (Some(threshold), None),
            AntiAliasing::Recursive { threshold, depth } => (Some(threshold), Some(depth)),
        };
        let threshold = self.aa_threshold.or(base_threshold).unwrap_or(DEFAULT_AA_THRESHOLD);
        let depth = self.aa_depth.or(base_depth).unwrap_or(DEFAULT_AA_DEPTH);
        let kind = match (self.aa, base.kind()) {
            (Some(kind), _) => kind,
            (None, _) if self.aa_depth.is_some() => AntiAliasingKind::Recursive,
            (None, AntiAliasingKind::Uniform) if self.aa_threshold.is_some() => AntiAliasingKind::Adaptive,
            (None, kind) => kind,
        };
        match kind {
            AntiAliasingKind::Uniform => AntiAliasing::Uniform,
            AntiAliasingKind::Adaptive => AntiAliasing::Adaptive { threshold },
            AntiAliasingKind::Recursive => AntiAliasing::Recursive { threshold, depth },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_threshold_alone_asks_for_adaptive_and_a_depth_for_recursive() {
        let base = RenderOptions::default();
        let t = RenderOverrides { aa_threshold: Some(0.1), ..Default::default() };
        assert_eq!(t.apply(base).aa, AntiAliasing::Adaptive { threshold: 0.1 });
        let d = RenderOverrides { aa_depth: Some(2), ..Default::default() };
        assert_eq!(d.apply(base).aa, AntiAliasing::Recursive { threshold: DEFAULT_AA_THRESHOLD, depth: 2 });
        let recursive = RenderOptions { aa: AntiAliasing::Recursive { threshold: 0.5, depth: 4 }, ..base };
        assert_eq!(t.apply(recursive).aa, AntiAliasing::Recursive { threshold: 0.1, depth: 4 });
        let uniform = RenderOverrides { aa: Some(AntiAliasingKind::Uniform), ..t };
        assert_eq!(uniform.apply(recursive).aa, AntiAliasing::Uniform);
        assert_eq!(RenderOverrides::default().apply(recursive), recursive);
    }

    #[test]
    fn given_fields_replace_the_bases_and_the_rest_stay() {
        let base = RenderOptions::default();
        let o = RenderOverrides {
            size: Some([40, 30]),
            shadows: Some(false),
            method: Some(Method::Trace),
            exposure: Some(1.0),
            ..Default::default()
        };
        let merged = o.apply(base);
        assert_eq!((merged.width, merged.height, merged.method, merged.exposure), (40, 30, Method::Trace, 1.0));
        assert!(!merged.shade.shadows);
        assert_eq!((merged.spp, merged.shade.normals), (base.spp, base.shade.normals));
        assert_eq!(o.aspect(&base), 40.0 / 30.0);
    }
}
