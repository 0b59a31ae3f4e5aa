//! `pointblend info FILE.vpc`: what a virtual point cloud states of its
//! files (PDAL's STAC FeatureCollection, [`pointblend::scene::vpc`]): how
//! many, their points (`pc:count`), their CRS (`proj:epsg`, units from
//! the code) and the box around theirs, then one line per file. No file is
//! opened; a local file that is not there is named on a line of its own,
//! and the command fails in one line saying how many are missing.

use std::path::Path;

use anyhow::{Result, bail};
use glam::DVec3;
use pointblend::scene::vpc::{self, VpcFile};

/// A box as `info` prints it.
fn shown_box((lo, hi): (DVec3, DVec3)) -> String {
    let z = |v: f64| if v.is_finite() { format!("{v:.6}") } else { "any".into() };
    format!("[{:.6}, {:.6}, {}] .. [{:.6}, {:.6}, {}]", lo.x, lo.y, z(lo.z), hi.x, hi.y, z(hi.z))
}

/// The CRS line: the one code the files state, or what is odd about them.
fn crs_line(files: &[VpcFile]) -> String {
    let mut codes: Vec<u32> = files.iter().filter_map(|f| f.epsg).collect();
    codes.sort_unstable();
    codes.dedup();
    let unstated = files.iter().filter(|f| f.epsg.is_none()).count();
    match codes.as_slice() {
        [] => "not stated (no proj:epsg)".into(),
        [code] if unstated == 0 => format!("EPSG:{code}"),
        [code] => format!("EPSG:{code} ({unstated} files state none)"),
        many => {
            let names: Vec<String> = many.iter().map(|c| format!("EPSG:{c}")).collect();
            format!("{} (mixed: layers must share one CRS)", names.join(", "))
        }
    }
}

pub fn run(file: &Path) -> Result<()> {
    let files = vpc::read(file).map_err(|reason| anyhow::anyhow!("{}: {reason}", file.display()))?;
    println!("file:        {}", file.display());
    println!("encoding:    virtual point cloud (STAC FeatureCollection), {} files", files.len());
    let counted: u64 = files.iter().filter_map(|f| f.points).sum();
    let uncounted = files.iter().filter(|f| f.points.is_none()).count();
    match uncounted {
        0 => println!("points:      {counted}"),
        n => println!("points:      {counted} in the files that state theirs ({n} state none)"),
    }
    println!("crs:         {}", crs_line(&files));
    let codes: std::collections::BTreeSet<u32> = files.iter().filter_map(|f| f.epsg).collect();
    if let (1, Some(&code)) = (codes.len(), codes.first()) {
        if let Some(unit) = pointblend::cloud::crs_units::unit_of_code(code) {
            println!("units:       horizontal {} (from EPSG:{code})", unit.name);
        }
    }
    let boxes: Vec<(DVec3, DVec3)> = files.iter().filter_map(|f| f.bounds).collect();
    if let Some(first) = boxes.first() {
        let around = boxes.iter().fold(*first, |(lo, hi), (l, h)| (lo.min(*l), hi.max(*h)));
        println!("bounds:      {}", shown_box(around));
    }
    let mut missing = 0;
    for f in &files {
        let shown = pointblend::copc::shown(&f.path.to_string_lossy());
        let absent = !pointblend::copc::is_url(&f.path.to_string_lossy()) && !f.path.is_file();
        missing += usize::from(absent);
        let points = f.points.map_or("? points".into(), |n| format!("{n} points"));
        let bounds = f.bounds.map_or("no box".into(), shown_box);
        let state = if absent { "  MISSING" } else { "" };
        println!("layer:       {shown}: {points}, {bounds}{state}");
    }
    if missing > 0 {
        bail!("{}: {missing} of its {} files are not there", file.display(), files.len());
    }
    Ok(())
}
