//! The profile's panel under the view: the slab's width (its handle), the
//! points it holds, the section drawn as distance along the line against
//! height at one scale in both (each point in the view's colour), picked
//! and measured by clicks (`profile_pick.rs`), and the
//! buttons that export it as `profile --csv`, `profile --points` and
//! `profile --out` do.

use egui::{Color32, RichText, Ui};

use super::profile_pick::SectionMeasure;
use super::state::{Action, Inspection, ProfileSlab, SectionLayout};

/// Most points drawn in the panel (every n-th beyond it); the export writes all.
const DRAWN_AT_MOST: usize = 60_000;

pub fn profile_panel(
    ui: &mut Ui,
    slab: &Result<ProfileSlab, String>,
    inspect: &mut Inspection,
    units: &str,
) -> Vec<Action> {
    let mut actions = Vec::new();
    ui.horizontal_wrapped(|ui| {
        ui.heading("Profile");
        width_and_buttons(ui, slab, inspect, units, &mut actions);
    });
    let slab = match slab {
        Ok(slab) => slab,
        Err(e) => {
            ui.colored_label(ui.visuals().warn_fg_color, e);
            return actions;
        }
    };
    section(ui, slab, inspect, units);
    actions
}

/// The width's handle, what the slab holds, and the export and close buttons.
fn width_and_buttons(
    ui: &mut Ui,
    slab: &Result<ProfileSlab, String>,
    inspect: &mut Inspection,
    units: &str,
    actions: &mut Vec<Action>,
) {
    let speed = (inspect.profile_width * 0.01).max(1e-6);
    ui.add(
        egui::DragValue::new(&mut inspect.profile_width)
            .speed(speed)
            .range(1e-6..=f64::MAX)
            .prefix("width ")
            .suffix(format!(" {units}")),
    )
    .on_hover_text("the slab: the points at most half this from the line, between its ends");
    if let Ok(slab) = slab {
        ui.label(format!("{} points, {:.3} {units} long", slab.points.len(), slab.profile.length()));
    }
    {
        if ui.button("export CSV…").on_hover_text("as profile --csv writes it").clicked() {
            if let Some(path) = rfd::FileDialog::new().add_filter("CSV", &["csv"]).save_file() {
                actions.push(Action::ExportProfile(path));
            }
        }
        if ui.button("export points…").on_hover_text("as profile --points writes them: LAS, LAZ or PLY").clicked() {
            if let Some(path) = rfd::FileDialog::new().add_filter("points", &["las", "laz", "ply"]).save_file() {
                actions.push(Action::ExportProfile(path));
            }
        }
        if ui.button("export PNG…").on_hover_text("the section drawn as profile --out draws it").clicked() {
            if let Some(path) = rfd::FileDialog::new().add_filter("image", &["png", "jpg"]).save_file() {
                actions.push(Action::ExportProfile(path));
            }
        }
        if ui.button("close").clicked() {
            inspect.profile_line.clear();
        }
    }
}

/// The slab from the side: distance along the line to the right, height up,
/// one scale; a click picks the point drawn nearest to it, two measure
/// between them (`profile_pick.rs`).
fn section(ui: &mut Ui, slab: &ProfileSlab, inspect: &mut Inspection, units: &str) {
    if slab.points.is_empty() {
        ui.label(RichText::new("no point in the slab").weak());
        return;
    }
    let marks = inspect.profile_marks.clone();
    match marks[..] {
        [a] => ui.label(format!(
            "picked: {:.3} {units} along, height {:.3} (x {:.3}, y {:.3})",
            slab.profile.place(a).0,
            a.z,
            a.x,
            a.y
        )),
        [a, b] => ui.label(RichText::new(SectionMeasure::between(slab, a, b).text(units)).strong()),
        _ => ui.label(RichText::new("click the section to pick a point, twice to measure").weak()),
    };
    let size = ui.available_size().max(egui::vec2(50.0, 50.0));
    let (rect, response) = ui.allocate_exact_size(size, egui::Sense::click());
    let layout = SectionLayout::fitting(slab, rect);
    inspect.profile_layout = Some(layout);
    if let Some(at) = response.interact_pointer_pos().filter(|_| response.clicked()) {
        if let Some(p) = layout.nearest(slab, at) {
            if inspect.profile_marks.len() == 2 {
                inspect.profile_marks.clear();
            }
            inspect.profile_marks.push(p);
        }
    }
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, Color32::from_gray(20));
    let step = slab.points.len().div_ceil(DRAWN_AT_MOST).max(1);
    for (p, c) in slab.points.iter().zip(&slab.colours).step_by(step) {
        painter.circle_filled(layout.screen(slab, *p), 1.2, Color32::from_rgb(c[0], c[1], c[2]));
    }
    let mark = Color32::from_rgb(255, 220, 60);
    let drawn: Vec<egui::Pos2> = inspect.profile_marks.iter().map(|p| layout.screen(slab, *p)).collect();
    if let [a, b] = drawn[..] {
        painter.line_segment([a, b], egui::Stroke::new(1.5, mark));
    }
    for at in drawn {
        painter.circle_stroke(at, 4.0, egui::Stroke::new(1.5, mark));
    }
}
