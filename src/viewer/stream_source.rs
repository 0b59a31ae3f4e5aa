//! A streamed file (COPC, from disk or a URL) as the viewer holds it: the
//! stream, and what the statistics show of it ([`super::streaming`] makes
//! models of its selections). When the camera rests (or the window or the
//! point budget changes), a background job selects the nodes of the new
//! view under the budget (1M by default) and loads what the cache lacks,
//! with at most four requests in flight, in steps, coarse first: each step
//! loads at most as many points as are drawn (65,536 to 262,144), and the
//! window shows the nodes loaded so far after the first step, then no more
//! often than it draws a frame, a node still loading drawn by its loaded
//! ancestors. Until the first step arrives the current selection stays on
//! screen, so nothing blinks, and each step shown uploads only the nodes it
//! adds (the GPU pool of `PreparedScene::show_selection`), at most
//! [`SHOWN_AT_MOST`] points: nodes loaded while the window drew its last
//! frame beyond those wait for the next ones, so one frame's upload is
//! bounded (524,288 points are 18.9 MB of records per GPU copy). The
//! job's progress bar is the "refining" bar, and the statistics show what
//! is shown, what was read, how fast, and the cache. A `.vpc` of streamed
//! files (the layers' own, or one opened) is one source of several streams
//! under one budget (`stream_layers.rs`).

use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use crate::cloud::LoadOptions;
use crate::copc::Left;
use crate::copc::subset::StreamSubset;
use crate::copc::{StreamBudget, StreamOptions, StreamStats};
use crate::frame::{Camera, CameraRequest};
use crate::scene::Scene;

/// What a selection is made for: the camera, the view's size, the budget
/// and how the frame's settings choose splats (as an in-memory budget does).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViewKey {
    pub camera: Camera,
    pub size: (u32, u32),
    pub budget: StreamBudget,
    pub choosing: crate::lod::Choosing,
}

/// What shows a step of a view still refining: its scene and load warnings.
pub type ShowStep<'a> = dyn FnMut(Scene, Vec<String>) -> Result<(), String> + 'a;

/// A scene to show, and its load warnings.
type Shown = (Scene, Vec<String>);

/// What the statistics show.
#[derive(Debug, Clone, Default)]
pub struct StreamStatus {
    pub nodes_shown: usize,
    pub points_shown: usize,
    pub nodes_known: usize,
    pub points_in_file: u64,
    pub stats: StreamStats,
    /// Bytes, nodes and bound of the node cache.
    pub cache: (usize, usize, usize),
    /// Megabytes per second of the last load that read anything.
    pub mb_per_s: Option<f64>,
    /// The view the last selection was made for.
    pub view: Option<ViewKey>,
    /// Streamed layers: each file's name, and the points and nodes of it drawn.
    pub layers: Vec<(String, usize, usize)>,
}

/// What a source streams: one file, or several as layers under one budget.
pub(super) enum Streams {
    One(Box<StreamSubset>),
    Layers(crate::copc::layered::LayeredStreams),
}

/// A streamed file, shared by the models of its selections.
pub struct StreamedSource {
    /// The stream, whose frames are chosen as a [`Subset`] (as `render` and bench choose theirs).
    pub(super) streams: Mutex<Streams>,
    pub(super) status: Mutex<StreamStatus>,
    /// The file's bounds ([`crate::copc::CopcStream::bounds_cloud`]; the
    /// layers' together), kept so that the window frames the file without
    /// waiting for a loading step's lock.
    pub(super) bounds: crate::cloud::PointCloud,
}

impl std::fmt::Debug for StreamedSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StreamedSource").finish_non_exhaustive()
    }
}

impl StreamedSource {
    pub fn open(path: &Path, options: StreamOptions) -> Result<Arc<Self>, String> {
        if crate::scene::vpc::is_vpc(path) {
            return Self::open_layers(path, options);
        }
        let stream = crate::copc::open_nodes(path, options).map_err(|e| e.to_string())?;
        let bounds = stream.bounds_cloud();
        let subset = StreamSubset::new(stream, StreamBudget::Default, LoadOptions::default());
        let status = Mutex::new(StreamStatus::default());
        Ok(Arc::new(Self { streams: Mutex::new(Streams::One(Box::new(subset))), status, bounds }))
    }

    pub fn status(&self) -> StreamStatus {
        self.status.lock().map(|s| s.clone()).unwrap_or_default()
    }

    /// The camera `asked` makes of the file's bounds (its header's) at `aspect`:
    /// with nothing asked, the default view framing them.
    pub fn home_camera(&self, asked: &CameraRequest, aspect: f32) -> Camera {
        asked.camera(&self.bounds, aspect).unwrap_or_else(|_| Camera::default_for(&self.bounds, aspect))
    }

