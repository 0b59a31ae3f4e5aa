//! One model's rows: its scene set up for the run (materials, environment,
//! lights), its GPU variants prepared (groupings, uploads), the exact
//! references of each view, and each variant timed and measured against
//! them. [`super::run`] calls this for files loaded whole, and
//! [`super::streamed`] once per view of a streamed file.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use super::cache::Ruler;
use super::report::{BenchRow, PassTime};
use super::ruler::{ruler, ruler_name};
use super::timing::time_frames;
use crate::cloud::LoadOptions;
use crate::frame::environment_effects::EnvironmentSettings;
use crate::frame::spec::Selection;
use crate::frame::{Camera, EyeDome, FrameSpec, ModeVariant, RenderMode, RenderSettings, View};
use crate::reference;
use crate::render::{Frame, GpuRenderer, PreparedScene};
use crate::scene::Scene;

use super::config::save_png;
use super::config::{BenchConfig, BenchError};

/// Median and range of some timings.
pub(super) struct Spread {
    pub(super) median: f64,
    pub(super) min: f64,
    pub(super) max: f64,
}

pub(super) fn spread(values: &[f64]) -> Spread {
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        return Spread { median: f64::NAN, min: f64::NAN, max: f64::NAN };
    }
    let median = if n % 2 == 1 { v[n / 2] } else { 0.5 * (v[n / 2 - 1] + v[n / 2]) };
    Spread { median, min: v[0], max: v[n - 1] }
}

/// A GPU variant ready to run: its settings and its grouping's K and time
/// (its upload is in the model's [`PreparedScene`]).
pub(super) struct Prepared {
    pub(super) variant: ModeVariant,
    pub(super) settings: RenderSettings,
    /// Its frame, decided once ([`crate::frame::resolve`]): bench's rows are labelled from it.
    pub(super) spec: FrameSpec,
    pub(super) k: usize,
    pub(super) group_s: Option<f64>,
    /// Milliseconds the shadow coefficients took and the MiB of their TSM tables (lit by scene lights).
    pub(super) shadows: Option<(f64, f64)>,
    /// Whether it is only `--ruler`'s variant, not a row of its own.
    pub(super) ruler_only: bool,
}

/// A model's scene as the run sets it up: materials, environment, background.
pub(super) struct Opened {
    pub(super) scene: Arc<Scene>,
    /// The settings every variant starts from, with the scene's background.
    pub(super) base: RenderSettings,
    pub(super) load_s: f64,
}

/// Loads `model` and applies the run's materials and environment.
pub(super) fn open_model(model: &Path, config: &BenchConfig) -> Result<Opened, BenchError> {
    let started = Instant::now();
    let (scene, warnings) = crate::scene::open(model, &LoadOptions { progress: config.progress, ..Default::default() })
        .map_err(|e| BenchError::Invalid(e.to_string()))?;
    for warning in &warnings {
        log::warn!("{warning}");
    }
    set_up(scene, &model.display().to_string(), (config, &config.materials), started.elapsed().as_secs_f64())
}

/// Applies the run's materials, environment, background and lights to
/// `scene` (of the file `name`, read in `load_s` seconds).
pub(super) fn set_up(
    mut scene: Scene,
    name: &str,
    (config, materials): (&BenchConfig, &crate::scene::Materials),
    load_s: f64,
) -> Result<Opened, BenchError> {
    materials.apply(&mut scene).map_err(BenchError::Invalid)?;
    if config.environment.is_some() {
        scene.environment = config.environment.clone();
    }
    let mut base = config.settings;
    if let (true, Some(bg)) = (config.materials.scene_background, scene.background) {
        base.shading.background = bg;
    }
    // The scene file's lights and `--light`s, both in file coordinates, in the scene's frame.
    let lights: Vec<_> =
        scene.lights.iter().chain(config.settings.lights.as_slice()).map(|l| scene.light_in_frame(l)).collect();
    base.lights =
        crate::frame::Lights::new(&lights).map_err(|e| BenchError::Invalid(format!("{name}: lights: {e}")))?;
    Ok(Opened { scene: Arc::new(scene), base, load_s })
}

