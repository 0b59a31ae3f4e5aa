//! The viewer's scene lights: add, move (drag the numbers, or the sliders
//! around the model's centre) and delete point lights, and choose how their
//! shadows are found. Every change is a settings change, so the render
//! thread recomputes the shadow coefficients (a TSM build per light) and
//! redraws while a light moves.

use crate::frame::lights::{MAX_LIGHTS, MAX_TSM_CELLS};
use crate::frame::{Camera, Light, LightKind, RenderSettings, ShadowMethod};
use egui::{RichText, Ui};

/// The list of lights, with a row of controls each.
pub fn lights_widget(ui: &mut Ui, settings: &mut RenderSettings, camera: &Camera) {
    let speed = (camera.distance * 0.005).max(1e-6) as f64;
    let mut remove = None;
    for (k, light) in settings.lights.as_mut_slice().iter_mut().enumerate() {
        ui.horizontal(|ui| {
            ui.label(format!("light {}", k + 1));
            match &mut light.kind {
                LightKind::Point(p) => {
                    for (axis, v) in ["x", "y", "z"].iter().zip([&mut p.x, &mut p.y, &mut p.z]) {
                        ui.add(egui::DragValue::new(v).speed(speed).prefix(format!("{axis} ")));
                    }
                }
                LightKind::Directional(d) => {
                    ui.label(format!("directional ({:.2}, {:.2}, {:.2})", d.x, d.y, d.z));
                }
            }
            ui.add(egui::DragValue::new(&mut light.intensity).speed(0.01).range(0.0..=100.0).prefix("× "));
            if ui.small_button("delete").on_hover_text("delete this light").clicked() {
                remove = Some(k);
            }
        });
    }
    if let Some(k) = remove {
        settings.lights.remove(k);
    }
    ui.horizontal(|ui| {
        let room = settings.lights.len() < MAX_LIGHTS;
        let add = ui.add_enabled(room, egui::Button::new("add a light")).on_hover_text(
            "a white point light above and in front of the model; scene lights replace the headlight and cast shadows",
        );
        if add.clicked() {
            // Above the model's centre, towards the camera.
            let towards = camera.eye() - camera.target;
            let at = camera.target + glam::Vec3::Y * camera.distance * 0.6 + towards * 0.3;
            let _ = settings.lights.push(Light::point(at));
        }
        if settings.lights.is_empty() {
            ui.label(RichText::new("no scene lights: the headlight").weak());
        }
    });
}

/// How the lights' shadows are found, and the TSM table's size.
pub fn shadows_widget(ui: &mut Ui, settings: &mut RenderSettings, label: &str) {
    if settings.lights.is_empty() || !settings.lighting {
        ui.label(RichText::new(format!("{label}: from scene lights (none)")).weak());
        return;
    }
    let shadows = &mut settings.shadows;
    ui.horizontal(|ui| {
        ui.label(label);
        ui.radio_value(&mut shadows.method, ShadowMethod::Tsm, "TSM")
            .on_hover_text("Gunjee's translucent shadow map: one table per light");
        ui.radio_value(&mut shadows.method, ShadowMethod::Exact, "exact")
            .on_hover_text("a shadow ray from every splat to every light (slow on large models)");
        ui.radio_value(&mut shadows.method, ShadowMethod::Off, "off");
    });
    if shadows.method == ShadowMethod::Tsm {
        let mut side = shadows.cells[0].max(shadows.cells[1]);
        let slider =
            egui::Slider::new(&mut side, 16..=MAX_TSM_CELLS.min(4096)).logarithmic(true).text("TSM cells per side");
        if ui.add(slider).changed() {
            shadows.cells = [side, side];
        }
    }
}
