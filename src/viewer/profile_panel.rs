//! The profile's panel under the view: the slab's width (its handle), the
//! points it holds, the section drawn as distance along the line against
//! height at one scale in both (each point in the view's colour), and the
//! buttons that export it as `profile --csv` and `profile --points` do.

use egui::{Color32, RichText, Ui};

use super::state::{Action, Inspection, ProfileSlab};

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
    section(ui, slab);
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
        if ui.button("close").clicked() {
            inspect.profile_line.clear();
        }
    }
}

/// The slab from the side: distance along the line to the right, height up, one scale.
fn section(ui: &mut Ui, slab: &ProfileSlab) {
    let size = ui.available_size().max(egui::vec2(50.0, 50.0));
    let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
    let painter = ui.painter_at(rect);
    painter.rect_filled(rect, 0.0, Color32::from_gray(20));
    let (lo, hi) =
        slab.points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.z), hi.max(p.z)));
    if slab.points.is_empty() {
        ui.label(RichText::new("no point in the slab").weak());
        return;
    }
    let length = slab.profile.length();
    let scale = (f64::from(rect.width() - 8.0) / length).min(f64::from(rect.height() - 8.0) / (hi - lo).max(1e-9));
    let step = slab.points.len().div_ceil(DRAWN_AT_MOST).max(1);
    for (p, c) in slab.points.iter().zip(&slab.colours).step_by(step) {
        let (distance, _) = slab.profile.place(*p);
        let x = rect.left() + 4.0 + (distance * scale) as f32;
        let y = rect.bottom() - 4.0 - ((p.z - lo) * scale) as f32;
        painter.circle_filled(egui::pos2(x, y), 1.2, Color32::from_rgb(c[0], c[1], c[2]));
    }
}
