//! `pointblend convert IN OUT [--points N]`: a mesh or cloud (PLY, LAS,
//! LAZ, E57) to a splat cloud PLY, or to LAS/LAZ/COPC by OUT's extension, with
//! every attribute (a LAS/LAZ/COPC input to LAS/LAZ: its records copied as
//! they are, format, scale, offset and CRS kept); or a scalar volume (NIfTI-1, `.nii` / `.nii.gz`) to one point per
//! voxel above a threshold, coloured by a transfer function (`--transfer`).
//! OUT's extension must name a format the registry says `convert` writes.
//! `--clip-box`, `--clip-plane`, `--classes`, `--filter` and `--returns`
//! write only the points they keep ([`super::subset_args`]).

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use pointblend::cloud::{self, LoadOptions};
use pointblend::formats::{self, Format, Reader};

#[derive(clap::Args, Debug)]
pub struct Args {
    #[arg(help = super::formats_help::converted_input())]
    pub input: PathBuf,
    #[arg(help = super::formats_help::converted_output())]
    pub output: PathBuf,
    /// Sample this many splats uniformly over the mesh surface instead of using its vertices.
    #[arg(long)]
    pub points: Option<usize>,
    /// A volume's transfer function: VALUE:R/G/B/A,... with values increasing, R, G, B in 0..255 and A in 0..1
    /// [default: transparent below the values' 60th percentile, faint at the 80th, white and 0.7 at the 99th].
    #[arg(long, value_parser = parse_transfer)]
    pub transfer: Option<pointblend::cloud::volume::Transfer>,
    /// A volume's least value that makes a point [default: where the transfer function's opacity rises above 0].
    #[arg(long, allow_negative_numbers = true)]
    pub threshold: Option<f32>,
    #[command(flatten)]
    pub subset: super::subset_args::SubsetArgs,
}

fn parse_transfer(text: &str) -> Result<pointblend::cloud::volume::Transfer, String> {
    text.parse()
}

/// Whether `path` names a NIfTI volume.
fn is_volume(path: &std::path::Path) -> bool {
    let name = path.file_name().map(|n| n.to_string_lossy().to_lowercase()).unwrap_or_default();
    name.ends_with(".nii") || name.ends_with(".nii.gz")
}

/// A volume to points.
fn run_volume(args: &Args, format: &Format) -> Result<()> {
    if format.reader == Reader::Copc {
        bail!("a volume converts to PLY, LAS or LAZ; convert that file to COPC");
    }
    if args.points.is_some() {
        bail!("--points samples a mesh; a volume makes one point per voxel above --threshold");
    }
    if let Some(t) = args.threshold.filter(|t| !t.is_finite()) {
        bail!("--threshold must be a finite value, not {t}");
    }
    super::shared::prepare_output(&args.output)?;
    let options = pointblend::cloud::volume::VolumeOptions {
        transfer: args.transfer.clone(),
        threshold: args.threshold,
        progress: true,
    };
    let (cloud, report) = pointblend::cloud::volume::volume_to_points(&args.input, &options)?;
    let source = args.input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let comments = vec![
        format!("pointblend convert from {source}: one point per voxel at or above {}", report.threshold),
        format!("transfer {}", report.transfer.to_text()),
        format!("normals from the 3D Sobel gradient, radius half the voxel diagonal, units {}", report.units),
    ];
    if format.reader == Reader::Las {
        cloud::write_las::write_las(&cloud, &args.output)?;
    } else {
        cloud::write::write_ply(&cloud, &args.output, &comments)?;
    }
    let [x, y, z] = report.dims;
    println!(
        "{} -> {}: {x}x{y}x{z} voxels of {:.3}x{:.3}x{:.3} {}, values {}..{}, {} points at or above {} (transfer {})",
        args.input.display(),
        args.output.display(),
        report.voxel[0],
        report.voxel[1],
        report.voxel[2],
        report.units,
        report.range.0,
        report.range.1,
        cloud.len(),
        report.threshold,
        report.transfer.to_text()
    );
    Ok(())
}

/// The format OUT's extension names, refused unless `convert` writes it.
fn output_format(output: &Path) -> Result<&'static Format> {
    let name = output.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    match formats::by_extension(&name) {
        Some(format) if format.written => Ok(format),
        found => {
            let what = match (found, output.extension()) {
                (Some(format), _) => format!("not {}", format.name),
                (None, Some(ext)) => format!("not '.{}'", ext.to_string_lossy()),
                (None, None) => "and this name has no extension".to_string(),
            };
            bail!("{}: convert writes {}, {what}", output.display(), formats::names_with_extensions(|f| f.written))
        }
    }
}

