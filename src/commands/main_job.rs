//! The headless main job of `pointblend view` (no display, or no window):
//! without FILE, the opaque modes on the bundled lion and every transparent
//! mode on the demo scene and on the lidar demo (a tile coloured by class,
//! its vegetation translucent), each against its model's exact reference; with
//! FILE, every mode on it. It prints one row per mode at its defaults (what
//! it renders, ε, ms, geometry passes), writes `bench.json` and the
//! error-against-time plot of every row, and the contact sheet `modes.png`
//! (`bench::sheet`), and says in one line where they are.

use std::path::PathBuf;

use anyhow::{Context, Result};
use pointblend::bench::{self, BenchConfig, BenchRow};
use pointblend::frame::{Parameter, RenderSettings};
use pointblend::render::{GpuRenderer, RenderMode};

use super::view_args::Args;

/// One model of the main job, the modes it is rendered in, and the folder.
struct Part {
    model: PathBuf,
    modes: Vec<RenderMode>,
    out: PathBuf,
}

/// With `file` (FILE, or the `.vpc` of FILE and MORE): every mode on it, into `args.out`. Without: the opaque modes
/// on the bundled lion and the transparent ones on the demo scene (the
/// lion at 0.5 with opaque balls inside and around it) and the lidar demo, each into its own
/// folder under `args.out`, so that every transparent mode shows what it is
/// for. Then one compact table, `bench.json` and the plot of all rows, and
/// the contact sheet `modes.png`.
pub fn run(args: &Args, file: Option<&std::path::Path>) -> Result<()> {
    let asset = |name| pointblend::assets::path(name).map_err(anyhow::Error::msg);
    let parts = match file {
        Some(file) => vec![Part { model: file.to_path_buf(), modes: RenderMode::ALL.to_vec(), out: args.out.clone() }],
        None => {
            let (transparent, opaque): (Vec<RenderMode>, Vec<RenderMode>) =
                RenderMode::ALL.into_iter().filter(|m| m.is_gpu()).partition(|m| m.info().transparent);
            let with_ruler = |modes: Vec<RenderMode>| [modes, vec![RenderMode::RULER]].concat();
            vec![
                Part {
                    model: asset(pointblend::assets::BUNDLED_MODEL)?,
                    modes: with_ruler(opaque),
                    out: args.out.join("lion"),
                },
                Part {
                    model: asset(pointblend::assets::DEMO_SCENE)?,
                    modes: with_ruler(transparent.clone()),
                    out: args.out.join("demo-scene"),
                },
                Part {
                    model: asset(pointblend::assets::LIDAR_DEMO)?,
                    modes: with_ruler(transparent),
                    out: args.out.join("lidar"),
                },
            ]
        }
    };
    let mut renderer = GpuRenderer::new().context("opening the GPU")?;
    eprintln!("GPU: {}", renderer.ctx.describe());
    let environment = match &args.env {
        Some(path) => Some(std::sync::Arc::new(pointblend::scene::environment_map::EnvironmentMap::load(path)?)),
        None => None,
    };
    let mut rows = Vec::new();
    let mut sheet = Vec::new();
    for part in &parts {
        let mut variants = Vec::new();
        for mode in &part.modes {
            variants.extend(pointblend::bench::variants::expand(mode.name()).map_err(anyhow::Error::msg)?);
        }
        let mut settings = RenderSettings::default();
        args.view.parameters.apply(&mut settings).map_err(anyhow::Error::msg)?;
        let config = BenchConfig {
            environment: environment.clone(),
            stream: args.view.stream.options(true),
            variants,
            settings,
            materials: args.view.scene.materials(args.view.parameters.given(Parameter::Background).is_some()),
            width: args.view.size.0,
            height: args.view.size.1,
            frames: 5,
            warm_up: 2,
            views: 1,
            out: part.out.clone(),
            progress: true,
            orders: false,
            animate: None,
            camera: args.camera_flags.request(),
            time: args.time,
            path: None,
            stream_budget: args.view.stream_budget()?,
            ruler: None,
            no_reference: false,
        };
        let outcome = bench::run(std::slice::from_ref(&part.model), &config, &mut renderer)?;
        sheet.push(sheet_row(part, &outcome.rows));
        rows.extend(outcome.rows);
    }
    print!("{}", compact_table(&rows));
    let json = args.out.join("bench.json");
    bench::report::write_json(&rows, &json).with_context(|| format!("{}: cannot write", json.display()))?;
    let title = format!("error against frame time, {}x{}", args.view.size.0, args.view.size.1);
    bench::plot::write(&rows, &title, &args.out.join("error_vs_time.png")).map_err(anyhow::Error::msg)?;
    bench::sheet::write(&sheet, 256, &args.out.join("modes.png")).map_err(anyhow::Error::msg)?;
    println!(
        "wrote {0}/modes.png (every mode side by side), {0}/bench.json, {0}/error_vs_time.png, and each image with its difference image in {1}",
        args.out.display(),
        if parts.len() > 1 { "the model folders under it" } else { "it" }
    );
    Ok(())
}

