//! The viewer's state and its per-frame logic: polling background jobs,
//! running the panels and applying the actions they return, deciding whether
//! the 3D view needs a new frame, and the screenshot-and-exit sequence used
//! for documentation and tests. The 3D view and its input are in `view3d.rs`.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::scene::environment::EnvironmentMap;
use std::time::{Duration, Instant};

use crate::grouping::cache::Cache;
use crate::reference::{self, ImageError, ReferenceOptions};
use crate::view::sidecar::SidecarModel;
use crate::view::{Camera, RenderMode, RenderSettings, Sidecar};

use super::camera_input::SceneSphere;
use super::jobs::Job;
use super::model::{GroupedModel, Model};
use super::render_thread::{FrameRequest, FrameStats, Purpose, RenderThread};
use super::state::{
    Action, FrameKey, JobInfo, JobKind, Measurement, ModelInfo, PanelInfo, ScreenshotSize, ShownInfo, UiState,
};

/// How long after the last camera move large models still draw their preview.
pub(super) const SETTLE: Duration = Duration::from_millis(300);

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
    /// Materials every object opened gets (`--opacity`, `--color`).
    pub materials: crate::bench::Materials,
    /// Background colour (0..1) that overrides the scene's.
    pub background: Option<glam::Vec3>,
    /// Environment map every model opened is set in (in place of a scene file's).
    pub environment: Option<PathBuf>,
}

/// The frame on screen.
pub(super) struct ShownFrame {
    pub texture: egui::TextureHandle,
    pub image: Arc<image::RgbaImage>,
    pub key: FrameKey,
    pub stats: FrameStats,
}

/// What a measurement job returns before its texture exists.
pub(super) struct MeasuredImages {
    key: FrameKey,
    error: ImageError,
    seconds: f64,
    difference: image::RgbaImage,
}

pub struct ViewerApp {
    pub(super) options: ViewerOptions,
    pub(super) ui: UiState,
    pub(super) model: Option<Arc<Model>>,
    load: Option<Job<Result<Model, String>>>,
    load_error: Option<String>,
    generations: u64,
    pub(super) home: Camera,
    pub(super) scene: SceneSphere,
    grouped: Option<Arc<GroupedModel>>,
    grouping_job: Option<(crate::grouping::GroupingSpec, Job<Result<GroupedModel, String>>)>,
    grouping_error: Option<String>,
    renderer: RenderThread,
    next_request: u64,
    requested: Option<FrameKey>,
    /// Display frames sent and not yet back, oldest first.
    in_flight: Vec<(u64, FrameKey)>,
    pub(super) frame_error: Option<String>,
    pub(super) shown: Option<ShownFrame>,
    pub(super) view_size: (u32, u32),
    last_camera_move: Option<Instant>,
    measure: Option<Job<Result<MeasuredImages, String>>>,
    measurement: Option<Measurement>,
    measure_error: Option<String>,
    status: Option<String>,
    pub(super) ui_fps: f32,
    /// UI frame intervals of the last two seconds, for the slowest one.
    pub(super) recent_ui_frames: std::collections::VecDeque<(Instant, f32)>,
    pub(super) last_ui_frame: Option<Instant>,
    pub(super) frames_since_ready: u64,
    pub(super) window_shot_requested: bool,
}

