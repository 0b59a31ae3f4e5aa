//! The frame the 3D view needs and its way through the render thread: the
//! key of the current frame, the grouping its mode draws (computed or read
//! from the cache on a worker thread), the requests sent, and the finished
//! frames put on screen.

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::app::{ShownFrame, ViewerApp};
use super::jobs::Job;
use super::model::GroupedModel;
use super::render_thread::{FrameRequest, Purpose};
use super::state::FrameKey;
use crate::frame::View;
use crate::frame::spec::Preview;
use crate::grouping::GroupingSpec;
use crate::grouping::cache::Cache;

/// How long after the last camera move large models still draw their budgeted preview.
pub(super) const SETTLE: Duration = Duration::from_millis(300);

/// The grouping (from the grouping job) a full frame of `settings` waits
/// for, if any: the one its spec draws ([`crate::frame::resolve`]), unless
/// that is redone every frame in the render thread (a moving scene, or
/// splats chosen per view under a point budget or beside triangles).
pub(super) fn drawn_grouping(
    model: &super::model::Model,
    settings: &crate::render::RenderSettings,
    size: (u32, u32),
) -> Option<GroupingSpec> {
    let spec = crate::frame::resolve(settings, &model.facts(), &View::still(size));
    spec.grouping.filter(|g| !g.per_frame).map(|g| g.spec)
}

impl ViewerApp {
    /// The frame the view should show now, if a model is loaded.
    pub fn current_key(&self) -> Option<FrameKey> {
        self.frame_key(true)
    }

    /// The frame of the current state; `may_preview`: a large model whose
    /// camera just moved is drawn under the moving budget (never in a screenshot).
    pub(super) fn frame_key(&self, may_preview: bool) -> Option<FrameKey> {
        let model = self.model.as_ref()?;
        let budget = self.ui.moving_budget.min(self.ui.settings.point_budget.unwrap_or(u32::MAX));
        // A streamed model is the selection under the budget already.
        let large = model.cloud.len() > budget as usize && !model.is_animated() && model.streamed.is_none();
        let moving = may_preview && large && self.last_camera_move.is_some_and(|t| t.elapsed() < SETTLE);
        // The viewer's preview rule (`preview.rs`), under the moving budget.
        let preview = moving.then(|| Preview { mode: super::preview::preview_mode(self.ui.settings.mode), budget });
        let mut settings = self.ui.settings;
        settings.clip = model.scene.clip_in_frame(&self.ui.inspect.region());
        let grouping = if preview.is_some() { None } else { drawn_grouping(model, &settings, self.view_size) };
        Some(FrameKey {
            generation: model.generation,
            grouping: grouping.map(|g| g.to_string()),
            camera: self.ui.camera,
            settings,
            size: self.view_size,
            preview,
            time: model.is_animated().then_some(self.ui.time),
        })
    }

    /// Whether the view shows the full-quality frame for the current state, with nothing pending.
    pub fn is_settled(&self) -> bool {
        let current = self.current_key();
        self.load.is_none()
            && self.grouping_job.is_none()
            && (self.model.is_none() || (current.is_some() && self.shown.as_ref().map(|s| &s.key) == current.as_ref()))
    }

    /// Progress of a CPU-mode frame (the reference) the view is waiting for.
    pub(super) fn view_progress(&self) -> Option<(String, Option<f32>)> {
        let (_, key) = self.in_flight.last()?;
        (!key.settings.mode.is_gpu() && key.preview.is_none()).then(|| self.renderer.tracker.snapshot())
    }

    /// Starts a grouping when the mode draws groups and the one it needs is not there.
    pub(super) fn ensure_grouping(&mut self, ctx: &egui::Context) {
        let Some(model) = self.model.clone() else { return };
        let Some(spec) = drawn_grouping(&model, &self.ui.settings, self.view_size) else { return };
        let have = self.grouped.as_ref().is_some_and(|g| g.generation == model.generation && g.spec == spec);
        let running = self.grouping_job.as_ref().is_some_and(|(s, _)| *s == spec);
        if have || running || ctx.input(|i| i.pointer.any_down()) {
            return; // wait for a slider to be released before regrouping
        }
        if let Some((_, old)) = self.grouping_job.take() {
            old.cancel();
        }
        let generation = model.generation;
        let cache = self.options.cache.clone().unwrap_or_else(Cache::from_env);
        let job = Job::spawn(format!("grouping {spec}"), ctx.clone(), move || {
            let started = Instant::now();
            let (grouping, cached) =
                spec.compute_cached_for_hash(&cache, model.hash, &model.cloud).map_err(|e| e.to_string())?;
            let grouping = std::sync::Arc::new(grouping);
            Ok(GroupedModel { generation, spec, grouping, seconds: started.elapsed().as_secs_f64(), cached })
        });
        self.grouping_job = Some((spec, job));
    }