/// Every GPU variant's settings, and its grouping (set up through the cache)
/// and upload in `frames`.
pub(super) fn prepare_variants(
    config: &BenchConfig,
    opened: &Opened,
    frames: &mut PreparedScene,
    renderer: &GpuRenderer,
) -> Result<Vec<Prepared>, BenchError> {
    let mut prepared = Vec::new();
    // The reference's rows are the rulers: one number of rays for all of them.
    for variant in config.variants.iter().filter(|v| !v.mode.is_gpu()) {
        let settings = variant.apply(&opened.base).map_err(BenchError::Invalid)?;
        if settings.supersample != opened.base.supersample {
            return Err(BenchError::Invalid(format!(
                "{variant}: the reference is every row's ruler, so its rays are set for all rows: use --supersample {}",
                settings.supersample
            )));
        }
    }
    let ruler = config.ruler.iter().filter(|r| !config.variants.contains(r));
    for (variant, ruler_only) in config.variants.iter().map(|v| (v, false)).chain(ruler.map(|r| (r, true))) {
        if !variant.mode.is_gpu() {
            continue;
        }
        let settings = variant.apply(&opened.base).map_err(BenchError::Invalid)?;
        let spec = frames.resolve(&settings, View::still((config.width, config.height)));
        if spec.selection.changes_with_view() {
            // The hierarchy is built (or read) here, not in a timed frame; its
            // splats, groups and shadows depend on the view: made by each frame
            // (see time_frames). So do a frame with triangles' splats.
            if matches!(spec.selection, Selection::Budget(_)) {
                frames.hierarchy();
            }
            let k = match spec.grouping.map(|g| g.spec.algo) {
                Some(crate::grouping::GroupingAlgo::Hash { k, .. }) => k,
                _ => 1,
            };
            let shadows = None;
            prepared.push(Prepared { variant: variant.clone(), settings, spec, k, group_s: None, shadows, ruler_only });
            continue;
        }
        let (k, group_s) = match spec.grouping {
            Some(drawn) => {
                let grouping = frames.grouping(drawn.spec).map_err(|e| BenchError::Invalid(e.to_string()))?;
                (grouping.grouping.k(), Some(grouping.seconds))
            }
            None => (1, None),
        };
        let shadows = frames.shadows(&spec.drawn).map_err(|e| BenchError::Invalid(e.to_string()))?.map(|c| {
            let table_bytes: u64 = c.tables.iter().map(|t| t.bytes).sum();
            (c.seconds * 1e3, table_bytes as f64 / (1u64 << 20) as f64)
        });
        frames.gpu_scene(renderer, &spec).map_err(|e| BenchError::Invalid(e.to_string()))?;
        prepared.push(Prepared { variant: variant.clone(), settings, spec, k, group_s, shadows, ruler_only });
    }
    Ok(prepared)
}

/// The exact references one view's rows are measured against.
pub(super) struct Rulers {
    /// Every splat opaque (for opaque modes).
    pub(super) opaque: Ruler,
    /// With the scene's opacities (for transparent modes and the reference mode itself).
    pub(super) with_opacity: Ruler,
    /// With a map: the reference of what a transparent variant draws (its own
    /// environment settings, or none), keyed by those settings.
    pub(super) own: Vec<(Option<EnvironmentSettings>, Ruler)>,
    /// Every splat opaque, with the eye-dome lighting an opaque variant asks
    /// for: a shading, not an approximation, so its rows are measured with it.
    pub(super) eye_dome_lit: Vec<(EyeDome, Ruler)>,
}

/// Whether (and with which settings) a frame of `settings` draws `scene`'s environment map.
pub(super) fn drawn_environment(scene: &Scene, settings: &RenderSettings) -> Option<EnvironmentSettings> {
    (scene.environment.is_some() && settings.draws_environment()).then_some(settings.environment)
}

