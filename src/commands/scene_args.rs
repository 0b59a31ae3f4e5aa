//! Flags that change the scene rather than the rendering parameters: every
//! object's opacity and colour, and point lights added to the scene's. `render`,
//! `bench` and `view` all take them from here.

use pointblend::scene::{Materials, Scene};

#[derive(clap::Args, Debug, Clone, Default)]
pub struct SceneArgs {
    /// Opacity of every object, 0..1 (transparent objects are drawn two-sided;
    /// only transparent modes and the reference show it).
    #[arg(long, value_parser = parse_opacity)]
    pub opacity: Option<f32>,
    /// Colour R,G,B (0..255) that replaces every object's own.
    #[arg(long = "color", value_parser = parse_rgb)]
    pub colour: Option<[u8; 3]>,
    /// A white point light at X,Y,Z in the model's file coordinates (repeatable, at most 8 with the scene's);
    /// any light replaces the headlight, and casts translucent shadows.
    #[arg(long = "light", value_parser = parse_light, allow_hyphen_values = true)]
    pub lights: Vec<pointblend::frame::Light>,
}

impl SceneArgs {
    /// Applies `--opacity` and `--color` to the scene's objects.
    pub fn apply_materials(&self, scene: &mut Scene) {
        if let Some(opacity) = self.opacity {
            scene.set_opacity(opacity);
        }
        if let Some(colour) = self.colour {
            scene.set_colour(colour);
        }
    }

    /// The materials of every object opened; `background_given`: the scene's
    /// own background is not used.
    pub fn materials(&self, background_given: bool) -> Materials {
        Materials { opacity: self.opacity, colour: self.colour, scene_background: !background_given }
    }
}

/// `R,G,B`, each 0..255.
pub fn parse_rgb(text: &str) -> Result<[u8; 3], String> {
    let values: Vec<&str> = text.split(',').map(str::trim).collect();
    match values[..] {
        [r, g, b] => {
            let c = |v: &str| v.parse::<u8>().map_err(|_| format!("'{v}' is not a value in 0..255"));
            Ok([c(r)?, c(g)?, c(b)?])
        }
        _ => Err(format!("'{text}' is not R,G,B (three values in 0..255)")),
    }
}

/// `A` in 0..1.
pub fn parse_opacity(text: &str) -> Result<f32, String> {
    text.parse::<f32>()
        .ok()
        .filter(|a| (0.0..=1.0).contains(a))
        .ok_or_else(|| format!("'{text}' is not an opacity in 0..1"))
}

/// `--light X,Y,Z`.
pub fn parse_light(text: &str) -> Result<pointblend::frame::Light, String> {
    pointblend::frame::Light::parse_point(text).map_err(|e| e.to_string())
}
