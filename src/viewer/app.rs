//! The viewer's state and its per-frame logic: polling background jobs,
//! reacting to input, deciding whether the 3D view needs a new frame, and
//! the screenshot-and-exit sequence used for documentation and tests.
//! The panels (`panels.rs`, `stats.rs`) draw from and edit this state.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use glam::Vec2;

use crate::grouping::GroupingSpec;
use crate::grouping::cache::Cache;
use crate::reference::{self, ImageError, ReferenceOptions};
use crate::view::sidecar::SidecarModel;
use crate::view::{Camera, RenderMode, RenderSettings, Sidecar};

use super::camera_input::{self, SceneSphere};
use super::jobs::Job;
use super::model::{GroupedModel, Model};
use super::render_thread::{FrameRequest, FrameStats, Purpose, RenderThread};

/// How long after the last camera move large models still draw their preview.
const SETTLE: Duration = Duration::from_millis(300);

/// How the viewer starts.
#[derive(Debug, Clone, Default)]
pub struct ViewerOptions {
    /// The model to open (the bundled bunny when `None`).
    pub file: Option<PathBuf>,
    /// Save a screenshot of the whole window here once the first full frame is shown...
    pub screenshot: Option<PathBuf>,
    /// ...after this many more UI frames, then close.
    pub exit_after_frames: Option<u64>,
    /// Where Ctrl+S writes screenshots.
    pub screenshot_dir: PathBuf,
    /// Mode, settings and camera to start with (a screenshot's sidecar).
    pub view: Option<Sidecar>,
    /// The mode to start in (overrides the sidecar's).
    pub mode: Option<RenderMode>,
    /// Where groupings are cached (default: the user's cache, see [`Cache::from_env`]).
    pub cache: Option<Cache>,
}

/// The size of an exported screenshot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScreenshotSize {
    Window,
    Double,
    Fixed(u32, u32),
}

impl ScreenshotSize {
    pub const CHOICES: [ScreenshotSize; 4] = [
        ScreenshotSize::Window,
        ScreenshotSize::Double,
        ScreenshotSize::Fixed(1920, 1080),
        ScreenshotSize::Fixed(3840, 2160),
    ];

    pub fn label(self) -> String {
        match self {
            ScreenshotSize::Window => "view size".into(),
            ScreenshotSize::Double => "2 × view size".into(),
            ScreenshotSize::Fixed(w, h) => format!("{w} × {h}"),
        }
    }

    fn pixels(self, view: (u32, u32)) -> (u32, u32) {
        match self {
            ScreenshotSize::Window => view,
            ScreenshotSize::Double => (view.0 * 2, view.1 * 2),
            ScreenshotSize::Fixed(w, h) => (w, h),
        }
    }
}

/// Everything that decides a frame of the 3D view.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameKey {
    pub generation: u64,
    pub grouping: Option<String>,
    pub camera: Camera,
    pub settings: RenderSettings,
    pub size: (u32, u32),
    pub preview: bool,
}

/// The frame on screen.
pub struct ShownFrame {
    pub texture: egui::TextureHandle,
    pub image: Arc<image::RgbaImage>,
    pub key: FrameKey,
    pub stats: FrameStats,
}

/// A finished error measurement.
pub struct Measurement {
    pub key: FrameKey,
    pub error: ImageError,
    pub reference_seconds: f64,
    pub difference: egui::TextureHandle,
}

/// What a measurement job returns before its texture exists.
pub struct MeasuredImages {
    key: FrameKey,
    error: ImageError,
    seconds: f64,
    difference: image::RgbaImage,
}

pub struct ViewerApp {
    pub(super) options: ViewerOptions,
    pub(super) model: Option<Arc<Model>>,
    pub(super) load: Option<Job<Result<Model, String>>>,
    pub(super) load_error: Option<String>,
    generations: u64,
    pub(super) camera: Camera,
    home: Camera,
    scene: SceneSphere,
    pub(super) settings: RenderSettings,
    /// Light direction in eye space as (azimuth, elevation) degrees, edited by the panel.
    pub(super) light_angles: (f32, f32),
    pub(super) grouping_spec: GroupingSpec,
    pub(super) grouped: Option<Arc<GroupedModel>>,
    pub(super) grouping_job: Option<(GroupingSpec, Job<Result<GroupedModel, String>>)>,
    pub(super) grouping_error: Option<String>,
    renderer: RenderThread,
    next_request: u64,
    requested: Option<FrameKey>,
    /// Display frames sent and not yet back, oldest first.
    in_flight: Vec<(u64, FrameKey)>,
    pub(super) frame_error: Option<String>,
    pub(super) shown: Option<ShownFrame>,
    pub(super) view_size: (u32, u32),
    last_camera_move: Option<Instant>,
    pub(super) measure: Option<Job<Result<MeasuredImages, String>>>,
    pub(super) measurement: Option<Measurement>,
    pub(super) measure_error: Option<String>,
    pub(super) screenshot_size: ScreenshotSize,
    pub(super) status: Option<String>,
    pub(super) ui_fps: f32,
    /// UI frame intervals of the last two seconds, for the slowest one.
    recent_ui_frames: std::collections::VecDeque<(Instant, f32)>,
    last_ui_frame: Option<Instant>,
    frames_since_ready: u64,
    window_shot_requested: bool,
}

