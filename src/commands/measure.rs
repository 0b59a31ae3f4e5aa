//! `pointblend measure FILE --at X1,Y1 --at X2,Y2 …`: the nearest layer's
//! point under each pixel (as `pick` finds it), and the distance, the
//! polyline's segments, the angles at its vertices and the height
//! differences along the view's up axis (crates/core/src/inspect/measure.rs).
//! With `--polygon`: the horizontal and surface areas inside it and, with
//! `--volume`, the volume above and below a base, over the file's records
//! ([`super::measure_area`]).

use anyhow::{Result, bail};
use pointblend::inspect::measure;
use serde_json::json;

use super::pick::Picking;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub pick: super::pick::Args,
    #[command(flatten)]
    pub area: super::measure_area::PolygonArgs,
}

pub fn run(args: &Args) -> Result<()> {
    if let Some(polygon) = &args.area.polygon {
        if !args.pick.at.is_empty() {
            bail!("--polygon measures the file's points inside it; --at picks pixels: give one or the other");
        }
        return super::measure_area::run(&args.pick, &args.area, polygon);
    }
    let args = &args.pick;
    if args.at.len() < 2 {
        bail!("measure needs at least two --at pixels, {} given", args.at.len());
    }
    let picking = Picking::open(args)?;
    let mut points = Vec::with_capacity(args.at.len());
    for &(x, y) in &args.at {
        let report = picking.pick((x, y));
        let Some(nearest) = report.layers.first() else {
            bail!("{}: pixel {x},{y} shows no surface (its ray meets nothing)", super::shared::shown_path(&args.file));
        };
        points.push(nearest.position);
    }
    let up = picking.camera.up.frame().0.as_dvec3();
    let m = measure(&points, up);
    if args.json {
        let value = json!({
            "points": args.at.iter().zip(&m.points).map(|(&(x, y), p)| json!({"pixel": [x, y], "position": p.to_array()})).collect::<Vec<_>>(),
            "distance": m.distance,
            "segments": m.segments.iter().map(|s| json!({"from": s.from, "to": s.to, "length": s.length, "height": s.height})).collect::<Vec<_>>(),
            "angle_deg": m.angles_deg.first(),
            "angles_deg": m.angles_deg,
            "height": m.height,
        });
        println!("{}", serde_json::to_string_pretty(&value)?);
        return Ok(());
    }
    for (k, (&(x, y), p)) in args.at.iter().zip(&m.points).enumerate() {
        println!("point {}: pixel ({x}, {y}) at ({:.4}, {:.4}, {:.4})", k + 1, p.x, p.y, p.z);
    }
    for s in &m.segments {
        println!("segment {}-{}: length {:.4}, height {:+.4}", s.from + 1, s.to + 1, s.length, s.height);
    }
    for (k, a) in m.angles_deg.iter().enumerate() {
        println!("angle at point {}: {a:.3}°", k + 2);
    }
    println!("distance: {:.4} (polyline), height difference first to last: {:+.4}", m.distance, m.height);
    Ok(())
}
