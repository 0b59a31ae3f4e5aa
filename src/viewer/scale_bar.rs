//! The scale bar of an orthographic view, in the units of the file's CRS.
//!
//! In orthographic, one point of the view spans the same length everywhere:
//! the window's height (2 · [`Camera::half_extent_y`], in the cloud's units)
//! over the view's height in points, times the frame's unit (file units per
//! unit of the frame, [`crate::scene::Scene::frame_placement`]). The bar's length is the longest 1, 2 or 5 × 10^k of those
//! units that fits in [`LONGEST_POINTS`]. A perspective view has no one
//! scale, so it gets no bar.

use egui::{Align2, Color32, FontId, Painter, Rect, Stroke, pos2};

use crate::cloud::crs_units::{CrsUnits, UNITS_OF_THE_FILE};
use crate::frame::Camera;

/// The longest the bar is drawn, in points.
pub const LONGEST_POINTS: f32 = 160.0;

/// A scale bar: its length in the file's units, on screen, and its label.
#[derive(Debug, Clone, PartialEq)]
pub struct ScaleBar {
    pub length: f64,
    pub points: f32,
    pub label: String,
}

/// The bar of a view of `view_height` points through `camera`, in a frame
/// whose unit is `unit` file units, in the file's `units`; `None` in perspective.
pub fn of(camera: &Camera, view_height: f32, unit: f64, units: &CrsUnits) -> Option<ScaleBar> {
    if !camera.is_ortho() || view_height <= 0.0 {
        return None;
    }
    let per_point = 2.0 * camera.half_extent_y() as f64 / view_height as f64 * unit;
    if !(per_point.is_finite() && per_point > 0.0) {
        return None;
    }
    let length = nice_length(per_point * LONGEST_POINTS as f64);
    let label = format!("{} {}", number(length), short_name(units.horizontal_name()));
    Some(ScaleBar { length, points: (length / per_point) as f32, label })
}

/// The longest 1, 2 or 5 × 10^k not above `at_most` (> 0).
pub fn nice_length(at_most: f64) -> f64 {
    let decade = 10f64.powf(at_most.log10().floor());
    [5.0, 2.0, 1.0].into_iter().map(|m| m * decade).find(|&l| l <= at_most * (1.0 + 1e-12)).unwrap_or(decade)
}

/// A length as written on the bar: no trailing zeros.
fn number(length: f64) -> String {
    if length >= 1.0 {
        format!("{length:.0}")
    } else {
        let decimals = (-length.log10().floor()) as usize;
        format!("{length:.decimals$}")
    }
}

/// The unit as a surveyor writes it beside a number.
pub fn short_name(unit: &str) -> &str {
    match unit {
        "metre" => "m",
        "international foot" => "ft",
        "US survey foot" => "US ft",
        "degree" => "°",
        UNITS_OF_THE_FILE => "units",
        other => other,
    }
}

/// Draws the bar over the view's lower right corner.
pub fn draw(painter: &Painter, view: Rect, bar: &ScaleBar) {
    let right = view.right() - 16.0;
    let y = view.bottom() - 16.0;
    let left = right - bar.points;
    let pad = Rect::from_min_max(pos2(left - 8.0, y - 24.0), pos2(right + 8.0, y + 8.0));
    painter.rect_filled(pad, 3.0, Color32::from_black_alpha(150));
    let stroke = Stroke::new(2.0, Color32::WHITE);
    painter.line_segment([pos2(left, y), pos2(right, y)], stroke);
    for x in [left, right] {
        painter.line_segment([pos2(x, y - 5.0), pos2(x, y + 3.0)], stroke);
    }
    let font = FontId::proportional(13.0);
    painter.text(pos2((left + right) / 2.0, y - 6.0), Align2::CENTER_BOTTOM, &bar.label, font, Color32::WHITE);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::crs_units::Unit;
    use crate::frame::Projection;

    #[test]
    fn a_nice_length_is_the_longest_one_two_or_five_that_fits() {
        assert_eq!(nice_length(7.3), 5.0);
        assert_eq!(nice_length(5.0), 5.0);
        assert_eq!(nice_length(19.9), 10.0);
        assert_eq!(nice_length(0.031), 0.02);
        assert_eq!(nice_length(2400.0), 2000.0);
    }

    #[test]
    fn the_bar_spans_its_length_at_the_view_scale_in_the_files_units() {
        let mut camera = Camera::framing(glam::Vec3::ZERO, 10.0, 1.0);
        let metres = CrsUnits { horizontal: Some(Unit::of_metres(1.0, "metre")), ..Default::default() };
        assert!(of(&camera, 500.0, 1.0, &metres).is_none(), "no bar in perspective");
        camera.projection = Projection::Ortho;
        let bar = of(&camera, 500.0, 1.0, &metres).unwrap();
        let per_point = 2.0 * camera.half_extent_y() as f64 / 500.0;
        assert!((bar.points as f64 * per_point - bar.length).abs() < 1e-6 * bar.length);
        assert!(bar.points <= LONGEST_POINTS && bar.points > LONGEST_POINTS * 0.4);
        assert!(bar.label.ends_with(" m"), "{}", bar.label);
        // A frame in thousandths of the file's units: the same view spans 1000 × fewer file units.
        let scaled = of(&camera, 500.0, 1e-3, &metres).unwrap();
        assert!((scaled.length - bar.length / 1000.0).abs() < 1e-9 * bar.length, "{scaled:?}");
        let feet = CrsUnits { horizontal: Some(Unit::of_metres(1200.0 / 3937.0, "")), ..Default::default() };
        assert!(of(&camera, 500.0, 1.0, &feet).unwrap().label.ends_with(" US ft"));
    }
}