    /// Takes the grouping the grouping job returned, if it has finished.
    pub(super) fn poll_grouping(&mut self) {
        if let Some(result) = self.grouping_job.as_ref().and_then(|(_, j)| j.poll()) {
            self.grouping_job = None;
            match result.and_then(|r| r) {
                Ok(g) => {
                    self.grouping_error = None;
                    self.grouped = Some(Arc::new(g));
                }
                Err(e) => self.grouping_error = Some(e),
            }
        }
    }

    /// Sends the current frame to the renderer unless it is on screen or on its way.
    pub(super) fn request_frame(&mut self, ctx: &egui::Context) {
        let Some(key) = self.current_key() else { return };
        if self.view_size.0 < 1 || self.view_size.1 < 1 || ctx.input(|i| i.viewport().minimized == Some(true)) {
            return;
        }
        if key.preview.is_some() {
            ctx.request_repaint_after(SETTLE); // to draw the full frame once the camera rests
        }
        if self.requested.as_ref() == Some(&key) {
            return;
        }
        let Some(request) = self.frame_request(&key, key.size, Purpose::Display) else { return };
        self.in_flight.push((request.id, key.clone()));
        self.requested = Some(key);
        self.renderer.request(request);
    }

    /// A request for the frame of `key` at `size`, or `None` while its grouping is not ready.
    pub(super) fn frame_request(&mut self, key: &FrameKey, size: (u32, u32), purpose: Purpose) -> Option<FrameRequest> {
        let model = self.model.clone()?;
        let grouping = if let Some(wanted) = &key.grouping {
            let g = self.grouped.clone().filter(|g| g.generation == model.generation && g.spec.to_string() == *wanted);
            Some(g?) // the old image stays until the grouping is ready
        } else {
            None
        };
        let id = self.next_request;
        self.next_request += 1;
        Some(FrameRequest {
            id,
            model,
            grouping,
            camera: key.camera,
            settings: key.settings,
            size,
            preview: key.preview,
            time: key.time,
            purpose,
        })
    }

    /// Takes the frames the render thread finished: the view's go on screen, screenshots report.
    pub(super) fn poll_frames(&mut self, ctx: &egui::Context) {
        for result in self.renderer.finished() {
            match (result.purpose, result.image) {
                (Purpose::Display, Ok(image)) => {
                    self.frame_error = None;
                    super::refine_steps::record_frame(&self.frame_pace, result.stats.frame_ms);
                    log::debug!(
                        "view frame {}x{} in {:.0} ms ({} splats{})",
                        image.width(),
                        image.height(),
                        result.stats.frame_ms,
                        result.stats.splats_drawn,
                        if result.stats.preview.is_some() { ", preview" } else { "" }
                    );
                    let Some(at) = self.in_flight.iter().position(|(id, _)| *id == result.id) else { continue };
                    // Requests before this one were skipped by the renderer.
                    let key = self.in_flight[at].1.clone();
                    self.in_flight.drain(..=at);
                    let colour = colour_image(&image);
                    match &mut self.shown {
                        Some(shown) => {
                            shown.texture.set(colour, egui::TextureOptions::LINEAR);
                            (shown.image, shown.key, shown.stats) = (image, key, result.stats);
                            shown.front_depth = result.front_depth;
                        }
                        None => {
                            let texture = ctx.load_texture("view", colour, egui::TextureOptions::LINEAR);
                            let (stats, front_depth) = (result.stats, result.front_depth);
                            self.shown = Some(ShownFrame { texture, image, key, stats, front_depth });
                        }
                    }
                }
                (Purpose::Display, Err(e)) => {
                    // The requests up to this one are answered (or were skipped) too.
                    if let Some(at) = self.in_flight.iter().position(|(id, _)| *id == result.id) {
                        self.in_flight.drain(..=at);
                    }
                    self.frame_error = Some(e);
                }
                (Purpose::Screenshot { png, .. }, Ok(_)) => {
                    self.status = Some(format!("saved {} and its .json", png.display()));
                }
                (Purpose::Screenshot { .. }, Err(e)) => self.status = Some(format!("screenshot failed: {e}")),
            }
        }
    }
}

pub(super) fn colour_image(image: &image::RgbaImage) -> egui::ColorImage {
    egui::ColorImage::from_rgba_unmultiplied([image.width() as usize, image.height() as usize], image.as_raw())
}
