//! The JSON sidecar written beside a screenshot: model, mode, parameters,
//! camera and size, so that `pointblend render --camera FILE.json` reproduces
//! the image. The parameters are written by the descriptor table (each
//! parameter's key and text form), so a new parameter is recorded with no
//! code here; sidecars from before the table are read through [`legacy`].

use std::collections::BTreeMap;
use std::path::Path;

use glam::Vec3;
use serde::{Deserialize, Serialize};

use super::{Camera, CameraRequest, Parameter, Projection, RenderMode, RenderSettings, UpAxis};

mod legacy;
pub mod lights;

pub use legacy::LegacySettings;

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
    /// The window drew the file node by node (a COPC file or a URL, or a
    /// point file held in memory as a tree of nodes); absent: whole.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub nodes: bool,
    /// The files shown as layers, when the window showed several (`path`
    /// is then the window's own `.vpc` of them): `render A B --camera`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub layers: Vec<String>,
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
    /// Always written; absent in files from before orthographic views: perspective.
    #[serde(default)]
    pub projection: Projection,
}

/// A reproducible view.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    pub generator: String,
    pub model: SidecarModel,
    pub mode: String,
    pub size: [u32; 2],
    pub camera: SidecarCamera,
    /// Every rendering parameter's text form, by its key (the descriptor
    /// table's; [`Parameter::text`]). Absent ones take their defaults.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub parameters: BTreeMap<String, String>,
    /// The headlight's direction in eye space.
    #[serde(default = "headlight")]
    pub light_dir_eye: [f32; 3],
    /// The settings of sidecars written before the descriptor table (read, never written).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub settings: Option<LegacySettings>,
    /// The time shown, in seconds, for a moving scene (absent for a still one).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time: Option<f64>,
    /// The colour and opacity by attribute drawn (absent: the files' own).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub style: Option<crate::style::record::StyleRecord>,
    /// The clip region, in file coordinates (absent: nothing clipped).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub clip: Option<super::ClipRegion>,
    /// The scene lights, in file coordinates (absent: the headlight).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub lights: Vec<lights::LightRecord>,
    /// The viewer's profile, if one was open: its line and width, as
    /// `profile --line X1,Y1,X2,Y2 --width W` takes them (recorded; `render` draws no profile).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<ProfileRecord>,
    /// Each object's opacity and colour (a layer's each), where the window
    /// changed one from the file's (absent: as loaded).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub looks: Vec<super::look::Look>,
}

/// A profile's line (X1, Y1, X2, Y2, file coordinates) and its slab's width.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProfileRecord {
    pub line: [f64; 4],
    pub width: f64,
}

const UP_AXES: [(UpAxis, [f32; 3]); 6] = [
    (UpAxis::PosX, [1.0, 0.0, 0.0]),
    (UpAxis::NegX, [-1.0, 0.0, 0.0]),
    (UpAxis::PosY, [0.0, 1.0, 0.0]),
    (UpAxis::NegY, [0.0, -1.0, 0.0]),
    (UpAxis::PosZ, [0.0, 0.0, 1.0]),
    (UpAxis::NegZ, [0.0, 0.0, -1.0]),
];

impl SidecarCamera {
    /// The orbit parameters of `camera`.
    pub fn of(camera: &Camera) -> Self {
        let up = UP_AXES.iter().find(|(a, _)| *a == camera.up).map(|(_, v)| *v).unwrap_or([0.0, 1.0, 0.0]);
        SidecarCamera {
            target: camera.target.to_array(),
            distance: camera.distance,
            azimuth_deg: camera.azimuth_deg,
            elevation_deg: camera.elevation_deg,
            fov_y_deg: camera.fov_y_deg,
            up,
            scene_radius: camera.scene_radius,
            projection: camera.projection,
        }
    }

    /// The up axis its `up` names.
    pub fn up_axis(&self) -> Result<UpAxis, String> {
        UP_AXES
            .iter()
            .find(|(_, v)| *v == self.up)
            .map(|(a, _)| *a)
            .ok_or_else(|| format!("up {:?} is not an axis", self.up))
    }

    /// Checks that a camera can be drawn from: the rule every camera request
    /// gets ([`CameraRequest::check`]), a finite target and scene radius, and an axis for up.
    pub fn check(&self) -> Result<(), String> {
        let request = CameraRequest {
            azimuth: Some(self.azimuth_deg),
            elevation: Some(self.elevation_deg),
            distance: Some(self.distance),
            fov: Some(self.fov_y_deg),
            ..Default::default()
        };
        request.check().map_err(|e| format!("the camera's {e}"))?;
        if !self.target.iter().all(|v| v.is_finite()) {
            return Err(format!("the camera's target {:?} is not finite", self.target));
        }
        if !(self.scene_radius.is_finite() && self.scene_radius > 0.0) {
            return Err(format!("the camera's scene radius must be a positive number, not {}", self.scene_radius));
        }
        self.up_axis().map(|_| ())
    }

    pub fn camera(&self) -> Camera {
        Camera {
            target: Vec3::from_array(self.target),
            distance: self.distance,
            azimuth_deg: self.azimuth_deg,
            elevation_deg: self.elevation_deg,
            fov_y_deg: self.fov_y_deg,
            up: self.up_axis().unwrap_or(UpAxis::PosY),
            scene_radius: self.scene_radius,
            projection: self.projection,
        }
    }
}

