//! Translucent shadows: the light each splat receives from each scene light
//! (its shadow coefficient, Gunjee et al. §4.1), by translucent shadow
//! mapping ([`table`]) or by exact shadow rays ([`rays`], the ruler), with
//! one per-layer absorbance for both ([`layers`]).
//!
//! Every GPU mode shades a lit splat with these coefficients (one byte per
//! light and splat, uploaded beside the splats); the CPU reference casts its
//! own shadow ray from each layer it shades.

pub mod layers;
pub mod rays;
pub mod table;

use glam::Vec3;

use crate::cloud::PointCloud;
use crate::frame::{Light, LightKind, RenderSettings, ShadowMethod, SplatKernel};

/// A shadow computation that cannot run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShadowError {
    #[error(
        "a TSM table of {cells} cells needs about {need} for {entries} entries, more than the {limit} it may take; try a smaller table, e.g. --shadows tsm-{hint}"
    )]
    TooLarge { cells: String, entries: u64, need: String, limit: String, hint: String },
}

/// The splats lights shine on, as the frame draws them.
#[derive(Clone, Copy)]
pub struct ShadowInput<'a> {
    /// World-space splats (a flattened scene).
    pub cloud: &'a PointCloud,
    pub radius_scale: f32,
    /// Read opacity; else every splat is opaque (what opaque modes draw).
    pub transparent: bool,
    /// Entries within this distance along a light direction join one layer.
    pub epsilon: f32,
    pub kernel: SplatKernel,
    /// What is cut away: a caster's hit whose point is not kept casts no shadow.
    pub clip: crate::frame::Clip,
}

impl<'a> ShadowInput<'a> {
    /// The input of a frame of `cloud` rendered with `settings`;
    /// `transparent`: the frame reads opacity.
    pub fn new(cloud: &'a PointCloud, settings: &RenderSettings, transparent: bool) -> Self {
        Self {
            cloud,
            radius_scale: settings.radius_scale,
            transparent,
            epsilon: settings.epsilon(cloud.mean_radius()),
            kernel: settings.kernel,
            clip: settings.clip,
        }
    }

    fn radius(&self, i: usize) -> f32 {
        self.cloud.radii[i] * self.radius_scale
    }

    fn opacity(&self, i: usize) -> f32 {
        if self.transparent { self.cloud.opacity[i].clamp(0.0, 1.0) } else { 1.0 }
    }

    /// Whether splat `i`'s normal points towards `light`.
    fn faces(&self, i: usize, light: &Light) -> bool {
        let p = self.cloud.positions[i];
        let to_light = match light.kind {
            LightKind::Point(position) => position - p,
            LightKind::Directional(d) => -d,
        };
        self.cloud.normals[i].dot(to_light) > 0.0
    }

    /// The centre and radius of a sphere around every splat.
    fn bounds(&self) -> (Vec3, f32) {
        let Some(bounds) = self.cloud.bounds() else { return (Vec3::ZERO, 1.0) };
        let centre = bounds.center();
        let positions = &self.cloud.positions;
        let max_radius = (0..self.cloud.len()).map(|i| self.radius(i)).fold(0.0f32, f32::max);
        let reach = positions.iter().map(|p| p.distance(centre)).fold(0.0f32, f32::max);
        (centre, (reach + max_radius).max(1e-6))
    }
}

/// The light each splat receives: per light, per splat, the transmittance on
/// the way from the light (1: unshadowed).
#[derive(Debug, Clone, Default)]
pub struct ShadowCoefficients {
    pub per_light: Vec<Vec<f32>>,
    /// What the tables took (empty for exact rays): one per light.
    pub tables: Vec<table::TableStats>,
    /// Seconds to compute them all.
    pub seconds: f64,
}

impl ShadowCoefficients {
    /// Splat `i`'s coefficients as bytes, one per light (the GPU's unorm8).
    pub fn bytes(&self, i: usize) -> [u8; crate::frame::lights::MAX_LIGHTS] {
        let mut out = [255u8; crate::frame::lights::MAX_LIGHTS];
        for (slot, light) in out.iter_mut().zip(&self.per_light) {
            *slot = (light[i].clamp(0.0, 1.0) * 255.0).round() as u8;
        }
        out
    }
}

/// The shadow coefficients of `input`'s splats for `lights` by `method`,
/// with tables of `cells` for TSM.
pub fn coefficients(
    input: &ShadowInput,
    lights: &[Light],
    method: ShadowMethod,
    cells: [u32; 2],
) -> Result<ShadowCoefficients, ShadowError> {
    let started = std::time::Instant::now();
    let n = input.cloud.len();
    let mut out = ShadowCoefficients::default();
    match method {
        ShadowMethod::Off => out.per_light = lights.iter().map(|_| vec![1.0; n]).collect(),
        ShadowMethod::Exact => {
            let caster = rays::ShadowRays::new(input);
            out.per_light = lights.iter().map(|light| caster.per_splat(light)).collect();
        }
        ShadowMethod::Tsm => {
            for light in lights {
                let (t, stats) = table::build(input, light, cells)?;
                out.per_light.push(t);
                out.tables.push(stats);
            }
        }
    }
    out.seconds = started.elapsed().as_secs_f64();
    Ok(out)
}
