//! The 3D view's renderer: a thread with its own headless GPU device that runs
//! the same [`GpuRenderer`] as `pointblend render`, reads each frame back
//! and hands it to the window as an image.
//!
//! Why a separate device and not the window's: on a software rasteriser
//! (lavapipe) a frame of a few million splats executes for seconds inside the
//! queue submission, and the window's own drawing would wait behind it on a
//! shared queue. With its own device the window stays responsive whatever the
//! frame costs; the price is one read-back and upload per frame (a few ms).
//!
//! Requests are coalesced: when several view requests queue up while a frame
//! renders, only the newest is drawn. Screenshot requests are never dropped.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::mpsc::{self, Receiver, Sender};
use std::time::Instant;

use crate::frame::spec::Preview;
use crate::frame::{Camera, FrontDepth, RenderSettings, Sidecar, View};
use crate::grouping::cache::Cache;
use crate::progress::{self, Tracker};
use crate::render::{Frame, GpuRenderer, PreparedScene, RenderPlan, SceneGrouping};

use super::model::{GroupedModel, Model};

/// What a frame is for.
#[derive(Debug, Clone)]
pub enum Purpose {
    /// The 3D view.
    Display,
    /// A PNG and its sidecar, written atomically, with the measurement drawn over the PNG.
    Screenshot { png: PathBuf, sidecar: Box<Sidecar>, annotation: Box<super::annotate::Annotation> },
}

/// One frame to draw.
#[derive(Debug, Clone)]
pub struct FrameRequest {
    pub id: u64,
    pub model: Arc<Model>,
    /// Present for modes that draw groups.
    pub grouping: Option<Arc<GroupedModel>>,
    pub camera: Camera,
    pub settings: RenderSettings,
    pub size: (u32, u32),
    /// While the camera moves: the preview's mode and budget.
    pub preview: Option<Preview>,
    /// The time to draw a moving scene at, in seconds.
    pub time: Option<f64>,
    pub purpose: Purpose,
}

/// What a frame cost and drew.
#[derive(Debug, Clone, Default)]
pub struct FrameStats {
    /// Wall time from the start of the frame to its pixels on the CPU.
    pub frame_ms: f64,
    /// GPU time per pass, where the adapter has timestamps.
    pub pass_ms: Vec<(String, f64)>,
    pub splats_drawn: usize,
    pub preview: Option<Preview>,
    pub plan: Option<String>,
    pub plan_bytes: u64,
    /// What the frame measured while it ran ([`crate::render::FrameReport`]), in lines.
    pub report: Vec<String>,
    pub geometry_passes: usize,
    /// A moving scene's frame: milliseconds to regroup its splats and to
    /// write them to the GPU (none when the time did not change).
    pub regroup_ms: Option<f64>,
    pub upload_ms: Option<f64>,
    /// Splats whose group was computed for this frame.
    pub regrouped: Option<usize>,
}

/// A drawn frame, or why it failed.
pub struct FrameResult {
    pub id: u64,
    pub purpose: Purpose,
    pub image: Result<Arc<image::RgbaImage>, String>,
    pub stats: FrameStats,
    /// The view frame's nearest surface per pixel, where its mode keeps one
    /// (two-pass): the cursor's coordinates are read from it.
    pub front_depth: Option<Arc<FrontDepth>>,
}

/// The handle the window keeps.
pub struct RenderThread {
    requests: Sender<FrameRequest>,
    results: Receiver<FrameResult>,
    /// Progress of a reference frame (the only slow mode).
    pub tracker: Arc<Tracker>,
    thread: Option<std::thread::JoinHandle<()>>,
}

/// How long closing waits for the render thread to release the GPU.
const CLOSE_WAIT: std::time::Duration = std::time::Duration::from_secs(3);

impl Drop for RenderThread {
    /// Ends the thread (its request channel closes) and waits a little for it
    /// to drop its GPU device: a process that exits while a thread is still
    /// tearing a Vulkan device down can crash in the driver. A long reference
    /// frame is not waited for, so closing the window never hangs.
    fn drop(&mut self) {
        let (closed, _) = mpsc::channel();
        drop(std::mem::replace(&mut self.requests, closed));
        let Some(thread) = self.thread.take() else { return };
        let started = std::time::Instant::now();
        while !thread.is_finished() && started.elapsed() < CLOSE_WAIT {
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        if thread.is_finished() {
            let _ = thread.join();
        }
    }
}

impl RenderThread {
    /// Starts the thread; `repaint` is woken after each frame.
    /// Groupings and hierarchies the thread makes are cached in `cache`.
    pub fn start(repaint: egui::Context, cache: Cache) -> Self {
        let (requests, inbox) = mpsc::channel::<FrameRequest>();
        let (outbox, results) = mpsc::channel::<FrameResult>();
        let tracker = Tracker::new();
        let thread_tracker = Arc::clone(&tracker);
        let spawned = std::thread::Builder::new()
            .name("pointblend renderer".into())
            .spawn(move || progress::track(thread_tracker, || serve(inbox, outbox, repaint, cache)));
        let thread = spawned.map_err(|e| log::error!("could not start the render thread: {e}")).ok();
        Self { requests, results, tracker, thread }
    }

