//! Box selection: with Inspect's "select" tool a drag on the view draws a
//! screen box; the points of every shown layer whose place on screen falls
//! in it (through the surface: hidden points too, as a segmentation tool
//! cuts) are the selection, and "export selection" writes them as `convert`
//! writes a subset: each file's records read again in f64 and copied with
//! every field, the CRS and the scale (LAS/LAZ), or as a splat PLY
//! ([`crate::cloud::records::Records::write_subset`]). The colour panel's
//! filters apply, as they apply to the view. Several layers write one file
//! each, named after the output and the layer. The export runs as a
//! background job.

use std::path::{Path, PathBuf};

use glam::{DVec3, Mat4, Vec2};

use super::app::ViewerApp;
use super::jobs::Job;
use super::state::ScreenBox;
use crate::cloud::records::Records;

/// What a screen box selects of: the camera's view-projection, the frame's
/// placement, and the box in normalised device coordinates.
#[derive(Debug, Clone)]
struct Selector {
    view_projection: Mat4,
    origin: DVec3,
    unit: f64,
    ndc_min: Vec2,
    ndc_max: Vec2,
}

impl Selector {
    fn holds(&self, file: DVec3) -> bool {
        let p = ((file - self.origin) / self.unit).as_vec3();
        let clip = self.view_projection * p.extend(1.0);
        if clip.w <= 0.0 || clip.z < 0.0 || clip.z > clip.w {
            return false;
        }
        let ndc = Vec2::new(clip.x / clip.w, clip.y / clip.w);
        ndc.cmpge(self.ndc_min).all() && ndc.cmple(self.ndc_max).all()
    }
}

impl ViewerApp {
    /// The select tool's drag on the view: a box from the press to the
    /// pointer; on release it is the selection. Whether the drag was taken.
    pub(super) fn select_input(&mut self, response: &egui::Response) -> bool {
        let inspect = &mut self.ui.inspect;
        if response.drag_started_by(egui::PointerButton::Primary) {
            let press = response.interact_pointer_pos().map(|p| p - response.drag_delta());
            inspect.selecting = press;
        }
        let Some(start) = inspect.selecting else { return false };
        if let Some(now) = response.interact_pointer_pos() {
            let rect = egui::Rect::from_two_pos(start, now);
            inspect.selection = Some(ScreenBox { rect, view: self.view_rect, camera: self.ui.camera });
        }
        if response.drag_stopped() {
            inspect.selecting = None;
        }
        true
    }

    /// The selection's box over the view.
    pub(super) fn draw_selection(&self, painter: &egui::Painter) {
        if let Some(selection) = &self.ui.inspect.selection {
            let colour = egui::Color32::from_rgb(255, 120, 220);
            painter.rect_filled(selection.rect, 0.0, colour.gamma_multiply(0.12));
            let stroke = egui::Stroke::new(1.5, colour);
            painter.rect_stroke(selection.rect, 0.0, stroke, egui::StrokeKind::Middle);
        }
    }

    /// Exports the selection to `output` in the background (its count and
    /// files in the status line when done).
    pub fn export_selection(&mut self, ctx: &egui::Context, output: &Path) {
        let (Some(model), Some(selection)) = (&self.model, &self.ui.inspect.selection) else {
            self.status = Some("no selection to export: draw a box with the select tool".into());
            return;
        };
        let view = selection.view;
        let (origin, unit) = model.scene.frame_placement();
        let aspect = view.width() / view.height().max(1.0);
        let camera = selection.camera;
        let to_ndc = |p: egui::Pos2| {
            Vec2::new((p.x - view.left()) / view.width() * 2.0 - 1.0, 1.0 - (p.y - view.top()) / view.height() * 2.0)
        };
        let (a, b) = (to_ndc(selection.rect.min), to_ndc(selection.rect.max));
        let selector = Selector {
            view_projection: camera.projection(aspect) * camera.view_matrix(),
            origin,
            unit,
            ndc_min: a.min(b),
            ndc_max: a.max(b),
        };
        let files = self.selected_files(&model.path);
        let style = model.style.as_deref().cloned();
        let output = output.to_path_buf();
        let job = Job::spawn("exporting the selection", ctx.clone(), move || {
            export(&files, &selector, style.as_ref(), &output)
        });
        self.export = Some(job);
    }

    /// The files a selection or a profile is taken from: the shown layers, else the model's file.
    pub(super) fn selected_files(&self, model_path: &Path) -> Vec<PathBuf> {
        let shown: Vec<PathBuf> = self.layers.iter().filter(|l| l.shown).map(|l| l.path.clone()).collect();
        if shown.is_empty() { vec![model_path.to_path_buf()] } else { shown }
    }

    /// Takes the export job's result when it is done.
    pub(super) fn poll_export(&mut self) {
        if let Some(result) = self.export.as_ref().and_then(|j| j.poll()) {
            self.export = None;
            self.status = Some(match result.and_then(|r| r) {
                Ok(done) => done,
                Err(e) => format!("export failed: {e}"),
            });
        }
    }

    /// Keeps only the selection (`keep`), or hides it, by the clip every mode
    /// draws (recorded in sidecars): the four planes through the box's edges
    /// keep its inside; hiding it is a clip box with its inside hidden, which
    /// a box on screen is only in an orthographic plan or elevation view.
    pub(super) fn clip_to_selection(&mut self, keep: bool) {
        let (Some(model), Some(selection)) = (&self.model, self.ui.inspect.selection) else { return };
        let (origin, unit) = model.scene.frame_placement();
        let bounds = model.cloud.bounds();
        let inspect = &mut self.ui.inspect;
        if keep {
            let planes = super::selection_clip::frustum_planes(&selection, origin, unit);
            let given = inspect.clip_planes.len();
            if given + planes.len() > crate::frame::clip::MAX_CLIP_PLANES {
                self.status = Some(format!("the clip already has {given} planes: keeping the selection needs 4 more"));
                return;
            }
            inspect.clip_planes.extend(planes);
        } else {
            let Some(b) = bounds else { return };
            let file = |p: glam::Vec3| p.as_dvec3() * unit + origin;
            match super::selection_clip::axis_box(&selection, origin, unit, (file(b.min), file(b.max))) {
                Some(clip_box) => inspect.clip_box = Some(clip_box),
                None => {
                    self.status =
                        Some("hiding a selection needs an orthographic plan or elevation view (O, 1-6)".into());
                    return;
                }
            }
        }
        inspect.clip_on = true;
        inspect.selection = None;
        self.camera_moved();
    }

    /// Whether an export is under way.
    pub fn is_exporting(&self) -> bool {
        self.export.is_some()
    }
}

/// Writes each file's selected records; what was written, in a line.
fn export(
    files: &[PathBuf],
    selector: &Selector,
    style: Option<&crate::style::Style>,
    output: &Path,
) -> Result<String, String> {
    let write = |records: &Records, keep: &[u32], out: &Path| {
        if keep.is_empty() {
            return Ok(false);
        }
        records.write_subset(keep, out).map(|()| true).map_err(|e| e.to_string())
    };
    let (total, written) = super::export_points::export_each(files, style, output, |p| selector.holds(p), write)?;
    if written.is_empty() {
        return Err("the box holds no point".into());
    }
    Ok(format!("exported {total} selected points to {}", written.join(", ")))
}
