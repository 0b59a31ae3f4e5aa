//! The environment effects on a transparent surface (Zhang & Pajarola
//! §5.2.3-5.2.4), applied per pixel to the nearest transparent layer after
//! compositing: the model every renderer that draws them shares.
//!
//! With d the view ray, n the nearest layer's normal turned to the viewer,
//! cos θ_I = -d·n, and per colour channel c an index η_c (η - δ, η, η + δ
//! for red, green, blue: chromatic dispersion δ):
//! - reflection: E_R = env(reflect(d, n));
//! - refraction: sin θ_T = (1/η_c)^m · sin θ_I, with m = 1 (single-layer) or
//!   m = 1 + l, l the transparent layers behind the nearest (multi-layer,
//!   Eq. 16, equal ratios at every interface); E_T,c = env(T_c)[c]; where
//!   sin θ_T ≥ 1 (total internal reflection) the reflection is seen instead;
//! - Fresnel: Schlick, F_c = F0 + (1 - F0)(1 - cos θ_I)^5 with
//!   F0 = ((η_c - 1)/(η_c + 1))², F_c = 1 under total internal reflection;
//! - what shows through: B = C_b + a·E_T, C_b the layers behind composited
//!   (premultiplied, over nothing), a what reaches the environment through
//!   them: their exact transmittance (single-layer) or Eq. 15's absorption
//!   (1 - α)^l (multi-layer), 0 when an opaque layer ends the ray;
//! - the pixel: I = F·E_R + (1 - F)·(α·C_F + (1 - α)·B).
//!
//! The power (1/η)^m is taken as exp(m·ln(1/η)) with the exponent clamped,
//! so a thousand layers neither overflow to Inf nor make NaN; (1 - α)^l
//! underflows cleanly to 0.

use glam::Vec3;

/// Which of §5.2.3's effects use the layer count.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LayerEffects {
    /// Refraction and reflection at the nearest layer only.
    #[default]
    Single,
    /// Eq. 15 absorption and Eq. 16 refraction through all the layers.
    Multi,
}

impl LayerEffects {
    pub const ALL: [LayerEffects; 2] = [LayerEffects::Single, LayerEffects::Multi];

    pub fn name(self) -> &'static str {
        match self {
            Self::Single => "single",
            Self::Multi => "multi",
        }
    }
}

crate::by_name!(LayerEffects, "layer effect");

/// The parameters of the environment effects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnvironmentSettings {
    /// Index of refraction η of the transparent material (green; 1: no bending).
    pub eta: f32,
    /// Chromatic dispersion δ: red sees η - δ, blue η + δ.
    pub dispersion: f32,
    pub layer_effects: LayerEffects,
    /// Show the map behind everything (a skybox) instead of the flat background.
    pub skybox: bool,
    /// Draw the effects when the scene has a map (off: as if it had none,
    /// the cost baseline of `bench`'s `env-layers=off`).
    pub enabled: bool,
}

impl Default for EnvironmentSettings {
    fn default() -> Self {
        Self { eta: 1.5, dispersion: 0.02, layer_effects: LayerEffects::Single, skybox: true, enabled: true }
    }
}

/// Smallest index used: η ≤ 0 has no meaning, and 1/η must stay finite.
pub const MIN_ETA: f32 = 0.05;

impl EnvironmentSettings {
    /// η of channel `c` (0 red, 1 green, 2 blue).
    pub fn eta_of(&self, c: usize) -> f32 {
        (self.eta + (c as f32 - 1.0) * self.dispersion).max(MIN_ETA)
    }

    /// The layers the transmitted ray crosses for Eq. 16: 1, or 1 + those behind.
    pub fn crossings(&self, behind: f32) -> f32 {
        match self.layer_effects {
            LayerEffects::Single => 1.0,
            LayerEffects::Multi => 1.0 + behind.max(0.0),
        }
    }
}

/// The mirror direction of `d` about `n`.
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// The ray `d` refracted at a surface of normal `n` (facing the viewer) by
/// Eq. 16 with index `eta` through `crossings` interfaces; `None` under
/// total internal reflection.
pub fn refract(d: Vec3, n: Vec3, eta: f32, crossings: f32) -> Option<Vec3> {
    let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
    let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
    // (1/η)^m, the exponent clamped so that it stays finite.
    let ratio = (crossings * -eta.max(MIN_ETA).ln()).clamp(-80.0, 80.0).exp();
    let sin_t = ratio * sin_i;
    if sin_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin_t * sin_t).max(0.0).sqrt();
    let along = d + cos_i * n; // d's part along the surface, of length sin θ_I
    let tangent = along.try_normalize().unwrap_or(Vec3::ZERO);
    Some((tangent * sin_t - n * cos_t).try_normalize().unwrap_or(d))
}

/// Schlick's Fresnel reflectance for index `eta` at cos θ_I = `cos_i`.
pub fn schlick(eta: f32, cos_i: f32) -> f32 {
    let f0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
    f0 + (1.0 - f0) * (1.0 - cos_i.clamp(0.0, 1.0)).powi(5)
}

/// Eq. 15: the share of light that crosses `layers` layers of opacity `alpha`.
pub fn absorption(alpha: f32, layers: f32) -> f32 {
    (1.0 - alpha.clamp(0.0, 1.0)).powf(layers.max(0.0))
}