impl ViewerApp {
    pub fn new(cc: &eframe::CreationContext<'_>, options: ViewerOptions) -> Self {
        let ctx = cc.egui_ctx.clone();
        let mut settings = match &options.view {
            Some(view) => view.settings(),
            // Deferred starts in the paper's opaque setting (MGC c = 0.4 with Voronoi), as everywhere.
            None => RenderSettings::default(),
        };
        if let Some(mode) = options.mode {
            settings.mode = mode;
        }
        let grouping_spec = options.view.as_ref().and_then(|v| v.grouping().ok()).unwrap_or_default();
        let d = settings.shading.light_dir_eye;
        let light_angles = (d.x.atan2(d.z).to_degrees(), d.y.clamp(-1.0, 1.0).asin().to_degrees());
        let camera = Camera::framing(glam::Vec3::ZERO, 1.0, 1.0);
        let mut app = Self {
            model: None,
            load: None,
            load_error: None,
            generations: 0,
            camera,
            home: camera,
            scene: SceneSphere { centre: glam::Vec3::ZERO, radius: 1.0 },
            settings,
            light_angles,
            grouping_spec,
            grouped: None,
            grouping_job: None,
            grouping_error: None,
            renderer: RenderThread::start(ctx.clone()),
            next_request: 0,
            requested: None,
            in_flight: Vec::new(),
            frame_error: None,
            shown: None,
            view_size: (1, 1),
            last_camera_move: None,
            measure: None,
            measurement: None,
            measure_error: None,
            screenshot_size: ScreenshotSize::Window,
            status: None,
            ui_fps: 0.0,
            recent_ui_frames: Default::default(),
            last_ui_frame: None,
            frames_since_ready: 0,
            window_shot_requested: false,
            options,
        };
        let file = app.options.file.clone().unwrap_or_else(|| PathBuf::from(super::BUNDLED_MODEL));
        app.open(&ctx, &file);
        app
    }

    /// Starts loading `path` in the background; the current model stays until it succeeds.
    pub fn open(&mut self, ctx: &egui::Context, path: &Path) {
        if let Some(old) = self.load.take() {
            old.cancel();
        }
        self.generations += 1;
        let generation = self.generations;
        let path = path.to_path_buf();
        let label = format!("loading {}", path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default());
        self.load = Some(Job::spawn(label, ctx.clone(), move || Model::load(&path, generation)));
    }

    /// The model on screen.
    pub fn model(&self) -> Option<&Model> {
        self.model.as_deref()
    }

    pub fn load_error(&self) -> Option<&str> {
        self.load_error.as_deref()
    }

    pub fn is_loading(&self) -> bool {
        self.load.is_some()
    }

    /// The frame on screen: its image and what it was drawn with.
    pub fn shown_frame(&self) -> Option<(&image::RgbaImage, &FrameKey)> {
        self.shown.as_ref().map(|s| (s.image.as_ref(), &s.key))
    }

    pub fn status(&self) -> Option<&str> {
        self.status.as_deref()
    }

    /// The frame the view should show now, if a model is loaded.
    pub fn current_key(&self) -> Option<FrameKey> {
        let model = self.model.as_ref()?;
        let preview = model.preview.is_some() && self.last_camera_move.is_some_and(|t| t.elapsed() < SETTLE);
        let grouping = (self.settings.mode.needs_grouping() && !preview).then(|| self.grouping_spec.to_string());
        Some(FrameKey {
            generation: model.generation,
            grouping,
            camera: self.camera,
            settings: self.settings,
            size: self.view_size,
            preview,
        })
    }

