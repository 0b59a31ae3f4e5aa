//! `pointblend measure FILE --polygon "X1,Y1 X2,Y2 ..." [--volume [--base
//! OTHER]] [--cell C]`: areas and volumes over the file's records at full
//! resolution ([`pointblend::inspect::area_volume`]), after `--classes`,
//! `--filter` and `--returns`, in the CRS's units; text, or `--json`.

use anyhow::Result;
use pointblend::cloud::records::Records;
use pointblend::inspect::area_volume::{self, Base, BaseUsed};
use pointblend::inspect::polygon::Polygon;
use pointblend::style::filter;

use super::pick;
use super::shared;

/// The flags of `measure` that measure inside a polygon.
#[derive(clap::Args, Debug)]
pub struct PolygonArgs {
    /// Measure inside this polygon instead of between pixels: "X1,Y1 X2,Y2 X3,Y3 ..." in file
    /// coordinates; gives the horizontal area and the surface area of the points inside.
    #[arg(long, allow_hyphen_values = true)]
    pub polygon: Option<Polygon>,
    /// With --polygon: also the volume above and below a base (a plane fitted to the points along
    /// the polygon's border, or --base).
    #[arg(long, requires = "polygon")]
    pub volume: bool,
    /// With --volume: the base is this other cloud (the same CRS), e.g. the ground before: cut and fill.
    #[arg(long, requires = "volume", value_name = "FILE")]
    pub base: Option<std::path::PathBuf>,
    /// With --polygon: the grid's cell size, in the file's units [default: twice the mean spacing of the points inside].
    #[arg(long, requires = "polygon")]
    pub cell: Option<f64>,
}

/// The records of `file` around `polygon` (a streamed file's nodes that
/// meet its box, a margin of `cell` or 5 % of its size around it) the
/// scene flags keep, as file positions.
fn positions(
    file: &std::path::Path,
    args: &pick::Args,
    (polygon, cell): (&Polygon, Option<f64>),
) -> Result<(Vec<glam::DVec3>, Records)> {
    let (lo, hi) = polygon.bounds();
    let margin = glam::DVec2::splat(cell.unwrap_or(0.0).max(0.05 * lo.distance(hi)));
    let records = super::region_records::records_in(file, &args.view.stream, (lo - margin, hi + margin))?;
    let flags = &args.view.scene;
    let classes = (!flags.classes.is_empty()).then_some(flags.classes.as_slice());
    let kept = filter::kept_of(&records.attributes, records.len(), classes, &flags.filters, flags.returns)
        .map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))?;
    Ok((kept.iter().map(|&i| records.positions[i as usize]).collect(), records))
}

pub fn run(args: &pick::Args, area: &PolygonArgs, polygon: &Polygon) -> Result<()> {
    let file = &args.file;
    // Every layer's points (a `.vpc`'s files too), in one CRS.
    let paths: Vec<std::path::PathBuf> = std::iter::once(file.clone()).chain(args.layers.iter().cloned()).collect();
    let files = pointblend::scene::layers::layer_files(&paths)?;
    let (mut points, records) = positions(&files[0].path, args, (polygon, area.cell))?;
    // One CRS for the layers and the base, checked as `render A B` checks it.
    let mut crs = pointblend::scene::layers::SharedCrs::default();
    let mut admit = |path: &std::path::Path, r: &Records| {
        crs.admit(&path.display().to_string(), r.units.epsg, r.crs.as_deref())
            .map_err(|why| anyhow::anyhow!("{}: {why}", path.display()))
    };
    admit(&files[0].path, &records)?;
    for layer in &files[1..] {
        let (more, other) = positions(&layer.path, args, (polygon, area.cell))?;
        admit(&layer.path, &other)?;
        points.extend(more);
    }
    let base_cloud = match &area.base {
        Some(other) => {
            let (points, base_records) = positions(other, args, (polygon, area.cell))?;
            admit(other, &base_records)?;
            Some(points)
        }
        None => None,
    };
    let base = match (&base_cloud, area.volume) {
        (Some(points), _) => Some(Base::Points(points)),
        (None, true) => Some(Base::BorderPlane),
        (None, false) => None,
    };
    let m = area_volume::area_and_volume(polygon, &points, area.cell, base)
        .map_err(|e| anyhow::anyhow!("{}: {e}", file.display()))?;
    let (h, v) = (records.units.horizontal_name(), records.units.vertical_name());
    if m.cells_empty > 0 {
        log::warn!(
            "{}: {} of the {} cells inside have no point within {} cells and are left out",
            file.display(),
            m.cells_empty,
            m.cells,
            area_volume::FILL_RINGS
        );
    }
    if args.json {
        let base_file = area.base.as_ref().map(|p| p.display().to_string());
        let value = area_volume::report_json(&m, &records.units, base_file);
        println!("{}", serde_json::to_string_pretty(&value)?);
        return Ok(());
    }
    println!("{}: {} points inside the polygon, on cells of {:.4} {h}", shared::shown_path(file), m.points, m.cell);
    println!("area: {:.4} square {h} horizontal, {:.4} of surface", m.area_horizontal, m.area_surface);
    if let Some(volume) = &m.volume {
        let base = match &volume.base {
            BaseUsed::Plane { points, .. } => format!("a plane fitted to {points} points along the border"),
            BaseUsed::Cloud { points, .. } => format!("the {points} points of the base cloud"),
        };
        println!(
            "volume: {:.4} above and {:.4} below {base} ({h} x {h} x {v}), net {:+.4}",
            volume.above,
            volume.below,
            volume.above - volume.below
        );
    }
    Ok(())
}
