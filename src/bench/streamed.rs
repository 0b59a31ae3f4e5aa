//! Benchmarks of a streamed file (COPC, from disk or a URL): its views come
//! from the header's bounds, each view selects its nodes under the point
//! budget (`--point-budget`, 1M by default) and loads what it lacks, and
//! every mode and the reference draw those same points. The whole file is
//! never decoded. Each view prints what it read. A camera path's views
//! (`--path`) are measured in path order, each row with what its view cost
//! ([`ViewCosts`]): a node is decoded and estimated once, when it arrives,
//! and so are its groups for the first grouped variant. A new selection
//! is then built (re-centred, copies merged) and styled; each GPU copy of
//! an opaque selection keeps the nodes still drawn in their slots and writes
//! only the nodes added, dropped or changed (a node pool), and a view that
//! selects the same nodes as the last one prepares nothing.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use super::measure::{Opened, measure_views, prepare_variants, set_up};
use super::report::{BenchRow, ViewCosts};
use super::views::views_of;
use super::{BenchConfig, BenchError};
use crate::cloud::LoadOptions;
use crate::copc::StreamStats;
use crate::copc::subset::StreamSubset;
use crate::frame::subset::{Choosing, Subset};
use crate::render::{GpuRenderer, PreparedScene};
use crate::scene::Scene;

/// Every view and variant of a streamed model.
pub(super) fn bench_streamed(
    model: &Path,
    config: &BenchConfig,
    renderer: &mut GpuRenderer,
) -> Result<Vec<BenchRow>, BenchError> {
    let opened_at = Instant::now();
    let stream =
        crate::copc::open_nodes(model, config.stream.clone()).map_err(|e| BenchError::Invalid(e.to_string()))?;
    let open_s = opened_at.elapsed().as_secs_f64();
    // What the report names: the URL's credentials masked.
    let shown = stream.name().to_string();
    let views = views_of(config, &stream.bounds_cloud());
    // Chosen as the variants' base settings say (their radius scale, and
    // every node when lit: off-screen nodes cast shadows).
    let mut choosing = Choosing::of(&config.settings);
    // Nodes are labelled for the first grouped variant (another K regroups each selection whole).
    let variants = config.variants.iter().filter_map(|v| v.apply(&config.settings).ok());
    choosing.groups = variants.filter_map(|settings| Choosing::of(&settings).groups).next();
    let load = LoadOptions { progress: config.progress, ..Default::default() };
    let mut subset = StreamSubset::new(stream, config.stream_budget, load);
    let short = subset.stream.file_name().to_string();
    let stem = crate::output::safe_stem(Path::new(&short));
    let mut rows = Vec::new();
    // The last selection, set up and prepared: a view that selects the same nodes draws it again.
    let mut shown_last: Option<(Opened, PreparedScene)> = None;
    let mut pinned: Option<Arc<crate::style::Style>> = None;
    for (view_index, view) in views.iter().enumerate() {
        let before = subset.stream.stats();
        let started = Instant::now();
        let choice = subset
            .choose(&view.camera, (config.width, config.height), choosing)
            .map_err(|e| BenchError::Invalid(e.to_string()))?;
        let stream_s = started.elapsed().as_secs_f64();
        let after = subset.stream.stats();
        say_view(&short, &view.name, &subset, (&before, &after), stream_s);
        let mut costs = ViewCosts {
            view_index,
            nodes_added: after.nodes_loaded - before.nodes_loaded,
            bytes_read: after.bytes_read - before.bytes_read,
            ..Default::default()
        };
        let fresh = choice.cloud.is_some();
        costs.points_prepared = after.points_loaded - before.points_loaded;
        if let Some(cloud) = choice.cloud {
            // New nodes drawn: the stream estimated the nodes it added and built the
            // selection; it is styled here, then grouped and uploaded whole below.
            let styled_at = Instant::now();
            let scene = Scene::single(short.clone(), cloud, choice.key)
                .with_node_grouping(choice.grouping)
                .with_node_spans(choice.spans);
            let opened = set_up_pinned(scene, &shown, (config, open_s + stream_s), &mut pinned)?;
            costs.prepare_s = stream_s + styled_at.elapsed().as_secs_f64();
            shown_last = Some(match shown_last.take() {
                // The last selection's GPU copy is kept: a node still drawn stays where it is.
                Some((last, mut frames)) => {
                    drop(last); // the last selection's points go before this one's are written
                    let update = frames
                        .show_selection(Some(renderer), Arc::clone(&opened.scene), opened.scene.flattened())
                        .map_err(|e| BenchError::Invalid(e.to_string()))?;
                    costs.upload_bytes += update.uploaded_bytes;
                    (opened, frames)
                }
                // The stream applied the budget: every frame draws the points it selected.
                None => {
                    let frames = PreparedScene::of(Arc::clone(&opened.scene)).streamed();
                    (opened, frames)
                }
            });
        }
        let (opened, frames) = shown_last.as_mut().expect("a stream's first choice holds its points");
        let uploaded = frames.uploaded_bytes();
        let prepared = prepare_variants(config, opened, frames, renderer)?;
        if fresh {
            costs.prepare_s += prepared.iter().filter_map(|p| p.group_s).sum::<f64>();
        }
        costs.upload_bytes += frames.uploaded_bytes() - uploaded;
        let one = std::slice::from_ref(view);
        let mut view_rows = measure_views((&short, &stem), opened, frames, &prepared, one, config, renderer)?;
        if config.path.is_some() {
            view_rows.iter_mut().for_each(|row| row.path = Some(costs));
        }
        rows.extend(view_rows);
    }
    Ok(rows)
}

/// [`set_up`] of one view's selection: the first view's colours (the
/// default's or the flags'), their range fixed (`pinned`), style every later one.
pub(super) fn set_up_pinned(
    scene: Scene,
    name: &str,
    (config, load_s): (&BenchConfig, f64),
    pinned: &mut Option<Arc<crate::style::Style>>,
) -> Result<Opened, BenchError> {
    if let Some(style) = pinned {
        let materials = crate::scene::Materials { style: Some(Arc::clone(style)), ..config.materials.clone() };
        return set_up(scene, name, (config, &materials), load_s);
    }
    let opened = set_up(scene.coloured_by_default(), name, (config, &config.materials), load_s)?;
    *pinned = opened.scene.pinned_style().map(Arc::new);
    Ok(opened)
}

/// Prints what a view of `short` selected and read.
fn say_view(short: &str, view: &str, subset: &StreamSubset, (before, after): (&StreamStats, &StreamStats), s: f64) {
    let (cache, _, bound) = subset.stream.cache_usage();
    let made = |what: &str, points: u64, seconds: f64| {
        if points > 0 { format!(", {points} points {what} in {seconds:.2} s") } else { String::new() }
    };
    println!(
        "{short} {view} view: {} points of {} nodes ({} new), {:.1} MB read in {} requests, {s:.2} s to select, load and build{}{}; cache {:.0} of {:.0} MB{}",
        subset.last.points,
        subset.last.drawn,
        after.nodes_loaded - before.nodes_loaded,
        (after.bytes_read - before.bytes_read) as f64 / 1e6,
        after.requests - before.requests,
        made(
            "estimated",
            after.points_estimated - before.points_estimated,
            after.estimate_seconds - before.estimate_seconds
        ),
        made("grouped", after.points_labelled - before.points_labelled, after.label_seconds - before.label_seconds),
        cache as f64 / 1e6,
        bound as f64 / 1e6,
        if after.failed > 0 { format!(", {} nodes failed", after.failed) } else { String::new() }
    );
}
