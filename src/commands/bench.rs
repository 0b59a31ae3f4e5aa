//! `pointblend bench FILE...`: error against run time for every mode variant, and load speed.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use pointblend::bench::{self, BenchConfig};
use pointblend::cloud;
use pointblend::frame::Parameter;
use pointblend::render::{GpuRenderer, RenderMode};

use super::shared::ViewArgs;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[arg(required = true, help = super::formats_help::benched_files())]
    pub files: Vec<PathBuf>,
    /// Draw the files together, as layers of one scene (each its own object and origin),
    /// instead of one benchmark each.
    #[arg(long)]
    pub together: bool,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Mode variants to run, comma-separated: a mode name runs it with its
    /// defaults, then its cheaper settings (two-pass: unfiltered; depth-peel and
    /// approx-peel: fewer layers, down to 2); MODE:KEY=VALUE...
    /// runs one, e.g. deferred:group=wgc-k8:voronoi=off, two-pass:quality=unfiltered.
    /// The reference is always rendered (it is the ruler).
    #[arg(long, value_delimiter = ',', default_value = "two-pass,deferred,reference")]
    pub modes: Vec<String>,
    /// Measure every row against this mode variant (MODE[:KEY=VALUE...]) instead of
    /// the exact reference, e.g. depth-peel:layers=8, the ruler of Zhang & Pajarola's
    /// ε (its own row, if listed, is still measured against the reference) [default: reference].
    #[arg(long, value_name = "VARIANT")]
    pub ruler: Option<String>,
    /// Time the GPU modes without rendering the exact reference, for a scene whose
    /// CPU reference would take too long (assets/lion-grid.toml at 1920x1080 on a GPU
    /// machine): rows have no error, bench.md gives millions of splats per second instead.
    #[arg(long, conflicts_with_all = ["ruler", "animate"])]
    pub no_reference: bool,
    /// Timed frames per mode and view.
    #[arg(long, default_value_t = 10)]
    pub frames: usize,
    /// Untimed frames before them (lavapipe compiles and warms up on the first frames).
    #[arg(long, default_value_t = 5)]
    pub warm_up: usize,
    /// Views per model: front, side, back-top, close-up, grazing (in this order).
    #[arg(long, default_value_t = bench::views::MAX_VIEWS)]
    pub views: usize,
    /// perspective or ortho: the projection of every view [default: perspective].
    #[arg(long)]
    pub projection: Option<pointblend::frame::Projection>,
    /// A named view (top, bottom, front, back, left, right, iso) as the first view; the
    /// others turn around it.
    #[arg(long = "view", value_name = "VIEW", conflicts_with = "path")]
    pub named_view: Option<pointblend::frame::NamedView>,
    /// Times the views of a camera path instead (a views file: what `render --path` flies
    /// through and the viewer's bookmarks save), in path order in one process. Each row of
    /// a path view carries what that view cost: view_index, nodes_added, bytes_read,
    /// points_prepared, prepare_s and upload_bytes.
    #[arg(long, value_name = "VIEWS.json", conflicts_with_all = ["views", "animate"])]
    pub path: Option<PathBuf>,
    /// Timed loads per file for the decode speed.
    #[arg(long, default_value_t = 3)]
    pub loads: usize,
    /// Also time the back-to-front orders (BSP, bucket, full sort) on each view: orders.json and a table in bench.md.
    /// With --modes none, only the orders are timed.
    #[arg(long)]
    pub orders: bool,
    /// Output folder for bench.json, bench.md, error_vs_time.png, images and the reference cache.
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Renders N frames spread evenly over one period of a moving scene's
    /// longest animation (or its whole sequence): each row gets its frame,
    /// time, regroup and upload milliseconds and ε against that frame's reference.
    #[arg(long, value_name = "N")]
    pub animate: Option<usize>,
    #[arg(long, value_name = "FILE", help = format!("{}; variants choose the effects with env-layers=single|multi|off", super::shared::environment_help()))]
    pub env: Option<PathBuf>,
}

/// Most frames `--animate` renders.
const MAX_ANIMATE_FRAMES: usize = 1000;

