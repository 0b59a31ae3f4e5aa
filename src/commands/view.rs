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

use anyhow::{Context, Result};
use pointblend::frame::{Parameter, Sidecar};
use pointblend::render::RenderMode;
use pointblend::viewer::{self, ViewerError, ViewerOptions};

pub use super::view_args::Args;

pub fn run(args: &Args) -> Result<()> {
    // Several files open as the virtual point cloud of them, which lives while the viewer runs.
    let layers = match &args.file {
        Some(first) if !args.layers.is_empty() => {
            let files: Vec<_> = std::iter::once(first.clone()).chain(args.layers.iter().cloned()).collect();
            Some(super::layers::layers_file(&files)?)
        }
        _ => None,
    };
    let file = layers.as_ref().map(|l| l.path.clone()).or_else(|| args.file.clone());
    let view = args.camera.as_deref().map(Sidecar::read).transpose()?;
    if let Some(file) = args.file.as_ref().filter(|f| !pointblend::copc::is_url(&f.to_string_lossy())) {
        // Fail early and on one line, before a window opens, when the file is not
        // there or not a file (a URL is opened by the stream, which says why it cannot).
        pointblend::input::regular_size(file).with_context(|| format!("{}: cannot open", file.display()))?;
    }
    args.camera_flags.request().check().map_err(|e| anyhow::anyhow!("--{e}"))?;
    super::shared::check_time(args.time)?;
    // A first window shows what pointblend is for: see-through surfaces.
    let first_run = args.file.is_none() && args.camera.is_none();
    // The flags' clip, else a screenshot's.
    let shot_clip = view.as_ref().and_then(|v| v.clip.clone()).unwrap_or_default();
    let clip = args.view.scene.clip_region_or(&shot_clip).map_err(anyhow::Error::msg)?;
    let options = ViewerOptions {
        file: match &file {
            Some(file) => Some(file.clone()),
            None if first_run => {
                Some(pointblend::assets::path(pointblend::assets::DEMO_SCENE).map_err(anyhow::Error::msg)?)
            }
            None => None,
        },
        screenshot: args.screenshot.clone(),
        exit_after_frames: args.exit_after_frames,
        screenshot_dir: args.screenshot_dir.clone(),
        view,
        mode: args.mode.or_else(|| first_run.then_some(RenderMode::FIRST_RUN)),
        cache: None,
        materials: args.view.scene.materials(args.view.parameters.given(Parameter::Background).is_some()),
        parameters: args.view.parameters.values(),
        environment: args.env.clone(),
        lights: args.view.scene.lights.clone(),
        clip,
        camera: args.camera_flags.request(),
        stream: args.view.stream.options(false),
        time: args.time,
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
            super::main_job::run(args, file.as_deref())
        }
    }
}
