//! Plan and elevation views in the viewer, driven with egui_kittest: the
//! ortho key and a view key change the camera's projection and direction,
//! two equal roofs at different heights cover equal areas in the
//! orthographic top view (and unequal ones in perspective, which the test
//! also checks, so that it can tell the two apart), the help key shows
//! the list of the view's inputs, and fly mode's W flies along the view
//! while a drag turns it about the eye.

mod common;

use common::viewer::{harness, options, settled_in, wait_for};
use egui_kittest::kittest::Queryable;
use pointblend::frame::{CameraRequest, NamedView, Projection, UpAxis};
use pointblend::render::RenderMode;
use pointblend::viewer::{ViewerApp, ViewerOptions};

/// Two equal square roofs, red at z = 0 and blue at z = 0.8, side by side, z up.
fn two_roofs(dir: &std::path::Path) -> std::path::PathBuf {
    let mut text = String::new();
    for (x, z, colour) in [(-0.7, 0.0, [230, 30, 30]), (0.7, 0.8, [30, 30, 230])] {
        text.push_str(&format!(
            "[[object]]\nplane = {{ splats = 8000, size = 1.0, centre = [{x}, 0.0, {z}], normal = [0, 0, 1] }}\ncolor = {colour:?}\n\n"
        ));
    }
    let path = dir.join("roofs.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// Pixels of the red roof and of the blue roof in the frame on screen.
fn roof_areas(app: &ViewerApp) -> (usize, usize) {
    let image = app.shown_frame().unwrap().0;
    let dominant = |p: &image::Rgba<u8>, c: usize| (0..3).all(|o| o == c || p.0[c] as i32 > p.0[o] as i32 + 60);
    let red = image.pixels().filter(|p| dominant(p, 0)).count();
    let blue = image.pixels().filter(|p| dominant(p, 2)).count();
    (red, blue)
}

fn press(h: &mut egui_kittest::Harness<'_, ViewerApp>, key: egui::Key) {
    h.key_press(key);
    h.step();
}

/// Settled in two-pass with this projection and view.
fn shown_as(projection: Projection, view: NamedView) -> impl Fn(&ViewerApp) -> bool {
    move |app| {
        settled_in(RenderMode::TwoPass)(app)
            && app.shown_frame().is_some_and(|(_, key)| {
                key.camera.projection == projection
                    && (key.camera.azimuth_deg, key.camera.elevation_deg) == view.angles()
            })
    }
}

#[test]
fn the_ortho_key_and_a_view_key_give_a_plan_view_where_equal_roofs_have_equal_areas() {
    let dir = tempfile::tempdir().unwrap();
    let camera = CameraRequest { up: Some(UpAxis::PosZ), ..Default::default() };
    let file = Some(two_roofs(dir.path()));
    let mut h = harness(ViewerOptions { file, camera, mode: Some(RenderMode::TwoPass), ..options(dir.path()) });
    wait_for(&mut h, "the roofs in two-pass", settled_in(RenderMode::TwoPass));
    assert_eq!(h.state().camera().projection, Projection::Perspective);

    press(&mut h, egui::Key::Num1);
    wait_for(&mut h, "the perspective top view", shown_as(Projection::Perspective, NamedView::Top));
    let (red, blue) = roof_areas(h.state());
    assert!(red > 2000 && blue > 2000, "both roofs are in view: {red} and {blue} pixels");
    let perspective = blue as f64 / red as f64;
    assert!(perspective > 1.2, "in perspective the higher roof looks larger: {blue} against {red} pixels");

    press(&mut h, egui::Key::O);
    assert_eq!(h.state().camera().projection, Projection::Ortho, "O switches to orthographic");
    wait_for(&mut h, "the orthographic top view", shown_as(Projection::Ortho, NamedView::Top));
    let (red, blue) = roof_areas(h.state());
    let ortho = blue as f64 / red as f64;
    // A roof is about 210 pixels a side: one row of pixels is half a percent of it.
    assert!((ortho - 1.0).abs() < 0.01, "in orthographic equal roofs have equal areas: {blue} against {red} pixels");

    press(&mut h, egui::Key::Num3);
    wait_for(&mut h, "the orthographic front view", shown_as(Projection::Ortho, NamedView::Front));
    let (red, blue) = roof_areas(h.state());
    assert!(red + blue < 2000, "seen edge-on from the front, the roofs are lines: {red} + {blue} pixels");
    press(&mut h, egui::Key::O);
    assert_eq!(h.state().camera().projection, Projection::Perspective, "O switches back");
}

#[test]
fn the_help_key_lists_the_views_inputs() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(options(dir.path()));
    wait_for(&mut h, "the lion in two-pass", settled_in(RenderMode::TwoPass));
    let before = h.render().expect("the window renders");
    press(&mut h, egui::Key::H);
    h.step();
    let after = h.render().expect("the window renders");
    // The overlay sits over the view's upper right corner.
    let view = h.state().view_rect();
    let ppp = before.width() as f32 / 900.0;
    let changed = |a: &image::RgbaImage, b: &image::RgbaImage| {
        let (x0, y0) = (((view.right() - 250.0) * ppp) as u32, ((view.top() + 20.0) * ppp) as u32);
        let (w, h) = ((200.0 * ppp) as u32, (150.0 * ppp) as u32);
        let mut count = 0;
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                let (p, q) = (a.get_pixel(x, y), b.get_pixel(x, y));
                count += usize::from((0..3).any(|c| p.0[c].abs_diff(q.0[c]) > 24));
            }
        }
        count as f64 / (w * h) as f64
    };
    let shown = changed(&before, &after);
    assert!(shown > 0.5, "the overlay covers the corner: {:.1}% of its pixels changed", 100.0 * shown);
    assert!(h.query_by_label("help").is_some(), "the Camera section's help box");
    press(&mut h, egui::Key::H);
    h.step();
    let hidden = h.render().expect("the window renders");
    let left = changed(&before, &hidden);
    assert!(left < 0.01, "H hides it again: {:.1}% of the corner still differs", 100.0 * left);
}

