//! The benchmark views around a model: the standard ones, or a camera
//! path's (`--path`, the views file `render --path` flies through).
//!
//! All start from the model's default camera: its front, a side view from
//! above, the back from higher up, a close-up (0.45x the framing distance:
//! large splats, crossing the image border) and a steep view from above in
//! which most surfaces are seen at grazing angles. A single-view scan is
//! one-sided (its back faces are culled), so its views stay within 40° of the
//! scanner's direction, the grazing one looking steeply down across it.

use crate::cloud::PointCloud;
use crate::frame::{Camera, CameraRequest, ViewPath};

/// A named camera.
#[derive(Debug, Clone)]
pub struct NamedView {
    pub name: String,
    pub camera: Camera,
}

/// (name, azimuth offset, elevation offset, distance factor)
const VIEWS: [(&str, f32, f32, f32); 5] = [
    ("front", 0.0, 10.0, 1.0),
    ("side", 90.0, 25.0, 1.0),
    ("back-top", 200.0, 40.0, 1.0),
    ("close-up", 30.0, 15.0, 0.45),
    ("grazing", 60.0, 78.0, 1.0),
];

/// The same for a single-view scan, around the scanner's direction.
const SINGLE_VIEW_SCAN_VIEWS: [(&str, f32, f32, f32); 5] = [
    ("front", 0.0, 0.0, 1.0),
    ("side", 35.0, 10.0, 1.0),
    ("above", -25.0, 30.0, 1.0),
    ("close-up", 15.0, 5.0, 0.45),
    ("grazing", 0.0, 55.0, 1.0),
];

/// The first `count` standard views (at most 5) of `cloud` for images of
/// `aspect`; when `asked` asks for anything, the first is the camera it
/// makes (named "asked") and the others turn around that one.
pub fn standard_views(cloud: &PointCloud, aspect: f32, count: usize, asked: &CameraRequest) -> Vec<NamedView> {
    let mut base = Camera::default_for(cloud, aspect);
    // A projection alone projects every standard view.
    let projection_only = CameraRequest { projection: asked.projection, ..Default::default() };
    if let Some(projection) = asked.projection {
        base.projection = projection;
    }
    if !asked.is_empty() && *asked != projection_only {
        // Checked by the command line before the run.
        let camera = asked.camera(cloud, aspect).unwrap_or(base);
        let mut views = vec![NamedView { name: "asked".into(), camera }];
        views.extend(turned_views(camera, cloud, aspect).into_iter().skip(1).take(count.saturating_sub(1)));
        return views;
    }
    turned_views(base, cloud, aspect).into_iter().take(count).collect()
}

/// Every standard view, turned from `base`.
fn turned_views(base: Camera, cloud: &PointCloud, aspect: f32) -> Vec<NamedView> {
    let table = if cloud.scanner_position.is_some() { &SINGLE_VIEW_SCAN_VIEWS } else { &VIEWS };
    table
        .iter()
        .map(|&(name, az, el, factor)| {
            let mut camera = base;
            camera.azimuth_deg += az;
            camera.elevation_deg = (camera.elevation_deg + el).clamp(-89.0, 89.0);
            camera.distance = camera.fit_distance(&cloud.positions, aspect) * factor;
            NamedView { name: name.into(), camera }
        })
        .collect()
}

/// The views of a camera path (`--path`), in path order: `path-0`, `path-1`...
pub fn path_views(path: &ViewPath) -> Vec<NamedView> {
    let cameras = path.views.iter().map(crate::frame::sidecar::SidecarCamera::camera);
    cameras.enumerate().map(|(k, camera)| NamedView { name: format!("path-{k}"), camera }).collect()
}

/// The views a model is measured from: the path's when one is given, else
/// the standard views of `cloud` (see [`standard_views`]).
pub fn views_of(config: &super::BenchConfig, cloud: &PointCloud) -> Vec<NamedView> {
    match &config.path {
        Some(path) => path_views(path),
        None => standard_views(cloud, config.width as f32 / config.height as f32, config.views, &config.camera),
    }
}

/// Most views [`standard_views`] can give.
pub const MAX_VIEWS: usize = VIEWS.len();
