//! What the panels work with: the UI state they edit ([`UiState`]), a
//! read-only picture of everything else they show ([`PanelInfo`]), and the
//! [`Action`]s they ask the app to take. The panels import only this module
//! and the widgets; the app builds a `PanelInfo`, runs the panels and applies
//! their actions, so no module depends on the app's internals.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use crate::frame::{Camera, RenderSettings};
use crate::reference::ImageError;

use super::model::GroupedModel;
use super::render_thread::FrameStats;

/// The size of an exported screenshot.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScreenshotSize {
    Window,
    /// N × the view's size (each side at most [`crate::frame::settings::MAX_IMAGE_SIDE`]).
    Times(u32),
    Fixed(u32, u32),
}

impl ScreenshotSize {
    pub const CHOICES: [ScreenshotSize; 6] = [
        ScreenshotSize::Window,
        ScreenshotSize::Times(2),
        ScreenshotSize::Times(4),
        ScreenshotSize::Times(8),
        ScreenshotSize::Fixed(1920, 1080),
        ScreenshotSize::Fixed(3840, 2160),
    ];

    pub fn label(self) -> String {
        match self {
            ScreenshotSize::Window => "view size".into(),
            ScreenshotSize::Times(n) => format!("{n} × view size"),
            ScreenshotSize::Fixed(w, h) => format!("{w} × {h}"),
        }
    }

    pub fn pixels(self, view: (u32, u32)) -> (u32, u32) {
        match self {
            ScreenshotSize::Window => view,
            ScreenshotSize::Times(n) => (view.0.saturating_mul(n), view.1.saturating_mul(n)),
            ScreenshotSize::Fixed(w, h) => (w, h),
        }
    }
}

/// Everything that decides a frame of the 3D view.
#[derive(Debug, Clone, PartialEq)]
pub struct FrameKey {
    pub generation: u64,
    /// The grouping drawn, for modes that draw groups.
    pub grouping: Option<String>,
    pub camera: Camera,
    pub settings: RenderSettings,
    pub size: (u32, u32),
    /// Set while the camera moves on a large model: the faster mode and budget drawn.
    pub preview: Option<crate::frame::spec::Preview>,
    /// The time shown, in seconds, for a moving scene.
    pub time: Option<f64>,
}

/// A finished error measurement.
pub struct Measurement {
    pub key: FrameKey,
    pub error: ImageError,
    pub reference_seconds: f64,
    pub difference: egui::TextureHandle,
}

/// What the panels edit directly.
#[derive(Debug, Clone)]
pub struct UiState {
    pub settings: RenderSettings,
    pub camera: Camera,
    /// Light direction in eye space as (azimuth, elevation) degrees.
    pub light_angles: (f32, f32),
    pub screenshot_size: ScreenshotSize,
    /// The opacity slider's value while it is dragged, and until the model
    /// holds the value it was let go at.
    pub opacity_pending: Option<f32>,
    /// The URL typed in the Model section, to open.
    pub url_text: String,
    /// A layer's opacity slider while it is dragged: the layer and its value.
    pub layer_opacity_pending: Option<(usize, f32)>,
    /// A moving scene's time (seconds) and whether it plays.
    pub time: f64,
    pub playing: bool,
    /// Most splats a frame draws while the camera moves (a still scene with
    /// more splats is drawn from its hierarchy under this budget until the camera stops).
    pub moving_budget: u32,
    /// The clip box, the pick and the measurement ([`super::inspect`]).
    pub inspect: Inspection,
    /// Views bookmarked for a camera path (`render --path`).
    pub bookmarks: Vec<Camera>,
    /// N of Ctrl+Shift+S: a screenshot at N × the view's size.
    pub large_factor: u32,
    /// Whether the help overlay lists the view's inputs (H).
    pub help_shown: bool,
    /// Fly mode (F): W A S D Q E move the eye, a drag looks around.
    pub fly: bool,
}

/// What a click in the 3D view does.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Tool {
    /// Nothing: the view only orbits, pans and zooms.
    #[default]
    Look,
    /// List the layers under the pixel.
    Pick,
    /// Add the nearest surface under the pixel to the measured polyline.
    Measure,
    /// Add the nearest surface under the pixel as a vertex of the polygon (its x and y).
    Polygon,
    /// A drag draws a box: the points on screen inside it are the selection.
    Select,
    /// A drag draws a free outline: the points on screen inside it are the selection.
    Lasso,
    /// Two clicks: the ends of a profile's line (their x and y).
    Profile,
}

/// A selection drawn on screen: its box (a lasso's bounds), a lasso's
/// outline (empty for a box), the view it was drawn on (points), and the
/// camera it was drawn through.
#[derive(Debug, Clone, PartialEq)]
pub struct ScreenSelection {
    pub rect: egui::Rect,
    pub lasso: Vec<egui::Pos2>,
    pub view: egui::Rect,
    pub camera: crate::frame::Camera,
}

