//! The benchmark loop: models x views x modes.

use std::path::{Path, PathBuf};
use std::time::Instant;

use super::cache;
use super::modes::ModeSpec;
use super::report::{BenchRow, PassTime};
use super::views::standard_views;
use crate::cloud::{self, CloudError, LoadOptions};
use crate::grouping::cache::Cache as GroupCache;
use crate::output::write_atomically;
use crate::reference::{self, ReferenceOptions};
use crate::render::{GpuError, HeadlessRenderer};
use crate::view::{Quality, RenderMode, RenderSettings};

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
    /// Modes with their quality level; `reference` is always rendered (it is the ruler).
    pub modes: Vec<(ModeSpec, Quality)>,
    /// ε, kernel, shading and culling shared by all modes.
    pub settings: RenderSettings,
    pub width: u32,
    pub height: u32,
    pub frames: usize,
    pub warm_up: usize,
    pub views: usize,
    /// Where images, the cache and the reports go.
    pub out: PathBuf,
    pub progress: bool,
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
            Ok(rows) => outcome.rows.extend(rows),
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
    if outcome.rows.is_empty() {
        return Err(BenchError::Invalid(format!("no model could be benchmarked: {}", outcome.skipped.join("; "))));
    }
    let json = config.out.join("bench.json");
    super::report::write_json(&outcome.rows, &json).map_err(io_error(&json))?;
    let md = config.out.join("bench.md");
    write_atomically(&md, super::report::markdown(&outcome.rows).as_bytes()).map_err(io_error(&md))?;
    let title = format!("error against frame time, {}x{}", config.width, config.height);
    super::plot::write(&outcome.rows, &title, &config.out.join("error_vs_time.png")).map_err(BenchError::Invalid)?;
    Ok(outcome)
}

