//! The app's side of the panels: the read-only [`PanelInfo`] they show, and
//! the [`Action`]s they return, applied to the app.

use super::app::ViewerApp;
use super::state::{Action, JobInfo, JobKind, ModelInfo, PanelInfo, ShownInfo};

impl ViewerApp {
    /// What the panels show.
    pub(super) fn panel_info(&self) -> PanelInfo<'_> {
        let job_info = |kind, label: &str, (stage, fraction), seconds| JobInfo {
            kind,
            label: label.to_string(),
            stage,
            fraction,
            seconds,
        };
        let mut jobs = Vec::new();
        if let Some(j) = &self.load {
            jobs.push(job_info(JobKind::Load, j.label(), j.progress(), j.seconds()));
        }
        if let Some((_, j)) = &self.grouping_job {
            jobs.push(job_info(JobKind::Grouping, j.label(), j.progress(), j.seconds()));
        }
        if let Some(j) = &self.measure {
            jobs.push(job_info(JobKind::Measure, j.label(), j.progress(), j.seconds()));
        }
        PanelInfo {
            model: self.model.as_ref().map(|m| ModelInfo {
                name: &m.name,
                path: &m.path,
                splats: m.cloud.len(),
                warnings: &m.warnings,
                opacity: m.opacity(),
                transparent: m.transparent,
                environment: m.scene.environment.as_ref().map(|e| e.name.as_str()),
                period: m.period,
                style: m.style.as_deref(),
                summary: &m.summary,
            }),
            load_error: self.load_error.as_deref(),
            jobs,
            view_progress: self.view_progress(),
            grouped: self.grouped.as_ref(),
            grouping_error: self.grouping_error.as_deref(),
            shown: self.shown.as_ref().map(|s| ShownInfo { key: &s.key, stats: &s.stats }),
            current: self.current_key(),
            ui_fps: self.frame_clock.fps(),
            slowest_ui_frame_ms: self.slowest_ui_frame_ms(),
            measurement: self.measurement.as_ref(),
            measure_error: self.measure_error.as_deref(),
            screenshot_dir: &self.options.screenshot_dir,
            status: self.status.as_deref(),
            streaming: self.model.as_ref().and_then(|m| m.streamed.as_ref()).map(|s| (s.status(), self.load.is_some())),
            layers: &self.layers,
            layer_looks: self.layer_looks(),
            polygon: self.polygon_report.as_ref().map(|(_, report)| report),
        }
    }

    /// Takes the actions the panels returned.
    pub(super) fn apply(&mut self, ctx: &egui::Context, actions: Vec<Action>) {
        for action in actions {
            match action {
                Action::Open(path) => self.open_or_add(ctx, &path),
                Action::SetLayerLook(k, look) => self.set_layer_look(ctx, k, look),
                Action::ShowLayer(k, shown) => self.show_layer(ctx, k, shown),
                Action::RemoveLayer(k) => self.remove_layer(ctx, k),
                Action::ExportSelection(path) => self.export_selection(ctx, &path),
                Action::KeepSelection(keep) => self.clip_to_selection(ctx, keep),
                Action::ClearRegions => self.clear_regions(ctx),
                Action::ExportProfile(path) => self.export_profile(ctx, &path),
                Action::Cancel(JobKind::Load) => self.cancel_load(),
                Action::Cancel(JobKind::Grouping) => {
                    if let Some((_, job)) = self.grouping_job.take() {
                        job.cancel();
                    }
                    // Back to the grouping on screen, so the job does not restart at once.
                    if let Some(g) = &self.grouped {
                        self.ui.settings.grouping = g.spec;
                    }
                }
                Action::Cancel(JobKind::Measure) => {
                    if let Some(job) = self.measure.take() {
                        job.cancel();
                    }
                }
                Action::MeasureError => self.measure_error(ctx),
                Action::SaveScreenshot => self.save_screenshot(),
                Action::SaveLargeScreenshot => self.save_large_screenshot(),
                Action::SaveViews => self.save_views(),
                Action::ResetCamera => self.reset_camera(),
                Action::CameraMoved => self.camera_moved(),
                Action::SetOpacity(opacity) => self.set_opacity(ctx, opacity),
                Action::SetStyle(style) => self.set_style(ctx, style),
                Action::SetEnvironment(path) => self.set_environment(ctx, path),
                Action::ShowError(message) => self.load_error = Some(message),
            }
        }
    }
}
