//! The benchmark loop: scenes x views x mode variants.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::cache;
use super::orders::{OrderRow, time_orders};
use super::report::{BenchRow, PassTime};
use super::views::standard_views;
use crate::cloud::{CloudError, LoadOptions};
use crate::frame::environment::EnvironmentSettings;
use crate::frame::{Camera, ModeVariant, RenderMode, RenderSettings};
use crate::grouping::cache::Cache as GroupCache;
use crate::output::write_atomically;
use crate::reference::{self, ReferenceOptions};
use crate::render::{GpuError, GpuScene, HeadlessRenderer, RenderPlan};
use crate::scene::{Materials, Scene};

#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error(transparent)]
    Cloud(#[from] CloudError),
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{0}")]
    Invalid(String),
}

/// What to run.
#[derive(Debug, Clone)]
pub struct BenchConfig {
    /// The mode variants, one row each per view; the reference is always
    /// rendered (it is the ruler) and gets a row when listed.
    pub variants: Vec<ModeVariant>,
    /// The settings every variant starts from (ε, kernel, shading, culling...).
    pub settings: RenderSettings,
    pub materials: Materials,
    pub width: u32,
    pub height: u32,
    pub frames: usize,
    pub warm_up: usize,
    pub views: usize,
    /// Where images, the cache and the reports go.
    pub out: PathBuf,
    pub progress: bool,
    /// Also time the back-to-front orders (`orders.json`, a table in `bench.md`).
    pub orders: bool,
    /// The environment map every model is set in, if any (§5.2.3).
    pub environment: Option<std::sync::Arc<crate::scene::environment::EnvironmentMap>>,
}

fn io_error(path: &Path) -> impl FnOnce(std::io::Error) -> BenchError + '_ {
    move |source| BenchError::Io { path: path.to_path_buf(), source }
}

fn save_png(image: &image::RgbaImage, path: &Path) -> Result<(), BenchError> {
    crate::output::save_png(image, path).map_err(io_error(path))
}

struct Spread {
    median: f64,
    min: f64,
    max: f64,
}

fn spread(values: &[f64]) -> Spread {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return Spread { median: f64::NAN, min: f64::NAN, max: f64::NAN };
    }
    let median = if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) };
    Spread { median, min: v[0], max: v[n - 1] }
}

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
pub fn run(
    models: &[PathBuf],
    config: &BenchConfig,
    renderer: &mut HeadlessRenderer,
) -> Result<BenchOutcome, BenchError> {
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
                let shown = model.display().to_string();
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
    if !outcome.rows.is_empty() {
        let title = format!("error against frame time, {}x{}", config.width, config.height);
        super::plot::write(&outcome.rows, &title, &config.out.join("error_vs_time.png"))
            .map_err(BenchError::Invalid)?;
    }
    Ok(outcome)
}

/// A GPU variant ready to run: its settings, its upload and its grouping's K and time.
struct Prepared {
    variant: ModeVariant,
    settings: RenderSettings,
    scene: usize,
    k: usize,
    group_s: Option<f64>,
}

