//! `pointblend convert IN OUT [--points N]`: a mesh or cloud to a splat cloud PLY.

use std::path::PathBuf;

use anyhow::{Result, bail};
use pointblend::cloud::{self, LoadOptions};

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Input PLY (mesh or cloud).
    pub input: PathBuf,
    /// Output PLY: binary, x y z nx ny nz radius red green blue.
    pub output: PathBuf,
    /// Sample this many splats uniformly over the mesh surface instead of using its vertices.
    #[arg(long)]
    pub points: Option<usize>,
}

pub fn run(args: &Args) -> Result<()> {
    if args.input == args.output {
        bail!("{}: the output would overwrite the input", args.output.display());
    }
    let (cloud, report) = match args.points {
        Some(0) => bail!("--points must be at least 1"),
        Some(n) => {
            check_sample_count(n)?;
            let options = LoadOptions { progress: true, ..Default::default() };
            let (cloud, report) = cloud::load_surface_samples(&args.input, n, &options)?;
            for w in &report.warnings {
                log::warn!("{}: {w}", args.input.display());
            }
            (cloud, report)
        }
        None => super::shared::load(&args.input)?,
    };
    super::shared::prepare_output(&args.output)?;
    let source = args.input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let mut comments = vec![format!("pointblend convert from {source}")];
    comments.push(format!("normals {}, radii {}, colours {}", report.normals, report.radii, report.colours));
    cloud::write::write_ply(&cloud, &args.output, &comments)?;
    println!(
        "{} -> {}: {} splats (normals {}, radii {}, mean radius {:.6})",
        args.input.display(),
        args.output.display(),
        cloud.len(),
        report.normals,
        report.radii,
        cloud.mean_radius()
    );
    Ok(())
}

/// Refuses a sample count that the splat indices (u32) or the machine's
/// memory cannot hold, before any work starts.
fn check_sample_count(n: usize) -> Result<()> {
    if n > u32::MAX as usize {
        bail!("--points {n}: at most {} splats can be rendered (32-bit indices)", u32::MAX);
    }
    let needed = (n as u64).saturating_mul(pointblend::cloud::mesh::BYTES_PER_SAMPLE);
    if let Some(available) = pointblend::memory::available_bytes() {
        if needed > available {
            let most = available / pointblend::cloud::mesh::BYTES_PER_SAMPLE;
            bail!(
                "--points {n}: sampling needs about {} but only {} of memory is available; use at most about {most}",
                pointblend::memory::gib(needed),
                pointblend::memory::gib(available)
            );
        }
    }
    Ok(())
}
