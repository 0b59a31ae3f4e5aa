//! The Inspect section's polygon: its vertices (clicked with the polygon
//! tool), the volume switch, the measure (`polygon_measure.rs`) and the
//! buttons that copy its JSON (as `measure --polygon --json` prints it) and
//! its `--polygon` text, or clear it.

use egui::{RichText, Ui};

use super::state::{Layer, PolygonReport, UiState};

pub fn polygon_section(
    ui: &mut Ui,
    state: &mut UiState,
    report: Option<&Result<PolygonReport, String>>,
    layers: &[Layer],
) {
    let inspect = &mut state.inspect;
    if inspect.polygon.is_empty() {
        return;
    }
    ui.label(format!("polygon: {} vertices (click to add)", inspect.polygon.len()));
    ui.checkbox(&mut inspect.polygon_volume, "volume")
        .on_hover_text("the volume above and below a plane fitted to the points along the border, or a base layer");
    let shown: Vec<&Layer> = layers.iter().filter(|l| l.shown).collect();
    if inspect.polygon_volume && shown.len() > 1 {
        let name = |base: &Option<std::path::PathBuf>| match base {
            Some(path) => format!("layer {}", Layer::name_of(path)),
            None => "the border's plane".to_string(),
        };
        egui::ComboBox::new("volume against", "volume against")
            .selected_text(name(&inspect.polygon_base))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut inspect.polygon_base, None, name(&None));
                for layer in shown {
                    let label = format!("layer {}", layer.name());
                    ui.selectable_value(&mut inspect.polygon_base, Some(layer.path.clone()), label);
                }
            })
            .response
            .on_hover_text("a base layer (e.g. the ground before): the other layers' cut and fill against it");
    }
    match report {
        Some(Ok(r)) => {
            let u = &r.units;
            ui.label(format!("{} points inside", r.points));
            ui.label(
                RichText::new(format!(
                    "area {:.4} sq {u} horizontal, {:.4} of surface",
                    r.area_horizontal, r.area_surface
                ))
                .strong(),
            );
            if let Some((above, below)) = r.volume {
                ui.label(format!("volume {above:.4} above, {below:.4} below, net {:+.4}", above - below));
            }
            ui.horizontal(|ui| {
                if ui.button("copy JSON").on_hover_text("as measure --polygon --json prints it").clicked() {
                    ui.ctx().copy_text(r.json.clone());
                }
                if ui.button("copy --polygon").clicked() {
                    ui.ctx().copy_text(polygon_text(&inspect.polygon));
                }
            });
        }
        Some(Err(e)) => {
            ui.colored_label(ui.visuals().warn_fg_color, e);
        }
        None => {}
    }
    if ui.button("clear polygon").clicked() {
        inspect.polygon.clear();
    }
}

/// The polygon as `measure --polygon` takes it: "X1,Y1 X2,Y2 ...", exact.
fn polygon_text(vertices: &[glam::DVec3]) -> String {
    vertices.iter().map(|v| format!("{},{}", v.x, v.y)).collect::<Vec<_>>().join(" ")
}