/// The rows of the modes at their defaults (one per mode and model), each
/// model's reference first.
fn default_rows(rows: &[BenchRow]) -> Vec<&BenchRow> {
    let mut models: Vec<&str> = rows.iter().map(|r| r.model.as_str()).collect();
    models.dedup();
    let mut out = Vec::new();
    for model in models {
        let of_model = rows.iter().filter(|r| r.model == model);
        out.extend(of_model.clone().filter(|r| r.ruler));
        out.extend(of_model.filter(|r| !r.ruler && r.variant == r.mode));
    }
    out
}

/// ε with three digits below 0.1, two above.
fn eps_text(eps: f64) -> String {
    if eps < 0.1 { format!("{eps:.3}") } else { format!("{eps:.2}") }
}

/// Whether a row's mode draws transparency.
fn transparent_mode(row: &BenchRow) -> bool {
    row.mode.parse::<RenderMode>().is_ok_and(|m| m.info().transparent && m.is_gpu())
}

/// What a row renders: its model, transparent or opaque, and the fallback if any.
fn renders(row: &BenchRow) -> String {
    match &row.fallback {
        _ if row.ruler => format!("{} (exact, on the CPU)", row.model),
        Some(note) => format!("{} ({note})", row.model),
        None if transparent_mode(row) => format!("{} (transparent)", row.model),
        None => format!("{} (opaque)", row.model),
    }
}

/// One row per mode at its default settings: mode, what it renders, ε, ms, geometry passes.
fn compact_table(rows: &[BenchRow]) -> String {
    let mut out = String::from("| mode | renders | ε | ms | geometry passes |\n|---|---|---:|---:|---:|\n");
    for r in default_rows(rows) {
        let eps = if r.ruler { "ruler".to_string() } else { eps_text(r.eps) };
        let passes = match (r.ruler, r.geometry_passes) {
            (true, _) => "CPU".to_string(),
            // A GPU mode that draws no splat pass rasterises in compute passes.
            (false, 0) => "0 (compute)".to_string(),
            (false, n) => n.to_string(),
        };
        out.push_str(&format!("| {} | {} | {eps} | {:.0} | {passes} |\n", r.variant, renders(r), r.frame_ms));
    }
    out
}

/// The contact sheet's row of one part: its reference, then each mode at its defaults.
fn sheet_row(part: &Part, rows: &[BenchRow]) -> bench::sheet::SheetRow {
    let tiles = default_rows(rows)
        .into_iter()
        .map(|r| {
            let figures = match (&r.fallback, r.ruler) {
                (_, true) => format!("exact, {:.0} ms (CPU)", r.frame_ms),
                (Some(note), _) => format!("ε {}, {:.0} ms: {note}", eps_text(r.eps), r.frame_ms),
                (None, _) => format!("ε {}, {:.0} ms", eps_text(r.eps), r.frame_ms),
            };
            bench::sheet::Tile { image: part.out.join(&r.image), title: r.variant.clone(), figures }
        })
        .collect();
    let model = rows.first().map_or_else(|| part.model.display().to_string(), |r| r.model.clone());
    let kinds = match (rows.iter().any(transparent_mode), rows.iter().any(|r| !r.ruler && !transparent_mode(r))) {
        (true, false) => "transparent modes",
        (false, true) => "opaque modes",
        _ => "every mode",
    };
    bench::sheet::SheetRow { heading: format!("{model}: the exact reference, then the {kinds}"), tiles }
}
