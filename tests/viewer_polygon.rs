//! The polygon tool in the viewer, driven with egui_kittest: four clicks on
//! the orthographic top view of a sloping tile make a polygon whose areas
//! and volume are `measure --polygon --volume`'s for the same vertices (to
//! the precision the window holds its points in), in the JSON `measure
//! --json` prints, which the panel copies. Against a base layer, the
//! volume is `measure --base`'s cut and fill.

mod common;

use common::lidar::{tilted_grid, write};
use common::viewer::{Dropped, choose, click, harness_sized, options, settled_in, to_ortho_top, wait_for};
use egui_kittest::kittest::Queryable;
use glam::DVec3;
use pointblend::render::RenderMode;
use pointblend::viewer::ViewerOptions;

const TALL: [f32; 2] = [900.0, 1300.0];

/// A 40 m square tile rising 1 in 5 eastwards, with a bump of `bump` m in the middle.
fn slope(bump: f64) -> Vec<common::lidar::LidarPoint> {
    let mut points = tilted_grid(80, 0.5, 0.2, [1000.0, 2000.0, 50.0]);
    for p in &mut points {
        let d = ((p.xyz[0] - 1020.0).powi(2) + (p.xyz[1] - 2020.0).powi(2)).sqrt();
        p.xyz[2] += (bump - 0.5 * d).max(0.0);
    }
    points
}

/// Clicks the polygon's four vertices on the top view.
fn click_polygon(h: &mut egui_kittest::Harness<'_, pointblend::viewer::ViewerApp>) {
    h.get_by_label("polygon").click();
    h.step();
    for (x, y) in [(1010.0, 2010.0), (1031.0, 2008.0), (1030.0, 2031.0), (1009.0, 2029.0)] {
        let at = h.state().screen_position(DVec3::new(x, y, 50.0 + 0.2 * (x - 1000.0))).expect("in view");
        click(h, at);
    }
    assert_eq!(h.state().inspection().polygon.len(), 4, "four vertices clicked");
}

/// `measure FILE --polygon (the viewer's) --volume --json` and `more` flags: its JSON.
fn measure_json(
    h: &egui_kittest::Harness<'_, pointblend::viewer::ViewerApp>,
    file: &std::path::Path,
    more: &[&std::ffi::OsStr],
) -> serde_json::Value {
    let text: Vec<String> = h.state().inspection().polygon.iter().map(|v| format!("{},{}", v.x, v.y)).collect();
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["measure".as_ref(), file.as_os_str()])
        .args(["--polygon", &text.join(" "), "--volume", "--json"])
        .args(more)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    serde_json::from_slice(&output.stdout).unwrap()
}

/// The JSON value `key` of `json`, a number.
fn value(json: &serde_json::Value, key: &str) -> f64 {
    json[key].as_f64().unwrap()
}

#[test]
fn a_polygon_clicked_on_the_top_view_measures_what_measure_polygon_measures() {
    let dir = tempfile::tempdir().unwrap();
    // A bump in the middle, so that the volume is not zero.
    let file = write(&dir.path().join("slope.las"), &slope(3.0), [0.0; 3], None);
    let viewer = ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(dir.path()) };
    let mut h = harness_sized(viewer, TALL);
    to_ortho_top(&mut h);
    click_polygon(&mut h);
    h.get_by_label("volume").click();
    wait_for(&mut h, "the polygon's measure with its volume", |app| {
        app.polygon_report().is_some_and(|r| r.as_ref().is_ok_and(|r| r.volume.is_some()))
    });
    let report = h.state().polygon_report().unwrap().clone().unwrap();
    let shown: serde_json::Value = serde_json::from_str(&report.json).unwrap();

    let measured = measure_json(&h, &file, &[]);
    assert_eq!(shown["points"], measured["points"], "the same points inside");
    for key in ["area_horizontal", "cell"] {
        let (a, b) = (value(&shown, key), value(&measured, key));
        assert!((a - b).abs() <= 1e-9 * b.abs(), "{key}: the viewer {a}, measure {b}");
    }
    // The window holds the points as f32 around the tile's centre, to within
    // RESIDUAL_KEPT of a file unit (measure reads the records in f64): each
    // cell's height, and the base plane's, may move by that much.
    let height_slack = 2.0 * value(&measured, "area_horizontal") * pointblend::cloud::placement::RESIDUAL_KEPT;
    for key in ["area_surface", "volume_above", "volume_below"] {
        let (a, b) = (value(&shown, key), value(&measured, key));
        assert!((a - b).abs() <= height_slack, "{key}: the viewer {a}, measure {b}, more than {height_slack} apart");
    }
    assert!(shown["volume_above"].as_f64().unwrap() > 1.0, "the bump stands above the border's plane: {shown}");
    assert_eq!(shown["base"]["points"], measured["base"]["points"], "the base plane is fitted to the same points");
}

#[test]
fn a_polygons_volume_against_a_base_layer_is_measure_bases_cut_and_fill() {
    let dir = tempfile::tempdir().unwrap();
    // The ground after a 3 m heap was made on it, and before.
    let after = write(&dir.path().join("after.las"), &slope(3.0), [0.0; 3], None);
    let before = write(&dir.path().join("before.las"), &slope(0.0), [0.0; 3], None);
    let viewer = ViewerOptions { file: Some(after.clone()), mode: Some(RenderMode::TwoPass), ..options(dir.path()) };
    // Taller: the two layers' rows push the polygon's section down the panel.
    let mut h = harness_sized(viewer, [900.0, 1700.0]);
    wait_for(&mut h, "the ground after", settled_in(RenderMode::TwoPass));
    h.input_mut().dropped_files.push(std::sync::Arc::new(Dropped(before.clone())));
    h.step();
    wait_for(&mut h, "both layers", |app| {
        settled_in(RenderMode::TwoPass)(app) && app.model().is_some_and(|m| m.scene.objects.len() == 2)
    });
    to_ortho_top(&mut h);
    click_polygon(&mut h);
    h.get_by_label("volume").click();
    h.step();
    choose(&mut h, "volume against", "layer before.las");
    wait_for(&mut h, "the volume against the base layer", |app| {
        app.polygon_report().is_some_and(|r| r.as_ref().is_ok_and(|r| r.json.contains("\"cloud\"")))
    });
    let report = h.state().polygon_report().unwrap().clone().unwrap();
    let shown: serde_json::Value = serde_json::from_str(&report.json).unwrap();
    let measured = measure_json(&h, &after, &["--base".as_ref(), before.as_os_str()]);
    assert_eq!(shown["points"], measured["points"], "the same points of the surface inside (not the base's)");
    assert_eq!(shown["base"]["points"], measured["base"]["points"], "the same points of the base");
    let height_slack = 2.0 * value(&measured, "area_horizontal") * pointblend::cloud::placement::RESIDUAL_KEPT;
    for key in ["volume_above", "volume_below"] {
        let (a, b) = (value(&shown, key), value(&measured, key));
        assert!((a - b).abs() <= height_slack, "{key}: the viewer {a}, measure {b}, more than {height_slack} apart");
    }
    // The heap: a cone of height 3 and radius 6, π·6²·3/3 ≈ 113 m³, on cells of the grid's size.
    assert!((value(&shown, "volume_above") - std::f64::consts::PI * 36.0).abs() < 5.0, "{shown}");
}
