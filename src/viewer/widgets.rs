//! Widgets the panels share: a job's progress row with Cancel, and number formatting.

use egui::Ui;

use super::state::JobInfo;

/// A progress bar with a Cancel button; returns whether Cancel was clicked.
pub fn job_row(ui: &mut Ui, job: &JobInfo) -> bool {
    let mut cancel = false;
    ui.horizontal(|ui| {
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
    #[test]
    fn thousands_are_grouped() {
        assert_eq!(super::thousands(1234567), "1,234,567");
        assert_eq!(super::thousands(12), "12");
    }
}
