//! The settings a mode can read, each with the one name it has everywhere:
//! on the command line (`--group wgc-k8`), in bench variants
//! (`deferred:group=wgc-k8`), in the viewer's panel and in sidecars.
//!
//! Each parameter is one row of the descriptor table ([`TABLE`]): its name,
//! help, values, viewer control, and the two functions that parse and write
//! its text form. Front ends are made from the table (the command line's
//! flags, bench's keys, the sidecar, the viewer's widgets) and show a control
//! for each [`Parameter`] of the chosen mode (the registry in
//! [`super::modes`] lists them), so neither a new mode nor a new parameter
//! needs UI code (docs/ADDING_A_PARAMETER.md).

mod table;

pub use table::{Control, ParameterInfo, TABLE};

use super::RenderSettings;

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
    /// The least radius in pixels far splats are drawn with.
    MinPixelRadius,
    BackfaceCulling,
    /// Phong lighting on/off and the light direction.
    Lighting,
    /// Eye-dome lighting: its strength and radius, or off.
    EyeDome,
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
    /// Every parameter, in the table's order (read from the table, so a
    /// new parameter is its variant and its row).
    pub const ALL: [Parameter; TABLE.len()] = {
        let mut all = [Parameter::Quality; TABLE.len()];
        let mut i = 0;
        while i < all.len() {
            all[i] = TABLE[i].parameter;
            i += 1;
        }
        all
    };

    /// This parameter's row of the descriptor table.
    pub fn info(self) -> &'static ParameterInfo {
        &TABLE[self as usize]
    }

    /// The name in `key=value` settings (bench variants, sidecars).
    pub fn key(self) -> &'static str {
        self.info().key
    }

    /// The values it takes, for messages.
    pub fn values(self) -> &'static str {
        self.info().values
    }

    pub fn from_key(key: &str) -> Option<Parameter> {
        TABLE.iter().find(|row| row.key == key).map(|row| row.parameter)
    }

    /// The modes that read it, from the mode registry.
    pub fn used_by(self) -> impl Iterator<Item = super::RenderMode> {
        super::RenderMode::ALL.into_iter().filter(move |m| m.parameters().contains(&self))
    }

    /// Sets this parameter of `settings` from its text form.
    pub fn apply(self, settings: &mut RenderSettings, value: &str) -> Result<(), String> {
        let row = self.info();
        (row.set)(settings, value).map_err(|detail| {
            let detail = if detail.is_empty() { String::new() } else { format!(" ({detail})") };
            format!("{}={value}: expected {}{detail}", row.key, row.values)
        })
    }

    /// The text form `settings` hold (`None`: left to the mode's default).
    pub fn text(self, settings: &RenderSettings) -> Option<String> {
        (self.info().get)(settings)
    }

    /// The text form the viewer shows: [`Self::text`], or the mode's default.
    pub fn shown_text(self, settings: &RenderSettings) -> String {
        match self {
            Parameter::PeelLayers => settings.peel_layers_or_default().to_string(),
            _ => self.text(settings).unwrap_or_default(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::grouping::GroupingSpec;

    #[test]
    fn the_table_is_in_the_enums_order_with_one_name_and_flag_each() {
        // `info()` finds a row by the variant's discriminant.
        for (i, row) in TABLE.iter().enumerate() {
            assert_eq!(row.parameter as usize, i, "row {i} is {}", row.key);
        }
        let mut names: Vec<&str> = TABLE.iter().flat_map(|r| [r.flag].into_iter().chain(r.off_switch)).collect();
        names.sort();
        let count = names.len();
        names.dedup();
        assert_eq!(names.len(), count, "two rows share a flag");
    }

    #[test]
    fn every_parameters_text_form_reads_back_as_the_same_settings() {
        let mut changed = RenderSettings::default();
        for (p, value) in [
            (Parameter::Quality, "unfiltered"),
            (Parameter::Epsilon, "0.7"),
            (Parameter::DepthStep, "2.5"),
            (Parameter::RadiusScale, "1.3"),
            (Parameter::BackfaceCulling, "off"),
            (Parameter::Lighting, "off"),
            (Parameter::EyeDome, "0.5,2"),
            (Parameter::Grouping, "hash-k8-kept"),
            (Parameter::Voronoi, "off"),
            (Parameter::Background, "255,0,51"),
            (Parameter::PeelLayers, "5"),
            (Parameter::EnvironmentLayers, "multi"),
            (Parameter::Eta, "1.6"),
            (Parameter::Dispersion, "0.02"),
            (Parameter::Order, "bsp"),
            (Parameter::Shadows, "tsm-256x128"),
            (Parameter::Prefilter, "ewa"),
            (Parameter::Supersample, "3"),
            (Parameter::PointBudget, "5000"),
            (Parameter::HybridPixels, "inf"),
        ] {
            p.apply(&mut changed, value).unwrap();
            assert_eq!(p.text(&changed).as_deref(), Some(value), "{}", p.key());
        }
        for settings in [RenderSettings::default(), changed] {
            let mut back = RenderSettings::default();
            for p in Parameter::ALL {
                if let Some(text) = p.text(&settings) {
                    p.apply(&mut back, &text).unwrap_or_else(|e| panic!("{e}"));
                }
            }
            assert_eq!(back, settings);
        }
    }

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