fn key(h: &mut egui_kittest::Harness<'_, ViewerApp>, key: egui::Key, pressed: bool) {
    let modifiers = egui::Modifiers::default();
    h.input_mut().events.push(egui::Event::Key { key, physical_key: None, pressed, repeat: false, modifiers });
    h.step();
}

#[test]
fn in_fly_mode_w_flies_along_the_view_and_a_drag_looks_around_the_eye() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(options(dir.path()));
    wait_for(&mut h, "the lion in two-pass", settled_in(RenderMode::TwoPass));
    let start = h.state().camera();
    key(&mut h, egui::Key::W, true);
    key(&mut h, egui::Key::W, false);
    assert_eq!(h.state().camera(), start, "W does nothing outside fly mode");

    press(&mut h, egui::Key::F);
    key(&mut h, egui::Key::W, true);
    for _ in 0..10 {
        h.step();
    }
    key(&mut h, egui::Key::W, false);
    let flown = h.state().camera();
    let moved = flown.eye() - start.eye();
    assert!(moved.length() > 0.01 * start.distance, "W flew: {moved}");
    assert!(moved.normalize().dot(-start.direction()) > 0.999, "along the view: {moved}");
    assert_eq!((flown.azimuth_deg, flown.elevation_deg), (start.azimuth_deg, start.elevation_deg));
    h.step();
    assert_eq!(h.state().camera(), flown, "the flight stops when W is let go");

    let centre = h.state().view_rect().center();
    common::viewer::drag(&mut h, centre, centre + egui::vec2(60.0, 0.0), 4);
    let looked = h.state().camera();
    assert!((looked.eye() - flown.eye()).length() < 1e-3 * start.distance, "a drag in fly mode keeps the eye");
    assert!((looked.azimuth_deg - flown.azimuth_deg).abs() > 5.0, "and turns the view");
}
