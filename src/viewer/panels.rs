//! The left panel's controls: model, background jobs, mode and its
//! parameters, camera, screenshot. Parameters come from the mode registry
//! ([`RenderMode::parameters`]): each [`Parameter`] has one widget here, and a
//! mode shows the widgets of the parameters it lists.

use egui::{RichText, Ui};

use crate::grouping::{GroupingSpec, MAX_GROUPS};
use crate::view::{Parameter, Quality, RenderMode};

use super::app::{ScreenshotSize, ViewerApp};

pub(super) fn controls(app: &mut ViewerApp, ui: &mut Ui) {
    model_section(app, ui);
    jobs_section(app, ui);
    ui.separator();
    mode_section(app, ui);
    ui.separator();
    camera_section(app, ui);
    ui.separator();
    super::stats::stats_section(app, ui);
    ui.separator();
    super::stats::error_section(app, ui);
    ui.separator();
    screenshot_section(app, ui);
}

fn model_section(app: &mut ViewerApp, ui: &mut Ui) {
    ui.heading("Model");
    match &app.model {
        Some(m) => {
            ui.label(RichText::new(&m.name).strong()).on_hover_text(m.path.display().to_string());
            ui.label(format!("{} splats", thousands(m.cloud.len())));
            if !m.warnings.is_empty() {
                ui.collapsing(format!("{} load warnings", m.warnings.len()), |ui| {
                    for w in &m.warnings {
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
            let picked = rfd::FileDialog::new().add_filter("PLY", &["ply", "PLY"]).pick_file();
            if let Some(path) = picked {
                app.open(&ui.ctx().clone(), &path);
            }
        }
        ui.label(RichText::new("or drop a .ply file").weak());
    });
    if let Some(e) = &app.load_error {
        ui.colored_label(egui::Color32::LIGHT_RED, format!("Could not open: {e}"));
    }
}

fn jobs_section(app: &mut ViewerApp, ui: &mut Ui) {
    if let Some((stage, fraction)) = app.view_progress() {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!("drawing the view: {stage}"));
        });
        ui.add(egui::ProgressBar::new(fraction.unwrap_or(0.0)).show_percentage());
    }
    let mut cancel_load = false;
    if let Some(job) = &app.load {
        cancel_load = job_row(ui, job.label(), job.progress(), job.seconds());
    }
    if cancel_load {
        if let Some(job) = app.load.take() {
            job.cancel();
        }
    }
    let mut cancel_grouping = false;
    if let Some((_, job)) = &app.grouping_job {
        cancel_grouping = job_row(ui, job.label(), job.progress(), job.seconds());
    }
    if cancel_grouping {
        if let Some((_, job)) = app.grouping_job.take() {
            job.cancel();
        }
        // Back to the grouping on screen, so the job does not restart at once.
        if let Some(g) = &app.grouped {
            app.grouping_spec = g.spec;
        }
    }
}

/// A progress bar with a Cancel button; returns whether Cancel was clicked.
pub(super) fn job_row(ui: &mut Ui, label: &str, (stage, fraction): (String, Option<f32>), seconds: f64) -> bool {
    let mut cancel = false;
    ui.horizontal(|ui| {
        ui.spinner();
        ui.label(format!("{label}: {stage} ({seconds:.1} s)"));
    });
    ui.horizontal(|ui| {
        let bar = match fraction {
            Some(f) => egui::ProgressBar::new(f).show_percentage(),
            None => egui::ProgressBar::new(0.0).animate(true),
        };
        ui.add_sized([ui.available_width() - 70.0, 18.0], bar);
        cancel = ui.button("Cancel").clicked();
    });
    cancel
}

fn mode_section(app: &mut ViewerApp, ui: &mut Ui) {
    ui.heading("Mode");
    ui.horizontal_wrapped(|ui| {
        for mode in RenderMode::ALL {
            ui.selectable_value(&mut app.settings.mode, mode, mode.name()).on_hover_text(mode.description());
        }
    });
    ui.label(RichText::new(app.settings.mode.description()).weak());
    for &parameter in app.settings.mode.parameters() {
        parameter_widget(app, ui, parameter);
    }
}

