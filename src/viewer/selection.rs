//! Selections: with Inspect's "select" tool a drag on the view draws a
//! screen box, with "lasso" a free outline; the points of every shown layer
//! whose place on screen falls inside it (through the surface: hidden
//! points too, as a segmentation tool cuts) are the selection, a
//! [`Region`] of file space. "export selection" writes them as `convert`
//! writes a subset: each file's records read again in f64 and copied with
//! every field, the CRS and the scale (LAS/LAZ), or as a splat PLY
//! ([`crate::cloud::records::Records::write_subset`]). The colour panel's
//! filters apply, as they apply to the view. Several layers write one file
//! each, named after the output and the layer. The export runs as a
//! background job. "keep only" and "hide" cut a box per pixel by the clip
//! where the clip can hold it, and otherwise (a lasso; hiding a box outside
//! an axis-aligned orthographic view) add the region to the style, which
//! drops whole points in every mode ([`crate::style::region`]).

use std::path::{Path, PathBuf};

use glam::DVec3;

use super::app::ViewerApp;
use super::jobs::Job;
use super::state::{ScreenSelection, Tool};
use crate::cloud::records::Records;
use crate::style::region::Region;

/// Closer lasso points than this (points on screen) are not added.
const LASSO_STEP: f32 = 3.0;

/// The region of file space `selection` holds, kept (`keep`) or hidden,
/// in the frame placed at `origin` with `unit`.
pub fn region_of(selection: &ScreenSelection, (origin, unit): (DVec3, f64), keep: bool) -> Region {
    let view = selection.view;
    let aspect = view.width() / view.height().max(1.0);
    let camera = selection.camera;
    let to_ndc = |p: &egui::Pos2| {
        let x = (p.x - view.left()) / view.width() * 2.0 - 1.0;
        let y = 1.0 - (p.y - view.top()) / view.height() * 2.0;
        [f64::from(x), f64::from(y)]
    };
    let r = selection.rect;
    let corners = [r.left_bottom(), r.right_bottom(), r.right_top(), r.left_top()];
    let outline = if selection.lasso.len() >= 3 { selection.lasso.as_slice() } else { &corners[..] };
    Region {
        view_projection: (camera.projection(aspect) * camera.view_matrix()).as_dmat4().to_cols_array(),
        origin: origin.to_array(),
        unit,
        outline: outline.iter().map(to_ndc).collect(),
        keep,
    }
}

impl ViewerApp {
    /// The select and lasso tools' drag on the view: a box from the press to
    /// the pointer, or the outline the pointer draws; on release it is the
    /// selection. Whether the drag was taken.
    pub(super) fn select_input(&mut self, response: &egui::Response) -> bool {
        let lasso = self.ui.inspect.tool == Tool::Lasso;
        let inspect = &mut self.ui.inspect;
        if response.drag_started_by(egui::PointerButton::Primary) {
            let press = response.interact_pointer_pos().map(|p| p - response.drag_delta());
            inspect.selecting = press;
            inspect.selection = None;
        }
        let Some(start) = inspect.selecting else { return false };
        if let Some(now) = response.interact_pointer_pos() {
            let (view, camera) = (self.view_rect, self.ui.camera);
            let selection = inspect.selection.get_or_insert_with(|| ScreenSelection {
                rect: egui::Rect::from_two_pos(start, start),
                lasso: if lasso { vec![start] } else { Vec::new() },
                view,
                camera,
            });
            if !lasso {
                selection.rect = egui::Rect::from_two_pos(start, now);
            } else if selection.lasso.last().is_none_or(|last| last.distance(now) >= LASSO_STEP) {
                selection.lasso.push(now);
                selection.rect = selection.rect.union(egui::Rect::from_pos(now));
            }
        }
        if response.drag_stopped() {
            inspect.selecting = None;
            // A lasso of fewer than three points holds nothing.
            if inspect.selection.as_ref().is_some_and(|s| lasso && s.lasso.len() < 3) {
                inspect.selection = None;
            }
        }
        true
    }

