//! The panel's live statistics (frame and pass times, splats, groups, the
//! render plan) and the error measurement against the exact reference.

use egui::{RichText, Ui};

use super::app::ViewerApp;
use super::panels::{job_row, thousands};

pub(super) fn stats_section(app: &mut ViewerApp, ui: &mut Ui) {
    ui.heading("Statistics");
    ui.label(format!("window: {:.0} fps, slowest frame {:.0} ms (last 2 s)", app.ui_fps, app.slowest_ui_frame_ms()));
    let Some(shown) = &app.shown else {
        ui.label("no frame yet");
        return;
    };
    let stats = &shown.stats;
    let (w, h) = shown.key.size;
    let what = if stats.preview { "preview (two-pass on a subsample)" } else { shown.key.settings.mode.name() };
    ui.label(format!("{what}, {w}×{h}: {:.1} ms per frame", stats.frame_ms));
    ui.label(format!("{} splats drawn, {} geometry pass(es)", thousands(stats.splats_drawn), stats.geometry_passes));
    if !stats.pass_ms.is_empty() {
        egui::Grid::new("passes").striped(true).show(ui, |ui| {
            for (pass, ms) in &stats.pass_ms {
                ui.label(pass);
                ui.label(format!("{ms:.2} ms"));
                ui.end_row();
            }
        });
    } else if shown.key.settings.mode.is_gpu() {
        ui.label(RichText::new("no GPU timestamps on this adapter").weak());
    }
    if let Some(plan) = &stats.plan {
        ui.collapsing(
            format!("render plan ({:.1} MiB of targets)", stats.plan_bytes as f64 / (1 << 20) as f64),
            |ui| {
                ui.label(RichText::new(plan).monospace().size(10.0));
            },
        );
    }
}

pub(super) fn error_section(app: &mut ViewerApp, ui: &mut Ui) {
    ui.heading("Error against the reference");
    let ctx = ui.ctx().clone();
    let current = app.current_key();
    let shown_key = app.shown.as_ref().map(|s| &s.key);
    let comparable = shown_key.is_some_and(|k| !k.preview && k.settings.mode.is_gpu()) && shown_key == current.as_ref();
    let mut cancel = false;
    if let Some(job) = &app.measure {
        cancel = job_row(ui, job.label(), job.progress(), job.seconds());
    } else if ui
        .add_enabled(comparable, egui::Button::new("Measure error"))
        .on_disabled_hover_text("needs a finished GPU frame of the current view")
        .clicked()
    {
        app.measure_error(&ctx);
    }
    if cancel {
        if let Some(job) = app.measure.take() {
            job.cancel();
        }
    }
    if let Some(e) = &app.measure_error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
    if let Some(m) = &app.measurement {
        let stale = current.as_ref() != Some(&m.key);
        let psnr = if m.error.psnr.is_finite() { format!("{:.2} dB", m.error.psnr) } else { "∞".into() };
        ui.label(format!(
            "{}: ε {:.3}, PSNR {psnr}, {:.2}% pixels off by > 8/255",
            m.key.settings.mode,
            m.error.eps,
            100.0 * m.error.bad_pixel_share
        ));
        ui.label(RichText::new(format!("reference rendered in {:.1} s", m.reference_seconds)).weak());
        if stale {
            ui.label(RichText::new("(for an earlier view)").italics());
        }
        let size = m.difference.size_vec2();
        let width = ui.available_width().min(280.0);
        ui.add(egui::Image::new((m.difference.id(), size * (width / size.x.max(1.0)))))
            .on_hover_text("difference × 8 (false colour)");
    }
}
