//! The left panel's controls: model, colour by attribute
//! ([`super::colour_panel`]), background jobs, mode and its parameters, camera, statistics, error and screenshot. The controls edit
//! the [`UiState`] and return [`Action`]s for the app to take. Parameters come
//! from the mode registry ([`crate::frame::RenderMode::parameters`]): a mode
//! shows the widget of each parameter it lists, made from the parameter's row
//! of the descriptor table ([`super::parameter_widgets`]).

use egui::{RichText, Ui};

use super::state::{Action, JobKind, PanelInfo, ScreenshotSize, UiState};
use super::widgets::{job_row, thousands};
use crate::frame::{Projection, RenderMode};

pub fn controls(ui: &mut Ui, state: &mut UiState, info: &PanelInfo<'_>) -> Vec<Action> {
    let mut actions = Vec::new();
    model_section(ui, state, info, &mut actions);
    if let Some(model) = &info.model {
        super::colour_panel::colour_section(ui, model, &mut actions);
    }
    jobs_section(ui, info, &mut actions);
    ui.separator();
    mode_section(ui, state, info);
    ui.separator();
    camera_section(ui, state, &mut actions);
    ui.separator();
    super::inspect_panel::inspect_section(ui, state, info.model.is_some());
    let regions = info.model.as_ref().and_then(|m| m.style).map_or(0, |s| s.regions.len());
    super::inspect_panel::selection_section(ui, state, regions, &mut actions);
    super::polygon_panel::polygon_section(ui, state, info.polygon, info.layers);
    ui.separator();
    super::stats::stats_section(ui, info);
    ui.separator();
    super::stats::error_section(ui, info, &mut actions);
    ui.separator();
    screenshot_section(ui, state, info, &mut actions);
    actions
}

/// Play/pause and the time of a moving scene (it loops over `period` seconds).
fn animation_widget(ui: &mut Ui, state: &mut UiState, period: f64) {
    ui.horizontal(|ui| {
        let label = if state.playing { "pause" } else { "play" };
        if ui.button(label).on_hover_text("play the scene's animation (it loops)").clicked() {
            state.playing = !state.playing;
        }
        let slider = egui::Slider::new(&mut state.time, 0.0..=period).text("s").fixed_decimals(2);
        let response = ui.add(slider);
        // Taking the slider pauses; a value the slider rounds while playing does not.
        if response.drag_started() || response.clicked() || response.gained_focus() {
            state.playing = false;
        }
    });
}

fn model_section(ui: &mut Ui, state: &mut UiState, info: &PanelInfo<'_>, actions: &mut Vec<Action>) {
    ui.heading("Model");
    match &info.model {
        Some(m) => {
            ui.label(RichText::new(m.name).strong()).on_hover_text(crate::copc::shown(&m.path.to_string_lossy()));
            ui.label(format!("{} splats", thousands(m.splats)));
            opacity_widget(ui, &mut state.opacity_pending, m.opacity, actions);
            if state.settings.mode.info().transparent && !m.transparent && state.opacity_pending.is_none() {
                ui.label(RichText::new(OPAQUE_MODEL_HINT).color(ui.visuals().warn_fg_color));
            }
            environment_widget(ui, m.environment, actions);
            if m.period > 0.0 {
                animation_widget(ui, state, m.period);
            }
            if !m.warnings.is_empty() {
                ui.collapsing(format!("{} load warnings", m.warnings.len()), |ui| {
                    for w in m.warnings {
                        ui.label(w);
                    }
                });
            }
        }
        None => {
            ui.label("no model loaded");
        }
    }
    let clip_box = state.inspect.clip_box;
    super::layers_panel::layers_section(ui, info, clip_box, &mut state.layer_opacity_pending, actions);
    ui.horizontal(|ui| {
        if ui.button("Open…").clicked() {
            let kinds = ["ply", "PLY", "las", "LAS", "laz", "LAZ", "e57", "E57", "vpc", "toml"];
            if let Some(path) = rfd::FileDialog::new().add_filter("point cloud or scene", &kinds).pick_file() {
                actions.push(Action::Open(path));
            }
        }
        ui.label(RichText::new("or drop files: each adds a layer").weak());
    });
    ui.horizontal(|ui| {
        let field =
            egui::TextEdit::singleline(&mut state.url_text).hint_text("https://…/tile.copc.laz").desired_width(120.0);
        let label = ui.label("URL");
        ui.add(field)
            .labelled_by(label.id)
            .on_hover_text("a COPC file or a .vpc over HTTP(S): streamed node by node, added as a layer");
        let url = state.url_text.trim();
        let opens = url.starts_with("http://") || url.starts_with("https://");
        if ui.add_enabled(opens, egui::Button::new("open URL")).clicked() {
            actions.push(Action::Open(std::path::PathBuf::from(url)));
        }
    });
    if let Some(e) = info.load_error {
        ui.colored_label(egui::Color32::LIGHT_RED, format!("Could not open: {e}"));
    }
}

