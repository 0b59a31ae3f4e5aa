//! Benchmarks of a streamed file (COPC, from disk or a URL): its views come
//! from the header's bounds, each view selects its nodes under the point
//! budget (`--point-budget`, 1M by default) and loads what it lacks, and
//! every mode and the reference draw those same points. The whole file is
//! never decoded. Each view prints what it read.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use super::measure::{measure_views, prepare_variants, set_up};
use super::report::BenchRow;
use super::views::standard_views;
use super::{BenchConfig, BenchError};
use crate::cloud::LoadOptions;
use crate::copc::CopcStream;
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
    let name = model.to_string_lossy().to_string();
    let opened_at = Instant::now();
    let stream = CopcStream::open(&name, config.stream.clone()).map_err(|e| BenchError::Invalid(e.to_string()))?;
    let open_s = opened_at.elapsed().as_secs_f64();
    // What the report names: the URL's credentials masked.
    let shown = stream.name().to_string();
    let (w, h) = (config.width, config.height);
    let views = standard_views(&stream.bounds_cloud(), w as f32 / h as f32, config.views, &config.camera);
    // Chosen as the variants' base settings say (their radius scale, and
    // every node when lit: off-screen nodes cast shadows).
    let choosing = Choosing::of(&config.settings);
    let load = LoadOptions { progress: config.progress, ..Default::default() };
    let mut subset = StreamSubset::new(stream, config.stream_budget, load);
    let short = subset.stream.file_name().to_string();
    let stem = crate::output::safe_stem(Path::new(&short));
    let mut rows = Vec::new();
    for view in &views {
        let before = subset.stream.stats();
        let started = Instant::now();
        let choice = subset.choose(&view.camera, (w, h), choosing).map_err(|e| BenchError::Invalid(e.to_string()))?;
        let stream_s = started.elapsed().as_secs_f64();
        let after = subset.stream.stats();
        let (cache, _, bound) = subset.stream.cache_usage();
        println!(
            "{short} {} view: {} points of {} nodes, {:.1} MB read in {} requests, {:.2} s to select, load and build; cache {:.0} of {:.0} MB{}",
            view.name,
            subset.last.points,
            subset.last.drawn,
            (after.bytes_read - before.bytes_read) as f64 / 1e6,
            after.requests - before.requests,
            stream_s,
            cache as f64 / 1e6,
            bound as f64 / 1e6,
            if after.failed > 0 { format!(", {} nodes failed", after.failed) } else { String::new() }
        );
        let scene = Scene::single(short.clone(), choice.cloud.unwrap_or_default(), choice.key).coloured_by_default();
        let opened = set_up(scene, &shown, config, open_s + stream_s)?;
        // The stream applied the budget: every frame draws the points it selected.
        let mut frames = PreparedScene::of(Arc::clone(&opened.scene)).streamed();
        let prepared = prepare_variants(config, &opened, &mut frames, renderer)?;
        let one = std::slice::from_ref(view);
        rows.extend(measure_views((&short, &stem), &opened, &mut frames, &prepared, one, config, renderer)?);
    }
    Ok(rows)
}