fn parameter_widget(app: &mut ViewerApp, ui: &mut Ui, parameter: Parameter) {
    let s = &mut app.settings;
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
        Parameter::RadiusScale => {
            ui.add(egui::Slider::new(&mut s.radius_scale, 0.25..=3.0).text("splat radius scale"));
        }
        Parameter::BackfaceCulling => {
            ui.checkbox(&mut s.backface_culling, "back-face culling");
        }
        Parameter::Lighting => {
            ui.checkbox(&mut s.lighting, "lighting");
            if s.lighting {
                ui.add(egui::Slider::new(&mut app.light_angles.0, -90.0..=90.0).text("light azimuth °"));
                ui.add(egui::Slider::new(&mut app.light_angles.1, -90.0..=90.0).text("light elevation °"));
            }
        }
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
        Parameter::Grouping => grouping_widget(app, ui),
    }
}

fn grouping_widget(app: &mut ViewerApp, ui: &mut Ui) {
    let spec = &mut app.grouping_spec;
    let name = |s: &GroupingSpec| match s {
        GroupingSpec::Mgc { .. } => "MGC (overlap c)",
        GroupingSpec::Wgc { .. } => "WGC (K groups)",
        GroupingSpec::Hash { .. } => "hashing (K groups)",
    };
    ui.horizontal(|ui| {
        egui::ComboBox::new("grouping", "grouping").selected_text(name(spec)).show_ui(ui, |ui| {
            for choice in [
                GroupingSpec::Mgc { c: 0.4 },
                GroupingSpec::Wgc { k: 8 },
                GroupingSpec::Hash { k: 8, resolve_collisions: true },
            ] {
                let same = std::mem::discriminant(&choice) == std::mem::discriminant(spec);
                if ui.selectable_label(same, name(&choice)).clicked() && !same {
                    *spec = choice;
                }
            }
        });
    });
    match spec {
        GroupingSpec::Mgc { c } => {
            ui.add(egui::Slider::new(c, 0.05..=1.0).text("c (allowed overlap)"));
        }
        GroupingSpec::Wgc { k } => {
            ui.add(egui::Slider::new(k, 1..=MAX_GROUPS).text("K"));
        }
        GroupingSpec::Hash { k, resolve_collisions } => {
            ui.add(egui::Slider::new(k, 1..=MAX_GROUPS).text("K"));
            ui.checkbox(resolve_collisions, "resolve collisions");
        }
    }
    if let Some(g) = &app.grouped {
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
    if let Some(e) = &app.grouping_error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
}

fn camera_section(app: &mut ViewerApp, ui: &mut Ui) {
    ui.heading("Camera");
    let before = app.camera.fov_y_deg;
    ui.add(egui::Slider::new(&mut app.camera.fov_y_deg, 5.0..=120.0).text("field of view °"));
    if app.camera.fov_y_deg != before {
        app.camera_moved();
    }
    ui.horizontal(|ui| {
        if ui.button("Home").on_hover_text("reset the camera (Home key)").clicked() {
            app.reset_camera();
        }
    });
    ui.add(
        egui::Label::new(
            RichText::new("drag: orbit · right/middle drag: pan · wheel: zoom · double-click: centre").weak(),
        )
        .wrap(),
    );
}

fn screenshot_section(app: &mut ViewerApp, ui: &mut Ui) {
    ui.heading("Screenshot");
    ui.horizontal(|ui| {
        egui::ComboBox::new("shot size", "size").selected_text(app.screenshot_size.label()).show_ui(ui, |ui| {
            for choice in ScreenshotSize::CHOICES {
                ui.selectable_value(&mut app.screenshot_size, choice, choice.label());
            }
        });
        if ui.button("Save (Ctrl+S)").clicked() {
            app.save_screenshot();
        }
    });
    ui.label(RichText::new(format!("PNG + JSON sidecar in {}", app.options.screenshot_dir.display())).weak());
    if let Some(status) = &app.status {
        ui.label(status);
    }
}

/// 1234567 -> "1,234,567".
pub(super) fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}
