//! The Model section's list of layers (`layer_list.rs`), once there are
//! two: a box per layer, shown or hidden, and its remove button, as [`Action`]s.

use egui::{RichText, Ui};

use super::state::{Action, Layer};

/// The panel's list: a box per layer (shown or hidden) and its remove button.
pub fn layers_section(ui: &mut Ui, layers: &[Layer], actions: &mut Vec<Action>) {
    // One file is the model itself: the Model section names it.
    if layers.len() < 2 {
        return;
    }
    ui.label(RichText::new("layers (Open… or a drop adds one)").weak());
    for (k, layer) in layers.iter().enumerate() {
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
    }
}