    /// The scene of the nodes `view` selects (named `name`), and its load
    /// warnings; `None` when they are the nodes the last scene drew.
    ///
    /// The view is loaded in steps, coarse first, each loading at most as
    /// many points as are drawn (from [`FIRST_STEP`] to [`LARGEST_STEP`]),
    /// and each scene shown adds at most [`SHOWN_AT_MOST`] to the last one.
    /// `interim` is given the scene of the nodes loaded so far after the
    /// first step, then again each time `pace` has passed since it last was
    /// (the window passes its frame time, so steps come no faster than it
    /// draws them), while more nodes remain to load than the next step
    /// loads; a node still loading is drawn by its loaded ancestors.
    pub fn scene(
        &self,
        name: String,
        view: ViewKey,
        (interim, pace): (&mut ShowStep<'_>, &dyn Fn() -> Duration),
    ) -> Result<Option<Shown>, String> {
        if self.is_layered() {
            return self.layers_scene(view).map(Some);
        }
        let started = Instant::now();
        crate::progress::stage("selecting and loading nodes");
        let mut shown: Option<Instant> = None;
        // Nodes loaded that the last scene shown held back (the bound on one frame's upload).
        let mut held_back = 0;
        loop {
            // A cancelled job (another view or file asked for) stops between steps; its result is dropped.
            if crate::progress::cancelled() {
                return Err(format!("{name}: refining cancelled"));
            }
            let (left, step) = self.load_step(view)?;
            // Not shown: a step before the pace has passed, or one the next step completes.
            let wait = shown.map_or(Duration::ZERO, |at| pace().saturating_sub(at.elapsed()));
            if left.nodes > 0 && (!wait.is_zero() || left.points <= step) {
                continue;
            }
            // Everything loaded, some of it held back: shown at the window's pace.
            if held_back > 0 && !wait.is_zero() {
                std::thread::sleep(wait);
                continue;
            }
            let scene;
            (scene, held_back) = self.gather(&name, view, left.nodes, SHOWN_AT_MOST)?;
            if left.nodes == 0 && held_back == 0 {
                log::info!("{name}: view complete in {:.2} s", started.elapsed().as_secs_f64());
                return Ok(scene);
            }
            if let Some((scene, warnings)) = scene {
                interim(scene, warnings)?;
                shown = Some(Instant::now());
            }
        }
    }

    /// `work` on the one file's stream, under the source's lock.
    fn with_subset<R>(&self, work: impl FnOnce(&mut StreamSubset) -> Result<R, String>) -> Result<R, String> {
        let mut streams = self.streams.lock().map_err(|_| "the stream was poisoned".to_string())?;
        match &mut *streams {
            Streams::One(subset) => work(subset),
            Streams::Layers(_) => Err("the source streams layers".to_string()),
        }
    }

    /// One loading step of [`Self::scene`]; returns what remains to load,
    /// and the points the next step loads.
    fn load_step(&self, view: ViewKey) -> Result<(Left, u64), String> {
        self.with_subset(|subset| {
            let before = subset.stream.stats();
            subset.budget = view.budget;
            let step = (subset.last.points as u64).clamp(FIRST_STEP, LARGEST_STEP);
            let left = subset.load_step(&view.camera, view.size, view.choosing, step).map_err(|e| e.to_string())?;
            self.record(subset, view, before)?;
            Ok((left, step))
        })
    }

    /// The scene of the nodes of `view` loaded so far, adding at most
    /// `adding` points to what the last scene drew (`None`: the nodes the
    /// last one drew), `left` nodes short of the view; and the nodes loaded
    /// but held back by that bound.
    fn gather(&self, name: &str, view: ViewKey, left: usize, adding: u64) -> Result<(Option<Shown>, usize), String> {
        self.with_subset(|subset| {
            let before = subset.stream.stats();
            let choice =
                subset.choose_loaded(&view.camera, view.size, view.choosing, adding).map_err(|e| e.to_string())?;
            self.record(subset, view, before)?;
            let last = &subset.last;
            log::info!(
                "{}: {} points of {} nodes, {left} nodes left to load",
                subset.stream.name(),
                last.points,
                last.drawn
            );
            let (grouping, spans) = (choice.grouping, choice.spans);
            let scene = choice.cloud.map(|cloud| {
                let scene = Scene::single(name.to_string(), cloud, choice.key)
                    .with_node_grouping(grouping)
                    .with_node_spans(spans);
                (scene, last.warnings.clone())
            });
            Ok((scene, last.held_back))
        })
    }

    /// What the statistics show after a step that began at `before`.
    fn record(&self, subset: &StreamSubset, view: ViewKey, before: StreamStats) -> Result<(), String> {
        let (stream, last) = (&subset.stream, &subset.last);
        let after = stream.stats();
        let seconds = after.load_seconds - before.load_seconds;
        let read = after.bytes_read - before.bytes_read;
        let mut status = self.status.lock().map_err(|_| "the stream was poisoned".to_string())?;
        *status = StreamStatus {
            nodes_shown: last.drawn,
            points_shown: last.points,
            nodes_known: stream.tree.nodes.len(),
            points_in_file: stream.points(),
            stats: after,
            cache: stream.cache_usage(),
            mb_per_s: if read > 0 && seconds > 0.0 { Some(read as f64 / 1e6 / seconds) } else { status.mb_per_s },
            view: Some(view),
            layers: Vec::new(),
        };
        Ok(())
    }
}

/// The points a view's first loading step loads at most (more when more
/// are drawn already), and the most any step loads: 262,144 points are
/// 9.4 MB of GPU records.
pub const FIRST_STEP: u64 = 65_536;
pub const LARGEST_STEP: u64 = 262_144;
/// The most points a scene shown adds to the last one: two of the largest
/// steps, 18.9 MB of records per GPU copy. One step held back 3-4 s of a
/// 1M-point view on lavapipe, where every frame shown takes a second or
/// more (docs/BENCHMARKS.md).
pub const SHOWN_AT_MOST: u64 = 2 * LARGEST_STEP;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::subset::Choosing;
    use glam::Vec3;

