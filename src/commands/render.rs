//! `pointblend render FILE`: one frame to a PNG, written atomically.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result};
use pointblend::render::HeadlessRenderer;

use super::shared::{self, ViewArgs};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// PLY file (a cloud, a mesh, or 3D Gaussian splats).
    pub file: PathBuf,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Output PNG.
    #[arg(long, default_value = "pointblend.png")]
    pub out: PathBuf,
    /// Print the passes and targets that will run.
    #[arg(long)]
    pub explain: bool,
}

impl Args {
    /// The no-subcommand default: the bundled bunny at 512x512.
    pub fn bundled_default() -> Self {
        use clap::Parser;
        #[derive(clap::Parser)]
        struct Wrapper {
            #[command(flatten)]
            args: Args,
        }
        let mut args = Wrapper::parse_from(["pointblend", shared::BUNDLED_MODEL]).args;
        args.out = PathBuf::from("pointblend.png");
        args
    }
}

pub fn run(args: &Args) -> Result<()> {
    let settings = args.view.settings()?;
    let started = Instant::now();
    let (cloud, _report) = shared::load(&args.file)?;
    let load_seconds = started.elapsed().as_secs_f64();
    let camera = args.view.camera(&cloud)?;
    let mut renderer = HeadlessRenderer::new().context("opening the GPU")?;
    log::info!("GPU: {}", renderer.ctx.describe());
    let gpu_cloud = renderer.upload(&cloud);
    let (width, height) = args.view.size;
    let render_started = Instant::now();
    let (image, plan) = renderer.render_image(&gpu_cloud, &camera, &settings, width, height)?;
    let render_seconds = render_started.elapsed().as_secs_f64();
    if args.explain {
        println!("{plan}");
    }
    shared::write_png_atomically(&image, &args.out)?;
    println!(
        "{}: {} splats, {} {}x{} in {:.0} ms (load {:.2} s) -> {}",
        args.file.display(),
        cloud.len(),
        plan.mode,
        width,
        height,
        render_seconds * 1e3,
        load_seconds,
        args.out.display()
    );
    Ok(())
}
