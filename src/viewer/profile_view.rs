//! The profile tool: two clicks on the view (draw them on the top view)
//! give a line on the ground, the panel's width its slab
//! ([`crate::inspect::profile::Profile`], what `profile --line --width`
//! cuts). The slab of the points on screen (every layer's, after the
//! filters, in file coordinates) is found again only when the line, the
//! width or the model changes, and shown under the view
//! (`profile_panel.rs`). Exporting reads each file's records again, as the
//! command does, and writes the slab's CSV (`profile --csv`) or its records
//! (`profile --points`), in the background; a PNG is the section drawn as
//! `profile --out` draws it ([`crate::render::section`]), of the points on
//! screen, in the view's mode, style and clip, at the panel section's size.

use std::path::{Path, PathBuf};

use super::app::ViewerApp;
use super::jobs::Job;
use super::state::ProfileSlab;
use crate::cloud::records::Records;
use crate::inspect::profile::Profile;

impl ViewerApp {
    /// Cuts the slab again if the line, the width or the model changed.
    pub(super) fn cut_profile(&mut self) {
        let inspect = &self.ui.inspect;
        let Some(model) = self.model.as_ref().filter(|_| inspect.profile_line.len() == 2) else {
            self.profile_slab = None;
            return;
        };
        let (a, b) = (inspect.profile_line[0], inspect.profile_line[1]);
        let key = (vec![a, b], inspect.profile_width.to_bits(), model.generation);
        if self.profile_slab.as_ref().is_some_and(|(k, _)| *k == key) {
            return;
        }
        let slab = Profile::new(a.truncate(), b.truncate(), inspect.profile_width).map(|profile| {
            let mut slab = ProfileSlab { profile, points: Vec::new(), colours: Vec::new() };
            for object in &model.scene.objects {
                let cloud = &object.cloud;
                for i in 0..cloud.len() {
                    let p = cloud.file_position(i);
                    if profile.holds(p) {
                        slab.points.push(p);
                        slab.colours.push(cloud.colours.get(i).copied().unwrap_or([200; 3]));
                    }
                }
            }
            slab
        });
        self.profile_slab = Some((key, slab));
    }

    /// The profile's panel under the view, while its line has two ends.
    pub(super) fn profile_side_panel(&mut self, ui: &mut egui::Ui) -> Vec<super::state::Action> {
        let Some((_, slab)) = &self.profile_slab else { return Vec::new() };
        let units = self.model.as_ref().map_or(String::new(), |m| m.cloud.units.horizontal_name().to_string());
        let inspect = &mut self.ui.inspect;
        let mut actions = Vec::new();
        // Under the view, above the status line: a section is long and low.
        egui::Panel::bottom("profile").resizable(true).default_size(240.0).show(ui, |ui| {
            actions = super::profile_panel::profile_panel(ui, slab, inspect, &units);
        });
        actions
    }

    /// The profile's slab of the points on screen, once its line has two ends.
    pub fn profile_slab(&self) -> Option<&Result<ProfileSlab, String>> {
        self.profile_slab.as_ref().map(|(_, slab)| slab)
    }

    /// Writes the slab of every shown file to `output`: CSV rows (`.csv`),
    /// the records (LAS, LAZ, PLY), or the section drawn (PNG, JPEG), in the background.
    pub fn export_profile(&mut self, ctx: &egui::Context, output: &Path) {
        if self.export_under_way() {
            return;
        }
        let (Some(model), Some(Ok(slab))) = (&self.model, self.profile_slab()) else {
            self.status = Some("no profile to export: click its line's two ends with the profile tool".into());
            return;
        };
        let profile = slab.profile;
        if crate::output::ImageFormat::of(output).is_ok() {
            let heights = slab.points.iter().fold((f64::MAX, f64::MIN), |(l, h), p| (l.min(p.z), h.max(p.z)));
            if slab.points.is_empty() {
                self.status = Some("the slab holds no point, so there is nothing to draw".into());
                return;
            }
            let mut scene = (*model.scene).clone();
            // The panel's section at its size on screen (at least 64 pixels a side).
            let ppp = ctx.pixels_per_point();
            let panel = self.ui.inspect.profile_layout.map_or(egui::vec2(1024.0, 256.0), |l| l.rect.size() * ppp);
            let size = (panel.x.round().max(64.0) as u32, panel.y.round().max(64.0) as u32);
            let (settings, region) = (self.ui.settings, self.ui.inspect.region());
            let output = output.to_path_buf();
            self.export = Some(Job::spawn("drawing the profile", ctx.clone(), move || {
                crate::render::section::face_the_side(&mut scene, &profile);
                let (image, mode) = crate::render::section::draw(scene, &profile, heights, settings, region, size)
                    .map_err(|e| e.to_string())?;
                crate::output::save_image(&image, &output).map_err(|e| format!("{}: {e}", output.display()))?;
                Ok(format!("drew the profile ({mode}, {}x{}) to {}", size.0, size.1, output.display()))
            }));
            return;
        }
        let files = self.selected_files(&model.path);
        let style = model.style.as_deref().cloned();
        let output = output.to_path_buf();
        self.export = Some(Job::spawn("exporting the profile", ctx.clone(), move || {
            export(&files, &profile, style.as_ref(), &output)
        }));
    }
}

/// Writes each file's slab; what was written, in a line.
fn export(
    files: &[PathBuf],
    profile: &Profile,
    style: Option<&crate::style::Style>,
    output: &Path,
) -> Result<String, String> {
    let csv = output.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
    let write = |records: &Records, slab: &[u32], out: &Path| {
        if csv {
            crate::inspect::profile_table::write_csv(profile, records, slab, out).map_err(|e| e.to_string())?;
        } else if slab.is_empty() {
            return Ok(false);
        } else {
            records.write_subset(slab, out).map_err(|e| e.to_string())?;
        }
        Ok(true)
    };
    let (total, written) = super::export_points::export_each(files, style, output, |p| profile.holds(p), write)?;
    if written.is_empty() {
        return Err("the slab holds no point".into());
    }
    Ok(format!("exported the profile's {total} points to {}", written.join(", ")))
}