    /// A COPC file of two 360,000-splat planes 4 units apart, each point
    /// moved off its plane and coloured at random as a scan's are (a
    /// perfect grid of one colour compresses beyond what a chunk is taken
    /// to hold), made by `convert`'s writer.
    fn two_planes(dir: &Path) -> std::path::PathBuf {
        let mut cloud = crate::scene::primitives::plane(360_000, 150.0, Vec3::ZERO, Vec3::Z);
        let upper = crate::scene::primitives::plane(360_000, 150.0, Vec3::new(0.0, 0.0, 4.0), Vec3::Z);
        cloud.positions.extend(upper.positions);
        cloud.normals.extend(upper.normals);
        cloud.radii.extend(upper.radii);
        cloud.colours.extend(upper.colours);
        cloud.opacity.extend(upper.opacity);
        let mut seed = 5u64;
        let mut random = move || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 40) as u32
        };
        for (p, c) in cloud.positions.iter_mut().zip(&mut cloud.colours) {
            p.z += (random() % 100) as f32 * 1e-3;
            *c = [random() as u8, random() as u8, random() as u8];
        }
        let las = dir.join("planes.las");
        crate::cloud::write_las::write_las(&cloud, &las).unwrap();
        let copc = dir.join("planes.copc.laz");
        crate::copc::write::write_copc(&las, &copc, false).unwrap();
        copc
    }

    /// A refining job cancelled while it shows its first step loads no
    /// further step: it ends with an error (which the window drops), having
    /// loaded fewer nodes than the view needs, which the same view asked
    /// again then loads.
    #[test]
    fn a_refining_job_cancelled_at_its_first_step_loads_no_more() {
        let dir = tempfile::tempdir().unwrap();
        let source = StreamedSource::open(&two_planes(dir.path()), StreamOptions::default()).unwrap();
        let camera = source.home_camera(&CameraRequest::default(), 1.0);
        let budget = StreamBudget::Points(1_000_000);
        let view = ViewKey { camera, size: (1024, 1024), budget, choosing: Choosing::default() };
        let tracker = crate::progress::Tracker::new();
        let mut steps = 0;
        let mut show = |_: Scene, _: Vec<String>| {
            steps += 1;
            tracker.cancel();
            Ok(())
        };
        let cancelled = crate::progress::track(Arc::clone(&tracker), || {
            source.scene("planes".into(), view, (&mut show, &|| Duration::ZERO))
        });
        assert!(cancelled.is_err_and(|e| e.contains("cancelled")), "the job ends as cancelled");
        assert_eq!(steps, 1, "no step after the cancel is shown");
        let at_cancel = source.status().stats.nodes_loaded;
        let mut later = 0;
        let mut show_later = |_: Scene, _: Vec<String>| {
            later += 1;
            Ok(())
        };
        let whole = source.scene("planes".into(), view, (&mut show_later, &|| Duration::ZERO)).unwrap();
        assert!(whole.is_some(), "asked again, the view is drawn whole");
        let needed = source.status().stats.nodes_loaded;
        println!("cancelled at {at_cancel} nodes loaded; the view needs {needed} ({later} more steps shown)");
        assert!(at_cancel < needed, "the cancelled job loaded {at_cancel} of the view's {needed} nodes");
    }
}
