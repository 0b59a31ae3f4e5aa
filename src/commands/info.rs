//! `pointblend info FILE`: counts, properties, bounds, and what loading estimated or repaired.

use std::path::PathBuf;

use anyhow::Result;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[arg(help = super::formats_help::described_by_info())]
    pub file: PathBuf,
}

pub fn run(args: &Args) -> Result<()> {
    if pointblend::scene::vpc::is_vpc(&args.file) {
        return super::info_vpc::run(&args.file);
    }
    if pointblend::copc::is_streamed(&args.file) {
        return super::info_streamed::run(&args.file);
    }
    let started = std::time::Instant::now();
    let (cloud, report) = super::shared::load(&args.file)?;
    let seconds = started.elapsed().as_secs_f64();
    println!("file:        {}", args.file.display());
    println!("encoding:    {}", report.encoding);
    for line in &report.format_details {
        println!("format:      {line}");
    }
    match &report.crs {
        Some(crs) => println!("crs:         {}", crs.split_whitespace().collect::<Vec<_>>().join(" ")),
        None if !report.format_details.is_empty() => println!("crs:         none declared"),
        None => {}
    }
    super::shared::print_units(&cloud.units, report.crs.is_some());
    for comment in &report.comments {
        println!("comment:     {comment}");
    }
    for (name, count, properties) in &report.elements {
        println!("element:     {name} x {count}: {}", properties.join(" "));
    }
    println!("splats:      {} (of {} vertices in the file)", cloud.len(), report.vertices_in_file);
    if report.faces_in_file > 0 {
        println!("faces:       {}", report.faces_in_file);
    }
    if let Some(b) = cloud.bounds() {
        let (o, unit) = (cloud.origin, cloud.unit());
        let file = |v: glam::Vec3| [0, 1, 2].map(|a| v[a] as f64 * unit + o[a]);
        let (lo, hi) = (file(b.min), file(b.max));
        println!(
            "bounds:      [{:.6}, {:.6}, {:.6}] .. [{:.6}, {:.6}, {:.6}]",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]
        );
        let size = (b.max - b.min).as_dvec3() * unit;
        println!("size:        {:.6} x {:.6} x {:.6}", size.x, size.y, size.z);
        println!("re-centred:  by ({:.6}, {:.6}, {:.6})", o[0], o[1], o[2]);
        if cloud.scale_exponent != 0 {
            println!("rescaled:    positions and radii are in units of 1e{}", cloud.scale_exponent);
        }
    }
    super::shared::print_attributes(&cloud.attributes);
    println!("normals:     {}", report.normals);
    println!("radii:       {} (mean {:.6})", report.radii, cloud.mean_radius());
    println!("colours:     {}", report.colours);
    println!(
        "opacity:     {}{}",
        report.opacity,
        if cloud.has_transparency() { " (some splats are transparent)" } else { "" }
    );
    if let Some(s) = cloud.scanner_position {
        println!(
            "scan:        single view, scanner at the file origin ({:.4}, {:.4}, {:.4} after re-centring)",
            s.x, s.y, s.z
        );
    }
    if report.warnings.is_empty() {
        println!("repairs:     none");
    }
    for w in &report.warnings {
        println!("repaired:    {w}");
    }
    println!(
        "load time:   {:.3} s (body decoded in {:.3} s = {:.1} M vertices/s; estimation {:.3} s)",
        seconds,
        report.decode_seconds,
        report.vertices_in_file as f64 / report.decode_seconds.max(1e-9) / 1e6,
        report.estimate_seconds
    );
    Ok(())
}