    pub fn request(&self, request: FrameRequest) {
        if self.requests.send(request).is_err() {
            log::error!("the render thread has stopped");
        }
    }

    /// Frames finished since the last call.
    pub fn finished(&self) -> Vec<FrameResult> {
        self.results.try_iter().collect()
    }
}

/// The model ready to render, kept while the model stays the same.
struct Scenes {
    cache: Cache,
    /// The model drawn (its generation), its prepared scene, and the streamed file it is a selection of.
    full: Option<(u64, PreparedScene, Option<Arc<super::stream_source::StreamedSource>>)>,
    /// The time the full scene is at, when it moves.
    time: Option<f64>,
}

fn serve(inbox: Receiver<FrameRequest>, outbox: Sender<FrameResult>, repaint: egui::Context, cache: Cache) {
    let mut renderer = GpuRenderer::new().map_err(|e| format!("opening the GPU: {e}"));
    if let Ok(r) = &mut renderer {
        log::info!("viewer GPU: {}", r.ctx.describe());
        r.renderer.enable_pass_timing(&r.ctx);
    }
    let mut scenes = Scenes { cache, full: None, time: None };
    while let Ok(first) = inbox.recv() {
        let mut pending = vec![first];
        pending.extend(inbox.try_iter());
        // Keep every screenshot and only the newest view frame.
        let newest_display = pending.iter().rposition(|r| matches!(r.purpose, Purpose::Display));
        for (i, request) in pending.into_iter().enumerate() {
            if matches!(request.purpose, Purpose::Display) && Some(i) != newest_display {
                continue;
            }
            let result = match &mut renderer {
                Ok(r) => draw(r, &mut scenes, &request),
                Err(e) => FrameResult {
                    id: request.id,
                    purpose: request.purpose.clone(),
                    image: Err(e.clone()),
                    stats: FrameStats::default(),
                    front_depth: None,
                },
            };
            let result = finish(result);
            if outbox.send(result).is_err() {
                return;
            }
            repaint.request_repaint();
        }
    }
}

/// Writes a screenshot's files; the result says where, or why not.
fn finish(mut result: FrameResult) -> FrameResult {
    if let (Purpose::Screenshot { png, sidecar, annotation }, Ok(image)) = (&result.purpose, &result.image) {
        let json = png.with_extension("json");
        let annotated = match annotation.is_empty() {
            true => Ok(std::borrow::Cow::Borrowed(image.as_ref())),
            false => super::annotate::draw(image, annotation).map(std::borrow::Cow::Owned),
        };
        let written = annotated
            .and_then(|image| crate::output::save_png(&image, png).map_err(|e| e.to_string()))
            .map_err(|e| format!("{}: {e}", png.display()))
            .and_then(|_| sidecar.write(&json).map_err(|e| format!("{}: {e}", json.display())));
        if let Err(e) = written {
            result.image = Err(e);
        }
    }
    result
}

fn draw(r: &mut GpuRenderer, scenes: &mut Scenes, request: &FrameRequest) -> FrameResult {
    let started = Instant::now();
    let mut stats = FrameStats { preview: request.preview, ..Default::default() };
    let frames = match request.time {
        Some(t) => moving_frames(r, scenes, request, t, &mut stats),
        None => Ok(prepared_scene(r, scenes, request)),
    };
    let frame = frames.and_then(|frames| {
        let spec = frames.resolve(&request.settings, View { size: request.size, preview: request.preview });
        frames
            .render_frame(Some(&mut *r), &request.camera, &spec, crate::render::Readback::Image)
            .map_err(|e| e.to_string())
    });
    let mut front_depth = None;
    let image = frame.map(|Frame { image, plan, report }| {
        stats.report = report.lines();
        stats.splats_drawn = plan.splats;
        stats.pass_ms = if plan.steps.is_empty() { Vec::new() } else { pass_times(r, &plan) };
        describe_plan(&mut stats, &plan);
        // A still view's frame: a preview is drawn while the camera moves, when no coordinate holds still.
        if matches!(request.purpose, Purpose::Display) && request.preview.is_none() {
            let reading = Instant::now();
            front_depth = match r.front_depth(&plan, &request.camera) {
                Ok(depth) => {
                    log::debug!("front depth read back in {:.2} ms", reading.elapsed().as_secs_f64() * 1e3);
                    depth.map(Arc::new)
                }
                Err(e) => {
                    log::warn!("reading the frame's depth back: {e}");
                    None
                }
            };
        }
        image
    });
    stats.frame_ms = started.elapsed().as_secs_f64() * 1e3;
    FrameResult { id: request.id, purpose: request.purpose.clone(), image: image.map(Arc::new), stats, front_depth }
}

/// The model this request draws, with the request's grouping handed in; one
/// grouped GPU copy is kept at a time. A preview draws the same model under a
/// point budget (its hierarchy is built on first use and kept with it).
/// A streamed file's next selection is shown in the last one's scene, whose
/// GPU copy keeps the nodes still drawn where they are.
fn prepared_scene<'a>(r: &GpuRenderer, scenes: &'a mut Scenes, request: &FrameRequest) -> &'a mut PreparedScene {
    let model = &request.model;
    let generation = model.generation;
    let (slot, cloud) = (&mut scenes.full, &model.cloud);
    let next_selection = |(_, frames, source): &(u64, PreparedScene, Option<_>)| {
        frames.is_streamed() && model.streamed.as_ref().zip(source.as_ref()).is_some_and(|(a, b)| Arc::ptr_eq(a, b))
    };
    if let Some(kept) = slot.as_mut().filter(|(g, ..)| *g != generation).filter(|kept| next_selection(kept)) {
        let (g, frames, _) = kept;
        match frames.show_selection(Some(r), Arc::clone(&model.scene), Arc::clone(cloud)) {
            Ok(update) => {
                log::debug!("next selection: {} bytes written to the GPU", update.uploaded_bytes);
                *g = generation;
            }
            // Prepared anew below.
            Err(e) => log::warn!("showing the next selection: {e}; preparing it anew"),
        }
    }
    if slot.as_ref().is_none_or(|(g, ..)| *g != generation) {
        *slot = None; // free the old copies first
        let mut frames = PreparedScene::new(Arc::clone(&model.scene), Arc::clone(cloud))
            .handed_groupings(1)
            .with_cache(scenes.cache.clone());
        if model.streamed.is_some() {
            frames = frames.streamed(); // the selection applied the budget
        }
        if let Some(hierarchy) = &model.hierarchy {
            frames = frames.with_hierarchy(Arc::clone(hierarchy));
        }
        *slot = Some((generation, frames, model.streamed.clone()));
    }
    let (_, frames, _) = slot.as_mut().expect("filled above");
    if let Some(grouped) = request.grouping.as_ref().filter(|g| g.generation == generation && request.preview.is_none())
    {
        frames.add_grouping(SceneGrouping {
            spec: grouped.spec,
            grouping: Arc::clone(&grouped.grouping),
            seconds: grouped.seconds,
            cached: grouped.cached,
        });
    }
    frames
}

