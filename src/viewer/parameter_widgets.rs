//! The widget of each rendering parameter, made from its row of the
//! descriptor table ([`crate::frame::parameters::TABLE`]): the row's control
//! (choices, a toggle, a slider over its range, a colour), its label and its
//! help as hover text. A widget reads the parameter's text form and writes
//! it back through the row's parser, so the viewer takes exactly the values
//! the command line, bench and sidecars take. The parameters whose control is
//! `Custom` (grouping, lighting, eye-dome lighting, shadows, environment, point budget) have
//! widgets of their own below, each under the row's label.

use egui::{RichText, Ui};

use super::state::{PanelInfo, UiState};
use super::widgets::thousands;
use crate::frame::parameters::Control;
use crate::frame::{Parameter, RenderSettings};
use crate::grouping::{Extension, GroupingAlgo, GroupingSpec, MAX_GROUPS};

/// The budget the "point budget" switch starts at.
const DEFAULT_STILL_BUDGET: u32 = 250_000;

/// The widget of `parameter`, as its row's control says.
pub fn parameter_widget(ui: &mut Ui, state: &mut UiState, info: &PanelInfo<'_>, parameter: Parameter) {
    let row = parameter.info();
    let settings = &mut state.settings;
    let shown = parameter.shown_text(settings);
    // A value the row's parser refuses (one typed into a slider) leaves the setting as it was.
    let set = |settings: &mut RenderSettings, text: String| {
        let _ = parameter.apply(settings, &text);
    };
    match row.control {
        Control::Choices(choices) => {
            ui.horizontal(|ui| {
                ui.label(row.label).on_hover_text(row.help);
                for &choice in choices {
                    if ui.radio(shown == choice, choice).clicked() {
                        set(settings, choice.to_string());
                    }
                }
            });
        }
        Control::Toggle => {
            let mut on = shown == "on";
            if ui.checkbox(&mut on, row.label).on_hover_text(row.help).changed() {
                set(settings, if on { "on" } else { "off" }.to_string());
            }
        }
        Control::Number { min, max, logarithmic } => {
            let mut value: f32 = shown.parse().unwrap_or(min);
            // Not clamped: a value given outside the slider (`--hybrid-px inf`) stays as it was given.
            let slider = egui::Slider::new(&mut value, min..=max)
                .logarithmic(logarithmic)
                .clamping(egui::SliderClamping::Never)
                .text(row.label);
            if ui.add(slider).on_hover_text(row.help).changed() {
                set(settings, value.to_string());
            }
        }
        Control::Count { min, max } => {
            let mut value: u32 = shown.parse().unwrap_or(min);
            // Written only when moved, so a mode's own default stays until then.
            if ui.add(egui::Slider::new(&mut value, min..=max).text(row.label)).on_hover_text(row.help).changed() {
                set(settings, value.to_string());
            }
        }
        Control::Colour => {
            ui.horizontal(|ui| {
                let mut rgb = settings.shading.background.to_array();
                if ui.color_edit_button_rgb(&mut rgb).changed() {
                    let [r, g, b] = rgb.map(|c| c * 255.0);
                    set(settings, format!("{r},{g},{b}"));
                }
                ui.label(row.label).on_hover_text(row.help);
            });
        }
        Control::Custom => custom_widget(ui, state, info, parameter),
    }
}

