//! The flags of `pointblend view`, which the window and the headless main
//! job both read (its own module, so that neither imports the other).

use std::path::PathBuf;

use pointblend::render::RenderMode;

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
    #[command(flatten)]
    pub scene: super::scene_args::SceneArgs,
    #[command(flatten)]
    pub parameters: super::parameter_flags::ParameterFlags,
    /// Environment map the model is set in (equirectangular OpenEXR, HDR, PNG
    /// or JPEG; assets/venice.exr is bundled); alg2 and the reference draw it.
    #[arg(long, value_name = "FILE")]
    pub env: Option<PathBuf>,
}
