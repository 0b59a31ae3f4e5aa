//! The flags of `pointblend view`, which the window and the headless main
//! job both read (its own module, so that neither imports the other). The
//! window takes every camera, streaming and time flag that `render` takes.

use std::path::PathBuf;

use pointblend::render::RenderMode;

use super::shared::{CameraArgs, ViewArgs};

#[derive(clap::Args, Debug)]
pub struct Args {
    #[arg(help = super::formats_help::opened_by_view())]
    pub file: Option<PathBuf>,
    /// More files opened with the first, as layers of one scene (each its own object and origin).
    #[arg(id = "more_files", value_name = "MORE")]
    pub layers: Vec<PathBuf>,
    /// Save a screenshot of the whole window (UI included) to this PNG once the
    /// first full-quality frame is shown, then close (for documentation and tests).
    #[arg(long)]
    pub screenshot: Option<PathBuf>,
    /// Close after this many frames once the view has settled.
    #[arg(long)]
    pub exit_after_frames: Option<u64>,
    /// Start with the mode, parameters and camera of a screenshot's JSON sidecar.
    #[arg(long, value_name = "SIDECAR.json")]
    pub camera: Option<PathBuf>,
    /// Mode to start in [default: two-pass; alg2 with no file, on the demo
    /// scene]: tiled (exact) is the fastest mode on an H200 but takes
    /// 1.16-2.19 times two-pass's frame on lavapipe (README, "Render modes").
    #[arg(long, value_parser = super::shared::mode_parser())]
    pub mode: Option<RenderMode>,
    /// Folder for screenshots saved with Ctrl+S and Ctrl+Shift+S.
    #[arg(long, default_value = "screenshots")]
    pub screenshot_dir: PathBuf,
    /// Output folder of the headless main job (when no window can open).
    #[arg(long, default_value = "out")]
    pub out: PathBuf,
    #[command(flatten)]
    pub camera_flags: CameraArgs,
    /// Size of the headless main job's images, and the rest of `render`'s view flags.
    #[command(flatten)]
    pub view: ViewArgs,
    #[arg(long, value_name = "FILE", help = super::shared::environment_help())]
    pub env: Option<PathBuf>,
    /// Start a moving scene at this time, in seconds (paused there; animations loop).
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub time: Option<f64>,
}
