//! The profile tool in the viewer, driven with egui_kittest: a line clicked
//! on the orthographic top view of a lidar tile cuts a slab holding the
//! points `profile` holds for the same line and width, the panel's CSV
//! export is the file `profile --csv` writes, and a screenshot's sidecar
//! records the line and the width.

mod common;

use common::lidar::{tilted_grid, write};
use common::viewer::{click, harness_sized, options, save_screenshot, to_ortho_top, wait_for};
use egui_kittest::kittest::Queryable;
use glam::DVec3;
use pointblend::render::RenderMode;
use pointblend::viewer::ViewerOptions;

const TALL: [f32; 2] = [900.0, 1300.0];

/// (x, y, z) of every row of a profile CSV, sorted.
fn rows(csv: &str) -> Vec<[f64; 3]> {
    let mut rows: Vec<[f64; 3]> = csv
        .lines()
        .skip(1)
        .map(|line| {
            let v: Vec<f64> = line.split(',').take(5).map(|f| f.parse().unwrap()).collect();
            [v[2], v[3], v[4]]
        })
        .collect();
    rows.sort_by(|a, b| a.partial_cmp(b).unwrap());
    rows
}

#[test]
fn a_profile_drawn_on_the_top_view_holds_the_points_profile_holds() {
    let dir = tempfile::tempdir().unwrap();
    let mut points = tilted_grid(80, 0.5, 0.1, [1000.0, 2000.0, 50.0]);
    for p in &mut points {
        p.xyz[2] += (4.0 - 0.5 * (p.xyz[0] - 1020.0).abs()).max(0.0);
    }
    let file = write(&dir.path().join("ridge.las"), &points, [0.0; 3], None);
    let viewer = ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(dir.path()) };
    let mut h = harness_sized(viewer, TALL);
    to_ortho_top(&mut h);
    h.get_by_label("profile").click();
    h.step();
    for (x, y) in [(1004.0, 2012.0), (1036.0, 2023.0)] {
        let at = h.state().screen_position(DVec3::new(x, y, 53.0)).expect("in view");
        click(&mut h, at);
    }
    wait_for(&mut h, "the profile's slab", |app| app.profile_slab().is_some_and(|s| s.is_ok()));
    let inspect = h.state().inspection().clone();
    let [a, b] = inspect.profile_line[..] else { panic!("two ends: {:?}", inspect.profile_line) };
    let mut shown: Vec<[f64; 3]> =
        h.state().profile_slab().unwrap().as_ref().unwrap().points.iter().map(|p| p.to_array()).collect();
    shown.sort_by(|p, q| p.partial_cmp(q).unwrap());

    let csv = dir.path().join("profile.csv");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["profile".as_ref(), file.as_os_str()])
        .args(["--line", &format!("{},{},{},{}", a.x, a.y, b.x, b.y), "--width", &inspect.profile_width.to_string()])
        .arg("--csv")
        .arg(&csv)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let profiled = rows(&std::fs::read_to_string(&csv).unwrap());
    assert!(profiled.len() > 100, "{} points in the slab", profiled.len());
    assert_eq!(shown.len(), profiled.len(), "the slab on screen holds the points profile holds");
    // The window holds its points in f32 to within RESIDUAL_KEPT of a file unit.
    let slack = pointblend::cloud::placement::RESIDUAL_KEPT;
    for (p, q) in shown.iter().zip(&profiled) {
        assert!((0..3).all(|k| (p[k] - q[k]).abs() <= slack), "{p:?} against {q:?}");
    }

    let exported = dir.path().join("exported.csv");
    let ctx = h.ctx.clone();
    h.state_mut().export_profile(&ctx, &exported);
    wait_for(&mut h, "the export", |app| !app.is_exporting());
    assert_eq!(std::fs::read(&exported).unwrap(), std::fs::read(&csv).unwrap(), "the panel's CSV is profile --csv's");

    let sidecar = save_screenshot(&mut h, dir.path()).with_extension("json");
    let recorded =
        pointblend::frame::Sidecar::read(&sidecar).unwrap().profile.expect("the sidecar records the profile");
    assert_eq!(recorded.line, [a.x, a.y, b.x, b.y]);
    assert_eq!(recorded.width, inspect.profile_width);
}
