//! The status line under the view: the file's coordinates (f64, in its
//! CRS) of the surface under the cursor, with the EPSG code and the units.
//!
//! They come from the depth the frame on screen already has
//! ([`crate::frame::FrontDepth`], two-pass's visibility depth, read back
//! with the frame): the cursor's place in the frame's image gives a ray
//! and its pixel a depth, and the frame's placement turns the point into
//! file coordinates. Nothing is picked again. A mode whose frame keeps no
//! such depth says so.

use glam::{DVec2, DVec3};

use super::app::ViewerApp;
use crate::cloud::crs_units::CrsUnits;

/// What is under the cursor.
#[derive(Debug, Clone, PartialEq)]
pub enum Reading {
    /// The surface's file coordinates.
    Point(DVec3),
    /// The frame drew nothing there.
    Nothing,
    /// The frame on screen keeps no depth (its mode is not two-pass, or it is not drawn yet).
    NoDepth,
}

impl ViewerApp {
    /// What lies under `cursor` (points) in the frame on screen; `None` off the view.
    pub fn reading_at(&self, cursor: egui::Pos2) -> Option<Reading> {
        let rect = self.view_rect;
        if !rect.contains(cursor) {
            return None;
        }
        let (Some(model), Some(shown)) = (&self.model, &self.shown) else { return Some(Reading::NoDepth) };
        let Some(front) = shown.front_depth.as_ref().filter(|_| shown.key.generation == model.generation) else {
            return Some(Reading::NoDepth);
        };
        let (w, h) = front.size;
        let at = DVec2::new(
            f64::from((cursor.x - rect.left()) / rect.width()) * f64::from(w),
            f64::from((cursor.y - rect.top()) / rect.height()) * f64::from(h),
        );
        let (origin, unit) = model.scene.frame_placement();
        Some(front.point_at(at).map_or(Reading::Nothing, |p| Reading::Point(origin + p * unit)))
    }

    /// The view depth of the surface under the pointer in the frame on screen (fly mode's speed).
    pub(super) fn depth_under_pointer(&self) -> Option<f32> {
        let (pointer, shown) = (self.pointer?, self.shown.as_ref()?);
        let front = shown.front_depth.as_ref()?;
        let rect = self.view_rect;
        let (w, h) = front.size;
        let x = (pointer.x - rect.left()) / rect.width() * w as f32;
        let y = (pointer.y - rect.top()) / rect.height() * h as f32;
        (x >= 0.0 && y >= 0.0).then(|| front.depth_at(x as u32, y as u32)).flatten()
    }

    /// The file coordinates of the surface under the pointer, if it is over one.
    pub fn cursor_coordinates(&self) -> Option<DVec3> {
        match self.status_reading() {
            Some(Reading::Point(p)) => Some(p),
            _ => None,
        }
    }

    fn status_reading(&self) -> Option<Reading> {
        self.reading_at(self.pointer?)
    }

    /// The status line's text.
    pub fn status_line(&self) -> String {
        let units = self.model.as_ref().map(|m| m.cloud.units.clone()).unwrap_or_default();
        match self.status_reading() {
            None => "move the cursor over the view for its coordinates".into(),
            Some(Reading::Point(p)) => describe(p, &units),
            Some(Reading::Nothing) => "no surface under the cursor".into(),
            Some(Reading::NoDepth) => {
                "no coordinates: they are read from two-pass's depth, which this frame has not".into()
            }
        }
    }

    /// The status line under the view.
    pub(super) fn status_bar(&mut self, ui: &mut egui::Ui) {
        self.pointer = ui.ctx().input(|i| i.pointer.hover_pos());
        // One line whatever the text, so the view's height does not change with it.
        egui::Panel::bottom("status").show(ui, |ui| {
            ui.add(egui::Label::new(egui::RichText::new(self.status_line()).monospace()).truncate());
        });
    }
}

/// x, y and z with the units and the EPSG code.
pub fn describe(p: DVec3, units: &CrsUnits) -> String {
    let (h, v) = (units.horizontal_name(), units.vertical_name());
    // Degrees need eight decimals for a millimetre; linear units three.
    let decimals = if h == "degree" { 8 } else { 3 };
    let unit_text = if h == v { h.to_string() } else { format!("x, y in {h}, z in {v}") };
    let code = units.epsg.map_or("no EPSG code".to_string(), |c| format!("EPSG:{c}"));
    format!("x {:.decimals$}  y {:.decimals$}  z {:.3}  ({unit_text}; {code})", p.x, p.y, p.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cloud::crs_units::Unit;

    #[test]
    fn the_line_gives_the_coordinates_with_the_units_and_the_code() {
        let utm = CrsUnits { epsg: Some(32611), horizontal: Some(Unit::of_metres(1.0, "metre")), vertical: None };
        let line = describe(DVec3::new(500123.4567, 4100456.25, 101.5), &utm);
        assert_eq!(line, "x 500123.457  y 4100456.250  z 101.500  (metre; EPSG:32611)");
        let feet = CrsUnits {
            epsg: None,
            horizontal: Some(Unit::of_metres(1200.0 / 3937.0, "")),
            vertical: Some(Unit::of_metres(1.0, "metre")),
        };
        assert!(describe(DVec3::ZERO, &feet).ends_with("(x, y in US survey foot, z in metre; no EPSG code)"));
    }
}
