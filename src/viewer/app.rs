//! The viewer's state and its per-frame loop: the [`ViewerApp`] and what it
//! starts with, what it tells the outside (the model, the frame on screen,
//! whether it has settled), and the order of one UI frame: poll the jobs and
//! the render thread, take input, run the panels and apply their actions,
//! draw the 3D view, start what the view needs.
//!
//! The rest of its logic is split by concern: `loading.rs` (opening a model,
//! its opacity and environment), `frames.rs` (the frame the view needs, its
//! grouping, the render thread's results), `actions.rs` (what the panels see
//! and the actions they return), `export.rs` (screenshots and the error
//! measurement), and `view3d.rs` (the 3D view and its input).

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use crate::frame::{Camera, RenderMode, RenderSettings, Sidecar};
use crate::grouping::cache::Cache;
use crate::reference::ImageError;

use super::camera_input::SceneSphere;
use super::jobs::Job;
use super::model::{GroupedModel, Model};
use super::render_thread::{FrameStats, RenderThread};
use super::state::{FrameKey, Measurement, ScreenshotSize, UiState};

/// How the viewer starts.
#[derive(Debug, Clone, Default)]
pub struct ViewerOptions {
    /// The model to open (the bundled lion when `None`).
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
    pub materials: crate::scene::Materials,
    /// Rendering parameters given on the command line (checked text forms),
    /// over the defaults or the sidecar's; a given background overrides the scene's.
    pub parameters: Vec<(crate::frame::Parameter, String)>,
    /// Environment map every model opened is set in (in place of a scene file's).
    pub environment: Option<PathBuf>,
    /// Point lights (file coordinates) every model opened is lit by, with its scene file's.
    pub lights: Vec<crate::frame::Light>,
    /// The clip region to start with (`--clip-box`, `--clip-plane`), in file coordinates.
    pub clip: crate::frame::ClipRegion,
    /// The camera the command line asks for (`--azimuth` and the like), over a
    /// scene file's `[camera]`; every model opened starts there, and Home returns there.
    pub camera: crate::frame::CameraRequest,
    /// How streamed files (COPC files and URLs) are read: the node cache's
    /// bound (`--cache-mb`) and the disk cache (`--disk-cache`).
    pub stream: crate::copc::StreamOptions,
    /// The time a moving scene starts at, paused (`--time`).
    pub time: Option<f64>,
}

/// The frame on screen.
pub(super) struct ShownFrame {
    pub texture: egui::TextureHandle,
    pub image: Arc<image::RgbaImage>,
    pub key: FrameKey,
    pub stats: FrameStats,
    /// Its nearest surface per pixel, where its mode keeps one.
    pub front_depth: Option<Arc<crate::frame::FrontDepth>>,
}

/// What a measurement job returns before its texture exists.
pub(super) struct MeasuredImages {
    pub key: FrameKey,
    pub error: ImageError,
    pub seconds: f64,
    pub difference: image::RgbaImage,
}

