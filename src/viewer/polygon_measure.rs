//! The polygon tool's measure: the horizontal area, the surface area and,
//! on request, the volume above a plane fitted along the border, or
//! between the other layers and a base layer (cut and fill, `measure
//! --base`), inside the polygon clicked on the view
//! ([`crate::inspect::area_volume`], what `measure --polygon` runs), over
//! the points of the model on screen in file coordinates (every layer's but
//! the base's; after the filters; a streamed file's selection). Measured
//! again only when the polygon, the volume switch, the base or the model
//! changes.

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
        let base = inspect.polygon_base.clone().filter(|_| inspect.polygon_volume);
        let key = (inspect.polygon.clone(), inspect.polygon_volume, base.clone(), model.generation);
        if self.polygon_report.as_ref().is_some_and(|(k, _)| *k == key) {
            return;
        }
        // The base layer's object: the shown layers are the scene's objects, in order.
        let base_object = match &base {
            Some(path) => match self.layers.iter().filter(|l| l.shown).position(|l| &l.path == path) {
                Some(k) if model.scene.objects.len() > 1 => Some((k, path.display().to_string())),
                _ => {
                    let why = format!("the base layer {} is not shown beside another", path.display());
                    self.polygon_report = Some((key, Err(why)));
                    return;
                }
            },
            None => None,
        };
        let volume = inspect.polygon_volume;
        let report = measure(&model.scene, &inspect.polygon, (volume, base_object), &model.cloud.units);
        self.polygon_report = Some((key, report));
    }

    /// The polygon's measure, once it has three vertices.
    pub fn polygon_report(&self) -> Option<&Result<PolygonReport, String>> {
        self.polygon_report.as_ref().map(|(_, report)| report)
    }
}

/// The points of the objects of `scene` `take` takes (by index), in file coordinates.
fn file_points(scene: &crate::scene::Scene, take: impl Fn(usize) -> bool) -> Vec<DVec3> {
    let mut points = Vec::new();
    for (_, object) in scene.objects.iter().enumerate().filter(|(k, _)| take(*k)) {
        points.extend((0..object.cloud.len()).map(|i| object.cloud.file_position(i)));
    }
    points
}

/// The measure inside `vertices`: with `volume`, against the border's
/// plane, or against `base` (an object's index and its layer's file).
fn measure(
    scene: &crate::scene::Scene,
    vertices: &[DVec3],
    (volume, base): (bool, Option<(usize, String)>),
    units: &crate::cloud::crs_units::CrsUnits,
) -> Result<PolygonReport, String> {
    let polygon = Polygon { vertices: vertices.iter().map(|v| v.truncate()).collect() };
    if polygon.area() == 0.0 {
        return Err("the polygon's area is zero".into());
    }
    let base_object = base.as_ref().map(|(k, _)| *k);
    let surface = file_points(scene, |k| Some(k) != base_object);
    let base_points = base_object.map(|b| file_points(scene, |k| k == b));
    let base_used = match (volume, &base_points) {
        (false, _) => None,
        (true, Some(points)) => Some(Base::Points(points)),
        (true, None) => Some(Base::BorderPlane),
    };
    let m = area_volume::area_and_volume(&polygon, &surface, None, base_used)?;
    let json = area_volume::report_json(&m, units, base.map(|(_, name)| name));
    Ok(PolygonReport {
        area_horizontal: m.area_horizontal,
        area_surface: m.area_surface,
        volume: m.volume.as_ref().map(|v| (v.above, v.below)),
        points: m.points,
        units: units.horizontal_name().to_string(),
        json: serde_json::to_string_pretty(&json).unwrap_or_default(),
    })
}
