//! Streamed files in the viewer: opening one (its home view's nodes), and
//! a new selection in the background whenever the camera rests somewhere
//! the last one was not made for (see [`super::stream_source`]).

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::app::ViewerApp;
use super::jobs::Job;
use super::model::Model;
use super::stream_source::{StreamedSource, ViewKey};
use crate::copc::StreamBudget;
use crate::scene::Materials;

/// The model of the nodes `view` selects from `source`, with `materials` and
/// `style`; `shown` again (the same generation: its GPU copies and grouping
/// stay) when they are the nodes it draws.
fn streamed_model(
    source: &Arc<StreamedSource>,
    (path, shown): (&Path, Option<Arc<Model>>),
    view: ViewKey,
    generation: u64,
    (materials, style): (&Materials, Option<Arc<crate::style::Style>>),
) -> Result<Model, String> {
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let Some((mut scene, warnings)) = source.scene(name, view)? else {
        return shown.map(|model| (*model).clone()).ok_or_else(|| format!("{}: no node selected", path.display()));
    };
    if style.is_none() && materials.style.is_none() {
        // The first selection: colours by default (a later one keeps the style shown, restyled once below).
        scene = scene.coloured_by_default();
    }
    Materials { style: None, ..materials.clone() }.apply(&mut scene)?;
    let model = Model::of_scene(path, scene, warnings, generation);
    let model = match style.or_else(|| materials.style.clone()) {
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
        self.load = Some(Job::spawn(label, ctx.clone(), move || {
            crate::progress::stage("reading the header and the hierarchy");
            let source = StreamedSource::open(&path, stream)?;
            let camera = source.home_camera(&asked, size.0 as f32 / size.1.max(1) as f32);
            let view = ViewKey { camera, size, budget, choosing };
            streamed_model(&source, (&path, None), view, generation, (&materials, None))
        }));
    }

    /// The budget a streamed view selects under: the panel's, else every
    /// point when the command line said `--point-budget all`, else 1M.
    fn stream_budget(&self) -> StreamBudget {
        let all = self.options.parameters.iter().any(|(p, v)| *p == crate::frame::Parameter::PointBudget && v == "all");
        StreamBudget::of_settings(self.ui.settings.point_budget, all)
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
        self.load = Some(Job::spawn("refining the view", ctx.clone(), move || {
            streamed_model(&source, (&path, Some(model)), view, generation, (&materials, style))
        }));
    }
}
