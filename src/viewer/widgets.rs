//! Widgets the panels share: a job's progress row with Cancel, and number formatting.

use egui::Ui;

use super::state::JobInfo;

/// A progress bar with a Cancel button; returns whether Cancel was clicked.
/// The job's label and stage wrap within the panel: in one row they widened
/// it (and narrowed the view) by as much as their longest stage, for good.
pub fn job_row(ui: &mut Ui, job: &JobInfo) -> bool {
    let mut cancel = false;
    ui.horizontal_wrapped(|ui| {
        ui.spinner();
        ui.label(format!("{}: {} ({:.1} s)", job.label, job.stage, job.seconds));
    });
    ui.horizontal(|ui| {
        let bar = match job.fraction {
            Some(f) => egui::ProgressBar::new(f).show_percentage(),
            None => egui::ProgressBar::new(0.0).animate(true),
        };
        ui.add_sized([ui.available_width() - 70.0, 18.0], bar);
        cancel = ui.button("Cancel").clicked();
    });
    cancel
}

/// 1234567 -> "1,234,567".
pub fn thousands(n: usize) -> String {
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::viewer::state::JobKind;

    /// The width a job row takes in a panel `panel` points wide.
    fn row_width(panel: f32, stage: &str) -> f32 {
        let job = JobInfo {
            kind: JobKind::Load,
            label: "refining the view".into(),
            stage: stage.into(),
            fraction: None,
            seconds: 12.3,
        };
        let ctx = egui::Context::default();
        let mut width = 0.0;
        let _ = ctx.run_ui(egui::RawInput::default(), |ui| {
            egui::Panel::left("controls").exact_size(panel).show(ui, |ui| {
                width = ui.scope(|ui| job_row(ui, &job)).response.rect.width();
            });
        });
        width
    }

    #[test]
    fn a_long_stage_wraps_within_the_panel() {
        let long = "selecting and loading nodes, then finding their neighbours and estimating their normals";
        let width = row_width(200.0, long);
        assert!(width <= 200.0, "a job row {width} points wide in a panel of 200");
        assert!(row_width(200.0, "done") <= 200.0);
    }

    #[test]
    fn thousands_are_grouped() {
        assert_eq!(super::thousands(1234567), "1,234,567");
        assert_eq!(super::thousands(12), "12");
    }
}