pub fn run(args: &Args) -> Result<()> {
    let format = output_format(&args.output)?;
    super::shared::refuse_same_file(&args.output, "the input", &args.input)?;
    if is_volume(&args.input) {
        if args.subset.is_given() {
            bail!(
                "--clip-box, --clip-plane, --classes, --filter and --returns choose points of a cloud, not of a volume"
            );
        }
        return run_volume(args, format);
    }
    if args.transfer.is_some() || args.threshold.is_some() {
        bail!("--transfer and --threshold apply to volumes (.nii, .nii.gz), not {}", args.input.display());
    }
    if is_url(&args.input) {
        if args.points.is_some() {
            bail!("{}: --points samples a mesh's surface; a URL is a point cloud", args.input.display());
        }
        // Its records, of the nodes that meet --clip-box: to LAS/LAZ/PLY as they are, or to COPC.
        return if format.reader == Reader::Copc { run_copc(args) } else { run_records(args) };
    }
    if format.reader == Reader::Copc && args.points.is_none() {
        return run_copc(args);
    }
    if cloud::las_file::is_las(&args.input) && format.reader == Reader::Las && args.points.is_none() {
        return run_records(args);
    }
    let (cloud, report) = load_for_convert(args)?;
    let (cloud, left_out) = args.subset.apply(cloud, &args.input)?;
    super::shared::prepare_output(&args.output)?;
    let source = args.input.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let mut comments = vec![format!("pointblend convert from {source}")];
    comments.push(format!("normals {}, radii {}, colours {}", report.normals, report.radii, report.colours));
    if format.reader != Reader::Ply {
        cloud::write_las::write_las(&cloud, &args.output)?;
    } else {
        cloud::write::write_ply(&cloud, &args.output, &comments)?;
    }
    let subset = if args.subset.is_given() { format!(", {left_out} left out by the subset") } else { String::new() };
    println!(
        "{} -> {}: {} splats (normals {}, radii {}, mean radius {:.6}{subset})",
        args.input.display(),
        args.output.display(),
        cloud.len(),
        report.normals,
        report.radii,
        cloud.mean_radius()
    );
    Ok(())
}

/// The input as a cloud: its points, or `--points` samples of its surface.
fn load_for_convert(args: &Args) -> Result<(cloud::PointCloud, cloud::LoadReport)> {
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
    Ok((cloud, report))
}

/// LAS/LAZ/COPC to LAS/LAZ: the records the subset keeps (all without
/// one), copied as they are: point format, scale and offset, CRS and every
/// field kept.
fn run_records(args: &Args) -> Result<()> {
    super::shared::prepare_output(&args.output)?;
    let started = std::time::Instant::now();
    let records = input_records(args, true)?;
    let keep = args.subset.kept_records(&records, &args.input)?;
    records.write_subset(&keep, &args.output)?;
    let subset = if args.subset.is_given() {
        format!(", {} left out by the subset", records.len() - keep.len())
    } else {
        String::new()
    };
    println!(
        "{} -> {}: {} of {} point records copied with every field, the scale, offset and CRS kept{subset}, in {:.1} s",
        args.input.display(),
        args.output.display(),
        keep.len(),
        records.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// To COPC: a LAS/LAZ input's records as they are (a subset's copied to a
/// temporary LAS first); any other cloud through
/// a LAS file of its splats (normals, radii and opacity as extra bytes).
fn run_copc(args: &Args) -> Result<()> {
    super::shared::prepare_output(&args.output)?;
    let started = std::time::Instant::now();
    let las_input;
    let url = is_url(&args.input);
    let input = if cloud::las_file::is_las(&args.input) && !args.subset.is_given() && !url {
        args.input.as_path()
    } else if cloud::las_file::is_las(&args.input) || url {
        let records = input_records(args, false)?;
        let keep = args.subset.kept_records(&records, &args.input)?;
        las_input = pointblend::output::Temporary::with_suffix(".las")?;
        records.write_subset(&keep, las_input.path())?;
        las_input.path()
    } else {
        let (cloud, _) = super::shared::load(&args.input)?;
        let (cloud, _) = args.subset.apply(cloud, &args.input)?;
        las_input = pointblend::output::Temporary::with_suffix(".las")?;
        cloud::write_las::write_las(&cloud, las_input.path())?;
        las_input.path()
    };
    let written = pointblend::copc::write::write_copc(input, &args.output, true)?;
    println!(
        "{} -> {}: {} points in {} nodes, {} levels, {:.1} MB, in {:.1} s",
        args.input.display(),
        args.output.display(),
        written.points,
        written.nodes,
        written.depth + 1,
        written.bytes as f64 / 1e6,
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// Whether the input is an http(s) URL (of a COPC file).
fn is_url(input: &std::path::Path) -> bool {
    pointblend::copc::is_url(&input.to_string_lossy())
}

/// The input's records: a URL's of the nodes that meet the subset's box
/// (every node without one), read node by node; a file's, read whole.
fn input_records(args: &Args, progress: bool) -> Result<cloud::records::Records> {
    if is_url(&args.input) {
        let stream = super::stream_args::StreamArgs::default();
        return super::region_records::records_in(&args.input, &stream, args.subset.region());
    }
    Ok(cloud::records::Records::read(&args.input, &LoadOptions { progress, ..Default::default() })?)
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
