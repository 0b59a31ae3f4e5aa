//! The left panel's controls: model, background jobs, mode and its
//! parameters, camera, statistics, error and screenshot. The controls edit
//! the [`UiState`] and return [`Action`]s for the app to take. Parameters come
//! from the mode registry ([`crate::frame::RenderMode::parameters`]): each
//! [`Parameter`] has one widget here, and a mode shows the widgets of the
//! parameters it lists.

use std::path::PathBuf;

use egui::{RichText, Ui};

use super::state::{Action, JobKind, PanelInfo, ScreenshotSize, UiState};
use super::widgets::{job_row, thousands};
use crate::frame::{Parameter, Quality, RenderMode};
use crate::grouping::{Extension, GroupingAlgo, GroupingSpec, MAX_GROUPS};

pub fn controls(ui: &mut Ui, state: &mut UiState, info: &PanelInfo<'_>) -> Vec<Action> {
    let mut actions = Vec::new();
    model_section(ui, state, info, &mut actions);
    jobs_section(ui, info, &mut actions);
    ui.separator();
    mode_section(ui, state, info);
    ui.separator();
    camera_section(ui, state, &mut actions);
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
            ui.label(RichText::new(m.name).strong()).on_hover_text(m.path.display().to_string());
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
    ui.horizontal(|ui| {
        if ui.button("Open…").clicked() {
            if let Some(path) = rfd::FileDialog::new().add_filter("PLY or scene", &["ply", "PLY", "toml"]).pick_file() {
                actions.push(Action::Open(path));
            }
        }
        ui.label(RichText::new("or drop a .ply file").weak());
    });
    if let Some(e) = info.load_error {
        ui.colored_label(egui::Color32::LIGHT_RED, format!("Could not open: {e}"));
    }
}

