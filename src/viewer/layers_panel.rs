//! The Model section's list of layers (`layer_list.rs`), once there are
//! two: per layer a box to show or hide it, its opacity, a colour that
//! replaces its splats' own, a box to cut it to the Inspect section's clip
//! box ([`crate::scene::cut`]), and its remove button, as [`Action`]s.

use egui::{RichText, Ui};

use super::state::{Action, PanelInfo};
use crate::frame::clip::{ClipBox, Hidden};
use crate::scene::Look;

/// The colours a layer can be drawn in instead of its own, by name.
pub const LAYER_COLOURS: [(&str, Option<[u8; 3]>); 8] = [
    ("own colours", None),
    ("red", Some([220, 60, 50])),
    ("orange", Some([240, 150, 40])),
    ("yellow", Some([235, 215, 60])),
    ("green", Some([70, 180, 80])),
    ("cyan", Some([60, 190, 210])),
    ("blue", Some([60, 100, 220])),
    ("white", Some([240, 240, 240])),
];

/// The name of a layer's colour (a colour not in the list by its values).
fn colour_name(colour: Option<[u8; 3]>) -> String {
    match LAYER_COLOURS.iter().find(|(_, c)| *c == colour) {
        Some((name, _)) => (*name).to_string(),
        None => colour.map_or_else(String::new, |[r, g, b]| format!("{r},{g},{b}")),
    }
}

/// The panel's list: per layer its box (shown or hidden), opacity, colour,
/// cut (to `clip_box`, the Inspect section's) and remove button.
pub fn layers_section(
    ui: &mut Ui,
    info: &PanelInfo<'_>,
    clip_box: Option<ClipBox>,
    pending: &mut Option<(usize, f32)>,
    actions: &mut Vec<Action>,
) {
    // One file is the model itself: the Model section names it.
    if info.layers.len() < 2 {
        return;
    }
    ui.label(RichText::new("layers (Open… or a drop adds one)").weak());
    for (k, layer) in info.layers.iter().enumerate() {
        let look = info.layer_looks.get(k).copied().unwrap_or_default();
        ui.horizontal(|ui| {
            let mut shown = layer.shown;
            let tip = crate::copc::shown(&layer.path.to_string_lossy());
            if ui.checkbox(&mut shown, layer.name()).on_hover_text(tip).changed() {
                actions.push(Action::ShowLayer(k, shown));
            }
            if ui.small_button("remove layer").clicked() {
                actions.push(Action::RemoveLayer(k));
            }
        });
        ui.horizontal(|ui| {
            ui.add_space(18.0);
            opacity_slider(ui, k, look, pending, actions);
            let mut colour = look.colour;
            egui::ComboBox::new(("layer colour", k), format!("colour {}", k + 1))
                .selected_text(colour_name(colour))
                .show_ui(ui, |ui| {
                    for (name, choice) in LAYER_COLOURS {
                        ui.selectable_value(&mut colour, choice, name);
                    }
                });
            if colour != look.colour {
                actions.push(Action::SetLayerLook(k, Look { colour, ..look }));
            }
        });
        ui.horizontal(|ui| {
            ui.add_space(18.0);
            // Streamed layers load each view's nodes afresh, uncut.
            let clip_box = clip_box.filter(|_| info.streaming.is_none());
            cut_box(ui, k, look, clip_box, actions);
        });
    }
}

/// Layer k's cut: ticked, the layer keeps only its points the clip box keeps (as the box is now).
fn cut_box(ui: &mut Ui, k: usize, look: Look, clip_box: Option<ClipBox>, actions: &mut Vec<Action>) {
    let mut cut = look.clip.is_some();
    let tip = match look.clip {
        Some(b) => format!("cut to {} (untick: whole again)", box_text(&b)),
        None => "keep only this layer's points the Inspect clip box keeps, as the box is now; \
                 the other layers stay whole once the clip is switched off"
            .to_string(),
    };
    let enabled = cut || clip_box.is_some();
    let checkbox = egui::Checkbox::new(&mut cut, format!("clip {}", k + 1));
    let response = ui
        .add_enabled(enabled, checkbox)
        .on_hover_text(tip)
        .on_disabled_hover_text("switch the clip box on in Inspect first (streamed layers are not cut)");
    if response.changed() {
        actions.push(Action::SetLayerLook(k, Look { clip: if cut { clip_box } else { None }, ..look }));
    }
}

/// A box in a line: its extent, and which side it hides.
fn box_text(b: &ClipBox) -> String {
    let side = match b.hide {
        Hidden::Outside => "keeping the inside",
        Hidden::Inside => "hiding the inside",
    };
    let axis = |a: usize| format!("{:.3}..{:.3}", b.min[a], b.max[a]);
    format!("x {}, y {}, z {}, {side}", axis(0), axis(1), axis(2))
}

/// Layer k's opacity: its own value while dragged, set when let go.
fn opacity_slider(ui: &mut Ui, k: usize, look: Look, pending: &mut Option<(usize, f32)>, actions: &mut Vec<Action>) {
    if pending.is_some_and(|(j, v)| j == k && (v - look.opacity).abs() <= 1e-6) {
        *pending = None;
    }
    let mut value = pending.filter(|(j, _)| *j == k).map_or(look.opacity, |(_, v)| v);
    let slider = egui::Slider::new(&mut value, 0.0..=1.0).text(format!("opacity {}", k + 1)).fixed_decimals(2);
    let response = ui.add(slider).on_hover_text("this layer's opacity (transparent modes show it)");
    if response.dragged() || response.changed() {
        *pending = Some((k, value));
    }
    if response.drag_stopped() || (response.changed() && !response.dragged()) {
        actions.push(Action::SetLayerLook(k, Look { opacity: value, ..look }));
    }
}