impl Sidecar {
    pub fn new(model: SidecarModel, camera: &Camera, settings: &RenderSettings, size: (u32, u32)) -> Self {
        Sidecar {
            generator: format!("pointblend {}", env!("CARGO_PKG_VERSION")),
            model,
            mode: settings.mode.name().to_string(),
            size: [size.0, size.1],
            camera: SidecarCamera::of(camera),
            parameters: Parameter::ALL
                .into_iter()
                .filter_map(|p| Some((p.key().to_string(), p.text(settings)?)))
                .collect(),
            light_dir_eye: settings.shading.light_dir_eye.to_array(),
            settings: None,
            time: None,
            style: None,
            clip: None,
            lights: Vec::new(),
            profile: None,
            looks: Vec::new(),
        }
    }

    /// Reads and checks a sidecar file.
    pub fn read(path: &Path) -> Result<Self, SidecarError> {
        let shown = path.display().to_string();
        let text =
            crate::input::read_settings(path).map_err(|source| SidecarError::Io { path: shown.clone(), source })?;
        let bad = |message: String| SidecarError::Format { path: shown.clone(), message };
        // Through a JSON value: its numbers are read exactly as f64 (file coordinates to the last
        // bit), and one too large for an f32 field becomes infinite there, which the checks below
        // name, rather than a parse error at a column.
        let value: serde_json::Value = serde_json::from_str(&text).map_err(|e| bad(e.to_string()))?;
        let sidecar: Sidecar = serde_json::from_value(value).map_err(|e| bad(e.to_string()))?;
        // The checks the command line's flags get.
        sidecar.settings().and_then(|s| s.check()).map_err(bad)?;
        sidecar.camera.check().map_err(bad)?;
        if let Some(clip) = &sidecar.clip {
            clip.check().map_err(|e| bad(format!("clip: {e}")))?;
        }
        sidecar.looks.iter().try_for_each(|look| look.check()).map_err(|e| bad(format!("looks: {e}")))?;
        let lights = sidecar.lights().map_err(|e| bad(format!("lights: {e}")))?;
        super::Lights::new(&lights).map_err(|e| bad(format!("lights: {e}")))?;
        super::settings::check_image_size(sidecar.size[0], sidecar.size[1]).map_err(|e| bad(format!("size {e}")))?;
        Ok(sidecar)
    }

    /// Writes the sidecar as pretty JSON, atomically.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        let text = serde_json::to_string_pretty(self).map_err(std::io::Error::other)?;
        crate::output::write_atomically(path, text.as_bytes())
    }

    pub fn camera(&self) -> Camera {
        self.camera.camera()
    }

    /// The scene lights the view was lit by, in file coordinates (none: the headlight).
    pub fn lights(&self) -> Result<Vec<super::Light>, String> {
        self.lights.iter().map(lights::LightRecord::light).collect()
    }

    /// The settings, starting from the defaults for what the sidecar does not hold.
    pub fn settings(&self) -> Result<RenderSettings, String> {
        let mut settings = match &self.settings {
            Some(legacy) => legacy.settings()?,
            None => RenderSettings {
                shading: super::Shading { light_dir_eye: Vec3::from_array(self.light_dir_eye), ..Default::default() },
                ..Default::default()
            },
        };
        settings.mode = self.mode.parse::<RenderMode>()?;
        for (key, value) in &self.parameters {
            let parameter = Parameter::from_key(key).ok_or_else(|| format!("'{key}' is not a parameter"))?;
            parameter.apply(&mut settings, value)?;
        }
        Ok(settings)
    }
}

fn headlight() -> [f32; 3] {
    super::Shading::default().light_dir_eye.to_array()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sidecar_round_trips_through_its_file() {
        let mut camera = Camera::framing(Vec3::new(1.0, 2.0, 3.0), 4.0, 1.5);
        camera.up = UpAxis::NegZ;
        camera.azimuth_deg = 33.0;
        camera.projection = Projection::Ortho;
        let settings = RenderSettings {
            mode: RenderMode::ALL[1],
            radius_scale: 1.3,
            depth_step: 2.0,
            grouping: crate::grouping::GroupingSpec::wgc(6),
            peel_layers: 5,
            environment: super::super::environment_effects::EnvironmentSettings { eta: 1.7, ..Default::default() },
            ..Default::default()
        };
        let model = SidecarModel {
            name: "m.ply".into(),
            path: "/x/m.ply".into(),
            hash: "00ff".into(),
            splats: 7,
            nodes: false,
            layers: Vec::new(),
        };
        let mut sidecar = Sidecar::new(model, &camera, &settings, (300, 200));
        // File coordinates far from the origin come back to the last bit (the viewer's profile
        // line once came back one bit off: JSON numbers are now parsed exactly).
        let line = [1004.0077452159455, 2011.9775082895771, 1035.9657060557554, 2023.0247046292645];
        sidecar.profile = Some(ProfileRecord { line, width: 1.6000000000000014 });
        let clip = super::super::clip::ClipBox {
            min: [1004.0077452159455, 2000.0, -5.0],
            max: [1035.9657060557554, 2023.0247046292645, 90.0],
            hide: super::super::clip::Hidden::Inside,
        };
        sidecar.looks = vec![super::super::look::Look { opacity: 0.38, colour: Some([220, 60, 50]), clip: Some(clip) }];
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("view.json");
        sidecar.write(&path).unwrap();
        let back = Sidecar::read(&path).unwrap();
        assert_eq!(back, sidecar);
        assert_eq!(back.camera(), camera);
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.contains(r#""projection": "ortho""#), "{text}");
        assert_eq!(back.settings(), Ok(settings));
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