pub struct ViewerApp {
    pub(super) options: ViewerOptions,
    pub(super) ui: UiState,
    pub(super) model: Option<Arc<Model>>,
    pub(super) load: Option<Job<Result<Model, String>>>,
    /// The newest step of a streamed view the load job is refining.
    pub(super) interim: super::refine_steps::Interim,
    /// The last frame of the view's time, which paces a refining view's steps.
    pub(super) frame_pace: super::refine_steps::FramePace,
    pub(super) load_error: Option<String>,
    pub(super) generations: u64,
    pub(super) home: Camera,
    pub(super) scene: SceneSphere,
    pub(super) grouped: Option<Arc<GroupedModel>>,
    pub(super) grouping_job: Option<(crate::grouping::GroupingSpec, Job<Result<GroupedModel, String>>)>,
    pub(super) grouping_error: Option<String>,
    pub(super) renderer: RenderThread,
    pub(super) next_request: u64,
    pub(super) requested: Option<FrameKey>,
    /// Display frames sent and not yet back, oldest first.
    pub(super) in_flight: Vec<(u64, FrameKey)>,
    pub(super) frame_error: Option<String>,
    pub(super) shown: Option<ShownFrame>,
    pub(super) view_size: (u32, u32),
    /// Where the 3D view is in the window (points).
    pub(super) view_rect: egui::Rect,
    pub(super) last_camera_move: Option<Instant>,
    pub(super) measure: Option<Job<Result<MeasuredImages, String>>>,
    pub(super) measurement: Option<Measurement>,
    pub(super) measure_error: Option<String>,
    pub(super) status: Option<String>,
    /// The window's frame rate and slowest frame, for the statistics.
    pub(super) frame_clock: super::frame_clock::FrameClock,
    pub(super) frames_since_ready: u64,
    pub(super) window_shot_requested: bool,
    /// While an animation plays: when it started playing, and from which time.
    pub(super) play_clock: Option<(Instant, f64)>,
    /// Where the wheel last zoomed: the cursor, and the point kept under it.
    pub(super) zoom_anchor: Option<(egui::Pos2, glam::Vec3)>,
    /// Where the pointer is over the window, for the status line.
    pub(super) pointer: Option<egui::Pos2>,
    /// The files opened as layers, and the list before the change being
    /// loaded (put back if it fails).
    pub(super) layers: Vec<super::state::Layer>,
    pub(super) layers_before: Option<Vec<super::state::Layer>>,
    /// The looks the next model opened gets, one per object (the shown layers' where one was set).
    pub(super) pending_looks: Option<Vec<crate::scene::Look>>,
    /// Where the layers' `.vpc` files are written.
    pub(super) layers_folder: Option<tempfile::TempDir>,
    /// The next model adopted keeps the view (a change of the layers).
    pub(super) keep_view: bool,
    /// The frame placement (origin, unit) of the last model adopted.
    pub(super) placement_shown: Option<(glam::DVec3, f64)>,
    /// The polygon's measure, and what it was measured of (vertices, volume, model generation).
    pub(super) polygon_report: Option<(super::state::PolygonKey, Result<super::state::PolygonReport, String>)>,
    /// The profile's slab, and what it was cut from.
    pub(super) profile_slab: Option<(super::state::ProfileKey, Result<super::state::ProfileSlab, String>)>,
    /// A selection or a profile being exported: the line to report when it is done.
    pub(super) export: Option<Job<Result<String, String>>>,
}