impl Rulers {
    /// Renders (or reads from the cache) the rulers of one view.
    pub(super) fn of(
        config: &BenchConfig,
        opened: &Opened,
        prepared: &[Prepared],
        camera: &Camera,
    ) -> Result<Self, BenchError> {
        // Eye-dome lighting is added below, for the variants that draw it.
        let base = &RenderSettings { eye_dome: None, ..opened.base };
        let scene = &opened.scene;
        // One image when the scene is opaque.
        let opaque = ruler(config, scene, base, camera, false)?;
        // The reference mode's own image (with the scene's map, if any).
        let reference = RenderSettings { mode: RenderMode::RULER, ..*base };
        let with_opacity =
            if scene.has_transparency() { ruler(config, scene, &reference, camera, true)? } else { opaque.clone() };
        let mut own = Vec::new();
        if scene.has_transparency() {
            for p in prepared.iter().filter(|p| p.variant.mode.info().transparent) {
                let key = drawn_environment(scene, &p.settings);
                if key != drawn_environment(scene, &reference) && !own.iter().any(|(k, _)| *k == key) {
                    let environment = EnvironmentSettings { enabled: key.is_some(), ..key.unwrap_or(base.environment) };
                    let settings = RenderSettings { environment, ..reference };
                    own.push((key, ruler(config, scene, &settings, camera, true)?));
                }
            }
        }
        let mut eye_dome_lit: Vec<(EyeDome, Ruler)> = Vec::new();
        for edl in prepared.iter().filter_map(|p| p.settings.eye_dome_drawn()) {
            if !eye_dome_lit.iter().any(|(e, _)| *e == edl) {
                let settings = RenderSettings { mode: RenderMode::RULER, eye_dome: Some(edl), ..*base };
                eye_dome_lit.push((edl, ruler(config, scene, &settings, camera, false)?));
            }
        }
        Ok(Rulers { opaque, with_opacity, own, eye_dome_lit })
    }

    /// The ruler of a mode that is `transparent` or not.
    pub(super) fn for_mode(&self, transparent: bool) -> &Ruler {
        if transparent { &self.with_opacity } else { &self.opaque }
    }

    /// The ruler of a prepared variant.
    pub(super) fn of_variant(&self, scene: &Scene, p: &Prepared) -> &Ruler {
        if !p.variant.mode.info().transparent {
            let lit = p.settings.eye_dome_drawn().and_then(|edl| self.eye_dome_lit.iter().find(|(e, _)| *e == edl));
            return lit.map_or(&self.opaque, |(_, r)| r);
        }
        let key = drawn_environment(scene, &p.settings);
        self.own.iter().find(|(k, _)| *k == key).map_or(&self.with_opacity, |(_, r)| r)
    }
}

/// The mark of a row whose transparent mode ran on an opaque scene.
pub const OPAQUE_FALLBACK: &str = "opaque scene: ran two-pass";

/// A row of `mode` from `view` with the model's facts filled in and nothing measured yet.
pub(super) fn blank_row(
    name: &str,
    opened: &Opened,
    view: &str,
    config: &BenchConfig,
    variant: &str,
    mode: RenderMode,
) -> BenchRow {
    BenchRow {
        model: name.to_string(),
        mode: mode.name().to_string(),
        variant: variant.to_string(),
        reference: ruler_name(mode.info().transparent, config.settings.supersample),
        ruler: mode == RenderMode::RULER,
        fallback: None,
        view: view.to_string(),
        frame_ms: 0.0,
        frame_ms_min: 0.0,
        frame_ms_max: 0.0,
        gpu_ms: None,
        passes: Vec::new(),
        eps: 0.0,
        eps_by_layers: Vec::new(),
        image: String::new(),
        psnr: None,
        bad_pixel_share: 0.0,
        geometry_passes: 0,
        points: opened.scene.len(),
        width: config.width,
        height: config.height,
        load_s: opened.load_s,
        k: 1,
        group_s: None,
        shadow_ms: None,
        shadow_table_mib: None,
        frames: config.frames,
        frame: None,
        time: None,
        regroup_ms: None,
        budget_select_ms: None,
        triangles: None,
        window_overflows: None,
        tile_list_bytes: None,
        tile_retried: None,
        parts: None,
        path: None,
        upload_ms: None,
    }
}