fn jobs_section(ui: &mut Ui, info: &PanelInfo<'_>, actions: &mut Vec<Action>) {
    if let Some((stage, fraction)) = &info.view_progress {
        ui.horizontal_wrapped(|ui| {
            ui.spinner();
            ui.label(format!("drawing the view: {stage}"));
        });
        ui.add(egui::ProgressBar::new(fraction.unwrap_or(0.0)).show_percentage());
    }
    for kind in [JobKind::Load, JobKind::Grouping] {
        if let Some(job) = info.job(kind) {
            if job_row(ui, job) {
                actions.push(Action::Cancel(kind));
            }
        }
    }
}

/// The environment map transparent surfaces reflect and refract (alg2 and
/// the reference draw it): none, the bundled one, or a file.
fn environment_widget(ui: &mut Ui, current: Option<&str>, actions: &mut Vec<Action>) {
    egui::ComboBox::new("environment", "environment").selected_text(current.unwrap_or("none")).show_ui(ui, |ui| {
        if ui.selectable_label(current.is_none(), "none").clicked() && current.is_some() {
            actions.push(Action::SetEnvironment(None));
        }
        if ui.selectable_label(false, "venice.exr (bundled)").clicked() {
            match crate::assets::path(crate::assets::BUNDLED_ENVIRONMENT) {
                Ok(map) => actions.push(Action::SetEnvironment(Some(map))),
                Err(e) => actions.push(Action::ShowError(e)),
            }
        }
        if ui.selectable_label(false, "Open…").clicked() {
            let dialog = rfd::FileDialog::new().add_filter("environment map", &["exr", "hdr", "png", "jpg", "jpeg"]);
            if let Some(path) = dialog.pick_file() {
                actions.push(Action::SetEnvironment(Some(path)));
            }
        }
    });
}

/// Shown beside the opacity slider when a transparent mode is chosen and
/// nothing is transparent: the mode then draws what two-pass draws.
pub const OPAQUE_MODEL_HINT: &str = "this model is opaque: set its opacity below 1 to see through it";

/// Opacity of every object: applied when the slider is let go (a new upload).
/// Transparent modes and the reference show it; opaque modes draw α = 1.
fn opacity_widget(ui: &mut Ui, pending: &mut Option<f32>, (opacity, shared): (f32, bool), actions: &mut Vec<Action>) {
    // The slider shows its own value while dragged and until the model holds
    // the value let go; otherwise the model's.
    if pending.is_some_and(|v| (v - opacity).abs() <= 1e-6) {
        *pending = None;
    }
    let mut value = pending.unwrap_or(opacity);
    let text = if shared { "opacity" } else { "opacity (objects differ; sets all)" };
    let response = ui.add(egui::Slider::new(&mut value, 0.0..=1.0).text(text)).on_hover_text(
        "Opacity of every object. Transparent modes (depth-peel, approx-peel) and the reference show it; \
         opaque modes draw every splat opaque.",
    );
    if response.dragged() || response.changed() {
        *pending = Some(value);
    }
    if response.drag_stopped() || (response.changed() && !response.dragged()) {
        actions.push(Action::SetOpacity(value));
    }
}