/// A moving scene at time `t`: made at that time for a new model, else moved
/// on to it ([`PreparedScene::advance`]: regrouped and rewritten, with the costs in `stats`).
fn moving_frames<'a>(
    r: &GpuRenderer,
    scenes: &'a mut Scenes,
    request: &FrameRequest,
    t: f64,
    stats: &mut FrameStats,
) -> Result<&'a mut PreparedScene, String> {
    let model = &request.model;
    let fresh = scenes.full.as_ref().is_none_or(|(g, ..)| *g != model.generation);
    if fresh || scenes.time != Some(t) {
        let at = model.scene.at_time(t)?;
        let scene = Arc::new(at.scene);
        let cloud = scene.flattened();
        if fresh {
            scenes.full = None; // free the old copies first
            let lattice = crate::render::rest_lattice(&model.scene)?;
            let frames = PreparedScene::new(scene, cloud).moving_on(lattice).with_cache(scenes.cache.clone());
            scenes.full = Some((model.generation, frames, None));
        } else if let Some((_, frames, _)) = scenes.full.as_mut() {
            let update = frames.advance(Some(r), scene, cloud).map_err(|e| e.to_string())?;
            (stats.regroup_ms, stats.upload_ms, stats.regrouped) =
                (Some(update.regroup_ms), Some(update.upload_ms), Some(update.regrouped));
        }
        scenes.time = Some(t);
    }
    Ok(&mut scenes.full.as_mut().expect("filled above").1)
}

fn pass_times(r: &GpuRenderer, plan: &RenderPlan) -> Vec<(String, f64)> {
    match r.renderer.pass_times(&r.ctx, plan) {
        Ok(Some(times)) => plan.steps.iter().zip(times).map(|(p, ms)| (p.name.to_string(), ms)).collect(),
        Ok(None) => Vec::new(),
        Err(e) => {
            log::warn!("pass timing: {e}");
            Vec::new()
        }
    }
}

fn describe_plan(stats: &mut FrameStats, plan: &RenderPlan) {
    stats.plan = Some(plan.to_string());
    // Targets, and the buffers of a mode that computes (the tile pipeline's).
    stats.plan_bytes = plan.target_bytes() + plan.buffer_bytes();
    stats.geometry_passes = plan.geometry_passes();
}
