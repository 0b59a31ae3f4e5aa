//! The inspection tools in the viewer, driven with egui_kittest: dragging a
//! clip-box handle hides the half beyond it, a click picks the layers under
//! the pixel, and two clicks measure the distance between the surfaces
//! under them (against the closed form of a plane), and Ctrl+Shift+S saves
//! 4× the view with the same content; the eye-dome toggle darkens the
//! steps in depth and nothing else.

mod common;

use common::tolerances::MAX_LARGE_SHOT_CHANGED;
use common::viewer::{click, drag, harness_sized, options, settled_in, wait_for};
use egui::accesskit::Role;
use egui_kittest::kittest::Queryable;
use glam::{DVec3, Vec2};
use pointblend::render::RenderMode;
use pointblend::viewer::{ViewerApp, ViewerOptions};

/// A window tall enough to show the whole left panel, Inspect included.
const TALL: [f32; 2] = [900.0, 1300.0];

/// The pixels of `image` that are not the background.
fn drawn(image: &image::RgbaImage) -> Vec<(u32, u32)> {
    let background = common::background_rgb();
    image.enumerate_pixels().filter(|(_, _, p)| p.0[..3] != background).map(|(x, y, _)| (x, y)).collect()
}

/// The screen rectangle (pixels of the view's image) around the box's eight corners.
fn box_on_screen(app: &ViewerApp, min: [f64; 3], max: [f64; 3]) -> egui::Rect {
    let view = app.view_rect();
    let scale = app.shown_frame().unwrap().0.width() as f32 / view.width();
    let mut rect = egui::Rect::NOTHING;
    for k in 0..8 {
        let corner = DVec3::new(
            if k & 1 == 0 { min[0] } else { max[0] },
            if k & 2 == 0 { min[1] } else { max[1] },
            if k & 4 == 0 { min[2] } else { max[2] },
        );
        let p = app.screen_position(corner).expect("the box is in front of the camera");
        rect.extend_with(((p - view.min) * scale).to_pos2());
    }
    rect
}

#[test]
fn dragging_a_clip_box_handle_hides_the_half_beyond_it() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness_sized(options(dir.path()), TALL);
    wait_for(&mut h, "the lion in two-pass", settled_in(RenderMode::TwoPass));
    let whole = drawn(h.state().shown_frame().unwrap().0).len();
    h.get_by_label("clip box").click();
    wait_for(&mut h, "the clip box", |app| app.is_settled() && app.inspection().clip_box.is_some());
    let bounds = h.state().inspection().clip_box.unwrap();
    // The handle of the box's +x face, dragged to the box's centre on screen.
    let handle = h.state().clip_handle(1).expect("the +x handle is on screen");
    let centre = h.state().screen_position((DVec3::from(bounds.min) + DVec3::from(bounds.max)) * 0.5).unwrap();
    drag(&mut h, handle, centre, 8);
    wait_for(&mut h, "the clipped frame", |app| {
        app.is_settled() && app.shown_frame().is_some_and(|(_, k)| !k.settings.clip.is_empty())
    });
    // The window, for people to look at (target/tmp).
    let window = h.render().expect("the window renders");
    window.save(std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-clip-box.png")).unwrap();
    let app = h.state();
    let moved = app.inspection().clip_box.unwrap();
    let middle = (bounds.min[0] + bounds.max[0]) * 0.5;
    let width = bounds.max[0] - bounds.min[0];
    assert!(
        (moved.max[0] - middle).abs() < 0.1 * width,
        "the +x face moved to {} (the middle is {middle})",
        moved.max[0]
    );
    assert_eq!(
        (moved.min, moved.max[1], moved.max[2]),
        (bounds.min, bounds.max[1], bounds.max[2]),
        "only that face moved"
    );
    let image = app.shown_frame().unwrap().0;
    let shown = drawn(image);
    let share = shown.len() as f64 / whole as f64;
    assert!((0.25..0.75).contains(&share), "{} of {whole} pixels are still drawn ({share:.2})", shown.len());
    // Everything drawn lies inside the kept box's outline on screen (a splat's
    // kept part reaches no farther than the box).
    let kept = box_on_screen(app, moved.min, moved.max).expand(2.0);
    let outside = shown.iter().filter(|(x, y)| !kept.contains(egui::pos2(*x as f32 + 0.5, *y as f32 + 0.5))).count();
    assert_eq!(outside, 0, "{outside} pixels are drawn outside the kept box {kept:?}");
    let before = box_on_screen(app, bounds.min, bounds.max);
    assert!(
        before.width() > kept.width() * 1.3,
        "the kept box is narrower on screen than the whole: {before:?} {kept:?}"
    );
}