/// The inspection tools' state: the clip region (file coordinates), the
/// last pick and the measured points.
#[derive(Debug, Clone, Default)]
pub struct Inspection {
    pub tool: Tool,
    pub clip_on: bool,
    /// Set to the model's bounds when the clip is first switched on.
    pub clip_box: Option<crate::frame::clip::ClipBox>,
    /// Planes from the command line (`--clip-plane`), applied while the clip is on.
    pub clip_planes: Vec<[f64; 4]>,
    pub picked: Option<crate::inspect::PickReport>,
    /// The measured points: the pixel clicked and the surface point under it.
    pub measured: Vec<([u32; 2], glam::DVec3)>,
    /// The box face whose handle is being dragged (axis · 2 + max).
    pub dragging: Option<usize>,
    /// The polygon's vertices (file coordinates; its area is horizontal) and
    /// whether its volume is measured too (above a plane fitted along its border).
    pub polygon: Vec<glam::DVec3>,
    pub polygon_volume: bool,
    /// The layer the volume is measured against (its file), instead of the border's plane.
    pub polygon_base: Option<PathBuf>,
    /// Where the select tool's drag was pressed, while it is drawn, and the selection.
    pub selecting: Option<egui::Pos2>,
    pub selection: Option<ScreenSelection>,
    /// The profile's line (its ends, file coordinates) and its slab's width (file units).
    pub profile_line: Vec<glam::DVec3>,
    pub profile_width: f64,
    /// The points picked on the profile's section (at most two: a measure) and where it was last drawn.
    pub profile_marks: Vec<glam::DVec3>,
    pub profile_layout: Option<SectionLayout>,
}

impl Inspection {
    /// A profile tool's click: the line's next end (a third click starts a new line).
    pub fn add_profile_end(&mut self, p: glam::DVec3) {
        if self.profile_line.len() == 2 {
            self.profile_line.clear();
        }
        self.profile_marks.clear();
        self.profile_line.push(p);
        if self.profile_line.len() == 2 && self.profile_width <= 0.0 {
            // A first width: a twentieth of the line.
            self.profile_width = self.profile_line[0].truncate().distance(self.profile_line[1].truncate()) / 20.0;
        }
    }

    /// The region frames are clipped by: the box and planes while the clip is on.
    pub fn region(&self) -> crate::frame::ClipRegion {
        if !self.clip_on {
            return Default::default();
        }
        crate::frame::ClipRegion { clip_box: self.clip_box, planes: self.clip_planes.clone() }
    }

    /// What the measured points measure along `up`, with at least two of them.
    pub fn measurement(&self, up: glam::DVec3) -> Option<crate::inspect::Measurement> {
        let points: Vec<glam::DVec3> = self.measured.iter().map(|(_, p)| *p).collect();
        (points.len() >= 2).then(|| crate::inspect::measure(&points, up))
    }
}

pub use super::model::DEFAULT_MOVING_BUDGET;

impl UiState {
    /// Light angles (degrees) of the light direction in `settings`.
    pub fn light_angles_of(settings: &RenderSettings) -> (f32, f32) {
        let d = settings.shading.light_dir_eye;
        (d.x.atan2(d.z).to_degrees(), d.y.clamp(-1.0, 1.0).asin().to_degrees())
    }

    /// Writes the light angles back into the settings' light direction.
    pub fn apply_light_angles(&mut self) {
        let (az, el) = (self.light_angles.0.to_radians(), self.light_angles.1.to_radians());
        self.settings.shading.light_dir_eye = glam::Vec3::new(az.sin() * el.cos(), el.sin(), az.cos() * el.cos());
    }
}

/// Which background job an action is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JobKind {
    Load,
    Grouping,
    Measure,
}

/// A running background job as the panels show it.
#[derive(Debug, Clone)]
pub struct JobInfo {
    pub kind: JobKind,
    pub label: String,
    pub stage: String,
    pub fraction: Option<f32>,
    pub seconds: f64,
}

/// What the panels ask the app to do.
#[derive(Debug, Clone, PartialEq)]
pub enum Action {
    Open(PathBuf),
    Cancel(JobKind),
    MeasureError,
    SaveScreenshot,
    /// A screenshot at N × the view's size (Ctrl+Shift+S).
    SaveLargeScreenshot,
    /// Write the bookmarked views to a views file beside the screenshots.
    SaveViews,
    ResetCamera,
    /// The camera was edited in the panel (field of view).
    CameraMoved,
    /// Give every object of the model this opacity (0..1).
    SetOpacity(f32),
    /// Set the model in this environment map (a file), or in none.
    SetEnvironment(Option<PathBuf>),
    /// Colour the model and set its opacity by its attributes (or draw it as loaded).
    SetStyle(Option<crate::style::Style>),
    /// Show this error where load errors are shown (a bundled file that is missing).
    ShowError(String),
    /// Show (true) or hide layer k.
    ShowLayer(usize, bool),
    /// Draw layer k in this opacity and colour.
    SetLayerLook(usize, crate::scene::Look),
    RemoveLayer(usize),
    /// Write the selected points to this file (LAS, LAZ or PLY).
    ExportSelection(PathBuf),
    /// Clip the view to the selection (true), or hide it (false).
    KeepSelection(bool),
    /// Show again the points kept or hidden selections dropped (the style's regions).
    ClearRegions,
    /// Write the profile's slab to this file (CSV rows, or LAS, LAZ or PLY points).
    ExportProfile(PathBuf),
}

