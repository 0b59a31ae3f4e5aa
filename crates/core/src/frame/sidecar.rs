//! The JSON sidecar written beside a screenshot: model, mode, parameters,
//! camera and size, so that `pointblend render --camera FILE.json` reproduces
//! the image.

use std::path::Path;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::{Camera, Quality, RenderMode, RenderSettings, UpAxis};
use crate::grouping::GroupingSpec;

/// Errors reading a sidecar.
#[derive(Debug, thiserror::Error)]
pub enum SidecarError {
    #[error("{path}: {source}")]
    Io { path: String, source: std::io::Error },
    #[error("{path}: not a pointblend view file: {message}")]
    Format { path: String, message: String },
}

/// The model a view was taken of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SidecarModel {
    pub name: String,
    pub path: String,
    /// FNV-1a 64 of the file's bytes, as 16 hex digits.
    pub hash: String,
    pub splats: usize,
}

/// The camera, as the orbit parameters [`Camera`] uses.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SidecarCamera {
    pub target: [f32; 3],
    pub distance: f32,
    pub azimuth_deg: f32,
    pub elevation_deg: f32,
    pub fov_y_deg: f32,
    pub up: [f32; 3],
    pub scene_radius: f32,
}

/// Everything besides the camera that decided the frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SidecarSettings {
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
    super::Prefilter::None.to_string()
}

fn one() -> f32 {
    1.0
}

fn bucket() -> String {
    crate::spatial::order::OrderKind::Bucket.to_string()
}

/// A reproducible view.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    pub generator: String,
    pub model: SidecarModel,
    pub mode: String,
    pub size: [u32; 2],
    pub camera: SidecarCamera,
    pub settings: SidecarSettings,
    /// The time shown, in seconds, for a moving scene (absent for a still one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
}

const UP_AXES: [(UpAxis, [f32; 3]); 6] = [
    (UpAxis::PosX, [1.0, 0.0, 0.0]),
    (UpAxis::NegX, [-1.0, 0.0, 0.0]),
    (UpAxis::PosY, [0.0, 1.0, 0.0]),
    (UpAxis::NegY, [0.0, -1.0, 0.0]),
    (UpAxis::PosZ, [0.0, 0.0, 1.0]),
    (UpAxis::NegZ, [0.0, 0.0, -1.0]),
];

impl Sidecar {
    pub fn new(model: SidecarModel, camera: &Camera, settings: &RenderSettings, size: (u32, u32)) -> Self {
        let up = UP_AXES.iter().find(|(a, _)| *a == camera.up).map(|(_, v)| *v).unwrap_or([0.0, 1.0, 0.0]);
        Sidecar {
            generator: format!("pointblend {}", env!("CARGO_PKG_VERSION")),
            model,
            mode: settings.mode.name().to_string(),
            size: [size.0, size.1],
            camera: SidecarCamera {
                target: camera.target.to_array(),
                distance: camera.distance,
                azimuth_deg: camera.azimuth_deg,
                elevation_deg: camera.elevation_deg,
                fov_y_deg: camera.fov_y_deg,
                up,
                scene_radius: camera.scene_radius,
            },
            settings: SidecarSettings {
                filtered: settings.quality == Quality::Filtered,
                epsilon_scale: settings.epsilon_scale,
                depth_step: settings.depth_step,
                radius_scale: settings.radius_scale,
                backface_culling: settings.backface_culling,
                voronoi: settings.voronoi,
                lighting: settings.lighting,
                grouping: settings.grouping.to_string(),
                light_dir_eye: settings.shading.light_dir_eye.to_array(),
                background: settings.shading.background.to_array(),
                order: settings.order.to_string(),
                prefilter: settings.prefilter.to_string(),
                point_budget: settings.point_budget,
                supersample: settings.supersample,
                hybrid_px: (settings.hybrid_pixels != super::settings::DEFAULT_HYBRID_PIXELS)
                    .then_some(settings.hybrid_pixels.min(f32::MAX)),
            },
            time: None,
        }
    }