/// Three translucent planes facing the camera at z = 0.3, 0 and -0.3, as a scene file.
fn three_planes(dir: &std::path::Path) -> std::path::PathBuf {
    let mut text = String::new();
    for (z, colour) in [(0.3, [220, 80, 60]), (0.0, [60, 200, 90]), (-0.3, [70, 110, 230])] {
        text.push_str(&format!(
            "[[object]]\nplane = {{ splats = 6000, size = 1.0, centre = [0.0, 0.0, {z}], normal = [0, 0, 1] }}\ncolor = {colour:?}\nopacity = 0.5\n\n"
        ));
    }
    let path = dir.join("planes.toml");
    std::fs::write(&path, text).unwrap();
    path
}

/// The file point where the ray through the view's point `at` meets the plane z = `z`.
fn on_plane(app: &ViewerApp, at: egui::Pos2, z: f64) -> DVec3 {
    let camera = app.shown_frame().unwrap().1.camera;
    let rect = app.view_rect();
    let image_width = app.shown_frame().unwrap().0.width() as f32;
    let ppp = image_width / rect.width();
    // The centre of the pixel the click falls in, as the viewer picks it.
    let pixel = ((at - rect.min) * ppp).floor() + egui::vec2(0.5, 0.5);
    let (w, h) = (rect.width() * ppp, rect.height() * ppp);
    let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let ndc = Vec2::new(pixel.x / w * 2.0 - 1.0, 1.0 - pixel.y / h * 2.0);
    let eye = (ndc * Vec2::new(tan_y * w / h, tan_y)).extend(-1.0);
    let to_world = camera.view_matrix().inverse();
    let origin = camera.eye().as_dvec3();
    let dir = to_world.transform_vector3(eye).as_dvec3();
    origin + dir * ((z - origin.z) / dir.z)
}