fn mode_section(ui: &mut Ui, state: &mut UiState, info: &PanelInfo<'_>) {
    ui.heading("Mode");
    ui.horizontal_wrapped(|ui| {
        for mode in RenderMode::ALL {
            ui.selectable_value(&mut state.settings.mode, mode, mode.name()).on_hover_text(mode.description());
        }
    });
    ui.label(RichText::new(state.settings.mode.description()).weak());
    for &parameter in state.settings.mode.parameters() {
        super::parameter_widgets::parameter_widget(ui, state, info, parameter);
    }
}

fn camera_section(ui: &mut Ui, state: &mut UiState, actions: &mut Vec<Action>) {
    ui.heading("Camera");
    let before = state.camera.fov_y_deg;
    ui.add(egui::Slider::new(&mut state.camera.fov_y_deg, 5.0..=120.0).text("field of view °"));
    if state.camera.fov_y_deg != before {
        actions.push(Action::CameraMoved);
    }
    projection_widgets(ui, state, actions);
    ui.horizontal(|ui| {
        if ui.button("Home").on_hover_text("reset the camera (Home key)").clicked() {
            actions.push(Action::ResetCamera);
        }
        if ui.button("bookmark view").on_hover_text("add this view to the camera path").clicked() {
            state.bookmarks.push(state.camera);
        }
    });
    if !state.bookmarks.is_empty() {
        ui.horizontal_wrapped(|ui| {
            let mut go = None;
            for k in 0..state.bookmarks.len() {
                if ui.small_button(format!("{}", k + 1)).on_hover_text("go to this view").clicked() {
                    go = Some(k);
                }
            }
            if let Some(k) = go {
                state.camera = state.bookmarks[k];
                actions.push(Action::CameraMoved);
            }
            if ui.button("save views").on_hover_text("views.json, for render --path").clicked() {
                actions.push(Action::SaveViews);
            }
            if ui.small_button("clear").clicked() {
                state.bookmarks.clear();
            }
        });
    }
    ui.add(
        egui::Label::new(
            RichText::new("drag: orbit · right/middle drag: pan · wheel: zoom · double-click: centre · H: help").weak(),
        )
        .wrap(),
    );
}

/// Perspective or orthographic (O), and the named views (1-7).
fn projection_widgets(ui: &mut Ui, state: &mut UiState, actions: &mut Vec<Action>) {
    ui.horizontal(|ui| {
        for projection in [Projection::Perspective, Projection::Ortho] {
            let chosen = ui.selectable_value(&mut state.camera.projection, projection, projection.name());
            if chosen.on_hover_text("O switches perspective and orthographic").changed() {
                actions.push(Action::CameraMoved);
            }
        }
        ui.checkbox(&mut state.help_shown, "help").on_hover_text("the view's keys and mouse inputs (H)");
        ui.checkbox(&mut state.fly, "fly").on_hover_text("W A S D Q E move the eye, a drag looks around (F)");
    });
    ui.horizontal_wrapped(|ui| {
        ui.label("view:");
        for (key, view) in super::view_keys::VIEW_KEYS {
            if ui.small_button(view.name()).on_hover_text(format!("key {}", key.name())).clicked() {
                state.camera.look_from(view);
                actions.push(Action::CameraMoved);
            }
        }
    });
}

fn screenshot_section(ui: &mut Ui, state: &mut UiState, info: &PanelInfo<'_>, actions: &mut Vec<Action>) {
    ui.heading("Screenshot");
    ui.horizontal(|ui| {
        egui::ComboBox::new("shot size", "size").selected_text(state.screenshot_size.label()).show_ui(ui, |ui| {
            for choice in ScreenshotSize::CHOICES {
                ui.selectable_value(&mut state.screenshot_size, choice, choice.label());
            }
        });
        if ui.button("Save (Ctrl+S)").clicked() {
            actions.push(Action::SaveScreenshot);
        }
    });
    ui.horizontal(|ui| {
        ui.add(egui::DragValue::new(&mut state.large_factor).range(1..=16).prefix("× "));
        if ui.button("Save large (Ctrl+Shift+S)").on_hover_text("N × the view's size, up to 16384 a side").clicked() {
            actions.push(Action::SaveLargeScreenshot);
        }
    });
    ui.label(RichText::new(format!("PNG + JSON sidecar in {}", info.screenshot_dir.display())).weak());
    if let Some(status) = info.status {
        ui.label(status);
    }
}
