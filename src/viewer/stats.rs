//! The panel's live statistics (frame and pass times, splats, groups, the
//! render plan) and the error measurement against the exact reference.

use egui::{RichText, Ui};

use super::state::{Action, JobKind, PanelInfo};
use super::widgets::{job_row, thousands};

pub fn stats_section(ui: &mut Ui, info: &PanelInfo<'_>) {
    ui.heading("Statistics");
    ui.label(format!("window: {:.0} fps, slowest frame {:.0} ms (last 2 s)", info.ui_fps, info.slowest_ui_frame_ms));
    if let Some((status, refining)) = &info.streaming {
        streaming_lines(ui, status, *refining);
    }
    let Some(shown) = &info.shown else {
        ui.label("no frame yet");
        return;
    };
    let stats = shown.stats;
    let (w, h) = shown.key.size;
    let what = match stats.preview {
        Some(p) => format!("preview ({} under a budget of {} splats)", p.mode, thousands(p.budget as usize)),
        None => shown.key.settings.mode.to_string(),
    };
    ui.label(format!("{what}, {w}×{h}: {:.1} ms per frame", stats.frame_ms));
    ui.label(format!("{} splats drawn, {} geometry pass(es)", thousands(stats.splats_drawn), stats.geometry_passes));
    if let (Some(regroup), Some(upload)) = (stats.regroup_ms, stats.upload_ms) {
        let time = shown.key.time.unwrap_or(0.0);
        ui.label(format!(
            "at {time:.2} s: regrouped {} splats in {regroup:.1} ms, uploaded in {upload:.1} ms",
            thousands(stats.regrouped.unwrap_or(0))
        ));
    }
    if !stats.pass_ms.is_empty() {
        egui::Grid::new("passes").striped(true).show(ui, |ui| {
            for (pass, ms) in &stats.pass_ms {
                ui.label(pass);
                // Of one width whatever the time, so that a slower frame does not widen the panel (and the view).
                ui.label(RichText::new(format!("{ms:>9.2} ms")).monospace());
                ui.end_row();
            }
        });
    } else if shown.key.settings.mode.is_gpu() {
        // No timestamps, or (lavapipe) none that enclose a compute pass's dispatches.
        ui.label(RichText::new("no per-pass GPU times on this adapter").weak());
    }
    if let Some(plan) = &stats.plan {
        ui.collapsing(
            format!("render plan ({:.1} MiB of GPU memory)", stats.plan_bytes as f64 / (1 << 20) as f64),
            |ui| {
                ui.label(RichText::new(plan).monospace().size(10.0));
            },
        );
    }
    if !stats.report.is_empty() {
        ui.collapsing("measured while drawing", |ui| {
            for line in &stats.report {
                ui.label(RichText::new(line).monospace().size(10.0));
            }
        });
    }
}

pub fn error_section(ui: &mut Ui, info: &PanelInfo<'_>, actions: &mut Vec<Action>) {
    ui.heading("Error against the reference");
    let shown_key = info.shown.as_ref().map(|s| s.key);
    let comparable = shown_key.is_some_and(|k| k.preview.is_none() && k.settings.mode.is_gpu())
        && shown_key == info.current.as_ref();
    if let Some(job) = info.job(JobKind::Measure) {
        if job_row(ui, job) {
            actions.push(Action::Cancel(JobKind::Measure));
        }
    } else if ui
        .add_enabled(comparable, egui::Button::new("Measure error"))
        .on_disabled_hover_text("needs a finished GPU frame of the current view")
        .clicked()
    {
        actions.push(Action::MeasureError);
    }
    if let Some(e) = info.measure_error {
        ui.colored_label(egui::Color32::LIGHT_RED, e);
    }
    if let Some(m) = info.measurement {
        let stale = info.current.as_ref() != Some(&m.key);
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

/// What a streamed file shows: the nodes and points on screen, what was read, the cache.
fn streaming_lines(ui: &mut Ui, s: &super::stream_source::StreamStatus, refining: bool) {
    let (used, nodes, bound) = s.cache;
    ui.label(format!(
        "streaming: {} nodes shown ({} of {} points){}",
        s.nodes_shown,
        thousands(s.points_shown),
        thousands(s.points_in_file as usize),
        if refining { ", refining the view" } else { "" }
    ));
    ui.label(format!(
        "read {:.1} MB in {} requests{}; {} nodes known, {} failed",
        s.stats.bytes_read as f64 / 1e6,
        s.stats.requests,
        s.mb_per_s.map_or(String::new(), |r| format!(", {r:.1} MB/s")),
        s.nodes_known,
        s.stats.failed
    ));
    ui.label(format!("node cache: {:.0} of {:.0} MB ({nodes} nodes)", used as f64 / 1e6, bound as f64 / 1e6));
    // Streamed layers: each file's share of the one budget.
    for (name, points, nodes) in &s.layers {
        ui.label(format!("{name}: {} points of {nodes} nodes", thousands(*points)));
    }
}
