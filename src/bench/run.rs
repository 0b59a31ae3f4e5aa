//! The benchmark loop: scenes x views x mode variants.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::measure::{
    Opened, Prepared, Rulers, blank_row, measure_variant, measure_views, open_model, prepare_variants,
};
use super::orders::{OrderRow, time_orders};
use super::report::{BenchRow, ViewCosts};
use super::views::views_of;
use crate::frame::RenderMode;
use crate::grouping::GroupingSpec;
use crate::output::write_atomically;
use crate::render::{GpuRenderer, PreparedScene};

pub use super::config::{BenchConfig, BenchError};
use super::config::{io_error, save_png};
pub use super::measure::OPAQUE_FALLBACK;

/// What a benchmark run gave: the rows, and the models it had to skip with why.
#[derive(Debug, Default)]
pub struct BenchOutcome {
    pub rows: Vec<BenchRow>,
    /// Order timings (`--orders`).
    pub orders: Vec<OrderRow>,
    /// One line per model that could not be loaded or rendered; its rows are left out.
    pub skipped: Vec<String>,
}

/// Runs the benchmark over `models` and writes images, `bench.json`, `bench.md`
/// and `error_vs_time.png` into `config.out`. A model that cannot be loaded
/// or rendered is skipped with a warning naming it, and the others go on;
/// the reports hold every row that was measured.
pub fn run(models: &[PathBuf], config: &BenchConfig, renderer: &mut GpuRenderer) -> Result<BenchOutcome, BenchError> {
    if config.frames == 0 || config.views == 0 {
        return Err(BenchError::Invalid("frames and views must be at least 1".into()));
    }
    std::fs::create_dir_all(config.out.join("cache")).map_err(io_error(&config.out))?;
    let timing = renderer.renderer.enable_pass_timing(&renderer.ctx);
    if !timing {
        log::info!("the adapter has no timestamp queries: wall time only");
    }
    let mut outcome = BenchOutcome::default();
    for model in models {
        match bench_model(model, config, renderer) {
            Ok((rows, orders)) => {
                outcome.rows.extend(rows);
                outcome.orders.extend(orders);
            }
            Err(e) => {
                // Loading errors name the file already.
                let text = e.to_string();
                let shown = crate::copc::shown(&model.to_string_lossy());
                let line = if text.starts_with(&shown) { text } else { format!("{shown}: {text}") };
                log::warn!("skipped {line}");
                outcome.skipped.push(line);
            }
        }
    }
    if outcome.rows.is_empty() && outcome.orders.is_empty() {
        return Err(BenchError::Invalid(format!("no model could be benchmarked: {}", outcome.skipped.join("; "))));
    }
    let json = config.out.join("bench.json");
    super::report::write_json(&outcome.rows, &json).map_err(io_error(&json))?;
    // A run of the orders alone (`--modes none`) has no image table.
    let mut markdown = if outcome.rows.is_empty() { String::new() } else { super::report::markdown(&outcome.rows) };
    if config.orders {
        let json = config.out.join("orders.json");
        let text = serde_json::to_string_pretty(&outcome.orders).map_err(|e| BenchError::Invalid(e.to_string()))?;
        write_atomically(&json, text.as_bytes()).map_err(io_error(&json))?;
        markdown.push_str("\nBack-to-front orders, CPU ms per view:\n\n");
        markdown.push_str(&super::orders::markdown(&outcome.orders));
    }
    let md = config.out.join("bench.md");
    write_atomically(&md, markdown.as_bytes()).map_err(io_error(&md))?;
    if !outcome.rows.is_empty() && !config.no_reference {
        let title = format!("error against frame time, {}x{}", config.width, config.height);
        super::plot::write(&outcome.rows, &title, &config.out.join("error_vs_time.png"))
            .map_err(BenchError::Invalid)?;
    }
    if outcome.rows.iter().any(|r| r.frame.is_some()) {
        let title = format!("per animation frame, {}x{}", config.width, config.height);
        super::plot::write_animation(&outcome.rows, &title, &config.out.join("animation.png"))
            .map_err(BenchError::Invalid)?;
    }
    Ok(outcome)
}
/// Every view and variant of one model.
fn bench_model(
    model: &Path,
    config: &BenchConfig,
    renderer: &mut GpuRenderer,
) -> Result<(Vec<BenchRow>, Vec<OrderRow>), BenchError> {
    let layered = super::streamed_layers::is_streamed_layers(model);
    if layered || crate::copc::drawn_by_nodes(model, config.stream_budget) {
        if config.animate.is_some() || config.orders {
            return Err(BenchError::Invalid(format!(
                "{}: --animate and --orders need a file loaded whole, not drawn node by node (a COPC file, a URL, or a point file under --point-budget N below its points)",
                model.display()
            )));
        }
        if layered {
            return Ok((super::streamed_layers::bench_streamed_layers(model, config, renderer)?, Vec::new()));
        }
        return Ok((super::streamed::bench_streamed(model, config, renderer)?, Vec::new()));
    }
    if let Some(count) = config.animate {
        return Ok((bench_animation(model, config, renderer, count)?, Vec::new()));
    }
    let mut opened = open_model(model, config)?;
    let moving = opened.scene.is_animated().then(|| crate::render::rest_lattice(&opened.scene));
    if moving.is_some() {
        let time = config.time.unwrap_or(0.0);
        log::info!(
            "{}: the scene moves; it is measured at {time} s (--animate N measures its frames)",
            model.display()
        );
        opened.scene = Arc::new(opened.scene.at_time(time).map_err(BenchError::Invalid)?.scene);
    }
    let frames = PreparedScene::of(Arc::clone(&opened.scene));
    let mut frames = match moving {
        Some(lattice) => frames.moving_on(lattice.map_err(BenchError::Invalid)?),
        None => frames,
    };
    let cloud = Arc::clone(frames.cloud());
    let prepared = prepare_variants(config, &opened, &mut frames, renderer)?;
    let name = model.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = crate::output::safe_stem(model);
    let views = views_of(config, &cloud);
    let orders = if config.orders {
        log::info!("timing the back-to-front orders of {name}");
        time_orders(&name, &cloud, &views, config.frames, config.warm_up)
    } else {
        Vec::new()
    };
    if config.variants.is_empty() {
        return Ok((Vec::new(), orders));
    }
    if config.path.is_none() {
        let rows = measure_views((&name, &stem), &opened, &mut frames, &prepared, &views, config, renderer)?;
        return Ok((rows, orders));
    }
    // A file opened whole is one node, read, estimated, grouped and uploaded for the path's first view.
    let mut rows = Vec::new();
    let mut costs = ViewCosts {
        nodes_added: 1,
        bytes_read: std::fs::metadata(model).map_or(0, |m| m.len()),
        points_prepared: cloud.len() as u64,
        prepare_s: opened.load_s + prepared.iter().filter_map(|p| p.group_s).sum::<f64>(),
        upload_bytes: frames.uploaded_bytes(),
        view_index: 0,
    };
    for (view_index, view) in views.iter().enumerate() {
        let uploaded = frames.uploaded_bytes();
        let one = std::slice::from_ref(view);
        let mut view_rows = measure_views((&name, &stem), &opened, &mut frames, &prepared, one, config, renderer)?;
        // What the view's own frames uploaded: a point budget's new selections.
        costs.upload_bytes += frames.uploaded_bytes() - uploaded;
        costs.view_index = view_index;
        view_rows.iter_mut().for_each(|row| row.path = Some(costs));
        rows.extend(view_rows);
        costs = ViewCosts::default();
    }
    Ok((rows, orders))
}
/// `count` frames of a moving scene spread over one period of its longest
/// animation, each measured from every view against its own reference; the
/// splats are regrouped and rewritten between frames ([`PreparedScene::advance`]).
fn bench_animation(
    model: &Path,
    config: &BenchConfig,
    renderer: &mut GpuRenderer,
    count: usize,
) -> Result<Vec<BenchRow>, BenchError> {
    let opened = open_model(model, config)?;
    let period = opened.scene.animation_period();
    if period <= 0.0 {
        return Err(BenchError::Invalid(format!(
            "{}: nothing in the scene moves, so --animate has nothing to time",
            model.display()
        )));
    }
    let at = |i: usize| {
        let t = i as f64 * period / count as f64;
        opened.scene.at_time(t).map(|s| (t, Arc::new(s.scene))).map_err(BenchError::Invalid)
    };
    let (_, first) = at(0)?;
    let lattice = crate::render::rest_lattice(&opened.scene).map_err(BenchError::Invalid)?;
    let mut frames = PreparedScene::of(Arc::clone(&first)).moving_on(lattice);
    let framed = Opened { scene: first, base: opened.base, load_s: opened.load_s };
    let prepared = prepare_variants(config, &framed, &mut frames, renderer)?;
    let name = model.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let views = views_of(config, frames.cloud());
    let bar = crate::progress::bar(
        (count * views.len() * (prepared.len() + 1)) as u64,
        &format!("bench {} frames", crate::output::safe_stem(model)),
        config.progress,
    );
    let mut rows = Vec::new();
    for i in 0..count {
        let (t, scene) = at(i)?;
        let update = if i == 0 {
            None
        } else {
            let cloud = scene.flattened();
            Some(frames.advance(Some(renderer), scene, cloud).map_err(|e| BenchError::Invalid(e.to_string()))?)
        };
        let now = Opened { scene: Arc::clone(frames.scene()), base: opened.base, load_s: opened.load_s };
        let stem = format!("{}-f{i:02}", crate::output::safe_stem(model));
        for view in &views {
            let rulers = Rulers::of(config, &now, &prepared, &view.camera)?;
            let ruler_file = format!("{stem}-{}-{}.png", view.name, RenderMode::RULER.name());
            save_png(&rulers.with_opacity.image, &config.out.join(&ruler_file))?;
            let mut ruler_row = blank_row(&name, &now, &view.name, config, RenderMode::RULER.name(), RenderMode::RULER);
            let ms = rulers.with_opacity.ms;
            (ruler_row.frame_ms, ruler_row.frame_ms_min, ruler_row.frame_ms_max, ruler_row.frames) = (ms, ms, ms, 1);
            (ruler_row.image, ruler_row.frame, ruler_row.time) = (ruler_file, Some(i), Some(t));
            rows.push(ruler_row);
            bar.inc(1);
            for p in &prepared {
                let reference = rulers.of_variant(&now.scene, p);
                let blank = blank_row(&name, &now, &view.name, config, &p.variant.label(), p.variant.mode);
                let spec = p.spec.grouping.map(|g| g.spec);
                let mut row = measure_variant(renderer, &mut frames, view, p, config, Some(reference), (&stem, blank))?;
                (row.frame, row.time) = (Some(i), Some(t));
                row.regroup_ms = match &update {
                    Some(u) => spec.map(|s| u.regroup_ms_for(Some(s))),
                    // Frame 0: the first grouping of this algorithm (variants of one share it).
                    None => spec.map(|s| first_regroup_ms(&prepared, s)),
                };
                row.upload_ms = update.as_ref().map(|u| u.upload_for(spec).0);
                rows.push(row);
                bar.inc(1);
            }
        }
    }
    bar.finish();
    Ok(rows)
}

/// The milliseconds of the first grouping by `spec`'s algorithm among the
/// prepared variants (the later ones of one algorithm reuse its groups).
fn first_regroup_ms(prepared: &[Prepared], spec: GroupingSpec) -> f64 {
    let same = |p: &&Prepared| p.spec.grouping.is_some_and(|g| g.spec.algo == spec.algo);
    prepared.iter().filter(same).filter_map(|p| p.group_s).fold(0.0, f64::max) * 1e3
}
