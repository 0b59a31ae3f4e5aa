//! `pointblend view [FILE]`: the interactive viewer, and the main job.
//!
//! With no display (no `DISPLAY`/`WAYLAND_DISPLAY`) or when the window cannot
//! open, it says why and does the headless main job instead: it renders the
//! model in every mode to `./out/` and prints the error-against-time table.

use std::path::PathBuf;

use anyhow::{Context, Result};
use pointblend::bench::{self, BenchConfig};
use pointblend::frame::ModeVariant;
use pointblend::frame::{RenderSettings, Sidecar};
use pointblend::render::{HeadlessRenderer, RenderMode};
use pointblend::scene::Materials;
use pointblend::viewer::{self, ViewerError, ViewerOptions};

#[derive(clap::Args, Debug, Default)]
pub struct Args {
    /// PLY file or scene file (.toml) to open (default: the bundled bunny).
    pub file: Option<PathBuf>,
    /// Save a screenshot of the whole window (UI included) to this PNG once the
    /// first full-quality frame is shown, then close (for documentation and tests).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Close after this many frames once the view has settled.
    #[arg(long)]
    pub exit_after_frames: Option<u64>,
    /// Start with the mode, parameters and camera of a screenshot's JSON sidecar.
    #[arg(long)]
    pub camera: Option<PathBuf>,
    /// Mode to start in (see `render --help` for the list).
    #[arg(long)]
    pub mode: Option<RenderMode>,
    /// Folder for screenshots saved with Ctrl+S.
    #[arg(long, default_value = "screenshots")]
    pub screenshot_dir: PathBuf,
    /// Output folder of the headless main job (when no window can open).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    /// Opacity of every object, 0..1.
    #[arg(long, value_parser = super::shared::parse_opacity)]
    pub opacity: Option<f32>,
    /// Colour R,G,B (0..255) that replaces every object's own.
    #[arg(long = "color", value_parser = super::shared::parse_rgb)]
    pub colour: Option<[u8; 3]>,
    /// Background colour R,G,B (0..255) [default: the scene's, else 28,31,36].
    #[arg(long, value_parser = super::shared::parse_rgb)]
    pub background: Option<[u8; 3]>,
    /// Environment map the model is set in (equirectangular OpenEXR, HDR, PNG
    /// or JPEG; assets/venice.exr is bundled); alg2 and the reference draw it.
    #[arg(long, value_name = "FILE")]
    pub env: Option<PathBuf>,
}

pub fn run(args: &Args) -> Result<()> {
    let view = args.camera.as_deref().map(Sidecar::read).transpose()?;
    if let Some(file) = &args.file {
        // Fail early and on one line, before a window opens, when the file is not there.
        std::fs::metadata(file).with_context(|| format!("{}: cannot open", file.display()))?;
    }
    let options = ViewerOptions {
        file: args.file.clone(),
        screenshot: args.screenshot.clone(),
        exit_after_frames: args.exit_after_frames,
        screenshot_dir: args.screenshot_dir.clone(),
        view,
        mode: args.mode,
        cache: None,
        materials: Materials {
            opacity: args.opacity,
            colour: args.colour,
            scene_background: args.background.is_none(),
        },
        background: args.background.map(|c| glam::Vec3::from_array(c.map(f32::from)) / 255.0),
        environment: args.env.clone(),
    };
    match viewer::run_window(options) {
        Ok(()) => Ok(()),
        Err(e) => {
            if args.screenshot.is_some() {
                // A requested window screenshot cannot be faked by the headless job.
                return Err(e).context("no window screenshot was taken");
            }
            match e {
                ViewerError::NoDisplay => eprintln!("pointblend: no window: {e}; rendering headless instead"),
                ViewerError::Window(_) => eprintln!("pointblend: {e}; rendering headless instead"),
            }
            headless_main_job(args)
        }
    }
}

/// Renders the model in every mode into `args.out` and prints the error-against-time table.
fn headless_main_job(args: &Args) -> Result<()> {
    let model = args.file.clone().unwrap_or_else(|| PathBuf::from(viewer::BUNDLED_MODEL));
    let mut renderer = HeadlessRenderer::new().context("opening the GPU")?;
    eprintln!("GPU: {}", renderer.ctx.describe());
    let mut variants = Vec::new();
    for mode in RenderMode::ALL {
        variants.extend(ModeVariant::expand(mode.name()).map_err(anyhow::Error::msg)?);
    }
    let mut settings = RenderSettings::default();
    if let Some(bg) = args.background {
        settings.shading.background = glam::Vec3::from_array(bg.map(f32::from)) / 255.0;
    }
    let environment = match &args.env {
        Some(path) => Some(std::sync::Arc::new(pointblend::scene::environment::EnvironmentMap::load(path)?)),
        None => None,
    };
    let config = BenchConfig {
        environment,
        variants,
        settings,
        materials: Materials {
            opacity: args.opacity,
            colour: args.colour,
            scene_background: args.background.is_none(),
        },
        width: 512,
        height: 512,
        frames: 5,
        warm_up: 2,
        views: 1,
        out: args.out.clone(),
        progress: true,
        orders: false,
    };
    let outcome = bench::run(&[model], &config, &mut renderer)?;
    print!("{}", bench::report::markdown(&outcome.rows));
    println!(
        "wrote one image per mode, the difference images, bench.json and error_vs_time.png to {}/",
        args.out.display()
    );
    Ok(())
}