    /// Whether the view shows the full-quality frame for the current state, with nothing pending.
    pub fn is_settled(&self) -> bool {
        let current = self.current_key();
        self.load.is_none()
            && self.grouping_job.is_none()
            && (self.model.is_none() || (current.is_some() && self.shown.as_ref().map(|s| &s.key) == current.as_ref()))
    }

    /// Progress of a reference frame the view is waiting for.
    pub(super) fn view_progress(&self) -> Option<(String, Option<f32>)> {
        let (_, key) = self.in_flight.last()?;
        (key.settings.mode == RenderMode::Reference && !key.preview).then(|| self.renderer.tracker.snapshot())
    }

    /// The slowest UI frame of the last two seconds, in ms.
    pub fn slowest_ui_frame_ms(&self) -> f32 {
        self.recent_ui_frames.iter().map(|(_, ms)| *ms).fold(0.0, f32::max)
    }

    pub(super) fn camera_moved(&mut self) {
        self.last_camera_move = Some(Instant::now());
    }

    pub(super) fn reset_camera(&mut self) {
        self.camera = self.home;
        self.camera_moved();
    }

    /// Polls jobs and the render thread.
    pub(super) fn poll(&mut self, ctx: &egui::Context) {
        if let Some(result) = self.load.as_ref().and_then(|j| j.poll()) {
            self.load = None;
            match result.and_then(|r| r) {
                Ok(model) => self.adopt(model),
                Err(e) => self.load_error = Some(e),
            }
        }
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
        if let Some(result) = self.measure.as_ref().and_then(|j| j.poll()) {
            self.measure = None;
            match result.and_then(|r| r) {
                Ok(m) => {
                    let difference = ctx.load_texture("difference", color_image(&m.difference), Default::default());
                    self.measure_error = None;
                    self.measurement =
                        Some(Measurement { key: m.key, error: m.error, reference_seconds: m.seconds, difference });
                }
                Err(e) => self.measure_error = Some(e),
            }
        }
        for result in self.renderer.finished() {
            match (result.purpose, result.image) {
                (Purpose::Display, Ok(image)) => {
                    self.frame_error = None;
                    log::debug!(
                        "view frame {}x{} in {:.0} ms ({} splats{})",
                        image.width(),
                        image.height(),
                        result.stats.frame_ms,
                        result.stats.splats_drawn,
                        if result.stats.preview { ", preview" } else { "" }
                    );
                    let Some(at) = self.in_flight.iter().position(|(id, _)| *id == result.id) else { continue };
                    // Requests before this one were skipped by the renderer.
                    let key = self.in_flight[at].1.clone();
                    self.in_flight.drain(..=at);
                    let colour = color_image(&image);
                    match &mut self.shown {
                        Some(shown) => {
                            shown.texture.set(colour, egui::TextureOptions::LINEAR);
                            (shown.image, shown.key, shown.stats) = (image, key, result.stats);
                        }
                        None => {
                            let texture = ctx.load_texture("view", colour, egui::TextureOptions::LINEAR);
                            self.shown = Some(ShownFrame { texture, image, key, stats: result.stats });
                        }
                    }
                }
                (Purpose::Display, Err(e)) => self.frame_error = Some(e),
                (Purpose::Screenshot { png, .. }, Ok(_)) => {
                    self.status = Some(format!("saved {} and its .json", png.display()));
                }
                (Purpose::Screenshot { .. }, Err(e)) => self.status = Some(format!("screenshot failed: {e}")),
            }
        }
    }

    fn adopt(&mut self, model: Model) {
        let aspect = self.view_size.0 as f32 / self.view_size.1.max(1) as f32;
        let fresh = Camera::default_for(&model.cloud, aspect);
        self.scene = SceneSphere { centre: fresh.target, radius: fresh.scene_radius };
        self.home = fresh;
        self.camera = match &self.options.view {
            // The starting view of a sidecar applies to the first model only.
            Some(view) if self.model.is_none() => view.camera(),
            _ => fresh,
        };
        self.load_error = None;
        self.grouped = None;
        self.measurement = None;
        for warning in &model.warnings {
            log::warn!("{}: {warning}", model.path.display());
        }
        self.model = Some(Arc::new(model));
    }

