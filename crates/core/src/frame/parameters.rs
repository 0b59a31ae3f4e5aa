//! The settings a mode can read, each with the one name it has everywhere:
//! on the command line (`--group wgc-k8`), in bench variants
//! (`deferred:group=wgc-k8`), in the viewer's panel and in sidecars.
//!
//! Front ends show a control for each [`Parameter`] of the chosen mode (the
//! registry in [`super::modes`] lists them), so a new mode needs no UI code.

use super::RenderSettings;
use crate::grouping::GroupingSpec;

/// A setting a mode reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parameter {
    /// Filtered (Gaussian blending) or unfiltered (nearest splat).
    Quality,
    /// ε of the depth test that decides which splats blend.
    Epsilon,
    /// Eq. 10's low-precision depth step, as a multiple of ε.
    DepthStep,
    /// A factor on every splat radius.
    RadiusScale,
    BackfaceCulling,
    /// Phong lighting on/off and the light direction.
    Lighting,
    /// Grouping algorithm and its parameters (c, K, collision handling).
    Grouping,
    /// Voronoi rasterisation inside a group (Zhang & Pajarola Eq. 14).
    Voronoi,
    Background,
    /// Transparent layers k a peeling mode draws.
    PeelLayers,
    /// Environment effects at the nearest layer, through all layers, or off (§5.2.3).
    EnvironmentLayers,
    /// Index of refraction η of the environment effects.
    Eta,
    /// Chromatic dispersion δ of the environment effects.
    Dispersion,
    /// The back-to-front order of modes that blend in order: Gunjee's bucket
    /// sort or Zhang & Pajarola's BSP traversal (§5.2.1).
    Order,
    /// How splats lit by scene lights find their light: Gunjee's translucent
    /// shadow map (with its table size), exact shadow rays, or none.
    Shadows,
    /// The splat passes' screen-space low-pass filter: Guennebaud's EWA approximation or none.
    Prefilter,
    /// Rays per pixel side of the reference (N×N, box-filtered).
    Supersample,
    /// Most splats a frame draws, from the multi-resolution hierarchy.
    PointBudget,
    /// Splat radius in pixels above which a hybrid object's leaf is drawn as triangles.
    HybridPixels,
}

impl Parameter {
    pub const ALL: [Parameter; 19] = [
        Parameter::Quality,
        Parameter::Epsilon,
        Parameter::DepthStep,
        Parameter::RadiusScale,
        Parameter::BackfaceCulling,
        Parameter::Lighting,
        Parameter::Grouping,
        Parameter::Voronoi,
        Parameter::Background,
        Parameter::PeelLayers,
        Parameter::EnvironmentLayers,
        Parameter::Eta,
        Parameter::Dispersion,
        Parameter::Order,
        Parameter::Shadows,
        Parameter::Prefilter,
        Parameter::Supersample,
        Parameter::PointBudget,
        Parameter::HybridPixels,
    ];

