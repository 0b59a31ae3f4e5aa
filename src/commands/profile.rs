//! `pointblend profile FILE --line X1,Y1,X2,Y2 --width W`: a cross-section.
//! The slab is every point of the file (at full resolution: its records,
//! [`pointblend::cloud::records`]; of a streamed file, the records of the
//! nodes the slab meets, [`super::region_records`]) within W/2 of the line and between its
//! ends ([`pointblend::inspect::profile`]), after `--classes`, `--filter`
//! and `--returns`. `--csv` writes its rows, `--points` its records (LAS/LAZ
//! copied with every field, or PLY), and `--out` draws it: the slab's
//! records and those within W/2 around it (a lidar file; another format as
//! loaded), styled by the view flags, drawn as
//! [`pointblend::render::section`] draws a section: clipped to the slab by
//! four planes and seen in orthographic from the right of the line
//! (distance along the line against height), in any mode, every splat
//! turned to face the viewer.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use glam::DVec2;
use pointblend::cloud::records::RecordSource;
use pointblend::frame::RenderMode;
use pointblend::inspect::profile::{self, Profile};
use pointblend::render::section;
use pointblend::scene::Scene;
use pointblend::style::filter;

use super::shared::{self, ViewArgs};

#[derive(clap::Args, Debug)]
pub struct Args {
    #[arg(help = super::formats_help::profiled_file())]
    pub file: PathBuf,
    /// The profile's line X1,Y1,X2,Y2 on the ground, in file coordinates (the CRS's units).
    #[arg(long, value_parser = profile::parse_line, allow_hyphen_values = true)]
    pub line: (DVec2, DVec2),
    /// The slab's width: the points at most W/2 from the line, between its ends.
    #[arg(long)]
    pub width: f64,
    /// Draw the slab from the side (orthographic, distance along the line against height) to this image.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the slab's points as CSV: distance,offset,x,y,z and every attribute, one row per point.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write the slab's points to this cloud (LAS/LAZ: the records with every field; PLY), by extension.
    #[arg(long)]
    pub points: Option<PathBuf>,
    /// Rendering mode of --out.
    #[arg(long, default_value_t = RenderMode::DEFAULT, value_parser = shared::mode_parser())]
    pub mode: RenderMode,
    /// --out's size, parameters and style; --classes, --filter and --returns choose the slab's points too.
    #[command(flatten)]
    pub view: ViewArgs,
}

pub fn run(args: &Args) -> Result<()> {
    let (start, end) = args.line;
    let profile = Profile::new(start, end, args.width).map_err(anyhow::Error::msg)?;
    for out in [&args.out, &args.csv, &args.points].into_iter().flatten() {
        shared::refuse_same_file(out, "the input", &args.file)?;
        shared::prepare_output(out)?;
    }
    // The points within half a width around the slab size its splats: read them too.
    let around = profile.widened(args.width * 0.5);
    let reach = DVec2::splat(around.width * 0.5);
    let region = (around.start.min(around.end) - reach, around.start.max(around.end) + reach);
    let records = super::region_records::records_in(&args.file, &args.view.stream, region)?;
    let scene_flags = &args.view.scene;
    let classes = (!scene_flags.classes.is_empty()).then_some(scene_flags.classes.as_slice());
    let chosen =
        filter::kept_of(&records.attributes, records.len(), classes, &scene_flags.filters, scene_flags.returns)
            .map_err(|e| anyhow::anyhow!("{}: {e}", args.file.display()))?;
    let slab: Vec<u32> = chosen.iter().copied().filter(|&i| profile.holds(records.positions[i as usize])).collect();
    println!(
        "{}: {} of {} points in the slab ({:.3} long, {} wide, {})",
        shared::shown_path(&args.file),
        slab.len(),
        records.len(),
        profile.length(),
        args.width,
        records.units.horizontal_name()
    );
    if let Some(csv) = &args.csv {
        pointblend::inspect::profile_table::write_csv(&profile, &records, &slab, csv)
            .with_context(|| format!("{}: cannot write", csv.display()))?;
        println!("{} rows -> {}", slab.len(), csv.display());
    }
    if let Some(points) = &args.points {
        records.write_subset(&slab, points)?;
        println!("{} points -> {}", slab.len(), points.display());
    }
    if let Some(out) = &args.out {
        if slab.is_empty() {
            bail!("{}: no point lies in the slab, so there is nothing to draw", shared::shown_path(&args.file));
        }
        let heights = slab.iter().map(|&i| records.positions[i as usize].z);
        let (low, high) = heights.fold((f64::MAX, f64::MIN), |(l, h), z| (l.min(z), h.max(z)));
        let scene = if matches!(records.source, RecordSource::Las(_) | RecordSource::Raw { .. }) {
            // A LAS, LAZ or COPC file (or URL) is drawn from the slab's own records and those
            // around it, not opened again whole: only their radii are estimated.
            let prefix = format!("{}-slab-", pointblend::output::safe_stem(&args.file));
            let slab_file = pointblend::output::Temporary::named(&prefix, ".las")?;
            // The slab and the points around it: the clip planes cut the drawing to the slab.
            let near: Vec<u32> = chosen.into_iter().filter(|&i| around.holds(records.positions[i as usize])).collect();
            records.write_subset(&near, slab_file.path())?;
            drop(records);
            shared::load_scene(slab_file.path())?
        } else {
            // Another format's records are its loaded splats, with the normals and radii it gives.
            drop(records);
            shared::load_scene(&args.file)?
        };
        draw(args, scene, &profile, (low, high), out)?;
    }
    Ok(())
}

/// The side view of the slab at `out` ([`pointblend::render::section`]).
fn draw(args: &Args, mut scene: Scene, profile: &Profile, heights: (f64, f64), out: &std::path::Path) -> Result<()> {
    section::face_the_side(&mut scene, profile);
    args.view.scene.apply_materials(&mut scene).map_err(anyhow::Error::msg)?;
    let settings = args.view.settings(&scene, args.mode)?;
    let region = args.view.scene.clip_region(&scene).map_err(anyhow::Error::msg)?;
    let (width, height) = args.view.size;
    let (image, mode) = section::draw(scene, profile, heights, settings, region, (width, height))?;
    shared::write_image(&image, out)?;
    println!("{mode} {width}x{height} side view -> {}", out.display());
    Ok(())
}
