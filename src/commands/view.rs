//! `pointblend view [FILE]`: the interactive viewer, and the main job.
//!
//! Without FILE the window opens on the demo scene (`assets/demo.toml`)
//! in `alg2`, so that the first frame shows see-through surfaces.
//!
//! With no display (no `DISPLAY`/`WAYLAND_DISPLAY`) or when the window cannot
//! open, it says why and does the headless main job instead: the opaque modes
//! on the bundled lion and the transparent modes on the demo scene (or every
//! mode on FILE), into `./out/`, with one compact table, `bench.json`, the
//! error-against-time plot and a contact sheet of every mode (`modes.png`).

use std::path::PathBuf;

use anyhow::{Context, Result};
use pointblend::frame::Sidecar;
use pointblend::render::RenderMode;
use pointblend::scene::Materials;
use pointblend::viewer::{self, ViewerError, ViewerOptions};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// PLY file or scene file (.toml) to open (default: the demo scene).
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
    /// Image size of the headless main job.
    #[arg(long, default_value = "512x512", value_parser = super::shared::parse_size)]
    pub size: (u32, u32),
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
    /// A white point light at X,Y,Z in the model's file coordinates (repeatable, at most 8 with the scene's);
    /// lights replace the headlight and cast translucent shadows. The viewer adds, moves and deletes them too.
    #[arg(long = "light", value_parser = super::shared::parse_light, allow_hyphen_values = true)]
    pub lights: Vec<pointblend::frame::Light>,
}

pub fn run(args: &Args) -> Result<()> {
    let view = args.camera.as_deref().map(Sidecar::read).transpose()?;
    if let Some(file) = &args.file {
        // Fail early and on one line, before a window opens, when the file is not there.
        std::fs::metadata(file).with_context(|| format!("{}: cannot open", file.display()))?;
    }
    // A first window shows what pointblend is for: see-through surfaces.
    let first_run = args.file.is_none() && args.camera.is_none();
    let options = ViewerOptions {
        file: args.file.clone().or_else(|| first_run.then(|| viewer::DEMO_SCENE.into())),
        screenshot: args.screenshot.clone(),
        exit_after_frames: args.exit_after_frames,
        screenshot_dir: args.screenshot_dir.clone(),
        view,
        mode: args.mode.or_else(|| first_run.then_some(RenderMode::FIRST_RUN)),
        cache: None,
        materials: Materials {
            opacity: args.opacity,
            colour: args.colour,
            scene_background: args.background.is_none(),
        },
        background: args.background.map(|c| glam::Vec3::from_array(c.map(f32::from)) / 255.0),
        environment: args.env.clone(),
        lights: args.lights.clone(),
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
            super::main_job::run(args)
        }
    }
}
