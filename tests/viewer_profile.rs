//! The profile tool in the viewer, driven with egui_kittest: a line clicked
//! on the orthographic top view of a lidar tile cuts a slab holding the
//! points `profile` holds for the same line and width, the panel's CSV
//! export is the file `profile --csv` writes, and a screenshot's sidecar
//! records the line and the width. Clicks on the section pick its points
//! and measure between them, and its PNG is `profile --out`'s drawing. A
//! handle on the slab's side sets its width.

mod common;

use common::lidar::{tilted_grid, write};
use common::viewer::{click, drag, harness_sized, options, save_screenshot, to_ortho_top, wait_for};
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

/// A tile with a ridge 4 m high along x = 1020, seen from the top, with a
/// profile's line clicked across it: the harness and the file.
fn ridge_profile(
    dir: &std::path::Path,
) -> (egui_kittest::Harness<'static, pointblend::viewer::ViewerApp>, std::path::PathBuf) {
    let mut points = tilted_grid(80, 0.5, 0.1, [1000.0, 2000.0, 50.0]);
    for p in &mut points {
        p.xyz[2] += (4.0 - 0.5 * (p.xyz[0] - 1020.0).abs()).max(0.0);
    }
    let file = write(&dir.join("ridge.las"), &points, [0.0; 3], None);
    let viewer = ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(dir) };
    let mut h = harness_sized(viewer, TALL);
    to_ortho_top(&mut h);
    h.get_by_label("profile").click();
    h.step();
    for (x, y) in [(1004.0, 2012.0), (1036.0, 2023.0)] {
        let at = h.state().screen_position(DVec3::new(x, y, 53.0)).expect("in view");
        click(&mut h, at);
    }
    wait_for(&mut h, "the profile's slab", |app| app.profile_slab().is_some_and(|s| s.is_ok()));
    (h, file)
}

#[test]
fn a_profile_drawn_on_the_top_view_holds_the_points_profile_holds() {
    let dir = tempfile::tempdir().unwrap();
    let (mut h, file) = ridge_profile(dir.path());
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

#[test]
fn clicks_on_the_section_pick_its_points_and_measure_between_them_and_its_png_is_profile_outs() {
    let dir = tempfile::tempdir().unwrap();
    let (mut h, file) = ridge_profile(dir.path());
    h.step();
    let slab = h.state().profile_slab().unwrap().clone().unwrap();
    let layout = h.state().inspection().profile_layout.expect("the section is drawn");
    // The ridge's highest point of the slab and its lowest.
    let by_height = |a: &&DVec3, b: &&DVec3| a.z.total_cmp(&b.z);
    let (top, foot) = (*slab.points.iter().max_by(by_height).unwrap(), *slab.points.iter().min_by(by_height).unwrap());
    for p in [foot, top] {
        click(&mut h, layout.screen(&slab, p));
    }
    let marks = h.state().inspection().profile_marks.clone();
    assert_eq!(marks.len(), 2, "two points picked");
    // A click takes the point drawn nearest; another drawn on the same pixel is as good.
    for (mark, want) in marks.iter().zip([foot, top]) {
        let (a, b) = (layout.screen(&slab, *mark), layout.screen(&slab, want));
        assert!(a.distance(b) < 1.0, "picked {mark:?} ({a:?}) for {want:?} ({b:?})");
    }
    let rise = marks[1].z - marks[0].z;
    assert!(rise > 3.0, "from the foot to the top of the ridge: {rise}");
    let text = format!("rise {rise:+.3} ");
    assert!(h.query_by_label_contains(&text).is_some(), "the panel says {text}");

    // The PNG, drawn in the view's mode at the view's size, against `profile --out` at that size.
    let png = dir.path().join("section.png");
    let ctx = h.ctx.clone();
    h.state_mut().export_profile(&ctx, &png);
    wait_for(&mut h, "the drawing", |app| !app.is_exporting());
    assert!(h.state().status().is_some_and(|s| s.starts_with("drew the profile")), "{:?}", h.state().status());
    let drawn = image::open(&png).unwrap().to_rgba8();
    let [a, b] = h.state().inspection().profile_line[..] else { panic!("two ends") };
    let out = dir.path().join("out.png");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["profile".as_ref(), file.as_os_str()])
        .args(["--line", &format!("{},{},{},{}", a.x, a.y, b.x, b.y)])
        .args(["--width", &h.state().inspection().profile_width.to_string(), "--mode", "two-pass"])
        .args(["--size", &format!("{}x{}", drawn.width(), drawn.height())])
        .arg("--out")
        .arg(&out)
        .env("POINTBLEND_CACHE", dir.path().join("cache"))
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let profiled = image::open(&out).unwrap().to_rgba8();
    if let Some(keep) = std::env::var_os("POINTBLEND_KEEP_IMAGES") {
        std::fs::copy(&png, std::path::Path::new(&keep).join("section-viewer.png")).unwrap();
        std::fs::copy(&out, std::path::Path::new(&keep).join("section-profile-out.png")).unwrap();
    }
    let epsilon = common::mean_difference(&drawn, &profiled);
    assert!(epsilon <= 0.05, "the viewer's section is profile --out's: ε = {epsilon:.3}");
}

#[test]
fn dragging_the_slabs_side_handle_sets_its_width() {
    let dir = tempfile::tempdir().unwrap();
    let (mut h, _) = ridge_profile(dir.path());
    let inspect = h.state().inspection().clone();
    let [a, b] = inspect.profile_line[..] else { panic!("two ends") };
    let width = inspect.profile_width;
    let left = (b - a).truncate().normalize().perp().extend(0.0);
    let middle = (a + b) * 0.5;
    let screen =
        |h: &egui_kittest::Harness<'_, pointblend::viewer::ViewerApp>, p: DVec3| h.state().screen_position(p).unwrap();
    let handle = screen(&h, middle + left * width * 0.5);
    let wider = screen(&h, middle + left * (width * 0.5 + 1.5));
    let camera = h.state().camera();
    drag(&mut h, handle, wider, 6);
    assert_eq!(h.state().camera(), camera, "dragging the handle does not orbit");
    // One point on screen, in file units across the line.
    let point = 1.0 / f64::from(screen(&h, middle + left).distance(screen(&h, middle)));
    let now = h.state().inspection().profile_width;
    assert!((now - (width + 3.0)).abs() <= point, "the width went from {width} to {now}, not {}", width + 3.0);
    wait_for(&mut h, "the wider slab", |app| {
        app.profile_slab().is_some_and(|s| s.as_ref().is_ok_and(|s| s.profile.width == now))
    });
}