    /// Reads and checks a sidecar file.
    pub fn read(path: &Path) -> Result<Self, SidecarError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SidecarError::Io { path: shown.clone(), source })?;
        let sidecar: Sidecar = serde_json::from_str(&text)
            .map_err(|e| SidecarError::Format { path: shown.clone(), message: e.to_string() })?;
        let bad = |message: String| SidecarError::Format { path: shown.clone(), message };
        // The checks the command line's flags get.
        sidecar.settings().and_then(|s| s.check()).map_err(bad)?;
        sidecar.up_axis().map_err(bad)?;
        let c = &sidecar.camera;
        let finite = c
            .target
            .iter()
            .chain([c.distance, c.azimuth_deg, c.elevation_deg, c.fov_y_deg, c.scene_radius].iter())
            .all(|v| v.is_finite());
        if !finite || c.distance <= 0.0 || !(c.fov_y_deg > 0.0 && c.fov_y_deg < 180.0) || c.scene_radius <= 0.0 {
            return Err(bad("the camera has a non-finite or out-of-range value".into()));
        }
        super::settings::check_image_size(sidecar.size[0], sidecar.size[1]).map_err(|e| bad(format!("size {e}")))?;
        Ok(sidecar)
    }

    /// Writes the sidecar as pretty JSON, atomically.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        crate::output::write_atomically(path, text.as_bytes())
    }

    fn up_axis(&self) -> Result<UpAxis, String> {
        UP_AXES
            .iter()
            .find(|(_, v)| *v == self.camera.up)
            .map(|(a, _)| *a)
            .ok_or_else(|| format!("up {:?} is not an axis", self.camera.up))
    }

    pub fn camera(&self) -> Camera {
        let c = &self.camera;
        Camera {
            target: Vec3::from_array(c.target),
            distance: c.distance,
            azimuth_deg: c.azimuth_deg,
            elevation_deg: c.elevation_deg,
            fov_y_deg: c.fov_y_deg,
            up: self.up_axis().unwrap_or(UpAxis::PosY),
            scene_radius: c.scene_radius,
        }
    }

    /// The settings, starting from the defaults for what the sidecar does not hold.
    pub fn settings(&self) -> Result<RenderSettings, String> {
        let s = &self.settings;
        let mut settings = RenderSettings {
            mode: self.mode.parse::<RenderMode>()?,
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
                .unwrap_or(super::settings::DEFAULT_HYBRID_PIXELS),
            ..RenderSettings::default()
        };
        settings.shading.light_dir_eye = Vec3::from_array(s.light_dir_eye);
        settings.shading.background = Vec3::from_array(s.background);
        Ok(settings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sidecar_round_trips_through_its_file() {
        let mut camera = Camera::framing(Vec3::new(1.0, 2.0, 3.0), 4.0, 1.5);
        camera.up = UpAxis::NegZ;
        camera.azimuth_deg = 33.0;
        let settings = RenderSettings {
            mode: RenderMode::ALL[1],
            radius_scale: 1.3,
            depth_step: 2.0,
            grouping: GroupingSpec::wgc(6),
            ..Default::default()
        };
        let model = SidecarModel { name: "m.ply".into(), path: "/x/m.ply".into(), hash: "00ff".into(), splats: 7 };
        let sidecar = Sidecar::new(model, &camera, &settings, (300, 200));
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("view.json");
        sidecar.write(&path).unwrap();
        let back = Sidecar::read(&path).unwrap();
        assert_eq!(back, sidecar);
        assert_eq!(back.camera(), camera);
        assert_eq!(back.settings(), Ok(settings));
    }

    #[test]
    fn a_sidecar_from_before_the_depth_step_setting_reads_as_step_1() {
        let settings = RenderSettings { depth_step: 3.0, ..Default::default() };
        let model = SidecarModel { name: "m.ply".into(), path: "/x/m.ply".into(), hash: "00ff".into(), splats: 7 };
        let sidecar = Sidecar::new(model, &Camera::framing(Vec3::ZERO, 1.0, 1.0), &settings, (30, 20));
        let mut json: serde_json::Value = serde_json::to_value(&sidecar).unwrap();
        json["settings"].as_object_mut().unwrap().remove("depth_step");
        let old: Sidecar = serde_json::from_value(json).unwrap();
        assert_eq!(old.settings().unwrap().depth_step, 1.0, "what such a sidecar's frame was rendered with");
    }

    #[test]
    fn a_broken_sidecar_names_the_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.json");
        std::fs::write(&path, "{\"mode\": 3}").unwrap();
        let message = Sidecar::read(&path).unwrap_err().to_string();
        assert!(message.contains("bad.json") && message.contains("not a pointblend view file"), "{message}");
    }
}
