//! `pointblend bench FILE...`: load speed and per-frame time, as medians over repeats.
//!
//! Frames are timed as wall time from submission to the GPU going idle
//! (`poll(wait)`), after warm-up frames; loads are repeated and the body
//! decode speed reported in vertices per second.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use pointblend::cloud;
use pointblend::render::{HeadlessRenderer, Quality};

use super::shared::ViewArgs;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// PLY files.
    #[arg(required = true)]
    pub files: Vec<PathBuf>,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Timed frames per quality level (after the warm-up frames).
    #[arg(long, default_value_t = 10)]
    pub frames: usize,
    /// Timed loads per file.
    #[arg(long, default_value_t = 5)]
    pub loads: usize,
}

/// Untimed frames first: lavapipe compiles and warms its threads on the first frames.
const WARM_UP_FRAMES: usize = 5;

struct Stats {
    median: f64,
    min: f64,
    max: f64,
}

fn stats(mut samples: Vec<f64>) -> Stats {
    samples.sort_by(f64::total_cmp);
    let n = samples.len();
    let median = if n % 2 == 1 { samples[n / 2] } else { 0.5 * (samples[n / 2 - 1] + samples[n / 2]) };
    Stats { median, min: samples[0], max: samples[n - 1] }
}

pub fn run(args: &Args) -> Result<()> {
    if args.frames == 0 || args.loads == 0 {
        bail!("--frames and --loads must be at least 1");
    }
    let mut renderer = HeadlessRenderer::new().context("opening the GPU")?;
    let (width, height) = args.view.size;
    println!("GPU: {}", renderer.ctx.describe());
    println!(
        "| model | splats | decode M vertices/s (median of {}) | full load s | quality | frame ms median (min-max) of {} |",
        args.loads, args.frames
    );
    println!("|---|---:|---:|---:|---|---:|");
    for file in &args.files {
        let mut decode_rates = Vec::new();
        let mut load_seconds = Vec::new();
        let mut loaded = None;
        for _ in 0..args.loads {
            let started = Instant::now();
            let (c, report) = cloud::load(file)?;
            load_seconds.push(started.elapsed().as_secs_f64());
            decode_rates.push(report.vertices_in_file as f64 / report.decode_seconds.max(1e-9) / 1e6);
            loaded = Some(c);
        }
        let Some(cloud) = loaded else { continue };
        let camera = args.view.camera(&cloud)?;
        let gpu_cloud = renderer.upload(&cloud);
        let decode = stats(decode_rates);
        let load = stats(load_seconds);
        for quality in [Quality::Filtered, Quality::Unfiltered] {
            let mut settings = args.view.settings()?;
            settings.quality = quality;
            let mut frame_ms = Vec::new();
            for frame in 0..args.frames + WARM_UP_FRAMES {
                let started = Instant::now();
                renderer.render(&gpu_cloud, &camera, &settings, width, height)?;
                renderer.ctx.wait_idle()?;
                if frame >= WARM_UP_FRAMES {
                    frame_ms.push(started.elapsed().as_secs_f64() * 1e3);
                }
            }
            let f = stats(frame_ms);
            println!(
                "| {} | {} | {:.1} | {:.2} | {} {:?} {}x{} | {:.1} ({:.1}-{:.1}) |",
                file.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default(),
                cloud.len(),
                decode.median,
                load.median,
                settings.mode,
                quality,
                width,
                height,
                f.median,
                f.min,
                f.max
            );
        }
    }
    Ok(())
}
