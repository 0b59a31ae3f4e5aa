//! The settings of sidecars written before the descriptor table, which
//! named a fixed set of fields. Such files still open: their fields become
//! settings here, and absent fields take the values those files were
//! rendered with.

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::super::{Quality, RenderSettings};
use crate::grouping::GroupingSpec;

/// Everything besides the camera that decided the frame, as sidecars wrote it
/// before the descriptor table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LegacySettings {
    pub filtered: bool,
    pub epsilon_scale: f32,
    /// Eq. 10's step in multiples of ε (1 in sidecars written before it was a setting).
    #[serde(default = "one")]
    pub depth_step: f32,
    pub radius_scale: f32,
    pub backface_culling: bool,
    pub voronoi: bool,
    pub lighting: bool,
    pub grouping: String,
    pub light_dir_eye: [f32; 3],
    pub background: [f32; 3],
    /// The back-to-front order (`bucket` in sidecars written before it was a choice).
    #[serde(default = "bucket")]
    pub order: String,
    /// The splat passes' prefilter (`none` in sidecars written before it was a choice).
    #[serde(default = "no_prefilter")]
    pub prefilter: String,
    /// The point budget, if the frame had one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub point_budget: Option<u32>,
    /// Rays per pixel side of a reference frame (1 when absent).
    #[serde(default = "one_ray", skip_serializing_if = "is_one_ray")]
    pub supersample: u32,
    /// The hybrid objects' triangle threshold in pixels (the default when
    /// absent; infinity is written as f32::MAX, which JSON can hold).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub hybrid_px: Option<f32>,
}

fn one_ray() -> u32 {
    1
}

fn is_one_ray(n: &u32) -> bool {
    *n == 1
}

fn no_prefilter() -> String {
    super::super::Prefilter::None.to_string()
}

fn one() -> f32 {
    1.0
}

fn bucket() -> String {
    crate::spatial::order::OrderKind::Bucket.to_string()
}

impl LegacySettings {
    pub fn settings(&self) -> Result<RenderSettings, String> {
        let s = self;
        let mut settings = RenderSettings {
            quality: if s.filtered { Quality::Filtered } else { Quality::Unfiltered },
            epsilon_scale: s.epsilon_scale,
            depth_step: s.depth_step,
            radius_scale: s.radius_scale,
            backface_culling: s.backface_culling,
            grouping: s.grouping.parse::<GroupingSpec>()?,
            voronoi: s.voronoi,
            lighting: s.lighting,
            order: s.order.parse()?,
            prefilter: s.prefilter.parse()?,
            point_budget: s.point_budget,
            supersample: s.supersample,
            // f32::MAX stands for infinity (splats only), which JSON cannot hold.
            hybrid_pixels: s
                .hybrid_px
                .filter(|p| *p >= 0.0)
                .map(|p| if p >= f32::MAX { f32::INFINITY } else { p })
                .unwrap_or(super::super::settings::DEFAULT_HYBRID_PIXELS),
            ..RenderSettings::default()
        };
        settings.shading.light_dir_eye = Vec3::from_array(s.light_dir_eye);
        settings.shading.background = Vec3::from_array(s.background);
        Ok(settings)
    }
}

#[cfg(test)]
mod tests {
    use super::super::Sidecar;

    /// A sidecar as pointblend wrote them before the descriptor table (and
    /// before the depth step was a setting).
    const OLD: &str = r#"{
      "generator": "pointblend 0.1.0",
      "model": {"name": "m.ply", "path": "/x/m.ply", "hash": "00ff", "splats": 7},
      "mode": "deferred",
      "size": [30, 20],
      "camera": {"target": [0, 0, 0], "distance": 2, "azimuth_deg": 10, "elevation_deg": 5,
                 "fov_y_deg": 35, "up": [0, 1, 0], "scene_radius": 1},
      "settings": {"filtered": true, "epsilon_scale": 0.8, "radius_scale": 1.0, "backface_culling": false,
                   "voronoi": true, "lighting": true, "grouping": "wgc-k6",
                   "light_dir_eye": [0, 0, 1], "background": [0.5, 0.25, 0]}
    }"#;

    #[test]
    fn a_sidecar_from_before_the_table_reads_with_the_values_it_was_rendered_with() {
        let old: Sidecar = serde_json::from_str(OLD).unwrap();
        // Written before orthographic views: perspective.
        assert_eq!(old.camera().projection, crate::frame::Projection::Perspective);
        let s = old.settings().unwrap();
        assert_eq!(s.mode.name(), "deferred");
        assert_eq!(s.depth_step, 1.0, "what such a sidecar's frame was rendered with");
        assert_eq!((s.epsilon_scale, s.backface_culling), (0.8, false));
        assert_eq!(s.grouping.to_string(), "wgc-k6");
        assert_eq!(s.shading.background, glam::Vec3::new(0.5, 0.25, 0.0));
    }
}