/// The parameters whose widget is more than one control.
fn custom_widget(ui: &mut Ui, state: &mut UiState, info: &PanelInfo<'_>, parameter: Parameter) {
    let row = parameter.info();
    let s = &mut state.settings;
    match parameter {
        Parameter::PointBudget => {
            let mut on = s.point_budget.is_some();
            ui.checkbox(&mut on, row.label).on_hover_text(row.help);
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
        Parameter::Lighting => {
            ui.checkbox(&mut s.lighting, row.label).on_hover_text(row.help);
            if s.lighting {
                if s.lights.is_empty() {
                    ui.add(egui::Slider::new(&mut state.light_angles.0, -90.0..=90.0).text("headlight azimuth °"));
                    ui.add(egui::Slider::new(&mut state.light_angles.1, -90.0..=90.0).text("headlight elevation °"));
                }
                super::lights_panel::lights_widget(ui, s, &state.camera);
            }
        }
        Parameter::EyeDome => {
            let mut on = s.eye_dome.is_some();
            if ui.checkbox(&mut on, row.label).on_hover_text(row.help).changed() {
                s.eye_dome = on.then(Default::default);
            }
            if let Some(edl) = &mut s.eye_dome {
                use crate::frame::eye_dome::{MAX_RADIUS_PX, MAX_STRENGTH};
                ui.add(egui::Slider::new(&mut edl.strength, 0.05..=MAX_STRENGTH).logarithmic(true).text("strength"));
                ui.add(egui::Slider::new(&mut edl.radius_px, 1.0..=MAX_RADIUS_PX).text("radius (px)"));
            }
        }
        Parameter::Shadows => super::lights_panel::shadows_widget(ui, s, row.label),
        Parameter::Grouping => {
            grouping_widget(ui, row.label, &mut s.grouping, info);
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
        Parameter::EnvironmentLayers => {
            use crate::frame::environment_effects::LayerEffects;
            ui.horizontal(|ui| {
                ui.checkbox(&mut s.environment.enabled, row.label).on_hover_text(row.help);
                ui.checkbox(&mut s.environment.skybox, "skybox");
            });
            ui.horizontal(|ui| {
                ui.radio_value(&mut s.environment.layer_effects, LayerEffects::Single, "single");
                ui.radio_value(&mut s.environment.layer_effects, LayerEffects::Multi, "multi-layer");
            });
            ui.label(RichText::new("with a map (Model panel)").weak());
        }
        other => {
            ui.label(format!("{}: {}", other.info().label, other.shown_text(s)));
        }
    }
}

fn grouping_widget(ui: &mut Ui, label: &str, spec: &mut GroupingSpec, info: &PanelInfo<'_>) {
    let name = |a: &GroupingAlgo| match a {
        GroupingAlgo::Mgc { .. } => "MGC (overlap c)",
        GroupingAlgo::Wgc { .. } => "WGC (K groups)",
        GroupingAlgo::Hash { .. } => "hashing (K groups)",
    };
    ui.horizontal(|ui| {
        egui::ComboBox::new("grouping", label).selected_text(name(&spec.algo)).show_ui(ui, |ui| {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::parameters::TABLE;
    use crate::frame::{Camera, RenderMode};
    use crate::viewer::state::ScreenshotSize;
    use egui_kittest::Harness;
    use egui_kittest::kittest::Queryable;

    fn panel_info() -> PanelInfo<'static> {
        PanelInfo {
            model: None,
            load_error: None,
            jobs: Vec::new(),
            view_progress: None,
            grouped: None,
            grouping_error: None,
            shown: None,
            current: None,
            ui_fps: 0.0,
            slowest_ui_frame_ms: 0.0,
            measurement: None,
            measure_error: None,
            screenshot_dir: std::path::Path::new("."),
            status: None,
            streaming: None,
            layers: &[],
            layer_looks: Vec::new(),
            polygon: None,
        }
    }

    fn state_in(mode: RenderMode) -> UiState {
        UiState {
            settings: RenderSettings { mode, ..Default::default() },
            camera: Camera::framing(glam::Vec3::ZERO, 1.0, 1.0),
            light_angles: (0.0, 0.0),
            screenshot_size: ScreenshotSize::Window,
            opacity_pending: None,
            layer_opacity_pending: None,
            url_text: String::new(),
            time: 0.0,
            playing: false,
            moving_budget: 100_000,
            inspect: Default::default(),
            bookmarks: Vec::new(),
            large_factor: 4,
            help_shown: false,
            fly: false,
        }
    }

    /// The panel of every mode shows a widget under the label of each
    /// parameter the mode reads, and none under the label of any other.
    #[test]
    fn each_modes_panel_has_the_widgets_of_exactly_its_rows_of_the_table() {
        for mode in RenderMode::ALL {
            let info = panel_info();
            let mut harness = Harness::new_ui_state(
                |ui, state: &mut UiState| {
                    for &parameter in state.settings.mode.parameters() {
                        parameter_widget(ui, state, &info, parameter);
                    }
                },
                state_in(mode),
            );
            harness.run();
            for row in &TABLE {
                let shown = harness.query_all_by_label_contains(row.label).next().is_some();
                let reads = mode.parameters().contains(&row.parameter);
                assert_eq!(shown, reads, "{mode}: the widget labelled '{}' ({})", row.label, row.key);
            }
        }
    }

    /// A widget writes its value through the row's parser: clicking a choice
    /// sets the parameter's text form.
    #[test]
    fn a_choice_clicked_in_the_panel_is_the_parameters_text_form() {
        let info = panel_info();
        let mut harness = Harness::new_ui_state(
            |ui, state: &mut UiState| parameter_widget(ui, state, &info, Parameter::Order),
            state_in(RenderMode::ALL.into_iter().find(|m| m.parameters().contains(&Parameter::Order)).unwrap()),
        );
        harness.get_by_label("sort").click();
        harness.run();
        assert_eq!(Parameter::Order.text(&harness.state().settings).as_deref(), Some("sort"));
    }
}