    /// The name in `key=value` settings (bench variants).
    pub fn key(self) -> &'static str {
        match self {
            Parameter::Quality => "quality",
            Parameter::Epsilon => "epsilon",
            Parameter::DepthStep => "step",
            Parameter::RadiusScale => "radius-scale",
            Parameter::BackfaceCulling => "cull",
            Parameter::Lighting => "lighting",
            Parameter::Grouping => "group",
            Parameter::Voronoi => "voronoi",
            Parameter::Background => "background",
            Parameter::PeelLayers => "layers",
            Parameter::EnvironmentLayers => "env-layers",
            Parameter::Eta => "eta",
            Parameter::Dispersion => "dispersion",
            Parameter::Order => "order",
            Parameter::Shadows => "shadows",
            Parameter::Prefilter => "prefilter",
            Parameter::Supersample => "supersample",
            Parameter::PointBudget => "point-budget",
            Parameter::HybridPixels => "hybrid-px",
        }
    }

    /// The values it takes, for messages.
    pub fn values(self) -> &'static str {
        match self {
            Parameter::Quality => "filtered or unfiltered",
            Parameter::Epsilon => "a positive multiple of the mean splat radius",
            Parameter::DepthStep => "a positive multiple of ε",
            Parameter::RadiusScale => "a positive factor",
            Parameter::BackfaceCulling | Parameter::Voronoi => "on or off",
            Parameter::Lighting => "on, off or headlight (the camera's light instead of the scene's lights)",
            Parameter::Grouping => {
                "mgc-cC, wgc-kK or hash-kK, then any of -kept, -eq7, -coplanar, -opposite, -dup, -radius"
            }
            Parameter::Background => "R,G,B (or R/G/B) in 0..255",
            Parameter::PeelLayers => "a number of layers, 2..=64",
            Parameter::EnvironmentLayers => "single, multi or off",
            Parameter::Eta => "a positive index of refraction",
            Parameter::Dispersion => "a dispersion of 0 or more",
            Parameter::Order => "bucket, bsp or sort",
            Parameter::Shadows => "tsm, tsm-POLxAZ (table cells), exact or off",
            Parameter::Prefilter => "ewa or none",
            Parameter::Supersample => "rays per pixel side, 1..=16",
            Parameter::PointBudget => "a number of splats, 1 or more, or all",
            Parameter::HybridPixels => {
                "a splat radius in pixels, 0 or more (0: every leaf as triangles), or inf (splats only)"
            }
        }
    }

    pub fn from_key(key: &str) -> Option<Parameter> {
        Parameter::ALL.into_iter().find(|p| p.key() == key)
    }

    /// Sets this parameter of `settings` from its text form.
    pub fn apply(self, settings: &mut RenderSettings, value: &str) -> Result<(), String> {
        let bad = || format!("{}={value}: expected {}", self.key(), self.values());
        let on_off = |v: &str| match v {
            "on" | "true" | "yes" => Ok(true),
            "off" | "false" | "no" => Ok(false),
            _ => Err(bad()),
        };
        let positive = |v: &str| v.parse::<f32>().ok().filter(|x| x.is_finite() && *x > 0.0).ok_or_else(bad);
        match self {
            Parameter::Quality => {
                settings.quality = match value {
                    "filtered" => super::Quality::Filtered,
                    "unfiltered" => super::Quality::Unfiltered,
                    _ => return Err(bad()),
                }
            }
            Parameter::Epsilon => settings.epsilon_scale = positive(value)?,
            Parameter::DepthStep => settings.depth_step = positive(value)?,
            Parameter::RadiusScale => settings.radius_scale = positive(value)?,
            Parameter::BackfaceCulling => settings.backface_culling = on_off(value)?,
            // `headlight`: lit, but by the camera's light rather than the scene's lights.
            Parameter::Lighting if value == "headlight" => {
                settings.lighting = true;
                settings.lights = Default::default();
            }
            Parameter::Lighting => settings.lighting = on_off(value)?,
            Parameter::Voronoi => settings.voronoi = on_off(value)?,
            Parameter::Grouping => {
                settings.grouping = value.parse::<GroupingSpec>().map_err(|e| format!("group={e}"))?
            }
            Parameter::PeelLayers => {
                let max = super::settings::MAX_PEEL_LAYERS;
                settings.peel_layers = value.parse::<u32>().ok().filter(|k| (2..=max).contains(k)).ok_or_else(bad)?;
            }
            Parameter::EnvironmentLayers => {
                let env = &mut settings.environment;
                (env.enabled, env.layer_effects) = match value {
                    "off" => (false, env.layer_effects),
                    other => (true, other.parse().map_err(|_| bad())?),
                };
            }
            Parameter::Eta => settings.environment.eta = positive(value)?,
            Parameter::Order => settings.order = value.parse().map_err(|_| bad())?,
            Parameter::Prefilter => settings.prefilter = value.parse().map_err(|_| bad())?,
            Parameter::PointBudget => {
                settings.point_budget = match value {
                    "all" => None,
                    _ => Some(value.parse::<u32>().ok().filter(|n| *n >= 1).ok_or_else(bad)?),
                }
            }
            Parameter::HybridPixels => {
                settings.hybrid_pixels = value.parse::<f32>().ok().filter(|p| *p >= 0.0).ok_or_else(bad)?;
            }
            Parameter::Supersample => {
                let max = super::settings::MAX_SUPERSAMPLE;
                settings.supersample = value.parse::<u32>().ok().filter(|n| (1..=max).contains(n)).ok_or_else(bad)?;
            }
            Parameter::Shadows => {
                let (method, cells) = match value.split_once('-') {
                    Some(("tsm", cells)) => ("tsm", Some(super::lights::parse_cells(cells).map_err(|_| bad())?)),
                    Some(_) => return Err(bad()),
                    None => (value, None),
                };
                settings.shadows.method = method.parse().map_err(|_| bad())?;
                if let Some(cells) = cells {
                    settings.shadows.cells = cells;
                }
            }
            // Checked alone (not against η, which may come later in the
            // variant): η - δ is kept above MIN_ETA where it is used.
            Parameter::Dispersion => {
                settings.environment.dispersion =
                    value.parse::<f32>().ok().filter(|d| d.is_finite() && *d >= 0.0).ok_or_else(bad)?;
            }
            Parameter::Background => {
                let rgb: Vec<f32> = value
                    .split([',', '/'])
                    .map(|c| c.trim().parse::<f32>().map_err(|_| bad()))
                    .collect::<Result<_, _>>()?;
                match rgb[..] {
                    [r, g, b] if [r, g, b].iter().all(|c| (0.0..=255.0).contains(c)) => {
                        settings.shading.background = glam::Vec3::new(r, g, b) / 255.0;
                    }
                    _ => return Err(bad()),
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_parameter_has_a_unique_key_that_applies() {
        for p in Parameter::ALL {
            assert_eq!(Parameter::from_key(p.key()), Some(p));
        }
        let mut s = RenderSettings::default();
        Parameter::Quality.apply(&mut s, "unfiltered").unwrap();
        Parameter::Grouping.apply(&mut s, "wgc-k8").unwrap();
        Parameter::Voronoi.apply(&mut s, "off").unwrap();
        Parameter::Background.apply(&mut s, "255,0,51").unwrap();
        Parameter::DepthStep.apply(&mut s, "2.5").unwrap();
        assert_eq!(s.depth_step, 2.5);
        assert_eq!(s.quality, crate::frame::Quality::Unfiltered);
        assert_eq!(s.grouping, GroupingSpec::wgc(8));
        assert!(!s.voronoi);
        assert!((s.shading.background - glam::Vec3::new(1.0, 0.0, 0.2)).length() < 1e-6);
        assert!(Parameter::Epsilon.apply(&mut s, "0").is_err());
        for bad in ["0", "-1", "NaN", "inf", "x"] {
            assert!(Parameter::DepthStep.apply(&mut s, bad).is_err(), "step={bad}");
        }
        assert!(Parameter::Lighting.apply(&mut s, "maybe").is_err());
        Parameter::Prefilter.apply(&mut s, "ewa").unwrap();
        assert_eq!(s.prefilter, crate::frame::Prefilter::Ewa);
        Parameter::Supersample.apply(&mut s, "4").unwrap();
        assert_eq!(s.supersample, 4);
        for bad in ["0", "17", "-1", "x"] {
            assert!(Parameter::Supersample.apply(&mut s, bad).is_err(), "supersample={bad}");
            assert!(bad == "17" || Parameter::PointBudget.apply(&mut s, bad).is_err(), "point-budget={bad}");
        }
        Parameter::PointBudget.apply(&mut s, "250000").unwrap();
        assert_eq!(s.point_budget, Some(250_000));
        Parameter::PointBudget.apply(&mut s, "all").unwrap();
        assert_eq!(s.point_budget, None);
    }
}