/// Every view and mode of one model.
fn bench_model(
    model: &Path,
    config: &BenchConfig,
    renderer: &mut HeadlessRenderer,
) -> Result<Vec<BenchRow>, BenchError> {
    let gpu_modes: Vec<&(ModeSpec, Quality)> = config.modes.iter().filter(|(m, _)| m.mode.is_gpu()).collect();
    let (w, h) = (config.width, config.height);
    let aspect = w as f32 / h as f32;
    let mut rows = Vec::new();
    let started = Instant::now();
    let (cloud, report) = cloud::load_with(model, &LoadOptions { progress: config.progress, ..Default::default() })?;
    for warning in &report.warnings {
        log::warn!("{}: {warning}", model.display());
    }
    let load_s = started.elapsed().as_secs_f64();
    let gpu_cloud = renderer.upload(&cloud);
    // Each deferred variant groups the splats once (set-up, cached) and uploads them in group order.
    let mut grouped = Vec::new();
    for (spec, _) in &gpu_modes {
        if let Some(g) = spec.grouping {
            let t = Instant::now();
            let (grouping, cached) = g
                .compute_cached(&GroupCache::from_env(), model, &cloud)
                .map_err(|e| BenchError::Invalid(e.to_string()))?;
            let seconds = if cached { 0.0 } else { t.elapsed().as_secs_f64() };
            grouped.push((spec.name.clone(), renderer.upload_grouped(&cloud, &grouping), grouping.k(), seconds));
        }
    }
    let name = model.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let stem = crate::output::safe_stem(model);
    let views = standard_views(&cloud, aspect, config.views);
    let steps = (views.len() * (gpu_modes.len() + 1)) as u64;
    let bar = crate::progress::bar(steps, &format!("bench {stem}"), config.progress);
    for view in &views {
        let base = |mode: &str, gpu: bool, quality: Quality| BenchRow {
            model: name.clone(),
            mode: mode.to_string(),
            quality: if gpu { format!("{quality:?}").to_lowercase() } else { "exact".into() },
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
            points: cloud.len(),
            width: w,
            height: h,
            load_s,
            k: 1,
            group_s: None,
            frames: config.frames,
        };

        // The ruler: the exact reference, from the cache when it is there.
        let entry = cache::entry(&config.out, model, &view.camera, &config.settings, (w, h));
        let (reference_image, reference_ms) = match entry.load() {
            Some(cached) => cached,
            None => {
                let options = ReferenceOptions::matching(&config.settings, &cloud);
                let t = Instant::now();
                let image = reference::render(&cloud, &view.camera, &options, w, h);
                let ms = t.elapsed().as_secs_f64() * 1e3;
                save_png(&image, &entry.image)?;
                write_atomically(&entry.millis, format!("{ms}").as_bytes()).map_err(io_error(&entry.millis))?;
                (image, ms)
            }
        };
        save_png(&reference_image, &config.out.join(format!("{stem}-{}-reference.png", view.name)))?;
        if config.modes.iter().any(|(m, _)| m.mode == RenderMode::Reference) {
            let mut row = base("reference", false, Quality::Filtered);
            (row.frame_ms, row.frame_ms_min, row.frame_ms_max, row.frames) =
                (reference_ms, reference_ms, reference_ms, 1);
            rows.push(row);
        }
        bar.inc(1);

        for &(spec, quality) in &gpu_modes {
            let mode = spec.mode;
            let quality = *quality;
            let settings = RenderSettings { mode, quality, voronoi: spec.voronoi, ..config.settings };
            let (gpu_cloud, k, group_s) = match grouped.iter().find(|g| g.0 == spec.name) {
                Some((_, c, k, s)) => (c, *k, Some(*s)),
                None => (&gpu_cloud, 1, None),
            };
            let mut wall = Vec::new();
            let mut per_pass: Vec<Vec<f64>> = Vec::new();
            let mut plan = None;
            for frame in 0..config.warm_up + config.frames {
                let t = Instant::now();
                let p = renderer
                    .render(gpu_cloud, &view.camera, &settings, w, h)
                    .map_err(|e| BenchError::Invalid(format!("{} ({} view): {e}", spec.name, view.name)))?;
                renderer.ctx.wait_idle()?;
                let ms = t.elapsed().as_secs_f64() * 1e3;
                if frame >= config.warm_up {
                    wall.push(ms);
                    if let Some(times) = renderer.renderer.pass_times(&renderer.ctx, &p)? {
                        per_pass.resize(times.len(), Vec::new());
                        for (i, t) in times.into_iter().enumerate() {
                            per_pass[i].push(t);
                        }
                    }
                }
                plan = Some(p);
            }
            let (image, _) = renderer
                .render_image(gpu_cloud, &view.camera, &settings, w, h)
                .map_err(|e| BenchError::Invalid(format!("{} ({} view): {e}", spec.name, view.name)))?;
            let Some(plan) = plan else { continue };
            let error = reference::compare(&image, &reference_image)
                .ok_or_else(|| BenchError::Invalid("image and reference sizes differ".into()))?;
            let tag = match quality {
                Quality::Filtered => spec.name.clone(),
                Quality::Unfiltered => format!("{}-unfiltered", spec.name),
            };
            save_png(&image, &config.out.join(format!("{stem}-{}-{tag}.png", view.name)))?;
            if let Some(diff) = reference::difference_image(&image, &reference_image, 8.0) {
                save_png(&diff, &config.out.join(format!("{stem}-{}-{tag}-diff.png", view.name)))?;
            }
            let frame = spread(&wall);
            let passes: Vec<PassTime> = plan
                .passes
                .iter()
                .zip(&per_pass)
                .map(|(kind, times)| {
                    let s = spread(times);
                    PassTime { pass: kind.label().to_string(), ms: s.median, ms_min: s.min, ms_max: s.max }
                })
                .collect();
            let mut row = base(&spec.name, true, quality);
            row.k = k;
            row.group_s = group_s;
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
    Ok(rows)
}