/// Times one GPU variant from one view, measures it against `reference`
/// (ε, and ε by the reference's layer count per pixel) and saves its image
/// (and difference image) as `{stem}-{view}-{tag}.png`.
pub(super) fn measure_variant(
    renderer: &mut GpuRenderer,
    frames: &mut PreparedScene,
    view: &super::views::NamedView,
    p: &Prepared,
    config: &BenchConfig,
    reference: Option<&Ruler>,
    (stem, mut row): (&str, BenchRow),
) -> Result<BenchRow, BenchError> {
    let (Frame { image, plan, report }, wall, per_pass, profiled) =
        time_frames(renderer, frames, &view.camera, &p.spec, config)
            .map_err(|e| BenchError::Invalid(format!("{} ({} view): {e}", p.variant, view.name)))?;
    row.fallback = p.spec.opaque_fallback.then(|| OPAQUE_FALLBACK.to_string());
    row.window_overflows = report.window_overflows;
    if let Some(lists) = &report.tile_lists {
        row.tile_list_bytes = Some(lists.buffers.iter().map(|b| b.bytes).sum());
        row.tile_retried = Some(lists.retried);
    }
    row.parts = report.subframes.as_ref().map(|s| s.count);
    if p.settings.eye_dome_drawn().is_some() {
        row.reference += ", eye-dome lit"; // its ruler is (`Rulers::of_variant`)
    }
    if let Some(budget) = &report.budget {
        row.points = budget.splats;
        row.budget_select_ms = Some(budget.select_ms);
    }
    if let Some(hybrid) = &report.hybrid {
        row.points = hybrid.splats;
        row.triangles = Some(hybrid.triangles);
    }
    let tag = p.variant.file_tag();
    let file = format!("{stem}-{}-{tag}.png", view.name);
    save_png(&image, &config.out.join(&file))?;
    row.image = file;
    match reference {
        Some(ruler) => {
            let sizes_differ = || BenchError::Invalid("image and reference sizes differ".into());
            let error = reference::compare(&image, &ruler.image).ok_or_else(sizes_differ)?;
            row.eps_by_layers =
                reference::error_by_layers(&image, &ruler.image, &ruler.layers).ok_or_else(sizes_differ)?;
            if let Some(diff) = reference::difference_image(&image, &ruler.image, 8.0) {
                save_png(&diff, &config.out.join(format!("{stem}-{}-{tag}-diff.png", view.name)))?;
            }
            row.eps = error.eps;
            row.psnr = error.psnr.is_finite().then_some(error.psnr);
            row.bad_pixel_share = error.bad_pixel_share;
        }
        None => {
            // `--no-reference`: nothing to measure against (null in bench.json).
            (row.eps, row.psnr, row.bad_pixel_share) = (f64::NAN, None, f64::NAN);
            row.reference = super::report::NO_REFERENCE.into();
        }
    }
    let frame = spread(&wall);
    let passes: Vec<PassTime> = plan
        .steps
        .iter()
        .zip(&per_pass)
        .map(|(step, times)| {
            let s = spread(times);
            let pass = if profiled { format!("{} (CPU wall, waited alone)", step.name) } else { step.name.to_string() };
            PassTime { pass, ms: s.median, ms_min: s.min, ms_max: s.max }
        })
        .collect();
    row.k = p.k;
    row.group_s = p.group_s;
    (row.shadow_ms, row.shadow_table_mib) = (p.shadows.map(|s| s.0), p.shadows.map(|s| s.1));
    row.frame_ms = frame.median;
    row.frame_ms_min = frame.min;
    row.frame_ms_max = frame.max;
    row.gpu_ms = (!passes.is_empty() && !profiled).then(|| passes.iter().map(|p| p.ms).sum());
    row.passes = passes;
    row.geometry_passes = plan.geometry_passes();
    Ok(row)
}