impl ViewerApp {
    pub fn new(cc: &eframe::CreationContext<'_>, options: ViewerOptions) -> Self {
        let ctx = cc.egui_ctx.clone();
        // Without a sidecar every mode starts in its defaults (deferred: the paper's MGC c = 0.4 with Voronoi).
        let mut settings = options.view.as_ref().and_then(|v| v.settings().ok()).unwrap_or_default();
        if let Some(mode) = options.mode {
            settings.mode = mode;
        }
        for (parameter, value) in &options.parameters {
            // Checked when the command line was read.
            let _ = parameter.apply(&mut settings, value);
        }
        let camera = Camera::framing(glam::Vec3::ZERO, 1.0, 1.0);
        let ui = UiState {
            light_angles: UiState::light_angles_of(&settings),
            settings,
            camera,
            screenshot_size: ScreenshotSize::Window,
            opacity_pending: None,
            layer_opacity_pending: None,
            url_text: String::new(),
            time: options.time.unwrap_or(0.0),
            playing: false,
            moving_budget: super::state::DEFAULT_MOVING_BUDGET,
            inspect: super::state::Inspection {
                clip_on: !options.clip.is_empty(),
                clip_box: options.clip.clip_box,
                clip_planes: options.clip.planes.clone(),
                ..Default::default()
            },
            bookmarks: Vec::new(),
            large_factor: 4,
            help_shown: false,
            fly: false,
        };
        let mut app = Self {
            ui,
            model: None,
            load: None,
            interim: Default::default(),
            frame_pace: Default::default(),
            load_error: None,
            generations: 0,
            home: camera,
            scene: SceneSphere { centre: glam::Vec3::ZERO, radius: 1.0 },
            grouped: None,
            grouping_job: None,
            grouping_error: None,
            renderer: RenderThread::start(ctx.clone(), options.cache.clone().unwrap_or_else(Cache::from_env)),
            next_request: 0,
            requested: None,
            in_flight: Vec::new(),
            frame_error: None,
            shown: None,
            view_size: (1, 1),
            view_rect: egui::Rect::NOTHING,
            last_camera_move: None,
            measure: None,
            measurement: None,
            measure_error: None,
            status: None,
            frame_clock: Default::default(),
            frames_since_ready: 0,
            window_shot_requested: false,
            play_clock: None,
            zoom_anchor: None,
            pointer: None,
            layers: Vec::new(),
            layers_before: None,
            pending_looks: None,
            layers_folder: None,
            keep_view: false,
            placement_shown: None,
            polygon_report: None,
            export: None,
            profile_slab: None,
            options,
        };
        match app.options.file.clone().map_or_else(|| crate::assets::path(crate::assets::BUNDLED_MODEL), Ok) {
            Ok(file) => app.open_first(&ctx, &file),
            Err(e) => app.load_error = Some(e),
        }
        app
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

    /// The camera of the view.
    pub fn camera(&self) -> Camera {
        self.ui.camera
    }

    /// How many splats the frame on screen drew.
    pub fn shown_splats(&self) -> Option<usize> {
        self.shown.as_ref().map(|s| s.stats.splats_drawn)
    }

    pub fn status(&self) -> Option<&str> {
        self.status.as_deref()
    }

    /// The settings the panels show now.
    pub fn settings(&self) -> &RenderSettings {
        &self.ui.settings
    }

    /// The clip box, the last pick and the measured points.
    pub fn inspection(&self) -> &super::state::Inspection {
        &self.ui.inspect
    }

    /// Where the 3D view is in the window, in points.
    pub fn view_rect(&self) -> egui::Rect {
        self.view_rect
    }

    /// The slowest UI frame of the last two seconds, in ms.
    pub fn slowest_ui_frame_ms(&self) -> f32 {
        self.frame_clock.slowest_ms()
    }

    pub(super) fn camera_moved(&mut self) {
        self.last_camera_move = Some(Instant::now());
    }

    pub(super) fn reset_camera(&mut self) {
        self.ui.camera = self.home;
        self.camera_moved();
    }

    /// Moves a playing animation on to the time of this UI frame (looping),
    /// and keeps the window repainting while it plays.
    fn play(&mut self, ctx: &egui::Context) {
        let period = self.model.as_ref().map_or(0.0, |m| m.period);
        match (self.ui.playing && period > 0.0, self.play_clock) {
            (true, Some((started, from))) => {
                self.ui.time = (from + started.elapsed().as_secs_f64()).rem_euclid(period);
                ctx.request_repaint();
            }
            (true, None) => {
                self.play_clock = Some((Instant::now(), self.ui.time));
                ctx.request_repaint();
            }
            (false, _) => self.play_clock = None,
        }
    }

    /// Polls jobs and the render thread.
    fn poll(&mut self, ctx: &egui::Context) {
        self.poll_load();
        self.poll_grouping();
        self.poll_measurement(ctx);
        self.poll_frames(ctx);
        self.poll_export();
    }
}

impl eframe::App for ViewerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let ctx = ui.ctx().clone();
        self.frame_clock.tick(Instant::now(), ctx.requested_repaint_last_pass());
        self.poll(&ctx);
        self.handle_input(&ctx);
        self.play(&ctx);
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
        self.ensure_clip_box();
        self.measure_polygon();
        self.cut_profile();
        self.status_bar(ui);
        let profile_actions = self.profile_side_panel(ui);
        self.apply(&ctx, profile_actions);
        egui::CentralPanel::no_frame().show(ui, |ui| self.view_ui(ui));
        self.refine_stream(&ctx);
        self.ensure_grouping(&ctx);
        self.request_frame(&ctx);
        self.scripted_exit(&ctx);
        if self.load.is_some() || self.grouping_job.is_some() || self.measure.is_some() {
            ctx.request_repaint_after(Duration::from_millis(100)); // progress bars
        }
    }
}