    /// The selection's box or outline over the view.
    pub(super) fn draw_selection(&self, painter: &egui::Painter) {
        let Some(selection) = &self.ui.inspect.selection else { return };
        let colour = egui::Color32::from_rgb(255, 120, 220);
        let stroke = egui::Stroke::new(1.5, colour);
        if selection.lasso.is_empty() {
            painter.rect_filled(selection.rect, 0.0, colour.gamma_multiply(0.12));
            painter.rect_stroke(selection.rect, 0.0, stroke, egui::StrokeKind::Middle);
        } else {
            painter.add(egui::Shape::closed_line(selection.lasso.clone(), stroke));
        }
    }

    /// Exports the selection to `output` in the background (its count and
    /// files in the status line when done).
    pub fn export_selection(&mut self, ctx: &egui::Context, output: &Path) {
        if self.export_under_way() {
            return;
        }
        let (Some(model), Some(selection)) = (&self.model, &self.ui.inspect.selection) else {
            self.status = Some("no selection to export: draw a box or a lasso with the select or lasso tool".into());
            return;
        };
        let selector = region_of(selection, model.scene.frame_placement(), true);
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

    /// Keeps only the selection (`keep`), or hides it. A box is cut per
    /// pixel by the clip every mode draws (recorded in sidecars) where the
    /// clip can hold it: kept, the four planes through its edges; hidden, a
    /// clip box with its inside hidden, which a box on screen is only in an
    /// orthographic plan or elevation view. Anything else (a lasso, or a
    /// box hidden in another view) is added to the style as a region,
    /// which drops the points it holds (or does not) in every mode.
    pub(super) fn clip_to_selection(&mut self, ctx: &egui::Context, keep: bool) {
        let (Some(model), Some(selection)) = (&self.model, self.ui.inspect.selection.clone()) else { return };
        let (origin, unit) = model.scene.frame_placement();
        let bounds = model.cloud.bounds();
        let file = |p: glam::Vec3| p.as_dvec3() * unit + origin;
        let clip_box =
            bounds.and_then(|b| super::selection_clip::axis_box(&selection, origin, unit, (file(b.min), file(b.max))));
        let given = self.ui.inspect.clip_planes.len();
        let clipped = match (selection.lasso.is_empty(), keep) {
            (true, true) if given + 4 <= crate::frame::clip::MAX_CLIP_PLANES => {
                let planes = super::selection_clip::frustum_planes(&selection, origin, unit);
                self.ui.inspect.clip_planes.extend(planes);
                true
            }
            (true, false) if clip_box.is_some() => {
                self.ui.inspect.clip_box = clip_box;
                true
            }
            _ => false,
        };
        let inspect = &mut self.ui.inspect;
        inspect.selection = None;
        if clipped {
            inspect.clip_on = true;
            self.camera_moved();
            return;
        }
        let mut style = model.style.as_deref().cloned().unwrap_or_default();
        style.regions.push(region_of(&selection, (origin, unit), keep));
        self.set_style(ctx, Some(style));
    }

    /// Shows again what kept or hidden selections (the style's regions) dropped.
    pub(super) fn clear_regions(&mut self, ctx: &egui::Context) {
        let Some(mut style) = self.model.as_ref().and_then(|m| m.style.as_deref().cloned()) else { return };
        style.regions.clear();
        self.set_style(ctx, (!style.is_plain()).then_some(style));
    }

    /// Whether an export is under way.
    pub fn is_exporting(&self) -> bool {
        self.export.is_some()
    }

    /// Whether an export is under way, said in the status line: one runs at a time, and its report is kept.
    pub(super) fn export_under_way(&mut self) -> bool {
        let busy = self.export.is_some();
        if busy {
            self.status = Some("an export is under way: the next one starts when it is done".into());
        }
        busy
    }
}

/// Writes each file's selected records; what was written, in a line.
fn export(
    files: &[PathBuf],
    selector: &Region,
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
        return Err("the selection holds no point".into());
    }
    Ok(format!("exported {total} selected points to {}", written.join(", ")))
}
