//! The colour panel's filters in the viewer, driven with egui_kittest:
//! choosing the first returns draws the frame `render --returns first`
//! draws of the same view, pixel for pixel, and the frame changes.

mod common;

use std::process::Command;

use common::lidar::{tilted_grid, write};
use common::viewer::{choose, harness_sized, options, save_screenshot, settled_in, wait_for};
use pointblend::render::RenderMode;
use pointblend::style::Returns;
use pointblend::viewer::ViewerOptions;

/// A window tall enough to show the colour panel's filters.
const TALL: [f32; 2] = [900.0, 1300.0];

#[test]
fn ticking_the_first_returns_draws_what_render_returns_first_draws() {
    let dir = tempfile::tempdir().unwrap();
    // Every third point is a first return (return_number 1, 2, 3 in turn); the file has colours.
    let file =
        write(&dir.path().join("returns.las"), &tilted_grid(90, 0.5, 0.2, [1000.0, 2000.0, 50.0]), [0.0; 3], None);
    let shots = dir.path().join("shots");
    let viewer = ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(&shots) };
    let mut h = harness_sized(viewer, TALL);
    wait_for(&mut h, "the tile in two-pass", settled_in(RenderMode::TwoPass));
    let every = h.state().shown_frame().unwrap().0.clone();
    let sidecar = save_screenshot(&mut h, &shots).with_extension("json");

    let rendered = dir.path().join("first.png");
    let output = Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["render".as_ref(), file.as_os_str(), "--camera".as_ref(), sidecar.as_os_str()])
        .args(["--returns", "first", "--out"])
        .arg(&rendered)
        .env("POINTBLEND_CACHE", dir.path().join("cache"))
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let rendered = image::open(&rendered).unwrap().to_rgba8();

    choose(&mut h, "returns", "first");
    wait_for(&mut h, "the first returns", |app| {
        settled_in(RenderMode::TwoPass)(app)
            && app.model().is_some_and(|m| m.style.as_ref().is_some_and(|s| s.returns == Some(Returns::First)))
    });
    let first = h.state().shown_frame().unwrap().0.clone();
    assert_eq!(first.dimensions(), rendered.dimensions());
    let changed = first.pixels().zip(every.pixels()).filter(|(a, b)| a != b).count();
    assert!(changed > 1000, "the first returns change the frame: {changed} pixels changed");
    let differing = first.pixels().zip(rendered.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(
        differing, 0,
        "{differing} pixels differ between the viewer's first returns and `render --returns first`"
    );
}