    /// Starts a grouping when the deferred mode needs one that is not there.
    pub(super) fn ensure_grouping(&mut self, ctx: &egui::Context) {
        let Some(model) = self.model.clone() else { return };
        if !self.settings.mode.needs_grouping() {
            return;
        }
        let spec = self.grouping_spec;
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
            Ok(GroupedModel { generation, spec, grouping, seconds: started.elapsed().as_secs_f64(), cached })
        });
        self.grouping_job = Some((spec, job));
    }

    /// Sends the current frame to the renderer unless it is on screen or on its way.
    pub(super) fn request_frame(&mut self, ctx: &egui::Context) {
        let Some(key) = self.current_key() else { return };
        if self.view_size.0 < 1 || self.view_size.1 < 1 || ctx.input(|i| i.viewport().minimized == Some(true)) {
            return;
        }
        if key.preview {
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

    fn frame_request(&mut self, key: &FrameKey, size: (u32, u32), purpose: Purpose) -> Option<FrameRequest> {
        let model = self.model.clone()?;
        let grouping = if key.grouping.is_some() {
            let g = self.grouped.clone().filter(|g| g.generation == model.generation && g.spec == self.grouping_spec);
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
            purpose,
        })
    }

    /// Renders the current view at the chosen size into a PNG and a JSON sidecar beside it.
    pub fn save_screenshot(&mut self) {
        let (Some(model), Some(mut key)) = (self.model.clone(), self.current_key()) else {
            self.status = Some("no model to take a screenshot of".into());
            return;
        };
        key.preview = false;
        key.grouping = self.settings.mode.needs_grouping().then(|| self.grouping_spec.to_string());
        let size = self.screenshot_size.pixels(self.view_size);
        let png = next_free_path(&self.options.screenshot_dir, &model.name, self.settings.mode);
        let model_info = SidecarModel {
            name: model.name.clone(),
            path: model.path.display().to_string(),
            hash: model.hash_hex(),
            splats: model.cloud.len(),
        };
        let sidecar = Box::new(Sidecar::new(model_info, &self.camera, &self.settings, self.grouping_spec, size));
        if let Err(e) = std::fs::create_dir_all(&self.options.screenshot_dir) {
            self.status = Some(format!("{}: {e}", self.options.screenshot_dir.display()));
            return;
        }
        match self.frame_request(&key, size, Purpose::Screenshot { png: png.clone(), sidecar }) {
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
        let job = Job::spawn("reference", ctx.clone(), move || {
            let started = Instant::now();
            let options = ReferenceOptions::matching(&key.settings, &model.cloud);
            let exact = reference::render(&model.cloud, &key.camera, &options, image.width(), image.height());
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

    /// Handles dropped files and keyboard shortcuts.
    pub(super) fn handle_input(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| i.raw.dropped_files.iter().map(|f| f.path().to_path_buf()).collect());
        if let Some(path) = dropped.first() {
            self.open(ctx, path);
        }
        if ctx.input_mut(|i| i.consume_key(egui::Modifiers::COMMAND, egui::Key::S)) {
            self.save_screenshot();
        }
        if ctx.input(|i| i.key_pressed(egui::Key::Home)) && !ctx.egui_wants_keyboard_input() {
            self.reset_camera();
        }
    }

    /// The 3D view: the latest frame, and the camera controls on it.
    pub(super) fn view_ui(&mut self, ui: &mut egui::Ui) {
        let (rect, response) = ui.allocate_exact_size(ui.available_size(), egui::Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point();
        let max_side = 8192.0;
        self.view_size = (
            (rect.width() * ppp).round().clamp(1.0, max_side) as u32,
            (rect.height() * ppp).round().clamp(1.0, max_side) as u32,
        );
        let painter = ui.painter_at(rect);
        let bg = self.settings.shading.background;
        painter.rect_filled(
            rect,
            0.0,
            egui::Color32::from_rgb((bg.x * 255.0) as u8, (bg.y * 255.0) as u8, (bg.z * 255.0) as u8),
        );
        if let Some(shown) = &self.shown {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            painter.image(shown.texture.id(), rect, uv, egui::Color32::WHITE);
        }
        if let Some(e) = &self.frame_error {
            painter.text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                e,
                egui::FontId::proportional(16.0),
                egui::Color32::LIGHT_RED,
            );
        }
        let to_vec = |v: egui::Vec2| Vec2::new(v.x, v.y);
        let mut moved = false;
        if response.dragged_by(egui::PointerButton::Primary) {
            camera_input::orbit(&mut self.camera, to_vec(response.drag_delta()));
            moved = true;
        }
        if response.dragged_by(egui::PointerButton::Secondary) || response.dragged_by(egui::PointerButton::Middle) {
            camera_input::pan(&mut self.camera, &self.scene, to_vec(response.drag_delta()), rect.height());
            moved = true;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                camera_input::zoom(&mut self.camera, scroll);
                moved = true;
            }
        }
        if response.double_clicked() {
            if let (Some(pos), Some(model)) = (response.interact_pointer_pos(), &self.model) {
                let uv = Vec2::new((pos.x - rect.left()) / rect.width(), (pos.y - rect.top()) / rect.height());
                let aspect = rect.width() / rect.height().max(1.0);
                if let Some(hit) = camera_input::pick(&model.cloud, &self.camera, uv, aspect) {
                    self.scene.retarget(&mut self.camera, hit);
                    moved = true;
                }
            }
        }
        if moved {
            self.camera_moved();
        }
    }

    /// `--screenshot` / `--exit-after-frames`: once settled, count frames, then shoot and close.
    pub(super) fn scripted_exit(&mut self, ctx: &egui::Context) {
        let Some(limit) = self.options.exit_after_frames.or(self.options.screenshot.as_ref().map(|_| 2)) else {
            return;
        };
        ctx.request_repaint();
        if !self.is_settled() || self.window_shot_requested {
            return;
        }
        self.frames_since_ready += 1;
        if self.frames_since_ready < limit {
            return;
        }
        self.window_shot_requested = true;
        let Some(path) = self.options.screenshot.clone() else {
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
            return;
        };
        let close = ctx.clone();
        ctx.request_screenshot(move |shot| {
            let [w, h] = shot.size;
            let bytes: Vec<u8> = shot.pixels.iter().flat_map(|c| c.to_array()).collect();
            match image::RgbaImage::from_raw(w as u32, h as u32, bytes) {
                Some(image) => match crate::output::save_png(&image, &path) {
                    Ok(()) => eprintln!("saved the window to {}", path.display()),
                    Err(e) => eprintln!("error: {}: {e}", path.display()),
                },
                None => eprintln!("error: the window screenshot has the wrong size"),
            }
            close.send_viewport_cmd(egui::ViewportCommand::Close);
        });
    }

    pub(super) fn count_ui_frame(&mut self) {
        let now = Instant::now();
        if let Some(last) = self.last_ui_frame {
            let seconds = now.duration_since(last).as_secs_f32().max(1e-4);
            let fps = 1.0 / seconds;
            self.ui_fps = if self.ui_fps == 0.0 { fps } else { 0.9 * self.ui_fps + 0.1 * fps };
            self.recent_ui_frames.push_back((now, seconds * 1e3));
            while self.recent_ui_frames.front().is_some_and(|(t, _)| now.duration_since(*t) > Duration::from_secs(2)) {
                self.recent_ui_frames.pop_front();
            }
            log::debug!("UI frame {:.1} ms", seconds * 1e3);
        }
        self.last_ui_frame = Some(now);
    }
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.count_ui_frame();
        self.poll(&ctx);
        self.handle_input(&ctx);
        let d = self.light_angles;
        let (az, el) = (d.0.to_radians(), d.1.to_radians());
        self.settings.shading.light_dir_eye = glam::Vec3::new(az.sin() * el.cos(), el.sin(), az.cos() * el.cos());
        egui::Panel::left("controls").resizable(true).default_size(310.0).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| super::panels::controls(self, ui));
        });
        egui::CentralPanel::no_frame().show(ui, |ui| self.view_ui(ui));
        self.ensure_grouping(&ctx);
        self.request_frame(&ctx);
        self.scripted_exit(&ctx);
        if self.load.is_some() || self.grouping_job.is_some() || self.measure.is_some() {
            ctx.request_repaint_after(Duration::from_millis(100)); // progress bars
        }
    }
}

fn color_image(image: &image::RgbaImage) -> egui::ColorImage {
    egui::ColorImage::from_rgba_unmultiplied([image.width() as usize, image.height() as usize], image.as_raw())
}

/// `DIR/pointblend-MODEL-MODE-NNN.png`, the first that does not exist.
fn next_free_path(dir: &Path, model: &str, mode: RenderMode) -> PathBuf {
    let stem = crate::output::safe_stem(Path::new(model));
    (1..)
        .map(|n| dir.join(format!("pointblend-{stem}-{mode}-{n:03}.png")))
        .find(|p| !p.exists() && !p.with_extension("json").exists())
        .unwrap_or_else(|| dir.join("pointblend.png"))
}