impl ViewerApp {
    pub fn new(cc: &eframe::CreationContext<'_>, options: ViewerOptions) -> Self {
        let ctx = cc.egui_ctx.clone();
        // Without a sidecar every mode starts in its defaults (deferred: the paper's MGC c = 0.4 with Voronoi).
        let mut settings = options.view.as_ref().and_then(|v| v.settings().ok()).unwrap_or_default();
        if let Some(mode) = options.mode {
            settings.mode = mode;
        }
        let camera = Camera::framing(glam::Vec3::ZERO, 1.0, 1.0);
        let ui = UiState {
            light_angles: UiState::light_angles_of(&settings),
            settings,
            camera,
            screenshot_size: ScreenshotSize::Window,
            opacity_pending: None,
        };
        let mut app = Self {
            ui,
            model: None,
            load: None,
            load_error: None,
            generations: 0,
            home: camera,
            scene: SceneSphere { centre: glam::Vec3::ZERO, radius: 1.0 },
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
        let materials = self.options.materials;
        let environment = self.options.environment.clone();
        self.load = Some(Job::spawn(label, ctx.clone(), move || {
            let model = Model::load(&path, generation, &materials)?;
            match environment {
                Some(env) => {
                    let map = EnvironmentMap::load(&env).map_err(|e| e.to_string())?;
                    Ok(model.with_environment(Some(Arc::new(map)), generation))
                }
                None => Ok(model),
            }
        }));
    }

    /// Gives every object of the model on screen `opacity`, in the
    /// background: the same geometry as a new model (new upload; the grouping
    /// comes back from the cache, keyed by geometry), with the camera kept.
    pub fn set_opacity(&mut self, ctx: &egui::Context, opacity: f32) {
        let Some(model) = self.model.clone() else { return };
        if let Some(old) = self.load.take() {
            old.cancel();
        }
        self.generations += 1;
        let generation = self.generations;
        let label = format!("opacity {opacity:.2}");
        self.load = Some(Job::spawn(label, ctx.clone(), move || Ok(model.with_opacity(opacity, generation))));
    }

    /// Sets the model on screen in the environment map at `path` (loaded in
    /// the background; an unreadable map is shown as the load error and the
    /// model kept), or in none: a new upload of the same geometry.
    pub fn set_environment(&mut self, ctx: &egui::Context, path: Option<PathBuf>) {
        let Some(model) = self.model.clone() else { return };
        if let Some(old) = self.load.take() {
            old.cancel();
        }
        self.generations += 1;
        let generation = self.generations;
        let label = match &path {
            Some(p) => format!("environment {}", p.file_name().map(|n| n.to_string_lossy()).unwrap_or_default()),
            None => "no environment".into(),
        };
        self.load = Some(Job::spawn(label, ctx.clone(), move || {
            let map = match path {
                Some(p) => Some(Arc::new(EnvironmentMap::load(&p).map_err(|e| e.to_string())?)),
                None => None,
            };
            Ok(model.with_environment(map, generation))
        }));
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

    /// The settings the panels show now.
    pub fn settings(&self) -> &RenderSettings {
        &self.ui.settings
    }

    /// The frame the view should show now, if a model is loaded.
    pub fn current_key(&self) -> Option<FrameKey> {
        let model = self.model.as_ref()?;
        let preview = model.preview.is_some() && self.last_camera_move.is_some_and(|t| t.elapsed() < SETTLE);
        let settings = self.ui.settings;
        let grouping = (settings.mode.needs_grouping_for(model.transparent) && !preview)
            .then(|| settings.grouping_for_mode().to_string());
        Some(FrameKey {
            generation: model.generation,
            grouping,
            camera: self.ui.camera,
            settings,
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

    /// Progress of a CPU-mode frame (the reference) the view is waiting for.
    fn view_progress(&self) -> Option<(String, Option<f32>)> {
        let (_, key) = self.in_flight.last()?;
        (!key.settings.mode.is_gpu() && !key.preview).then(|| self.renderer.tracker.snapshot())
    }

    /// The slowest UI frame of the last two seconds, in ms.
    pub fn slowest_ui_frame_ms(&self) -> f32 {
        self.recent_ui_frames.iter().map(|(_, ms)| *ms).fold(0.0, f32::max)
    }

    pub(super) fn camera_moved(&mut self) {
        self.last_camera_move = Some(Instant::now());
    }

    pub(super) fn reset_camera(&mut self) {
        self.ui.camera = self.home;
        self.camera_moved();
    }

    /// What the panels show.
    fn panel_info(&self) -> PanelInfo<'_> {
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
                environment: m.scene.environment.as_ref().map(|e| e.name.as_str()),
            }),
            load_error: self.load_error.as_deref(),
            jobs,
            view_progress: self.view_progress(),
            grouped: self.grouped.as_ref(),
            grouping_error: self.grouping_error.as_deref(),
            shown: self.shown.as_ref().map(|s| ShownInfo { key: &s.key, stats: &s.stats }),
            current: self.current_key(),
            ui_fps: self.ui_fps,
            slowest_ui_frame_ms: self.slowest_ui_frame_ms(),
            measurement: self.measurement.as_ref(),
            measure_error: self.measure_error.as_deref(),
            screenshot_dir: &self.options.screenshot_dir,
            status: self.status.as_deref(),
        }
    }

    /// Takes the actions the panels returned.
    fn apply(&mut self, ctx: &egui::Context, actions: Vec<Action>) {
        for action in actions {
            match action {
                Action::Open(path) => self.open(ctx, &path),
                Action::Cancel(JobKind::Load) => {
                    if let Some(job) = self.load.take() {
                        job.cancel();
                    }
                }
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
                Action::ResetCamera => self.reset_camera(),
                Action::CameraMoved => self.camera_moved(),
                Action::SetOpacity(opacity) => self.set_opacity(ctx, opacity),
                Action::SetEnvironment(path) => self.set_environment(ctx, path),
            }
        }
    }

    /// Polls jobs and the render thread.
    fn poll(&mut self, ctx: &egui::Context) {
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
        // The same file with other materials (the opacity slider) keeps the view.
        let same_geometry = self.model.as_ref().is_some_and(|m| m.path == model.path && m.hash == model.hash);
        self.ui.camera = match &self.options.view {
            _ if same_geometry => self.ui.camera,
            // The starting view of a sidecar applies to the first model only.
            Some(view) if self.model.is_none() => view.camera(),
            _ => fresh,
        };
        self.load_error = None;
        self.grouped = None;
        self.measurement = None;
        // The scene's background, unless the command line or a sidecar set one.
        if self.options.view.is_none() {
            if let Some(bg) = self.options.background.or(model.scene.background) {
                self.ui.settings.shading.background = bg;
            }
        }
        for warning in &model.warnings {
            log::warn!("{}: {warning}", model.path.display());
        }
        self.model = Some(Arc::new(model));
    }

    /// Starts a grouping when the mode draws groups and the one it needs is not there.
    fn ensure_grouping(&mut self, ctx: &egui::Context) {
        let Some(model) = self.model.clone() else { return };
        if !self.ui.settings.mode.needs_grouping_for(model.transparent) {
            return;
        }
        let spec = self.ui.settings.grouping_for_mode();
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
    fn request_frame(&mut self, ctx: &egui::Context) {
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
            let wanted = key.settings.grouping_for_mode();
            let g = self.grouped.clone().filter(|g| g.generation == model.generation && g.spec == wanted);
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
        let settings = self.ui.settings;
        key.preview = false;
        key.grouping =
            settings.mode.needs_grouping_for(model.transparent).then(|| settings.grouping_for_mode().to_string());
        let size = self.ui.screenshot_size.pixels(self.view_size);
        let png = next_free_path(&self.options.screenshot_dir, &model.name, settings.mode);
        let model_info = SidecarModel {
            name: model.name.clone(),
            path: model.path.display().to_string(),
            hash: model.hash_hex(),
            splats: model.cloud.len(),
        };
        let sidecar = Box::new(Sidecar::new(model_info, &self.ui.camera, &settings, size));
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
    fn measure_error(&mut self, ctx: &egui::Context) {
        let (Some(model), Some(shown)) = (self.model.clone(), self.shown.as_ref()) else { return };
        let (key, image) = (shown.key.clone(), Arc::clone(&shown.image));
        let job = Job::spawn(RenderMode::RULER.name(), ctx.clone(), move || {
            let started = Instant::now();
            let options = ReferenceOptions::matching(&key.settings, &model.scene);
            let exact = reference::render(&model.scene, &key.camera, &options, image.width(), image.height());
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
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.count_ui_frame();
        self.poll(&ctx);
        self.handle_input(&ctx);
        self.ui.apply_light_angles();
        let mut actions = Vec::new();
        egui::Panel::left("controls").resizable(true).default_size(310.0).show(ui, |ui| {
            egui::ScrollArea::vertical().show(ui, |ui| {
                let mut state = self.ui.clone();
                actions = super::panels::controls(ui, &mut state, &self.panel_info());
                self.ui = state;
            });
        });
        self.ui.apply_light_angles();
        self.apply(&ctx, actions);
        egui::CentralPanel::no_frame().show(ui, |ui| self.view_ui(ui));
        self.ensure_grouping(&ctx);
        self.request_frame(&ctx);
        self.scripted_exit(&ctx);
        if self.load.is_some() || self.grouping_job.is_some() || self.measure.is_some() {
            ctx.request_repaint_after(Duration::from_millis(100)); // progress bars
        }
    }
}

pub(super) fn color_image(image: &image::RgbaImage) -> egui::ColorImage {
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
