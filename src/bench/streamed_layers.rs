//! Benchmarks of layers drawn node by node: a `.vpc` (or `bench A B
//! --together`, which lists its files in one) that holds COPC files or
//! URLs. Each view selects the streamed files' nodes under one point budget
//! ([`crate::copc::layered`]: their octrees chosen as one), the files held
//! whole are drawn whole beside them, and every mode and the reference draw
//! that one scene. Each view prints what it read. Unlike one streamed
//! file's ([`super::streamed`]), a view's scene is uploaded whole and its
//! grouped modes group it whole: its nodes carry no groups or GPU slots of
//! their own across files.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use super::measure::{Opened, measure_views, prepare_variants};
use super::report::{BenchRow, ViewCosts};
use super::views::{NamedView, views_of};
use super::{BenchConfig, BenchError};
use crate::cloud::LoadOptions;
use crate::copc::is_streamed;
use crate::copc::layered::LayeredStreams;
use crate::frame::subset::Choosing;
use crate::render::{GpuRenderer, PreparedScene};
use crate::scene::Scene;
use crate::scene::layers::{self, SharedCrs};

/// Whether `model` is a `.vpc` that lists a streamed file.
pub(super) fn is_streamed_layers(model: &Path) -> bool {
    crate::scene::vpc::is_vpc(model)
        && crate::scene::vpc::read(model).is_ok_and(|files| files.iter().any(|f| is_streamed(&f.path)))
}

fn invalid(e: impl std::fmt::Display) -> BenchError {
    BenchError::Invalid(e.to_string())
}

/// The `.vpc`'s files held whole, as one scene, and its streamed files
/// opened, all in one CRS; each stream's node cache a share of the run's.
fn open_files(model: &Path, config: &BenchConfig) -> Result<(Scene, LayeredStreams), BenchError> {
    let files = layers::layer_files(&[model.to_path_buf()]).map_err(invalid)?;
    let (streamed, whole): (Vec<PathBuf>, Vec<PathBuf>) =
        files.into_iter().map(|f| f.path).partition(|p| is_streamed(p));
    let mut crs = SharedCrs::default();
    let whole = match whole.is_empty() {
        true => Scene::default(),
        false => {
            let paths: Vec<&Path> = whole.iter().map(PathBuf::as_path).collect();
            let load = LoadOptions { progress: config.progress, ..Default::default() };
            let (scene, warnings) = layers::open_layers_sharing(&paths, &load, &mut crs).map_err(invalid)?;
            warnings.iter().for_each(|w| log::warn!("{w}"));
            scene
        }
    };
    let paths: Vec<&Path> = streamed.iter().map(PathBuf::as_path).collect();
    let load = LoadOptions { progress: config.progress, ..Default::default() };
    let streams = LayeredStreams::open(&paths, config.stream.clone(), (config.stream_budget, load), &mut crs);
    Ok((whole, streams.map_err(invalid)?))
}

/// Every view and variant of a `.vpc` of streamed layers.
pub(super) fn bench_streamed_layers(
    model: &Path,
    config: &BenchConfig,
    renderer: &mut GpuRenderer,
) -> Result<Vec<BenchRow>, BenchError> {
    let opened_at = Instant::now();
    let (whole, mut layered) = open_files(model, config)?;
    let open_s = opened_at.elapsed().as_secs_f64();
    // The views frame the files held whole and the streamed files' bounds.
    let mut framing = whole.clone();
    for stream in layered.layers.iter().map(|l| &l.stream) {
        framing.objects.extend(Scene::single(stream.file_name(), stream.bounds_cloud(), 0).objects);
    }
    let views = views_of(config, &framing.flatten().cloud);
    let from = framing.frame_placement();
    let choosing = Choosing { groups: None, ..Choosing::of(&config.settings) };
    let name = model.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = crate::output::safe_stem(model);
    let mut rows = Vec::new();
    let mut pinned: Option<Arc<crate::style::Style>> = None;
    for (view_index, view) in views.iter().enumerate() {
        let before = totals(&layered);
        let started = Instant::now();
        let in_streams = layers::camera_in_frame(&view.camera, from, (layered.origin(), 1.0));
        let (streamed, _) = layered.scene(&in_streams, (config.width, config.height), choosing).map_err(invalid)?;
        let mut scene = whole.clone();
        scene.objects.extend(streamed.objects);
        if scene.objects.is_empty() {
            return Err(invalid(format!("{name}: no point of the layers is in the {} view", view.name)));
        }
        let stream_s = started.elapsed().as_secs_f64();
        let after = totals(&layered);
        println!(
            "{name} {} view: {} points of {} files, {} nodes new, {:.1} MB read, {stream_s:.2} s to select, load and build",
            view.name,
            scene.len(),
            scene.objects.len(),
            after.0 - before.0,
            (after.1 - before.1) as f64 / 1e6
        );
        let styled_at = Instant::now();
        let opened = super::streamed::set_up_pinned(scene, &name, (config, open_s + stream_s), &mut pinned)?;
        let mut costs = ViewCosts {
            view_index,
            nodes_added: after.0 - before.0,
            bytes_read: after.1 - before.1,
            points_prepared: after.2 - before.2,
            prepare_s: stream_s + styled_at.elapsed().as_secs_f64(),
            ..Default::default()
        };
        let mut frames = PreparedScene::of(Arc::clone(&opened.scene)).streamed();
        let prepared = prepare_variants(config, &opened, &mut frames, renderer)?;
        costs.prepare_s += prepared.iter().filter_map(|p| p.group_s).sum::<f64>();
        costs.upload_bytes = frames.uploaded_bytes();
        rows.extend(measure_view(
            (&name, &stem),
            (&opened, &mut frames, &prepared),
            view,
            from,
            config,
            renderer,
            costs,
        )?);
    }
    Ok(rows)
}

/// The rows of one view, its camera moved from the frame the views were
/// framed in (`from`) to the scene's; with the view's costs on a path.
fn measure_view(
    names: (&str, &str),
    (opened, frames, prepared): (&Opened, &mut PreparedScene, &[super::measure::Prepared]),
    view: &NamedView,
    from: (glam::DVec3, f64),
    config: &BenchConfig,
    renderer: &mut GpuRenderer,
    costs: ViewCosts,
) -> Result<Vec<BenchRow>, BenchError> {
    let camera = layers::camera_in_frame(&view.camera, from, opened.scene.frame_placement());
    let one = [NamedView { camera, ..view.clone() }];
    let mut rows = measure_views(names, opened, frames, prepared, &one, config, renderer)?;
    if config.path.is_some() {
        rows.iter_mut().for_each(|row| row.path = Some(costs));
    }
    Ok(rows)
}

/// Nodes loaded, bytes read and points loaded by all the layers so far.
fn totals(layered: &LayeredStreams) -> (usize, u64, u64) {
    layered
        .layers
        .iter()
        .map(|l| l.stream.stats())
        .fold((0, 0, 0), |(n, b, p), s| (n + s.nodes_loaded, b + s.bytes_read, p + s.points_loaded))
}
