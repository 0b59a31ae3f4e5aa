//! The perceptual colormaps a scalar attribute is shown through, from the
//! `colorous` crate (d3-scale-chromatic's tables): viridis, magma, inferno,
//! cividis and turbo, and a linear grey ramp.

/// A colormap, by its `--colormap` name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Colormap {
    #[default]
    Viridis,
    Magma,
    Inferno,
    Cividis,
    Turbo,
    Grey,
}

impl Colormap {
    pub const ALL: [Colormap; 6] =
        [Colormap::Viridis, Colormap::Magma, Colormap::Inferno, Colormap::Cividis, Colormap::Turbo, Colormap::Grey];

    pub fn name(self) -> &'static str {
        match self {
            Colormap::Viridis => "viridis",
            Colormap::Magma => "magma",
            Colormap::Inferno => "inferno",
            Colormap::Cividis => "cividis",
            Colormap::Turbo => "turbo",
            Colormap::Grey => "grey",
        }
    }

    /// The sRGB colour at `t` in 0..1 (clamped).
    pub fn colour(self, t: f64) -> [u8; 3] {
        let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
        let gradient = match self {
            Colormap::Viridis => colorous::VIRIDIS,
            Colormap::Magma => colorous::MAGMA,
            Colormap::Inferno => colorous::INFERNO,
            Colormap::Cividis => colorous::CIVIDIS,
            Colormap::Turbo => colorous::TURBO,
            Colormap::Grey => colorous::GREYS,
        };
        // d3's greys run from white to black; the grey ramp runs dark to light, as intensity does.
        let t = if self == Colormap::Grey { 1.0 - t } else { t };
        let c = gradient.eval_continuous(t);
        [c.r, c.g, c.b]
    }
}

impl std::str::FromStr for Colormap {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, String> {
        let text = text.trim().to_ascii_lowercase();
        let text = if text == "gray" { "grey".to_string() } else { text };
        Colormap::ALL.into_iter().find(|c| c.name() == text).ok_or_else(|| {
            format!("'{text}' is not a colormap; expected one of {}", Colormap::ALL.map(Colormap::name).join(", "))
        })
    }
}
