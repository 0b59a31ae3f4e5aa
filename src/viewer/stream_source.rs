//! A streamed file (COPC, from disk or a URL) as the viewer holds it: the
//! stream, and what the statistics show of it ([`super::streaming`] makes
//! models of its selections). The model on
//! screen is the selection of the last settled view. When the camera rests
//! (or the window or the point budget changes), a background job selects
//! the nodes of the new view under the budget (1M by default), loads what
//! the cache lacks with at most four requests in flight, and builds them
//! into the next model; until it arrives the current selection stays on
//! screen, so nothing blinks: a region whose nodes are still loading is
//! drawn by the nodes already there (its loaded ancestors). The job's
//! progress bar is the "refining" bar, and the statistics show what is
//! shown, what was read, how fast, and the cache.

use std::path::Path;
use std::sync::{Arc, Mutex};
use std::time::Instant;

use crate::cloud::LoadOptions;
use crate::copc::subset::StreamSubset;
use crate::copc::{CopcStream, StreamBudget, StreamOptions, StreamStats};
use crate::frame::subset::Subset;
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
}

/// A streamed file, shared by the models of its selections.
pub struct StreamedSource {
    /// The stream, whose frames are chosen as a [`Subset`] (as `render` and bench choose theirs).
    subset: Mutex<StreamSubset>,
    status: Mutex<StreamStatus>,
}

impl std::fmt::Debug for StreamedSource {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("StreamedSource").finish_non_exhaustive()
    }
}

impl StreamedSource {
    pub fn open(path: &Path, options: StreamOptions) -> Result<Arc<Self>, String> {
        let stream = CopcStream::open(&path.to_string_lossy(), options).map_err(|e| e.to_string())?;
        let subset = StreamSubset::new(stream, StreamBudget::Default, LoadOptions::default());
        Ok(Arc::new(Self { subset: Mutex::new(subset), status: Mutex::new(StreamStatus::default()) }))
    }

    pub fn status(&self) -> StreamStatus {
        self.status.lock().map(|s| s.clone()).unwrap_or_default()
    }

    /// The camera `asked` makes of the file's bounds (its header's) at `aspect`:
    /// with nothing asked, the default view framing them.
    pub fn home_camera(&self, asked: &CameraRequest, aspect: f32) -> Camera {
        let subset = self.subset.lock().expect("no panics while held");
        let bounds = subset.stream.bounds_cloud();
        asked.camera(&bounds, aspect).unwrap_or_else(|_| Camera::default_for(&bounds, aspect))
    }

    /// The scene of the nodes `view` selects (named `name`), and its load
    /// warnings; `None` when they are the nodes the last scene drew.
    pub fn scene(&self, name: String, view: ViewKey) -> Result<Option<(Scene, Vec<String>)>, String> {
        let mut subset = self.subset.lock().map_err(|_| "the stream was poisoned".to_string())?;
        let before = subset.stream.stats();
        let started = Instant::now();
        crate::progress::stage("selecting and loading nodes");
        subset.budget = view.budget;
        let choice = subset.choose(&view.camera, view.size, view.choosing).map_err(|e| e.to_string())?;
        let (stream, last) = (&subset.stream, &subset.last);
        let after = stream.stats();
        let seconds = after.load_seconds - before.load_seconds;
        let read = after.bytes_read - before.bytes_read;
        {
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
            };
        }
        log::info!(
            "{}: {} points of {} nodes in {:.2} s",
            stream.name(),
            last.points,
            last.drawn,
            started.elapsed().as_secs_f64()
        );
        let (grouping, spans) = (choice.grouping, choice.spans);
        Ok(choice.cloud.map(|cloud| {
            let scene = Scene::single(name, cloud, choice.key).with_node_grouping(grouping).with_node_spans(spans);
            (scene, last.warnings.clone())
        }))
    }
}