fn jobs_section(ui: &mut Ui, info: &PanelInfo<'_>, actions: &mut Vec<Action>) {
    if let Some((stage, fraction)) = &info.view_progress {
        ui.horizontal(|ui| {
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
            actions.push(Action::SetEnvironment(Some(PathBuf::from(crate::viewer::BUNDLED_ENVIRONMENT))));
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
        parameter_widget(ui, state, info, parameter);
    }
}

/// The budget the "point budget" switch starts at.
const DEFAULT_STILL_BUDGET: u32 = 250_000;

fn parameter_widget(ui: &mut Ui, state: &mut UiState, info: &PanelInfo<'_>, parameter: Parameter) {
    let s = &mut state.settings;
    match parameter {
        Parameter::Quality => {
            ui.horizontal(|ui| {
                ui.label("quality");
                ui.radio_value(&mut s.quality, Quality::Filtered, "filtered");
                ui.radio_value(&mut s.quality, Quality::Unfiltered, "unfiltered");
            });
        }
        Parameter::Epsilon => {
            ui.add(egui::Slider::new(&mut s.epsilon_scale, 0.05..=5.0).text("ε (× mean radius)"));
        }
        Parameter::DepthStep => {
            ui.add(egui::Slider::new(&mut s.depth_step, 0.25..=4.0).text("Eq. 10 depth step (× ε)"));
        }
        Parameter::RadiusScale => {
            ui.add(egui::Slider::new(&mut s.radius_scale, 0.25..=3.0).text("splat radius scale"));
        }
        Parameter::Prefilter => {
            use crate::frame::Prefilter;
            let mut ewa = s.prefilter == Prefilter::Ewa;
            ui.checkbox(&mut ewa, "EWA prefilter").on_hover_text(
                "Guennebaud's EWA approximation: splats smaller than a pixel are stretched to the low-pass filter, so a far model does not alias",
            );
            s.prefilter = if ewa { Prefilter::Ewa } else { Prefilter::None };
        }
        Parameter::PointBudget => {
            let mut on = s.point_budget.is_some();
            ui.checkbox(&mut on, "point budget").on_hover_text(
                "draw at most this many splats, chosen from a multi-resolution octree by screen-space error",
            );
            s.point_budget = match (on, s.point_budget) {
                (false, _) => None,
                (true, Some(n)) => Some(n),
                (true, None) => Some(DEFAULT_STILL_BUDGET),
            };
            if let Some(n) = &mut s.point_budget {
                ui.add(egui::Slider::new(n, 1_000..=10_000_000).logarithmic(true).text("splats"));
            }
            ui.add(
                egui::Slider::new(&mut state.moving_budget, 10_000..=2_000_000).logarithmic(true).text("while moving"),
            )
            .on_hover_text("splats drawn while the camera moves; the full frame follows when it stops");
        }
        Parameter::HybridPixels => {
            // Not clamped: `--hybrid-px inf` (splats only) stays as it was given.
            let slider = egui::Slider::new(&mut s.hybrid_pixels, 0.0..=32.0)
                .clamping(egui::SliderClamping::Never)
                .text("hybrid px");
            ui.add(slider).on_hover_text(
                "hybrid objects: a leaf is drawn as triangles where its splats would be wider than this radius in pixels",
            );
        }
        Parameter::Supersample => {
            ui.add(
                egui::Slider::new(&mut s.supersample, 1..=crate::frame::settings::MAX_SUPERSAMPLE)
                    .text("supersample N×N"),
            );
        }
        Parameter::BackfaceCulling => {
            ui.checkbox(&mut s.backface_culling, "back-face culling");
        }
        Parameter::Lighting => {
            ui.checkbox(&mut s.lighting, "lighting");
            if s.lighting {
                if s.lights.is_empty() {
                    ui.add(egui::Slider::new(&mut state.light_angles.0, -90.0..=90.0).text("headlight azimuth °"));
                    ui.add(egui::Slider::new(&mut state.light_angles.1, -90.0..=90.0).text("headlight elevation °"));
                }
                super::lights_panel::lights_widget(ui, s, &state.camera);
            }
        }
        Parameter::Shadows => super::lights_panel::shadows_widget(ui, s),
        Parameter::Background => {
            ui.horizontal(|ui| {
                let mut rgb = s.shading.background.to_array();
                ui.color_edit_button_rgb(&mut rgb);
                s.shading.background = glam::Vec3::from_array(rgb);
                ui.label("background");
            });
        }
        Parameter::Voronoi => {
            ui.checkbox(&mut s.voronoi, "Voronoi rasterisation (Eq. 14)");
        }
        Parameter::Grouping => {
            grouping_widget(ui, &mut s.grouping, info);
            let moving = info.model.as_ref().is_some_and(|m| m.period > 0.0);
            if moving {
                let drawn = crate::render::per_frame_grouping(s.grouping_for_mode());
                ui.label(
                    RichText::new(format!("the scene moves: {} draws {drawn}, regrouped every frame", s.mode)).weak(),
                );
            } else if s.grouping_for_mode() != s.grouping {
                ui.label(
                    RichText::new(format!(
                        "{} draws {}: its groups must cover the surface",
                        s.mode,
                        s.grouping_for_mode()
                    ))
                    .weak(),
                );
            }
        }
        Parameter::PeelLayers => {
            // Written only when moved, so each mode keeps its own default until then.
            let mut k = s.peel_layers_or_default();
            if ui.add(egui::Slider::new(&mut k, 2..=crate::frame::settings::MAX_PEEL_LAYERS).text("layers k")).changed()
            {
                s.peel_layers = k;
            }
        }
        Parameter::EnvironmentLayers => {
            use crate::frame::environment::LayerEffects;
            ui.horizontal(|ui| {
                ui.checkbox(&mut s.environment.enabled, "environment effects");
                ui.checkbox(&mut s.environment.skybox, "skybox");
            });
            ui.horizontal(|ui| {
                ui.radio_value(&mut s.environment.layer_effects, LayerEffects::Single, "single");
                ui.radio_value(&mut s.environment.layer_effects, LayerEffects::Multi, "multi-layer");
            });
            ui.label(RichText::new("with a map (Model panel)").weak());
        }
        Parameter::Eta => {
            ui.add(egui::Slider::new(&mut s.environment.eta, 0.5..=2.5).text("η refraction"));
        }
        Parameter::Dispersion => {
            ui.add(egui::Slider::new(&mut s.environment.dispersion, 0.0..=0.1).text("dispersion δ"));
        }
        Parameter::Order => {
            use crate::spatial::order::OrderKind;
            ui.horizontal(|ui| {
                ui.label("back to front:");
                ui.radio_value(&mut s.order, OrderKind::Bucket, "bucket sort")
                    .on_hover_text("Gunjee's bucket sort, O(n): exact up to one slab of thickness ε");
                ui.radio_value(&mut s.order, OrderKind::Bsp, "BSP tree").on_hover_text(
                    "Zhang & Pajarola §5.2.1: a BSP tree traversed far side first; unordered inside a leaf",
                );
            });
        }
    }
}

fn grouping_widget(ui: &mut Ui, spec: &mut GroupingSpec, info: &PanelInfo<'_>) {
    let name = |a: &GroupingAlgo| match a {
        GroupingAlgo::Mgc { .. } => "MGC (overlap c)",
        GroupingAlgo::Wgc { .. } => "WGC (K groups)",
        GroupingAlgo::Hash { .. } => "hashing (K groups)",
    };
    ui.horizontal(|ui| {
        egui::ComboBox::new("grouping", "grouping").selected_text(name(&spec.algo)).show_ui(ui, |ui| {
            for choice in [GroupingSpec::default().algo, GroupingSpec::wgc(8).algo, GroupingSpec::hash(8, true).algo] {
                let same = std::mem::discriminant(&choice) == std::mem::discriminant(&spec.algo);
                if ui.selectable_label(same, name(&choice)).clicked() && !same {
                    spec.algo = choice;
                }
            }
        });
    });
    match &mut spec.algo {
        GroupingAlgo::Mgc { c } => {
            ui.add(egui::Slider::new(c, 0.05..=1.0).text("c (allowed overlap)"));
        }
        GroupingAlgo::Wgc { k, eq7 } => {
            ui.add(egui::Slider::new(k, 1..=MAX_GROUPS).text("K"));
            ui.checkbox(eq7, "colours by Eq. 7 weight");
        }
        GroupingAlgo::Hash { k, resolve_collisions } => {
            ui.add(egui::Slider::new(k, 1..=MAX_GROUPS).text("K"));
            ui.checkbox(resolve_collisions, "resolve collisions");
        }
    }
    if !matches!(spec.algo, GroupingAlgo::Hash { .. }) {
        ui.checkbox(&mut spec.relax.coplanar, "relax coplanar overlaps");
        ui.checkbox(&mut spec.relax.opposite, "relax opposite normals");
    }
    let extension_name = |e: &Extension| match e {
        Extension::None => "none",
        Extension::Duplicate => "duplication",
        Extension::Enlarge => "radius enlargement",
        Extension::Estimate => "radius x√50/4 (hash estimate)",
    };
    egui::ComboBox::new("extension", "extension").selected_text(extension_name(&spec.extension)).show_ui(ui, |ui| {
        for choice in [Extension::None, Extension::Duplicate, Extension::Enlarge, Extension::Estimate] {
            ui.selectable_value(&mut spec.extension, choice, extension_name(&choice));
        }
    });
    if let Some(g) = info.grouped {
        let sizes = g.grouping.sizes();
        let (lo, hi) = (sizes.iter().min().copied().unwrap_or(0), sizes.iter().max().copied().unwrap_or(0));
        let origin = if g.cached { "from the cache" } else { "computed" };
        ui.label(format!(
            "{}: K = {}, groups of {}–{} splats ({origin}, {:.2} s)",
            g.spec,
            g.grouping.k(),
            thousands(lo),
            thousands(hi),
            g.seconds
        ));
    }
    if let Some(e) = info.grouping_error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
}

fn camera_section(ui: &mut Ui, state: &mut UiState, actions: &mut Vec<Action>) {
    ui.heading("Camera");
    let before = state.camera.fov_y_deg;
    ui.add(egui::Slider::new(&mut state.camera.fov_y_deg, 5.0..=120.0).text("field of view °"));
    if state.camera.fov_y_deg != before {
        actions.push(Action::CameraMoved);
    }
    ui.horizontal(|ui| {
        if ui.button("Home").on_hover_text("reset the camera (Home key)").clicked() {
            actions.push(Action::ResetCamera);
        }
    });
    ui.add(
        egui::Label::new(
            RichText::new("drag: orbit · right/middle drag: pan · wheel: zoom · double-click: centre").weak(),
        )
        .wrap(),
    );
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
    ui.label(RichText::new(format!("PNG + JSON sidecar in {}", info.screenshot_dir.display())).weak());
    if let Some(status) = info.status {
        ui.label(status);
    }
}
