//! The Inspect section of the left panel: what a click does (look, pick,
//! measure), the clip box (on, which side it hides, its extent in file
//! coordinates), the last pick's layers and the measurement, with a button
//! that copies the measurement as CSV.

use egui::{RichText, Ui};

use super::state::{Action, Tool, UiState};
use crate::frame::clip::Hidden;

pub fn inspect_section(ui: &mut Ui, state: &mut UiState, has_model: bool) {
    ui.heading("Inspect");
    let inspect = &mut state.inspect;
    ui.horizontal_wrapped(|ui| {
        ui.label("click:");
        ui.radio_value(&mut inspect.tool, Tool::Look, "look").on_hover_text("the view only moves the camera");
        ui.radio_value(&mut inspect.tool, Tool::Pick, "pick").on_hover_text("list every layer under the pixel");
        ui.radio_value(&mut inspect.tool, Tool::Measure, "measure")
            .on_hover_text("add the surface under the pixel to the measured polyline");
        ui.radio_value(&mut inspect.tool, Tool::Polygon, "polygon").on_hover_text(
            "add the surface under the pixel as a vertex of the polygon to measure areas and volumes in",
        );
        ui.radio_value(&mut inspect.tool, Tool::Select, "select")
            .on_hover_text("drag a box: the points of every shown layer inside it are the selection");
        ui.radio_value(&mut inspect.tool, Tool::Lasso, "lasso")
            .on_hover_text("drag an outline: the points of every shown layer inside it are the selection");
        ui.radio_value(&mut inspect.tool, Tool::Profile, "profile")
            .on_hover_text("click the two ends of a profile's line (on the top view): its slab opens beside the view");
    });
    ui.add_enabled_ui(has_model, |ui| {
        ui.checkbox(&mut inspect.clip_on, "clip box").on_hover_text(
            "cut the scene per pixel by a box (drag the handles in the view) and the --clip-plane planes",
        );
    });
    if inspect.clip_on {
        if let Some(b) = inspect.clip_box.as_mut() {
            ui.horizontal(|ui| {
                ui.label("hide:");
                ui.radio_value(&mut b.hide, Hidden::Outside, "outside");
                ui.radio_value(&mut b.hide, Hidden::Inside, "inside");
            });
            for (axis, name) in ["x", "y", "z"].iter().enumerate() {
                ui.horizontal(|ui| {
                    let speed = ((b.max[axis] - b.min[axis]).abs() * 0.005).max(1e-6);
                    ui.label(*name);
                    ui.add(egui::DragValue::new(&mut b.min[axis]).speed(speed).max_decimals(4));
                    ui.add(egui::DragValue::new(&mut b.max[axis]).speed(speed).max_decimals(4));
                    if b.min[axis] > b.max[axis] {
                        b.max[axis] = b.min[axis];
                    }
                });
            }
        }
        if ui.button("box to the model's bounds").clicked() {
            inspect.clip_box = None; // the app sets it to the bounds again
        }
    }
    if let Some(report) = &inspect.picked {
        ui.label(RichText::new(report.text()).monospace().small());
    }
    let up = state.camera.up.frame().0.as_dvec3();
    if !inspect.measured.is_empty() {
        for (k, (pixel, p)) in inspect.measured.iter().enumerate() {
            ui.label(format!("point {}: ({:.3}, {:.3}, {:.3}) at pixel {pixel:?}", k + 1, p.x, p.y, p.z));
        }
        if let Some(m) = inspect.measurement(up) {
            for s in &m.segments {
                ui.label(format!("{}-{}: {:.4}, height {:+.4}", s.from + 1, s.to + 1, s.length, s.height));
            }
            ui.label(RichText::new(format!("distance {:.4}, height {:+.4}", m.distance, m.height)).strong());
            for (k, a) in m.angles_deg.iter().enumerate() {
                ui.label(format!("angle at {}: {a:.2}°", k + 2));
            }
            if ui.button("copy CSV").on_hover_text("the segments, to paste in a spreadsheet").clicked() {
                ui.ctx().copy_text(m.csv());
            }
        }
        if ui.button("clear points").clicked() {
            inspect.measured.clear();
        }
    }
}

/// The selection's buttons: export it (a file dialog), keep only it, hide
/// it, or clear it; and, when selections were kept or hidden by the style
/// (`regions` of them), a button that shows every point again.
pub fn selection_section(ui: &mut Ui, state: &mut UiState, regions: usize, actions: &mut Vec<Action>) {
    if regions > 0 {
        ui.horizontal(|ui| {
            ui.label(format!("{regions} selection(s) kept or hidden"));
            if ui.button("show all").on_hover_text("show the points the kept or hidden selections dropped").clicked() {
                actions.push(Action::ClearRegions);
            }
        });
    }
    let inspect = &mut state.inspect;
    if inspect.selection.is_none() {
        return;
    }
    ui.horizontal_wrapped(|ui| {
        if ui.button("export selection…").on_hover_text("LAS, LAZ or PLY, every field kept").clicked() {
            let kinds = ["las", "laz", "ply"];
            if let Some(path) = rfd::FileDialog::new().add_filter("points", &kinds).save_file() {
                actions.push(Action::ExportSelection(path));
            }
        }
        let cut = "a box is cut per pixel by the clip; a lasso drops whole points (every mode; recorded in sidecars)";
        if ui.button("keep only").on_hover_text(cut).clicked() {
            actions.push(Action::KeepSelection(true));
        }
        if ui.button("hide").on_hover_text(cut).clicked() {
            actions.push(Action::KeepSelection(false));
        }
        if ui.button("clear selection").clicked() {
            inspect.selection = None;
        }
    });
}
