//! `measure --polygon --volume` on generated tiles far from the origin
//! (UTM): a cone of radius 10 and height 5 on flat ground. The polygon's
//! horizontal area is exact; the volume above the base plane fitted along
//! the polygon's border is π·r²·h/3 within 2 %, with almost nothing below;
//! and the flat ground alone, as `--base`, gives the same volume.

mod common;

use std::path::Path;

use common::lidar::{LidarPoint, write};

const ORIGIN: [f64; 2] = [512_000.0, 5_400_000.0];
const GROUND: f64 = 230.0;

/// A grid of points `spacing` apart over ±15 about the origin, at the
/// ground height plus `height(r)` (r the distance from the centre).
fn field(spacing: f64, height: impl Fn(f64) -> f64) -> Vec<LidarPoint> {
    let n = (30.0 / spacing).round() as i64;
    let mut points = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (-15.0 + i as f64 * spacing, -15.0 + j as f64 * spacing);
            points.push(LidarPoint {
                xyz: [ORIGIN[0] + x, ORIGIN[1] + y, GROUND + height(x.hypot(y))],
                intensity: 100,
                class: 2,
                return_number: 1,
                returns: 1,
                gps_time: points.len() as f64,
                rgb: [30000, 30000, 30000],
            });
        }
    }
    points
}

fn measure(file: &Path, extra: &[&str]) -> serde_json::Value {
    let square: Vec<String> = [(-14.0, -14.0), (14.0, -14.0), (14.0, 14.0), (-14.0, 14.0)]
        .iter()
        .map(|(x, y)| format!("{},{}", ORIGIN[0] + x, ORIGIN[1] + y))
        .collect();
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("measure")
        .arg(file)
        .args(["--polygon", &square.join(" "), "--json"])
        .args(extra)
        .output()
        .unwrap();
    assert!(out.status.success(), "{extra:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).unwrap()
}

#[test]
fn a_cone_on_flat_ground_has_its_volume_against_the_border_plane_and_against_the_ground() {
    let dir = tempfile::tempdir().unwrap();
    let offset = [ORIGIN[0], ORIGIN[1], 0.0];
    let cone = write(&dir.path().join("cone.laz"), &field(0.2, |r| (5.0 * (1.0 - r / 10.0)).max(0.0)), offset, None);
    let ground = write(&dir.path().join("ground.las"), &field(0.3, |_| 0.0), offset, None);
    let expected = std::f64::consts::PI * 100.0 * 5.0 / 3.0;

    let area = measure(&cone, &[]);
    assert!((area["area_horizontal"].as_f64().unwrap() - 784.0).abs() < 1e-6, "{area}");
    assert!(area["volume_above"].is_null(), "{area}");
    // The cone's side (π·r·√(r²+h²)) and the ground around it.
    let surface = std::f64::consts::PI * 10.0 * 125f64.sqrt() + 784.0 - std::f64::consts::PI * 100.0;
    let area_surface = area["area_surface"].as_f64().unwrap();
    assert!((area_surface / surface - 1.0).abs() < 0.02, "surface {area_surface} vs {surface}");

    let stockpile = measure(&cone, &["--volume"]);
    let (above, below) = (stockpile["volume_above"].as_f64().unwrap(), stockpile["volume_below"].as_f64().unwrap());
    assert!((above / expected - 1.0).abs() < 0.02, "volume {above} vs {expected}: {stockpile}");
    assert!(below < 0.002 * expected, "volume below {below}");
    assert!(stockpile["cell"].as_f64().unwrap() > 0.0 && stockpile["units"].is_string(), "{stockpile}");

    let cut_fill = measure(&cone, &["--volume", "--base", ground.to_str().unwrap()]);
    let (above_ground, below_ground) =
        (cut_fill["volume_above"].as_f64().unwrap(), cut_fill["volume_below"].as_f64().unwrap());
    assert!((above_ground / expected - 1.0).abs() < 0.02, "volume over the ground {above_ground} vs {expected}");
    assert!((above_ground / above - 1.0).abs() < 0.005, "over the ground {above_ground}, over the plane {above}");
    assert!(below_ground < 0.002 * expected, "volume below the ground {below_ground}");
}
