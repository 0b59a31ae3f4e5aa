//! Streamed files in the viewer: opening one (its home view's nodes), and
//! a new selection in the background whenever the camera rests somewhere
//! the last one was not made for (see [`super::stream_source`]). A view is
//! loaded in steps; the model of the nodes loaded so far goes to the window
//! through an [`Interim`] slot after the first step, then no more often
//! than the window draws ([`super::refine_steps`]), while nodes remain to
//! load. The window shows each at once (a newer one replaces one it has not
//! taken yet).

use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

use super::app::ViewerApp;
use super::jobs::Job;
use super::model::Model;
use super::refine_steps::{FramePace, Interim};
use super::stream_source::{StreamedSource, ViewKey};
use crate::copc::StreamBudget;
use crate::scene::{Materials, Scene};
use crate::style::Style;

/// The model of the nodes `view` selects from `source`, with `materials` and
/// `style`, refined in steps whose models go to `interim`; `shown` again
/// (the same generation: its GPU copies and grouping stay) when they are
/// the nodes it draws.
fn streamed_model(
    source: &Arc<StreamedSource>,
    (path, shown): (&Path, Option<Arc<Model>>),
    (view, generation): (ViewKey, u64),
    (materials, style): (&Materials, Option<Arc<Style>>),
    (interim, pace, repaint): (&Interim, &FramePace, &egui::Context),
) -> Result<Model, String> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let mut style = style.or_else(|| materials.style.clone());
    let mut latest: Option<Model> = None;
    let make = |scene, warnings, style: &Option<Arc<Style>>| {
        model_of(source, (path, scene, warnings), generation, (materials, style.clone()))
    };
    let pace = || super::refine_steps::pace(pace);
    let mut show = |scene, warnings| {
        let model = make(scene, warnings, &style)?;
        // Later steps keep the colours the first one showed.
        style = model.scene.pinned_style().map(Arc::new).or_else(|| model.style.clone());
        *interim.lock().map_err(|_| "the view's steps were poisoned".to_string())? = Some(model.clone());
        latest = Some(model);
        repaint.request_repaint();
        Ok(())
    };
    let last = source.scene(name, view, (&mut show, &pace))?;
    match last {
        Some((scene, warnings)) => make(scene, warnings, &style),
        None => latest
            .or_else(|| shown.map(|model| (*model).clone()))
            .ok_or_else(|| format!("{}: no node selected", path.display())),
    }
}

/// The model of one selection: coloured by default when it is the first
/// and nothing asks for a style, then given `materials` and `style`.
fn model_of(
    source: &Arc<StreamedSource>,
    (path, mut scene, warnings): (&Path, Scene, Vec<String>),
    generation: u64,
    (materials, style): (&Materials, Option<Arc<Style>>),
) -> Result<Model, String> {
    if style.is_none() {
        // The first selection: colours by default (a later one keeps the style shown, restyled once below).
        scene = scene.coloured_by_default();
    }
    Materials { style: None, ..materials.clone() }.apply(&mut scene)?;
    let model = Model::of_scene(path, scene, warnings, generation);
    let model = match style {
        Some(style) => model.with_style(Some(style), generation)?,
        None => model,
    };
    Ok(Model { streamed: Some(Arc::clone(source)), ..model })
}

impl ViewerApp {
    /// Opens a streamed file: the nodes of its home view, in the background.
    pub(super) fn open_streamed(&mut self, ctx: &egui::Context, path: PathBuf, generation: u64) {
        let size = self.view_size;
        let budget = self.stream_budget();
        let choosing = crate::lod::Choosing::of(&self.ui.settings);
        let materials = self.options.materials.clone();
        let (stream, asked) = (self.options.stream.clone(), self.options.camera);
        let label = format!("streaming {}", path.file_name().map(|n| n.to_string_lossy()).unwrap_or_default());
        let (interim, pace, repaint) = (self.new_interim(), Arc::clone(&self.frame_pace), ctx.clone());
        self.load = Some(Job::spawn(label, ctx.clone(), move || {
            crate::progress::stage("reading the header and the hierarchy");
            let source = StreamedSource::open(&path, stream)?;
            let camera = source.home_camera(&asked, size.0 as f32 / size.1.max(1) as f32);
            let view = ViewKey { camera, size, budget, choosing };
            streamed_model(&source, (&path, None), (view, generation), (&materials, None), (&interim, &pace, &repaint))
        }));
    }

    /// Whether the window draws `path` node by node ([`crate::copc::window_draws_by_nodes`]),
    /// or a `.vpc` of streamed files as layers under one budget.
    pub(super) fn drawn_by_nodes(&self, path: &std::path::Path) -> bool {
        super::stream_layers::streams_layers(path) || crate::copc::window_draws_by_nodes(path, self.stream_budget())
    }

    /// The budget a streamed view selects under: the panel's, else every
    /// point when the command line said `--point-budget all`, else 1M.
    fn stream_budget(&self) -> StreamBudget {
        let all = self.options.parameters.iter().any(|(p, v)| *p == crate::frame::Parameter::PointBudget && v == "all");
        StreamBudget::of_settings(self.ui.settings.point_budget, all)
    }

    /// What the statistics show of the streamed model on screen, if it is streamed.
    pub fn stream_status(&self) -> Option<super::stream_source::StreamStatus> {
        Some(self.model.as_ref()?.streamed.as_ref()?.status())
    }

    /// A new slot for the steps of the job about to start (a cancelled
    /// job's steps go to the old one, which nobody reads).
    fn new_interim(&mut self) -> Interim {
        self.interim = Arc::new(Mutex::new(None));
        Arc::clone(&self.interim)
    }

    /// When the camera rests somewhere the selection was not made for,
    /// selects and loads that view's nodes in the background.
    pub(super) fn refine_stream(&mut self, ctx: &egui::Context) {
        let Some(model) = self.model.clone() else { return };
        let Some(source) = model.streamed.clone() else { return };
        let moving = self.last_camera_move.is_some_and(|t| t.elapsed() < super::frames::SETTLE);
        if self.load.is_some() || moving {
            return;
        }
        let choosing = crate::lod::Choosing::of(&self.ui.settings);
        let view = ViewKey { camera: self.ui.camera, size: self.view_size, budget: self.stream_budget(), choosing };
        if source.status().view == Some(view) {
            return;
        }
        self.generations += 1;
        let generation = self.generations;
        let materials = self.options.materials.clone();
        // The colours shown stay: a range left to the percentiles is fixed at the first selection's.
        let style = model.scene.pinned_style().map(Arc::new).or_else(|| model.style.clone());
        let path = model.path.clone();
        let (interim, pace, repaint) = (self.new_interim(), Arc::clone(&self.frame_pace), ctx.clone());
        self.load = Some(Job::spawn("refining the view", ctx.clone(), move || {
            streamed_model(
                &source,
                (&path, Some(model)),
                (view, generation),
                (&materials, style),
                (&interim, &pace, &repaint),
            )
        }));
    }

    /// The newest step of the streamed view refining, if the window has
    /// not shown it yet: it gets a generation of its own.
    pub(super) fn take_interim(&mut self) -> Option<Model> {
        let mut model = self.interim.lock().ok()?.take()?;
        self.generations += 1;
        model.generation = self.generations;
        Some(model)
    }
}