/// Every view and variant of one model.
fn bench_model(
    model: &Path,
    config: &BenchConfig,
    renderer: &mut HeadlessRenderer,
) -> Result<(Vec<BenchRow>, Vec<OrderRow>), BenchError> {
    let (w, h) = (config.width, config.height);
    let started = Instant::now();
    let (mut scene, warnings) =
        crate::scene::open(model, &LoadOptions { progress: config.progress, ..Default::default() })
            .map_err(|e| BenchError::Invalid(e.to_string()))?;
    for warning in &warnings {
        log::warn!("{warning}");
    }
    if let Some(opacity) = config.materials.opacity {
        scene.set_opacity(opacity);
    }
    if let Some(colour) = config.materials.colour {
        scene.set_colour(colour);
    }
    if config.environment.is_some() {
        scene.environment = config.environment.clone();
    }
    let mut base = config.settings;
    if let (true, Some(bg)) = (config.materials.scene_background, scene.background) {
        base.shading.background = bg;
    }
    let load_s = started.elapsed().as_secs_f64();
    let flat = scene.flatten();
    // One upload for the ungrouped variants, one per grouping (set-up, cached).
    let mut uploads: Vec<(Option<crate::grouping::GroupingSpec>, GpuScene)> = Vec::new();
    let mut prepared = Vec::new();
    for variant in config.variants.iter().filter(|v| v.mode.is_gpu()) {
        let settings = variant.apply(&base).map_err(BenchError::Invalid)?;
        let spec = variant.mode.needs_grouping_for(scene.has_transparency()).then_some(settings.grouping_for_mode());
        let (mut k, mut group_s) = (1, None);
        if let Some(spec) = spec {
            let t = Instant::now();
            let cache = GroupCache::from_env();
            let (grouping, cached) = spec
                .compute_cached_for_hash(&cache, scene.geometry_hash(), &flat.cloud)
                .map_err(|e| BenchError::Invalid(e.to_string()))?;
            k = grouping.k();
            group_s = Some(if cached { 0.0 } else { t.elapsed().as_secs_f64() });
            if !uploads.iter().any(|(s, _)| *s == Some(spec)) {
                let mut gpu = GpuScene::upload_cloud(&renderer.ctx.device, &flat.cloud, Some(&grouping));
                gpu.set_environment(&renderer.ctx.device, &renderer.ctx.queue, scene.environment.as_deref());
                uploads.push((Some(spec), gpu));
            }
        } else if !uploads.iter().any(|(s, _)| s.is_none()) {
            let mut gpu = GpuScene::upload_cloud(&renderer.ctx.device, &flat.cloud, None);
            gpu.set_environment(&renderer.ctx.device, &renderer.ctx.queue, scene.environment.as_deref());
            uploads.push((None, gpu));
        }
        let scene = uploads.iter().position(|(s, _)| *s == spec).unwrap_or(0);
        prepared.push(Prepared { variant: variant.clone(), settings, scene, k, group_s });
    }
    let name = model.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = crate::output::safe_stem(model);
    let views = standard_views(&flat.cloud, w as f32 / h as f32, config.views);
    let orders = if config.orders {
        log::info!("timing the back-to-front orders of {name}");
        time_orders(&name, &flat.cloud, &views, config.frames, config.warm_up)
    } else {
        Vec::new()
    };
    if config.variants.is_empty() {
        return Ok((Vec::new(), orders));
    }
    let bar =
        crate::progress::bar((views.len() * (prepared.len() + 1)) as u64, &format!("bench {stem}"), config.progress);
    let mut rows = Vec::new();
    for view in &views {
        let row = |variant: &str, mode: RenderMode| BenchRow {
            model: name.clone(),
            mode: mode.name().to_string(),
            variant: variant.to_string(),
            reference: ruler_name(mode.info().transparent).to_string(),
            ruler: mode == RenderMode::RULER,
            view: view.name.to_string(),
            frame_ms: 0.0,
            frame_ms_min: 0.0,
            frame_ms_max: 0.0,
            gpu_ms: None,
            passes: Vec::new(),
            eps: 0.0,
            psnr: None,
            bad_pixel_share: 0.0,
            geometry_passes: 0,
            points: scene.len(),
            width: w,
            height: h,
            load_s,
            k: 1,
            group_s: None,
            frames: config.frames,
        };

        // The rulers: the exact reference with every splat opaque (for opaque
        // modes) and with the scene's opacities (for transparent modes, and
        // the reference mode itself); one image when the scene is opaque.
        let opaque = ruler(config, &scene, &base, &view.camera, false)?;
        // The reference mode's own image (with the scene's map, if any).
        let reference = RenderSettings { mode: RenderMode::RULER, ..base };
        let with_opacity = if scene.has_transparency() {
            ruler(config, &scene, &reference, &view.camera, true)?
        } else {
            opaque.clone()
        };
        // With a map, a transparent variant is measured against the reference
        // of what it draws: its own environment settings, or none for a mode
        // without the effects (or env-layers=off).
        let drawn =
            |s: &RenderSettings| (scene.environment.is_some() && s.draws_environment()).then_some(s.environment);
        let mut own_rulers = Vec::new();
        if scene.has_transparency() {
            for p in prepared.iter().filter(|p| p.variant.mode.info().transparent) {
                let key = drawn(&p.settings);
                if key != drawn(&reference) && !own_rulers.iter().any(|(k, _)| *k == key) {
                    let environment = EnvironmentSettings { enabled: key.is_some(), ..key.unwrap_or(base.environment) };
                    let settings = RenderSettings { environment, ..reference };
                    own_rulers.push((key, ruler(config, &scene, &settings, &view.camera, true)?));
                }
            }
        }
        let ruler_of = |p: &Prepared| {
            if !p.variant.mode.info().transparent {
                return &opaque;
            }
            let key = drawn(&p.settings);
            own_rulers.iter().find(|(k, _)| *k == key).map_or(&with_opacity, |(_, r)| r)
        };
        let ruler_for = |transparent: bool| if transparent { &with_opacity } else { &opaque };
        let name = RenderMode::RULER.name();
        save_png(&with_opacity.0, &config.out.join(format!("{stem}-{}-{name}.png", view.name)))?;
        if scene.has_transparency() {
            save_png(&opaque.0, &config.out.join(format!("{stem}-{}-{name}-opaque.png", view.name)))?;
        }
        for variant in config.variants.iter().filter(|v| !v.mode.is_gpu()) {
            let mut row = row(&variant.label(), variant.mode);
            let ms = ruler_for(variant.mode.info().transparent).1;
            (row.frame_ms, row.frame_ms_min, row.frame_ms_max, row.frames) = (ms, ms, ms, 1);
            rows.push(row);
        }
        bar.inc(1);

        for p in &prepared {
            let gpu_scene = &uploads[p.scene].1;
            let (image, plan, wall, per_pass) = time_frames(renderer, gpu_scene, &view.camera, p, config)
                .map_err(|e| BenchError::Invalid(format!("{} ({} view): {e}", p.variant, view.name)))?;
            let reference_image = &ruler_of(p).0;
            let error = reference::compare(&image, reference_image)
                .ok_or_else(|| BenchError::Invalid("image and reference sizes differ".into()))?;
            let tag = p.variant.file_tag();
            save_png(&image, &config.out.join(format!("{stem}-{}-{tag}.png", view.name)))?;
            if let Some(diff) = reference::difference_image(&image, reference_image, 8.0) {
                save_png(&diff, &config.out.join(format!("{stem}-{}-{tag}-diff.png", view.name)))?;
            }
            let frame = spread(&wall);
            let passes: Vec<PassTime> = plan
                .steps
                .iter()
                .zip(&per_pass)
                .map(|(pass, times)| {
                    let s = spread(times);
                    PassTime { pass: pass.name.to_string(), ms: s.median, ms_min: s.min, ms_max: s.max }
                })
                .collect();
            let mut row = row(&p.variant.label(), p.variant.mode);
            row.k = p.k;
            row.group_s = p.group_s;
            row.frame_ms = frame.median;
            row.frame_ms_min = frame.min;
            row.frame_ms_max = frame.max;
            row.gpu_ms = (!passes.is_empty()).then(|| passes.iter().map(|p| p.ms).sum());
            row.passes = passes;
            row.eps = error.eps;
            row.psnr = error.psnr.is_finite().then_some(error.psnr);
            row.bad_pixel_share = error.bad_pixel_share;
            row.geometry_passes = plan.geometry_passes();
            rows.push(row);
            bar.inc(1);
        }
    }
    bar.finish();
    Ok((rows, orders))
}

