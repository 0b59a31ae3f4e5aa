//! The flags of streamed files (COPC, from disk or over HTTP), shared by
//! `render` and `bench`, and the scene of one streamed frame.

use std::path::{Path, PathBuf};

use anyhow::Result;
use pointblend::cloud::LoadOptions;
use pointblend::copc::is_streamed;
use pointblend::copc::subset::StreamSubset;
use pointblend::copc::{self, CopcStream, StreamBudget, StreamOptions};
use pointblend::frame::Camera;
use pointblend::frame::subset::Subset;
use pointblend::lod::Choosing;
use pointblend::scene::Scene;

#[derive(clap::Args, Debug, Clone, Default)]
pub struct StreamArgs {
    /// Files drawn node by node (.copc.laz, an http(s) URL, or a point file
    /// under --point-budget N): decoded nodes kept in memory, in MB
    /// [default: a quarter of the free memory].
    #[arg(long, value_name = "MB")]
    pub cache_mb: Option<u64>,
    /// COPC files: keep the chunks fetched in this folder and read them from
    /// there next time (nothing is written to disk without it).
    #[arg(long, value_name = "DIR")]
    pub disk_cache: Option<PathBuf>,
}

impl StreamArgs {
    pub fn options(&self, progress: bool) -> StreamOptions {
        StreamOptions {
            cache_bytes: self.cache_mb.map_or_else(copc::stream::default_cache_bytes, |mb| (mb as usize) << 20),
            disk_cache: self.disk_cache.clone(),
            progress,
            ..Default::default()
        }
    }

    /// Opens `file` node by node when `by_nodes` says it is drawn so
    /// ([`copc::drawn_by_nodes`], or a screenshot's record of the window).
    pub fn open(&self, file: &Path, by_nodes: bool) -> Result<Option<CopcStream>> {
        if !by_nodes {
            if self.cache_mb.is_some() || self.disk_cache.is_some() {
                log::warn!(
                    "--cache-mb and --disk-cache apply to files drawn node by node (.copc.laz, a URL, or a point file under --point-budget N below its points) only"
                );
            }
            return Ok(None);
        }
        if self.disk_cache.is_some() && !is_streamed(file) {
            log::warn!(
                "--disk-cache applies to streamed files (.copc.laz or a URL); {} is held in memory",
                file.display()
            );
        }
        let stream = copc::open_nodes(file, self.options(true))?;
        let how = if is_streamed(file) { "COPC" } else { "held in memory as an octree" };
        log::info!(
            "{}: {how}, {} points in {} nodes known, drawn node by node under the point budget",
            stream.name(),
            stream.points(),
            stream.tree.nodes.len()
        );
        Ok(Some(stream))
    }
}

/// A scene standing for a streamed file before anything is loaded: the
/// corners of its header's bounds (what the default views frame).
pub fn bounds_scene(stream: &CopcStream) -> Scene {
    Scene::single(stream.file_name(), stream.bounds_cloud(), 0)
}

/// What the default view of a streamed file frames: with `--classes`,
/// `--filter` or `--returns`, the points of its root node (a sample of the
/// whole file) that they keep, in the frame of [`bounds_scene`]; else, or
/// when the root cannot be read or keeps nothing, its bounds.
pub fn framing_scene(stream: &mut CopcStream, flags: &super::scene_args::SceneArgs) -> Scene {
    let bounds = bounds_scene(stream);
    if flags.classes.is_empty() && flags.filters.is_empty() && flags.returns.is_none() {
        return bounds;
    }
    let Ok(records) = stream.root_records() else { return bounds };
    let classes = (!flags.classes.is_empty()).then_some(flags.classes.as_slice());
    let kept =
        pointblend::style::filter::kept_of(&records.attributes, records.len(), classes, &flags.filters, flags.returns);
    let Some(kept) = kept.ok().filter(|k| !k.is_empty()) else { return bounds };
    let frame = &bounds.objects[0].cloud;
    let origin = glam::DVec3::from_array(frame.origin);
    let positions = kept.iter().map(|&i| (records.positions[i as usize] - origin).as_vec3()).collect();
    let cloud = pointblend::cloud::PointCloud {
        origin: frame.origin,
        z_up: frame.z_up,
        ..pointblend::cloud::PointCloud::facing_z(positions, 0.0, [0; 3])
    };
    Scene::single(stream.file_name(), cloud, 0)
}

/// The scene of the nodes `stream` selects from `camera` at `size` under
/// `budget`, chosen as the frame's settings say (`choosing`), loaded as
/// needed: the stream's frame as a [`Subset`], as bench and the viewer
/// choose theirs. Returns the stream too, to choose the next frame's.
pub fn frame_scene(
    stream: CopcStream,
    camera: &Camera,
    size: (u32, u32),
    (budget, choosing): (StreamBudget, Choosing),
) -> Result<(Scene, StreamSubset)> {
    let mut subset = StreamSubset::new(stream, budget, LoadOptions { progress: true, ..Default::default() });
    let scene = chosen_scene(&mut subset, camera, size, choosing)?.unwrap_or_default();
    Ok((scene.coloured_by_default(), subset))
}

/// The scene of the nodes `subset` chooses for `camera` (`None`: the same
/// nodes as its last choice), with what it read in the log.
fn chosen_scene(
    subset: &mut StreamSubset,
    camera: &Camera,
    size: (u32, u32),
    choosing: Choosing,
) -> Result<Option<Scene>> {
    let choice = subset.choose(camera, size, choosing)?;
    let (stream, last) = (&subset.stream, &subset.last);
    for warning in &last.warnings {
        log::warn!("{}: {warning}", stream.name());
    }
    let stats = stream.stats();
    let (used, nodes, bound) = stream.cache_usage();
    log::info!(
        "{}: {} points of {} nodes drawn ({} selected); {:.1} MB read in {} requests; cache {:.0} of {:.0} MB ({nodes} nodes){}",
        stream.name(),
        last.points,
        last.drawn,
        last.selected,
        stats.bytes_read as f64 / 1e6,
        stats.requests,
        used as f64 / 1e6,
        bound as f64 / 1e6,
        if stats.failed > 0 { format!("; {} nodes failed and were skipped", stats.failed) } else { String::new() }
    );
    let Some(cloud) = choice.cloud else { return Ok(None) };
    // The scene's key names the nodes drawn, so caches keyed by it are not mixed up.
    let scene = Scene::single(stream.file_name(), cloud, choice.key);
    Ok(Some(scene.with_node_grouping(choice.grouping).with_node_spans(choice.spans)))
}

/// A flight through a streamed file (`render --path`): each camera selects
/// its own nodes, styled as the first selection was (its colours by
/// attribute, their range fixed), with the command's materials.
pub struct StreamedFlight {
    pub subset: StreamSubset,
    pub choosing: Choosing,
    pub size: (u32, u32),
    pub materials: pointblend::scene::Materials,
}

impl StreamedFlight {
    /// The scene of the nodes `camera` selects, when they are not the last
    /// ones drawn; `first` is the first selection's scene (its style pinned).
    pub fn next_scene(&mut self, camera: &Camera, first: &Scene) -> Result<Option<Scene>> {
        let Some(mut scene) = chosen_scene(&mut self.subset, camera, self.size, self.choosing)? else {
            return Ok(None);
        };
        let style = first.pinned_style().map(std::sync::Arc::new).or(self.materials.style.clone());
        let materials = pointblend::scene::Materials { style, ..self.materials.clone() };
        materials.apply(&mut scene).map_err(anyhow::Error::msg)?;
        Ok(Some(scene))
    }
}
