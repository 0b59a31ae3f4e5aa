//! A camera path: views bookmarked in the viewer, saved as a views file,
//! and flown through by `pointblend render --path views.json --path-frames N`.
//!
//! The file is JSON: `{"generator": ..., "views": [camera, ...]}`, each
//! camera the orbit parameters a screenshot's sidecar holds
//! ([`SidecarCamera`]). Frame k of N sits at k/(N−1) of the way along the
//! path, the views equally spaced; between two views the target, elevation
//! and field of view move linearly, the azimuth the short way round, and the
//! distance geometrically (a zoom at a steady rate). Every view keeps the
//! first one's up axis and projection.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::Camera;
use super::sidecar::{SidecarCamera, SidecarError};

/// Views to fly through, in order.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewPath {
    #[serde(default)]
    pub generator: String,
    pub views: Vec<SidecarCamera>,
}

impl ViewPath {
    pub fn new(cameras: &[Camera]) -> Self {
        ViewPath {
            generator: format!("pointblend {}", env!("CARGO_PKG_VERSION")),
            views: cameras.iter().map(SidecarCamera::of).collect(),
        }
    }

    /// Reads and checks a views file: at least one view, each one a camera that can be drawn from.
    pub fn read(path: &Path) -> Result<Self, SidecarError> {
        let shown = path.display().to_string();
        let text =
            crate::input::read_settings(path).map_err(|source| SidecarError::Io { path: shown.clone(), source })?;
        let bad = |message: String| SidecarError::Format { path: shown.clone(), message };
        let views: ViewPath = serde_json::from_str(&text).map_err(|e| bad(format!("not a views file: {e}")))?;
        if views.views.is_empty() {
            return Err(bad("the views file lists no view".into()));
        }
        for (k, view) in views.views.iter().enumerate() {
            view.check().map_err(|e| bad(format!("view {}: {e}", k + 1)))?;
        }
        Ok(views)
    }

    /// Writes the views as pretty JSON, atomically.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        crate::output::write_atomically(path, text.as_bytes())
    }

    /// The camera at `t` in 0..=1 along the path.
    pub fn camera_at(&self, t: f32) -> Camera {
        let cameras: Vec<Camera> = self.views.iter().map(SidecarCamera::camera).collect();
        let last = cameras.len() - 1;
        let at = t.clamp(0.0, 1.0) * last as f32;
        let k = (at.floor() as usize).min(last.saturating_sub(1));
        let (a, b) = (cameras[k], cameras[(k + 1).min(last)]);
        let s = at - k as f32;
        let lerp = |x: f32, y: f32| x + (y - x) * s;
        let turn = (b.azimuth_deg - a.azimuth_deg + 180.0).rem_euclid(360.0) - 180.0;
        Camera {
            target: a.target.lerp(b.target, s),
            distance: a.distance * (b.distance / a.distance).powf(s),
            azimuth_deg: (a.azimuth_deg + turn * s).rem_euclid(360.0),
            elevation_deg: lerp(a.elevation_deg, b.elevation_deg),
            fov_y_deg: lerp(a.fov_y_deg, b.fov_y_deg),
            up: cameras[0].up,
            scene_radius: lerp(a.scene_radius, b.scene_radius),
            projection: cameras[0].projection,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_path_passes_through_its_views_and_turns_the_short_way() {
        let a = Camera { azimuth_deg: 350.0, distance: 1.0, ..Camera::framing(glam::Vec3::ZERO, 1.0, 1.0) };
        let b = Camera { azimuth_deg: 30.0, distance: 4.0, target: glam::Vec3::X, ..a };
        let path = ViewPath::new(&[a, b, a]);
        assert_eq!(path.camera_at(0.0), a);
        assert_eq!(path.camera_at(0.5).target, b.target);
        assert!((path.camera_at(0.5).distance - 4.0).abs() < 1e-5);
        let quarter = path.camera_at(0.25);
        assert!((quarter.azimuth_deg - 10.0).abs() < 1e-3, "{}", quarter.azimuth_deg);
        assert!((quarter.distance - 2.0).abs() < 1e-5, "geometric: {}", quarter.distance);
        assert_eq!(path.camera_at(1.0), a);
    }
}
