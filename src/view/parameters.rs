//! The mode registry: what each render mode is and which parameters it reads.
//!
//! Front ends (the viewer's panels, help texts) iterate [`RenderMode::ALL`] and
//! show a control for each [`Parameter`] of the chosen mode, so a new mode
//! appears everywhere by adding it to the enum and listing its parameters here.

use super::RenderMode;

/// A setting a mode reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Parameter {
    /// Filtered (Gaussian blending) or unfiltered (nearest splat).
    Quality,
    /// ε of the depth test that decides which splats blend.
    Epsilon,
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
}

impl RenderMode {
    /// One sentence on what the mode does.
    pub fn description(self) -> &'static str {
        match self {
            RenderMode::TwoPass => {
                "Botsch & Kobbelt: ε-offset visibility, additive blending, normalisation (2+1 passes)."
            }
            RenderMode::Deferred => {
                "Zhang & Pajarola: one geometry pass into K group images, then ε-z compositing (1+1 passes)."
            }
            RenderMode::Reference => "Exact A-buffer ray casting on the CPU: the ground truth for error (slow).",
        }
    }

    /// The parameters the mode reads, in display order.
    pub fn parameters(self) -> &'static [Parameter] {
        use Parameter::*;
        match self {
            RenderMode::TwoPass => &[Quality, Epsilon, RadiusScale, BackfaceCulling, Lighting, Background],
            RenderMode::Deferred => &[Grouping, Voronoi, Epsilon, RadiusScale, BackfaceCulling, Lighting, Background],
            RenderMode::Reference => &[Epsilon, RadiusScale, BackfaceCulling, Lighting, Background],
        }
    }

    /// Whether the mode draws groups (and so needs a grouping before it can render).
    pub fn needs_grouping(self) -> bool {
        self.parameters().contains(&Parameter::Grouping)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_mode_has_a_description_and_parameters() {
        for mode in RenderMode::ALL {
            assert!(!mode.description().is_empty(), "{mode}");
            assert!(!mode.parameters().is_empty(), "{mode}");
        }
        assert!(RenderMode::Deferred.needs_grouping());
        assert!(!RenderMode::TwoPass.needs_grouping());
    }
}