pub fn run(args: &Args) -> Result<()> {
    if args.frames == 0 || args.loads == 0 {
        bail!("--frames and --loads must be at least 1");
    }
    if args.animate == Some(0) {
        bail!("--animate needs at least 1 frame");
    }
    if let Some(frames) = args.animate.filter(|n| *n > MAX_ANIMATE_FRAMES) {
        bail!(
            "--animate {frames}: at most {MAX_ANIMATE_FRAMES} frames (each frame writes an image and a difference image per mode and view)"
        );
    }
    if args.views == 0 || args.views > bench::views::MAX_VIEWS {
        bail!("--views must be 1..={}", bench::views::MAX_VIEWS);
    }
    let ruler = match args.ruler.as_deref() {
        None | Some("reference") => None,
        Some(text) => {
            match pointblend::bench::variants::expand(text).map_err(|e| anyhow::anyhow!("--ruler: {e}"))?.as_slice() {
                [one] if one.mode.is_gpu() => Some(one.clone()),
                [_] => bail!("--ruler {text}: the reference is the default ruler; give a GPU mode's variant"),
                _ => bail!("--ruler {text}: one variant, e.g. {text}:KEY=VALUE"),
            }
        }
    };
    if ruler.is_some() && args.animate.is_some() {
        bail!("--ruler measures still frames; --animate measures each frame against its own reference");
    }
    let mut variants = Vec::new();
    let no_modes = args.modes.iter().all(|m| m == "none");
    if no_modes && !args.orders {
        bail!("--modes none leaves nothing to run: add --orders, or name modes");
    }
    for text in args.modes.iter().filter(|m| *m != "none") {
        variants.extend(pointblend::bench::variants::expand(text).map_err(|e| anyhow::anyhow!("--modes: {e}"))?);
    }
    let budget = args.view.stream_budget()?;
    for file in args.files.iter().filter(|f| !pointblend::copc::drawn_by_nodes(f, budget)) {
        let mut rates = Vec::new();
        for _ in 0..args.loads {
            let started = Instant::now();
            // A file that does not load is reported (and skipped) by the benchmark itself.
            let Ok((_, report)) = cloud::load(file) else { break };
            let total = started.elapsed().as_secs_f64();
            rates.push((report.vertices_in_file as f64 / report.decode_seconds.max(1e-9) / 1e6, total));
        }
        if rates.is_empty() {
            continue;
        }
        rates.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (rate, total) = rates[rates.len() / 2];
        println!(
            "{}: body decode {rate:.1} M vertices/s, full load {total:.2} s (median of {})",
            file.display(),
            args.loads
        );
    }
    let mut renderer = GpuRenderer::new().context("opening the GPU")?;
    println!("GPU: {}", renderer.ctx.describe());
    let environment = match &args.env {
        Some(path) => {
            let map = pointblend::scene::environment_map::EnvironmentMap::load(path)?;
            if map.cleaned > 0 {
                log::warn!("{}: {} negative or non-finite values set to 0", path.display(), map.cleaned);
            }
            Some(std::sync::Arc::new(map))
        }
        None => None,
    };
    let config = BenchConfig {
        environment,
        stream: args.view.stream.options(true),
        variants,
        settings: args.view.base_settings(&pointblend::scene::Scene::default(), RenderMode::DEFAULT)?,
        materials: args.view.scene.materials(args.view.parameters.given(Parameter::Background).is_some()),
        width: args.view.size.0,
        height: args.view.size.1,
        frames: args.frames,
        warm_up: args.warm_up,
        views: args.views,
        out: args.out.clone(),
        progress: true,
        orders: args.orders,
        animate: args.animate,
        camera: pointblend::frame::CameraRequest {
            projection: args.projection,
            view: args.named_view,
            ..Default::default()
        },
        time: None,
        path: args.path.as_deref().map(pointblend::frame::ViewPath::read).transpose()?,
        stream_budget: args.view.stream_budget()?,
        ruler,
        no_reference: args.no_reference,
    };
    let (files, _layers) = benched(args)?;
    let outcome = bench::run(&files, &config, &mut renderer)?;
    if !outcome.rows.is_empty() {
        print!("{}", bench::report::markdown(&outcome.rows));
    }
    if args.orders {
        print!("{}", bench::orders::markdown(&outcome.orders));
    }
    if outcome.rows.is_empty() {
        println!("wrote {}/bench.json, bench.md and orders.json", args.out.display());
    } else if args.no_reference {
        println!("wrote {}/bench.json, bench.md and the images", args.out.display());
    } else {
        println!("wrote {}/bench.json, bench.md, error_vs_time.png and the images", args.out.display());
    }
    if !outcome.skipped.is_empty() {
        bail!(
            "{} of {} files could not be benchmarked and have no rows ({})",
            outcome.skipped.len(),
            args.files.len(),
            outcome.skipped.join("; ")
        );
    }
    Ok(())
}

/// The models to measure: the files, or with `--together` one `.vpc` of
/// them (kept alive by the second value while the benchmark runs).
fn benched(args: &Args) -> Result<(Vec<PathBuf>, Option<super::layers::LayersFile>)> {
    if !args.together {
        return Ok((args.files.clone(), None));
    }
    if args.files.len() < 2 {
        bail!("--together draws several files as layers of one scene; give at least two");
    }
    let layers = super::layers::layers_file(&args.files)?;
    Ok((vec![layers.path.clone()], Some(layers)))
}