/// The model on screen, as the panels show it.
pub struct ModelInfo<'a> {
    pub name: &'a str,
    pub path: &'a Path,
    pub splats: usize,
    pub warnings: &'a [String],
    /// The first object's opacity, and whether every object shares it.
    pub opacity: (f32, bool),
    /// Whether any splat is transparent (opacity below 1).
    pub transparent: bool,
    /// The environment map's name, if the model has one.
    pub environment: Option<&'a str>,
    /// Seconds after which the scene's animations repeat (0: nothing moves).
    pub period: f64,
    /// The colour and opacity by attribute drawn, and the attributes to choose from.
    pub style: Option<&'a crate::style::Style>,
    pub summary: &'a crate::style::summary::Summary,
}

/// The frame on screen, as the panels show it.
pub struct ShownInfo<'a> {
    pub key: &'a FrameKey,
    pub stats: &'a FrameStats,
}

/// Everything the panels show but do not edit.
pub struct PanelInfo<'a> {
    pub model: Option<ModelInfo<'a>>,
    pub load_error: Option<&'a str>,
    pub jobs: Vec<JobInfo>,
    /// Progress of a slow frame the view is waiting for (the reference).
    pub view_progress: Option<(String, Option<f32>)>,
    pub grouped: Option<&'a Arc<GroupedModel>>,
    pub grouping_error: Option<&'a str>,
    pub shown: Option<ShownInfo<'a>>,
    /// The frame the view should show now.
    pub current: Option<FrameKey>,
    pub ui_fps: f32,
    pub slowest_ui_frame_ms: f32,
    pub measurement: Option<&'a Measurement>,
    pub measure_error: Option<&'a str>,
    pub screenshot_dir: &'a Path,
    pub status: Option<&'a str>,
    /// A streamed file's state, and whether a new view is being loaded.
    pub streaming: Option<(super::stream_source::StreamStatus, bool)>,
    /// The files opened as layers.
    pub layers: &'a [Layer],
    /// Each layer's opacity and colour as drawn (as set, for a hidden one).
    pub layer_looks: Vec<crate::scene::Look>,
    /// The polygon's measure, or why there is none, once it has three vertices.
    pub polygon: Option<&'a Result<PolygonReport, String>>,
}

impl PanelInfo<'_> {
    pub fn job(&self, kind: JobKind) -> Option<&JobInfo> {
        self.jobs.iter().find(|j| j.kind == kind)
    }
}

/// One layer: its file (or URL), whether it is shown, and its opacity and
/// colour where the list set them (none: as the file and the flags give them).
#[derive(Debug, Clone, PartialEq)]
pub struct Layer {
    pub path: PathBuf,
    pub shown: bool,
    pub look: Option<crate::scene::Look>,
}

impl Layer {
    pub fn name(&self) -> String {
        Self::name_of(&self.path)
    }

    /// The name of a layer's file or URL: its last part.
    pub fn name_of(path: &Path) -> String {
        let text = path.to_string_lossy();
        text.rsplit(['/', '\\']).next().unwrap_or(&text).to_string()
    }
}

/// What a polygon's measure was made of: its vertices, whether the volume
/// was asked for and against which layer, and the model's generation.
pub type PolygonKey = (Vec<glam::DVec3>, bool, Option<PathBuf>, u64);

/// The polygon's measure, as the panel shows it: `measure --polygon`'s figures and its JSON.
#[derive(Debug, Clone, PartialEq)]
pub struct PolygonReport {
    pub area_horizontal: f64,
    pub area_surface: f64,
    /// Above and below the base, when the volume is measured.
    pub volume: Option<(f64, f64)>,
    pub points: usize,
    pub units: String,
    /// What `measure --polygon --json` prints for the same polygon and points.
    pub json: String,
}

/// What a profile's slab was cut from: the line's ends, the width's bits and the model's generation.
pub type ProfileKey = (Vec<glam::DVec3>, u64, u64);

/// Where the profile's section is drawn: its rectangle, the lowest
/// height, and points on screen per file unit (`profile_pick.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionLayout {
    pub rect: egui::Rect,
    pub low: f64,
    pub scale: f64,
}

/// A profile's slab of the points on screen: its points (file coordinates)
/// and their colours as the view draws them.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileSlab {
    pub profile: crate::inspect::profile::Profile,
    pub points: Vec<glam::DVec3>,
    pub colours: Vec<[u8; 3]>,
}