#[test]
fn a_click_picks_every_layer_under_it_and_two_clicks_measure_the_distance_between_them() {
    let dir = tempfile::tempdir().unwrap();
    let file = three_planes(dir.path());
    let mut h =
        harness_sized(ViewerOptions { file: Some(file), mode: Some(RenderMode::Alg2), ..options(dir.path()) }, TALL);
    wait_for(&mut h, "the planes in alg2", settled_in(RenderMode::Alg2));
    h.get_by_label("pick").click();
    h.step();
    let centre = h.state().view_rect().center();
    click(&mut h, centre);
    let report = h.state().inspection().picked.clone().expect("the click picked");
    assert_eq!(report.layers.len(), 3, "{}", report.text());
    for (layer, z) in report.layers.iter().zip([0.3, 0.0, -0.3]) {
        let exact = on_plane(h.state(), centre, z);
        assert!(layer.position.distance(exact) < 1e-3, "the layer at z = {z}: {} against {exact}", layer.position);
    }
    assert!(h.query_by_label_contains("3 layer(s)").is_some(), "the panel lists the layers");

    h.get_by_label("measure").click();
    h.step();
    let (a, b) = (centre + egui::vec2(-80.0, 40.0), centre + egui::vec2(60.0, -50.0));
    click(&mut h, a);
    click(&mut h, b);
    let window = h.render().expect("the window renders");
    window.save(std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-measure.png")).unwrap();
    let app = h.state();
    let measured: Vec<DVec3> = app.inspection().measured.iter().map(|(_, p)| *p).collect();
    assert_eq!(measured.len(), 2);
    let want = on_plane(app, a, 0.3).distance(on_plane(app, b, 0.3));
    let got = app.inspection().measurement(DVec3::Y).unwrap().distance;
    assert!((got - want).abs() < 1e-3 * want, "measured {got}, the front plane's closed form {want}");
    assert!(h.query_by_label_contains(&format!("distance {got:.4}")).is_some(), "the panel shows the distance");

    // A 4× screenshot carries the polyline, its dots and its label, where the view shows them.
    let shown = app.shown_frame().unwrap().0.clone();
    let scale = shown.width() as f32 / app.view_rect().width();
    let on_shot = |p: egui::Pos2| (p - app.view_rect().min) * scale * 4.0;
    let (a_shot, b_shot) = (on_shot(a), on_shot(b));
    let shot = save_large_screenshot(&mut h, dir.path());
    shot.save(std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-measure-shot.png")).unwrap();
    let is_line = |p: &image::Rgba<u8>| p.0[..3] == [255, 110, 90];
    assert_eq!(shown.pixels().filter(|p| is_line(p)).count(), 0, "the frame itself has no measurement drawn");
    let near = |x: u32, y: u32, c: egui::Vec2, reach: f32| (egui::vec2(x as f32, y as f32) - c).length() < reach;
    let dots = shot
        .enumerate_pixels()
        .filter(|(x, y, p)| is_line(p) && (near(*x, *y, a_shot, 20.0) || near(*x, *y, b_shot, 20.0)));
    assert!(dots.count() > 500, "the dots at both points");
    let middle = (a_shot + b_shot) * 0.5;
    let line = shot.enumerate_pixels().filter(|(x, y, p)| is_line(p) && near(*x, *y, middle, 20.0)).count();
    assert!(line > 100, "the segment through its middle: {line} pixels");
    let label = shot.enumerate_pixels().filter(|(x, y, p)| p.0[..3] == [255, 255, 255] && near(*x, *y, middle, 120.0));
    assert!(label.count() > 50, "the length's label over the middle");
}

/// Presses Ctrl+Shift+S and waits for the screenshot and its sidecar in `dir`: the PNG.
fn save_large_screenshot(h: &mut egui_kittest::Harness<'_, ViewerApp>, dir: &std::path::Path) -> image::RgbaImage {
    h.input_mut().events.push(egui::Event::Key {
        key: egui::Key::S,
        physical_key: None,
        pressed: true,
        repeat: false,
        modifiers: egui::Modifiers::COMMAND | egui::Modifiers::SHIFT,
    });
    h.step();
    let png = || {
        std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| e.ok().map(|e| e.path()))
            .find(|p| p.extension().is_some_and(|e| e == "png"))
    };
    wait_for(h, "the large screenshot", |_| png().is_some_and(|p| p.with_extension("json").exists()));
    image::open(png().unwrap()).unwrap().to_rgba8()
}

#[test]
fn ctrl_shift_s_saves_four_times_the_view_with_the_same_content() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = common::viewer::harness(options(dir.path()));
    wait_for(&mut h, "the lion in two-pass", settled_in(RenderMode::TwoPass));
    let shown = h.state().shown_frame().unwrap().0.clone();
    let large = save_large_screenshot(&mut h, dir.path());
    assert_eq!(large.dimensions(), (shown.width() * 4, shown.height() * 4), "4 × the view's {:?}", shown.dimensions());
    // Box-filtered down 4×, it is the view's image up to the splats' sampling.
    let small = image::imageops::resize(&large, shown.width(), shown.height(), image::imageops::FilterType::Triangle);
    let differing =
        small.pixels().zip(shown.pixels()).filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) > 24)).count();
    let share = differing as f64 / (shown.width() * shown.height()) as f64;
    assert!(share < MAX_LARGE_SHOT_CHANGED, "{share:.3} of the pixels differ by more than 24/255 from the view");
}

#[test]
fn the_eye_dome_toggle_darkens_the_steps_in_depth_and_nothing_else() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness_sized(options(dir.path()), TALL);
    wait_for(&mut h, "the lion in two-pass", settled_in(RenderMode::TwoPass));
    let before = h.state().shown_frame().unwrap().0.clone();
    h.get_by_role_and_label(Role::CheckBox, "eye-dome lighting").click();
    wait_for(&mut h, "the frame with eye-dome lighting", |app| {
        app.is_settled() && app.shown_frame().is_some_and(|(_, k)| k.settings.eye_dome.is_some())
    });
    let after = h.state().shown_frame().unwrap().0.clone();
    assert_eq!(before.dimensions(), after.dimensions());
    let background = common::background_rgb();
    let (mut darker, mut brighter, mut drawn) = (0, 0, 0);
    for (a, b) in before.pixels().zip(after.pixels()) {
        if a.0[..3] == background {
            assert_eq!(a, b, "the background changed");
            continue;
        }
        drawn += 1;
        darker += (0..3).any(|c| b[c] + 1 < a[c]) as u32;
        brighter += (0..3).any(|c| b[c] > a[c] + 1) as u32;
    }
    assert_eq!(brighter, 0, "eye-dome lighting only darkens: {brighter} pixels got brighter");
    assert!(darker * 20 > drawn, "only {darker} of {drawn} drawn pixels darkened");
    // Off again, the frame is the one before.
    h.get_by_role_and_label(Role::CheckBox, "eye-dome lighting").click();
    wait_for(&mut h, "the frame without", |app| {
        app.is_settled() && app.shown_frame().is_some_and(|(_, k)| k.settings.eye_dome.is_none())
    });
    assert!(h.state().shown_frame().unwrap().0.pixels().eq(before.pixels()), "off again is not the frame before");
}
