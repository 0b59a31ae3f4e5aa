//! The polygon tool's measure: the horizontal area, the surface area and,
//! on request, the volume above a plane fitted along the border, inside the
//! polygon clicked on the view ([`crate::inspect::area_volume`], what
//! `measure --polygon` runs), over the points of the model on screen in
//! file coordinates (every layer's; after the filters; a streamed file's
//! selection). Measured again only when the polygon, the volume switch or
//! the model changes.

use glam::DVec3;

use super::app::ViewerApp;
use super::state::PolygonReport;
use crate::inspect::area_volume::{self, Base};
use crate::inspect::polygon::Polygon;

impl ViewerApp {
    /// Measures the polygon if it, the volume switch or the model changed.
    pub(super) fn measure_polygon(&mut self) {
        let inspect = &self.ui.inspect;
        let Some(model) = self.model.as_ref().filter(|_| inspect.polygon.len() >= 3) else {
            self.polygon_report = None;
            return;
        };
        let key = (inspect.polygon.clone(), inspect.polygon_volume, model.generation);
        if self.polygon_report.as_ref().is_some_and(|(k, _)| *k == key) {
            return;
        }
        let report = measure(&model.scene, &inspect.polygon, inspect.polygon_volume, &model.cloud.units);
        self.polygon_report = Some((key, report));
    }

    /// The polygon's measure, once it has three vertices.
    pub fn polygon_report(&self) -> Option<&Result<PolygonReport, String>> {
        self.polygon_report.as_ref().map(|(_, report)| report)
    }
}

/// The points of every object of `scene`, in file coordinates.
fn file_points(scene: &crate::scene::Scene) -> Vec<DVec3> {
    let mut points = Vec::new();
    for object in &scene.objects {
        points.extend((0..object.cloud.len()).map(|i| object.cloud.file_position(i)));
    }
    points
}

fn measure(
    scene: &crate::scene::Scene,
    vertices: &[DVec3],
    volume: bool,
    units: &crate::cloud::crs_units::CrsUnits,
) -> Result<PolygonReport, String> {
    let polygon = Polygon { vertices: vertices.iter().map(|v| v.truncate()).collect() };
    if polygon.area() == 0.0 {
        return Err("the polygon's area is zero".into());
    }
    let base = volume.then_some(Base::BorderPlane);
    let m = area_volume::area_and_volume(&polygon, &file_points(scene), None, base)?;
    let json = area_volume::report_json(&m, units, None);
    Ok(PolygonReport {
        area_horizontal: m.area_horizontal,
        area_surface: m.area_surface,
        volume: m.volume.as_ref().map(|v| (v.above, v.below)),
        points: m.points,
        units: units.horizontal_name().to_string(),
        json: serde_json::to_string_pretty(&json).unwrap_or_default(),
    })
}
