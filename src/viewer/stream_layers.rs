//! Streamed layers in the viewer: a `.vpc` whose files all stream (COPC
//! files or URLs; the shown layers' own `.vpc`, or one opened) is one
//! [`StreamedSource`] of several streams selected as one forest under the
//! view's one point budget ([`crate::copc::layered::LayeredStreams`], what
//! `render A B` streams them with): the file with the largest projected
//! spacing is refined first, whichever it is, each file's node cache gets
//! an equal share, and the seams where two files meet are estimated
//! again. A view is loaded whole in one step (no coarse steps first, as a
//! single file has), and the statistics give each file's share.

use std::path::Path;
use std::sync::Mutex;

use glam::DVec3;

use super::stream_source::{StreamStatus, StreamedSource, Streams, ViewKey};
use crate::cloud::{LoadOptions, PointCloud};
use crate::copc::layered::LayeredStreams;
use crate::copc::{StreamBudget, StreamOptions, StreamStats};
use crate::scene::Scene;

/// Whether `path` is a `.vpc` whose files all stream, so that the window draws them node by node as layers.
pub fn streams_layers(path: &Path) -> bool {
    crate::scene::vpc::is_vpc(path)
        && crate::scene::vpc::read(path)
            .is_ok_and(|files| files.len() > 1 && files.iter().all(|f| crate::copc::is_streamed(&f.path)))
}

impl StreamedSource {
    /// The files of the `.vpc` at `path` as layers under one budget, in one CRS.
    pub(super) fn open_layers(path: &Path, options: StreamOptions) -> Result<std::sync::Arc<Self>, String> {
        let files = crate::scene::vpc::read(path).map_err(|e| e.to_string())?;
        let paths: Vec<&Path> = files.iter().map(|f| f.path.as_path()).collect();
        let mut crs = crate::scene::layers::SharedCrs::default();
        let load = (StreamBudget::Default, LoadOptions::default());
        let layers = LayeredStreams::open(&paths, options, load, &mut crs).map_err(|e| e.to_string())?;
        let bounds = bounds_of(&layers);
        let status = Mutex::new(StreamStatus::default());
        Ok(std::sync::Arc::new(Self { streams: Mutex::new(Streams::Layers(layers)), status, bounds }))
    }

    /// Whether the source streams several files.
    pub(super) fn is_layered(&self) -> bool {
        self.streams.lock().is_ok_and(|s| matches!(*s, Streams::Layers(_)))
    }

    /// The scene of the nodes `view` selects of every file, under its one
    /// budget (one object per file with points in view), and its warnings.
    pub(super) fn layers_scene(&self, view: ViewKey) -> Result<(Scene, Vec<String>), String> {
        crate::progress::stage("selecting and loading the layers' nodes");
        let mut streams = self.streams.lock().map_err(|_| "the streams were poisoned".to_string())?;
        let Streams::Layers(layers) = &mut *streams else { return Err("the source streams one file".into()) };
        let before = total_stats(layers);
        layers.set_budget(view.budget);
        let (scene, drawn) = layers.scene(&view.camera, view.size, view.choosing).map_err(|e| e.to_string())?;
        if drawn == 0 {
            return Err("no file of the layers has a node in view".into());
        }
        let after = total_stats(layers);
        let (read, seconds) = (after.bytes_read - before.bytes_read, after.load_seconds - before.load_seconds);
        let mut status = self.status.lock().map_err(|_| "the stream was poisoned".to_string())?;
        let cache = layers
            .layers
            .iter()
            .map(|l| l.stream.cache_usage())
            .fold((0, 0, 0), |a, c| (a.0 + c.0, a.1 + c.1, a.2 + c.2));
        *status = StreamStatus {
            nodes_shown: layers.layers.iter().map(|l| l.last.drawn).sum(),
            points_shown: drawn,
            nodes_known: layers.layers.iter().map(|l| l.stream.tree.nodes.len()).sum(),
            points_in_file: layers.layers.iter().map(|l| l.stream.points()).sum(),
            stats: after,
            cache,
            mb_per_s: if read > 0 && seconds > 0.0 { Some(read as f64 / 1e6 / seconds) } else { status.mb_per_s },
            view: Some(view),
            layers: layers
                .layers
                .iter()
                .map(|l| (l.stream.file_name().to_string(), l.last.points, l.last.drawn))
                .collect(),
        };
        let warnings = layers.layers.iter().flat_map(|l| l.last.warnings.clone()).collect();
        Ok((scene, warnings))
    }
}

/// What streaming every file has cost so far, summed.
fn total_stats(layers: &LayeredStreams) -> StreamStats {
    layers.layers.iter().map(|l| l.stream.stats()).fold(StreamStats::default(), |a, s| StreamStats {
        nodes_loaded: a.nodes_loaded + s.nodes_loaded,
        points_loaded: a.points_loaded + s.points_loaded,
        bytes_read: a.bytes_read + s.bytes_read,
        requests: a.requests + s.requests,
        failed: a.failed + s.failed,
        load_seconds: a.load_seconds + s.load_seconds,
        points_estimated: a.points_estimated + s.points_estimated,
        estimate_seconds: a.estimate_seconds + s.estimate_seconds,
        points_labelled: a.points_labelled + s.points_labelled,
        label_seconds: a.label_seconds + s.label_seconds,
    })
}

/// Every file's box corners, in the first file's frame (the camera's).
fn bounds_of(layers: &LayeredStreams) -> PointCloud {
    let origin = layers.origin();
    let mut corners = Vec::new();
    for layer in &layers.layers {
        let b = layer.stream.bounds_cloud();
        let o = DVec3::from_array(b.origin);
        corners.extend(b.positions.iter().map(|p| (p.as_dvec3() + o - origin).as_vec3()));
    }
    let first = layers.layers.first().map(|l| l.stream.bounds_cloud()).unwrap_or_default();
    PointCloud { origin: origin.to_array(), z_up: first.z_up, ..PointCloud::facing_z(corners, 0.0, [0; 3]) }
}