/// The nearest transparent layer of a pixel and what lies behind it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlassPixel {
    /// The nearest layer's shaded colour C_F and opacity α.
    pub front: Vec3,
    pub alpha: f32,
    /// Its normal, turned to face the viewer.
    pub normal: Vec3,
    /// The layers behind, composited premultiplied over nothing (C_b).
    pub behind: Vec3,
    /// Their transmittance (what reaches the environment), 0 when an opaque layer ends the ray.
    pub through: f32,
    /// How many transparent layers lie behind the nearest (l).
    pub layers_behind: f32,
    /// Whether an opaque layer ends the ray (no environment shows through).
    pub closed: bool,
}

/// The directions a glass pixel looks the environment up along: the
/// reflection, then the refraction of each channel (the reflection again
/// under total internal reflection), and whether each channel reflects totally.
pub fn glass_directions(d: Vec3, pixel: &GlassPixel, settings: &EnvironmentSettings) -> ([Vec3; 4], [bool; 3]) {
    let reflected = reflect(d, pixel.normal);
    let crossings = settings.crossings(pixel.layers_behind);
    let mut out = [reflected; 4];
    let mut total = [false; 3];
    for c in 0..3 {
        match refract(d, pixel.normal, settings.eta_of(c), crossings) {
            Some(t) => out[c + 1] = t,
            None => total[c] = true,
        }
    }
    (out, total)
}

/// The pixel's colour from the lookups `seen` along [`glass_directions`]
/// (`seen[0]` the reflection, `seen[1..4]` each channel's refraction).
pub fn glass_colour(
    d: Vec3,
    pixel: &GlassPixel,
    settings: &EnvironmentSettings,
    seen: [Vec3; 4],
    total: [bool; 3],
) -> Vec3 {
    let cos_i = (-d.dot(pixel.normal)).clamp(0.0, 1.0);
    let reaching = if pixel.closed {
        0.0
    } else {
        match settings.layer_effects {
            LayerEffects::Single => pixel.through,
            LayerEffects::Multi => absorption(pixel.alpha, pixel.layers_behind),
        }
    };
    let alpha = pixel.alpha.clamp(0.0, 1.0);
    let mut out = Vec3::ZERO;
    for c in 0..3 {
        let fresnel = if total[c] { 1.0 } else { schlick(settings.eta_of(c), cos_i) };
        let transmitted = pixel.behind[c] + reaching * seen[c + 1][c];
        let surface = alpha * pixel.front[c] + (1.0 - alpha) * transmitted;
        out[c] = fresnel * seen[0][c] + (1.0 - fresnel) * surface;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const D: Vec3 = Vec3::new(0.0, 0.0, -1.0);

    #[test]
    fn index_one_does_not_bend_and_reflects_only_at_grazing() {
        for n in [Vec3::Z, Vec3::new(0.3, 0.0, 1.0).normalize(), Vec3::new(0.0, -0.8, 0.6)] {
            let t = refract(D, n, 1.0, 1.0).unwrap();
            assert!((t - D).length() < 1e-5, "{t} for {n}");
            let t = refract(D, n, 1.0, 1000.0).unwrap();
            assert!((t - D).length() < 1e-5, "{t} for {n}, 1000 layers");
        }
        assert_eq!(schlick(1.0, 1.0), 0.0);
    }

    #[test]
    fn below_one_reflects_totally_at_grazing_angles() {
        let grazing = Vec3::new(0.0, 0.9, 0.1).normalize();
        assert!(refract(D, grazing, 0.7, 1.0).is_none());
        assert!(refract(D, Vec3::Z, 0.7, 1.0).is_some(), "head-on always transmits");
    }

    #[test]
    fn a_thousand_layers_stay_finite() {
        let n = Vec3::new(0.2, 0.1, 1.0).normalize();
        for eta in [0.05, 0.7, 1.5, 1e4] {
            let t = refract(D, n, eta, 1000.0);
            assert!(t.is_none_or(|t| t.is_finite() && (t.length() - 1.0).abs() < 1e-4), "{t:?} at η {eta}");
        }
        assert_eq!(absorption(0.5, 1000.0), 0.0);
        assert_eq!(absorption(0.0, 1000.0), 1.0);
        assert_eq!(absorption(1.0, 0.0), 1.0);
    }

    #[test]
    fn perpendicular_normals_give_finite_colours() {
        let n = Vec3::X; // across the view
        let pixel = GlassPixel {
            front: Vec3::splat(0.5),
            alpha: 0.5,
            normal: n,
            behind: Vec3::ZERO,
            through: 1.0,
            layers_behind: 0.0,
            closed: false,
        };
        let settings = EnvironmentSettings::default();
        let (dirs, total) = glass_directions(D, &pixel, &settings);
        assert!(dirs.iter().all(|d| d.is_finite()), "{dirs:?}");
        let c = glass_colour(D, &pixel, &settings, [Vec3::ONE; 4], total);
        assert!(c.is_finite(), "{c}");
        // Grazing: Schlick reflects everything.
        assert!((c - Vec3::ONE).length() < 1e-5, "{c}");
    }
}
