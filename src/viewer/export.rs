//! What leaves the viewer: screenshots (a PNG at the chosen size with its
//! JSON sidecar, rendered by the render thread) and the error measurement
//! (the exact reference of the frame on screen, rendered on a worker thread,
//! compared and shown with its difference image).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use super::app::{MeasuredImages, ViewerApp};
use super::frames::colour_image;
use super::jobs::Job;
use super::render_thread::Purpose;
use super::state::Measurement;
use crate::frame::sidecar::SidecarModel;
use crate::frame::{RenderMode, Sidecar};
use crate::reference::{self, ReferenceOptions};

impl ViewerApp {
    /// Renders the current view at the chosen size into a PNG and a JSON sidecar beside it.
    pub fn save_screenshot(&mut self) {
        self.save_screenshot_at(self.ui.screenshot_size);
    }

    /// Ctrl+Shift+S: the current view at N × the view's size (N in the panel).
    pub fn save_large_screenshot(&mut self) {
        self.save_screenshot_at(super::state::ScreenshotSize::Times(self.ui.large_factor));
    }

    /// Writes the bookmarked views to `views.json` beside the screenshots, for `render --path`.
    pub(super) fn save_views(&mut self) {
        let path = self.options.screenshot_dir.join("views.json");
        let written = std::fs::create_dir_all(&self.options.screenshot_dir)
            .and_then(|()| crate::frame::ViewPath::new(&self.ui.bookmarks).write(&path));
        self.status = Some(match written {
            Ok(()) => format!("{} views -> {}", self.ui.bookmarks.len(), path.display()),
            Err(e) => format!("{}: {e}", path.display()),
        });
    }

    /// Renders the current view at `size` into a PNG and a JSON sidecar beside it.
    fn save_screenshot_at(&mut self, size: super::state::ScreenshotSize) {
        // The full frame, never the preview's budget: what the sidecar says.
        let (Some(model), Some(key)) = (self.model.clone(), self.frame_key(false)) else {
            self.status = Some("no model to take a screenshot of".into());
            return;
        };
        let settings = self.ui.settings;
        let size = size.pixels(self.view_size);
        if let Err(e) = crate::frame::settings::check_image_size(size.0, size.1) {
            self.status = Some(format!("a screenshot of {e}"));
            return;
        }
        let png = next_free_path(&self.options.screenshot_dir, &model.name, settings.mode);
        let model_info = SidecarModel {
            name: model.name.clone(),
            path: crate::copc::shown(&model.path.to_string_lossy()),
            hash: model.hash_hex(),
            splats: model.cloud.len(),
            nodes: model.streamed.is_some(),
            layers: self.shown_layer_files(),
        };
        let style = model.style.as_deref().map(crate::style::record::StyleRecord::from);
        let region = self.ui.inspect.region();
        let clip = (!region.is_empty()).then_some(region);
        let lights = crate::frame::sidecar::lights::records(&settings.lights, model.scene.frame_placement());
        let profile = match self.ui.inspect.profile_line[..] {
            [a, b] => Some(crate::frame::sidecar::ProfileRecord {
                line: [a.x, a.y, b.x, b.y],
                width: self.ui.inspect.profile_width,
            }),
            _ => None,
        };
        let looks = model.scene.looks();
        let looks = if looks.iter().all(|l| *l == Default::default()) { Vec::new() } else { looks };
        let sidecar = Box::new(Sidecar {
            profile,
            looks,
            time: key.time,
            style,
            clip,
            lights,
            ..Sidecar::new(model_info, &self.ui.camera, &settings, size)
        });
        if let Err(e) = std::fs::create_dir_all(&self.options.screenshot_dir) {
            self.status = Some(format!("{}: {e}", self.options.screenshot_dir.display()));
            return;
        }
        let annotation = Box::new(self.screenshot_annotation(size));
        match self.frame_request(&key, size, Purpose::Screenshot { png: png.clone(), sidecar, annotation }) {
            Some(request) => {
                self.status = Some(format!("rendering {} at {}x{}…", png.display(), size.0, size.1));
                self.renderer.request(request);
            }
            None => self.status = Some("the grouping is not ready yet; try again in a moment".into()),
        }
    }

    /// Renders the exact reference of the frame on screen and compares.
    pub(super) fn measure_error(&mut self, ctx: &egui::Context) {
        let (Some(model), Some(shown)) = (self.model.clone(), self.shown.as_ref()) else { return };
        let (key, image) = (shown.key.clone(), Arc::clone(&shown.image));
        let job = Job::spawn(RenderMode::RULER.name(), ctx.clone(), move || {
            let started = Instant::now();
            // A moving scene is measured at the time on screen.
            let scene = match key.time {
                Some(t) => Arc::new(model.scene.at_time(t)?.scene),
                None => Arc::clone(&model.scene),
            };
            let options = ReferenceOptions::matching(&key.settings, &scene);
            let exact = reference::render(&scene, &key.camera, &options, image.width(), image.height());
            if crate::progress::cancelled() {
                return Err("cancelled".to_string());
            }
            let seconds = started.elapsed().as_secs_f64();
            let error = reference::compare(&image, &exact).ok_or("the images differ in size")?;
            let difference = reference::difference_image(&image, &exact, 8.0).ok_or("the images differ in size")?;
            Ok(MeasuredImages { key, error, seconds, difference })
        });
        self.measure = Some(job);
    }

    /// Takes the measurement the reference job returned, if it has finished.
    pub(super) fn poll_measurement(&mut self, ctx: &egui::Context) {
        if let Some(result) = self.measure.as_ref().and_then(|j| j.poll()) {
            self.measure = None;
            match result.and_then(|r| r) {
                Ok(m) => {
                    let difference = ctx.load_texture("difference", colour_image(&m.difference), Default::default());
                    self.measure_error = None;
                    self.measurement =
                        Some(Measurement { key: m.key, error: m.error, reference_seconds: m.seconds, difference });
                }
                Err(e) => self.measure_error = Some(e),
            }
        }
    }
}

/// `DIR/pointblend-MODEL-MODE-NNN.png`, the first that does not exist.
fn next_free_path(dir: &Path, model: &str, mode: RenderMode) -> PathBuf {
    let stem = crate::output::safe_stem(Path::new(model));
    (1..)
        .map(|n| dir.join(format!("pointblend-{stem}-{mode}-{n:03}.png")))
        .find(|p| !p.exists() && !p.with_extension("json").exists())
        .unwrap_or_else(|| dir.join("pointblend.png"))
}