/// What a row's error is measured against.
fn ruler_name(transparent: bool) -> &'static str {
    if transparent { "reference with the scene's opacity" } else { "reference with every splat opaque" }
}

/// The exact reference of `scene` from `camera`, reading opacity or not,
/// from the cache when it is there; and the milliseconds it took.
fn ruler(
    config: &BenchConfig,
    scene: &Scene,
    settings: &RenderSettings,
    camera: &Camera,
    transparent: bool,
) -> Result<(image::RgbaImage, f64), BenchError> {
    let size = (config.width, config.height);
    let environment = scene.environment.as_deref();
    let entry = cache::entry(&config.out, scene.content_hash(), camera, settings, transparent, size, environment);
    if let Some(cached) = entry.load() {
        return Ok(cached);
    }
    let options = ReferenceOptions { transparent, ..ReferenceOptions::matching(settings, scene) };
    let t = Instant::now();
    let image = reference::render(scene, camera, &options, size.0, size.1);
    let ms = t.elapsed().as_secs_f64() * 1e3;
    save_png(&image, &entry.image)?;
    write_atomically(&entry.millis, format!("{ms}").as_bytes()).map_err(io_error(&entry.millis))?;
    Ok((image, ms))
}

/// Warm-up and timed frames of one variant from one view: the last image,
/// the plan, wall times and GPU times per plan pass.
#[allow(clippy::type_complexity)]
fn time_frames(
    renderer: &mut HeadlessRenderer,
    scene: &GpuScene,
    camera: &Camera,
    p: &Prepared,
    config: &BenchConfig,
) -> Result<(image::RgbaImage, RenderPlan, Vec<f64>, Vec<Vec<f64>>), GpuError> {
    let (w, h) = (config.width, config.height);
    let mut wall = Vec::new();
    let mut per_pass: Vec<Vec<f64>> = Vec::new();
    for frame in 0..config.warm_up + config.frames {
        let t = Instant::now();
        let plan = renderer.render(scene, camera, &p.settings, w, h)?;
        renderer.ctx.wait_idle()?;
        let ms = t.elapsed().as_secs_f64() * 1e3;
        if frame >= config.warm_up {
            wall.push(ms);
            if let Some(times) = renderer.renderer.pass_times(&renderer.ctx, &plan)? {
                per_pass.resize(times.len(), Vec::new());
                for (i, t) in times.into_iter().enumerate() {
                    per_pass[i].push(t);
                }
            }
        }
    }
    let (image, plan) = renderer.render_image(scene, camera, &p.settings, w, h)?;
    Ok((image, plan, wall, per_pass))
}