/// `--ruler`'s ruler of one view: the variant's image (its frame time, and
/// the exact reference's layer count per pixel, for ε by layers), and its name.
fn mode_ruler(
    renderer: &mut GpuRenderer,
    frames: &mut PreparedScene,
    view: &super::views::NamedView,
    p: &Prepared,
    config: &BenchConfig,
    exact: &Ruler,
) -> Result<(Ruler, String), BenchError> {
    let (Frame { image, .. }, wall, _, _) = time_frames(renderer, frames, &view.camera, &p.spec, config)
        .map_err(|e| BenchError::Invalid(format!("{} ({} view, the ruler): {e}", p.variant, view.name)))?;
    let ms = spread(&wall).median;
    Ok((Ruler { image, ms, layers: exact.layers.clone() }, p.variant.label()))
}

/// Every view's rows of one model (`name`, its file stem `stem`): the
/// reference's, then each prepared variant's.
#[allow(clippy::too_many_arguments)]
pub(super) fn measure_views(
    (name, stem): (&str, &str),
    opened: &Opened,
    frames: &mut PreparedScene,
    prepared: &[Prepared],
    views: &[super::views::NamedView],
    config: &BenchConfig,
    renderer: &mut GpuRenderer,
) -> Result<Vec<BenchRow>, BenchError> {
    let bar =
        crate::progress::bar((views.len() * (prepared.len() + 1)) as u64, &format!("bench {stem}"), config.progress);
    let mut rows = Vec::new();
    for view in views {
        if config.no_reference {
            for p in prepared.iter().filter(|p| !p.ruler_only) {
                let blank = blank_row(name, opened, &view.name, config, &p.variant.label(), p.variant.mode);
                rows.push(measure_variant(renderer, frames, view, p, config, None, (stem, blank))?);
                bar.inc(1);
            }
            continue;
        }
        let row = |variant: &str, mode| blank_row(name, opened, &view.name, config, variant, mode);
        let rulers = Rulers::of(config, opened, prepared, &view.camera)?;
        let ruler_name = RenderMode::RULER.name();
        let with_opacity = format!("{stem}-{}-{ruler_name}.png", view.name);
        let opaque = format!("{stem}-{}-{ruler_name}-opaque.png", view.name);
        save_png(&rulers.with_opacity.image, &config.out.join(&with_opacity))?;
        if opened.scene.has_transparency() {
            save_png(&rulers.opaque.image, &config.out.join(&opaque))?;
        }
        for variant in config.variants.iter().filter(|v| !v.mode.is_gpu()) {
            let mut row = row(&variant.label(), variant.mode);
            let transparent = variant.mode.info().transparent;
            let ms = rulers.for_mode(transparent).ms;
            (row.frame_ms, row.frame_ms_min, row.frame_ms_max, row.frames) = (ms, ms, ms, 1);
            let apart = !transparent && opened.scene.has_transparency();
            row.image = if apart { opaque.clone() } else { with_opacity.clone() };
            rows.push(row);
        }
        bar.inc(1);
        // `--ruler MODE`: that mode's image of the view, with the reference's layer counts.
        let asked = match prepared.iter().find(|p| Some(&p.variant) == config.ruler.as_ref()) {
            Some(p) => Some(mode_ruler(renderer, frames, view, p, config, &rulers.with_opacity)?),
            None => None,
        };
        for p in prepared.iter().filter(|p| !p.ruler_only) {
            let mut blank = row(&p.variant.label(), p.variant.mode);
            let reference = match &asked {
                Some(asked) if Some(&p.variant) != config.ruler.as_ref() => {
                    blank.reference = format!("{} (--ruler)", asked.1);
                    &asked.0
                }
                _ => rulers.of_variant(&opened.scene, p),
            };
            rows.push(measure_variant(renderer, frames, view, p, config, Some(reference), (stem, blank))?);
            bar.inc(1);
        }
    }
    bar.finish();
    Ok(rows)
}
