//! Layers in the viewer, driven with egui_kittest: a file dropped on the
//! window is added as a layer beside the one shown (not in its place), the
//! view stays where it was, and the layer list's box hides the layer again;
//! each layer's colour, opacity and cut to the clip box, drawn again by
//! `render --camera`; streamed layers under one budget.

mod common;

use std::sync::Arc;

use common::lidar::{tilted_grid, write};
use common::viewer::{Dropped, choose, drag, harness_sized, options, save_screenshot, settled_in, wait_for};
use egui::accesskit::Role;
use egui_kittest::kittest::Queryable;
use glam::DVec3;
use pointblend::render::RenderMode;
use pointblend::viewer::{ViewerApp, ViewerOptions};

const TALL: [f32; 2] = [900.0, 1300.0];

/// Whether the frame on screen drew something at the file point `p`.
fn drawn_at(app: &ViewerApp, p: DVec3) -> bool {
    let (image, _) = app.shown_frame().unwrap();
    let view = app.view_rect();
    let at =
        (app.screen_position(p).expect("in front of the camera") - view.min) * (image.width() as f32 / view.width());
    let inside = at.x >= 0.0 && at.y >= 0.0 && (at.x as u32) < image.width() && (at.y as u32) < image.height();
    inside && image.get_pixel(at.x as u32, at.y as u32).0[..3] != common::background_rgb()
}

fn objects(app: &ViewerApp) -> usize {
    app.model().map_or(0, |m| m.scene.objects.len())
}

#[test]
fn a_dropped_file_is_added_as_a_layer_and_the_list_hides_it() {
    let dir = tempfile::tempdir().unwrap();
    let west = write(&dir.path().join("west.las"), &tilted_grid(60, 0.5, 0.0, [1000.0, 2000.0, 50.0]), [0.0; 3], None);
    let east = write(&dir.path().join("east.las"), &tilted_grid(60, 0.5, 0.0, [1034.0, 2000.0, 50.0]), [0.0; 3], None);
    let (west_centre, east_centre) = (DVec3::new(1015.0, 2015.0, 50.0), DVec3::new(1049.0, 2015.0, 50.0));
    let viewer = ViewerOptions { file: Some(west), mode: Some(RenderMode::TwoPass), ..options(dir.path()) };
    let mut h = harness_sized(viewer, TALL);
    wait_for(&mut h, "the west tile", settled_in(RenderMode::TwoPass));
    assert_eq!(h.state().layers().len(), 1, "the file opened is the first layer");
    let camera = h.state().camera();

    h.input_mut().dropped_files.push(Arc::new(Dropped(east.clone())));
    h.step();
    wait_for(&mut h, "both tiles", |app| settled_in(RenderMode::TwoPass)(app) && objects(app) == 2);
    let names: Vec<String> = h.state().layers().iter().map(|l| l.name()).collect();
    assert_eq!(names, ["west.las", "east.las"], "the dropped file is added, not opened in place");
    let kept = h.state().camera();
    assert!((kept.target - camera.target).length() < 1e-3 * camera.distance, "the view stays where it was");
    h.key_press(egui::Key::Home);
    wait_for(&mut h, "both tiles framed", |app| settled_in(RenderMode::TwoPass)(app) && app.camera() != kept);
    assert!(drawn_at(h.state(), west_centre) && drawn_at(h.state(), east_centre), "both tiles are drawn");

    h.get_by_role_and_label(Role::CheckBox, "east.las").click();
    wait_for(&mut h, "the east tile hidden", |app| settled_in(RenderMode::TwoPass)(app) && objects(app) == 1);
    assert!(!h.state().layers()[1].shown);
    assert!(drawn_at(h.state(), west_centre), "the west tile stays");
    assert!(!drawn_at(h.state(), east_centre), "the east tile is hidden");
}

#[test]
fn a_screenshot_of_an_ortho_filtered_two_layer_view_is_drawn_again_by_render_camera() {
    let dir = tempfile::tempdir().unwrap();
    let west = write(&dir.path().join("west.las"), &tilted_grid(60, 0.5, 0.1, [1000.0, 2000.0, 50.0]), [0.0; 3], None);
    let east = write(&dir.path().join("east.las"), &tilted_grid(60, 0.5, 0.1, [1031.0, 2000.0, 54.0]), [0.0; 3], None);
    let shots = dir.path().join("shots");
    let viewer = ViewerOptions { file: Some(west.clone()), mode: Some(RenderMode::TwoPass), ..options(&shots) };
    let mut h = harness_sized(viewer, TALL);
    wait_for(&mut h, "the west tile", settled_in(RenderMode::TwoPass));
    h.input_mut().dropped_files.push(Arc::new(Dropped(east.clone())));
    h.step();
    wait_for(&mut h, "both tiles", |app| settled_in(RenderMode::TwoPass)(app) && objects(app) == 2);
    for key in [egui::Key::Home, egui::Key::Num1, egui::Key::O] {
        h.key_press(key);
        h.step();
    }
    choose(&mut h, "returns", "first");
    wait_for(&mut h, "the first returns of both tiles from the top", |app| {
        settled_in(RenderMode::TwoPass)(app)
            && app.camera().projection == pointblend::frame::Projection::Ortho
            && app
                .model()
                .is_some_and(|m| m.style.as_ref().is_some_and(|s| s.returns.is_some()) && m.scene.objects.len() == 2)
    });
    let png = save_screenshot(&mut h, &shots);
    let sidecar = png.with_extension("json");
    let recorded: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&sidecar).unwrap()).unwrap();
    assert_eq!(recorded["model"]["layers"].as_array().map(Vec::len), Some(2), "the sidecar names both layers");
    assert_eq!(recorded["camera"]["projection"], "ortho");
    assert_eq!(recorded["style"]["returns"], "first");

    let shot = image::open(&png).unwrap().to_rgba8();
    let rendered = common::viewer::render_again(&[&west, &east], &sidecar, dir.path());
    let every = h.state().shown_frame().unwrap().0.clone();
    assert!(common::mean_difference(&shot, &every) < 0.05, "the screenshot is the view");

    let epsilon = common::mean_difference(&shot, &rendered);
    assert!(epsilon <= 0.05, "render --camera draws the screenshot again: ε = {epsilon:.3}");
}

/// A 60 × 60 tile of points 0.5 apart, level, from x = `x0`.
fn tile(x0: f64) -> Vec<common::lidar::LidarPoint> {
    tilted_grid(60, 0.5, 0.0, [x0, 2000.0, 50.0])
}

/// Where the east tile starts: 4 units east of the west one's end.
const EAST_X: f64 = 1034.0;

/// The west tile open in `mode` (screenshots in `dir/shots`), the east one
/// dropped beside it, both framed (Home); the window and the two files.
fn two_tiles(
    dir: &std::path::Path,
    mode: RenderMode,
) -> (egui_kittest::Harness<'static, ViewerApp>, std::path::PathBuf, std::path::PathBuf) {
    let west = write(&dir.join("west.las"), &tile(1000.0), [0.0; 3], None);
    let east = write(&dir.join("east.las"), &tile(EAST_X), [0.0; 3], None);
    let viewer = ViewerOptions { file: Some(west.clone()), mode: Some(mode), ..options(&dir.join("shots")) };
    let mut h = harness_sized(viewer, TALL);
    wait_for(&mut h, "the west tile", settled_in(mode));
    h.input_mut().dropped_files.push(Arc::new(Dropped(east.clone())));
    h.step();
    wait_for(&mut h, "both tiles", |app| settled_in(mode)(app) && objects(app) == 2);
    h.key_press(egui::Key::Home);
    h.step();
    (h, west, east)
}

#[test]
fn a_layers_colour_and_opacity_are_drawn_kept_and_drawn_again_by_render_camera() {
    let dir = tempfile::tempdir().unwrap();
    let east_centre = DVec3::new(1049.0, 2015.0, 50.0);
    let shots = dir.path().join("shots");
    let mode = RenderMode::DepthPeel;
    let (mut h, west, east) = two_tiles(dir.path(), mode);

    let red = [220, 60, 50];
    let east_look = |app: &ViewerApp| app.model().map(|m| m.scene.objects[1].material);
    choose(&mut h, "colour 2", "red");
    wait_for(&mut h, "the east tile red", |app| {
        settled_in(mode)(app) && objects(app) == 2 && east_look(app).is_some_and(|m| m.colour == Some(red))
    });
    assert_eq!(h.state().model().unwrap().scene.objects[0].material.colour, None, "the west tile keeps its colours");
    let (image, _) = h.state().shown_frame().unwrap();
    let view = h.state().view_rect();
    let at = (h.state().screen_position(east_centre).unwrap() - view.min) * (image.width() as f32 / view.width());
    let [r, g, b, _] = image.get_pixel(at.x as u32, at.y as u32).0;
    assert!(r > 2 * g.max(b), "the east tile is drawn red: {r},{g},{b}");

    // A click 40 % along layer 2's opacity slider.
    let slider = h.get_by_role_and_label(Role::Slider, "opacity 2").rect();
    let at = egui::pos2(slider.left() + 0.4 * slider.width(), slider.center().y);
    common::viewer::click(&mut h, at);
    wait_for(&mut h, "the east tile translucent", |app| {
        settled_in(mode)(app) && east_look(app).is_some_and(|m| m.opacity < 0.6 && m.opacity > 0.2)
    });
    let set = east_look(h.state()).unwrap();
    assert_eq!(set.colour, Some(red), "the colour stays");
    assert_eq!(h.state().model().unwrap().scene.objects[0].material.opacity, 1.0, "the west tile stays opaque");

    h.get_by_role_and_label(Role::CheckBox, "east.las").click();
    wait_for(&mut h, "the east tile hidden", |app| settled_in(mode)(app) && objects(app) == 1);
    h.get_by_role_and_label(Role::CheckBox, "east.las").click();
    wait_for(&mut h, "the east tile shown again", |app| settled_in(mode)(app) && objects(app) == 2);
    assert_eq!(east_look(h.state()), Some(set), "shown again, the layer keeps its look");

    let png = save_screenshot(&mut h, &shots);
    let sidecar = png.with_extension("json");
    let recorded: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&sidecar).unwrap()).unwrap();
    assert_eq!(recorded["looks"][1]["colour"], serde_json::json!(red), "the sidecar records each layer's look");
    let shot = image::open(&png).unwrap().to_rgba8();
    let rendered = common::viewer::render_again(&[&west, &east], &sidecar, dir.path());
    let epsilon = common::mean_difference(&shot, &rendered);
    assert!(epsilon <= 0.05, "render --camera draws the screenshot again: ε = {epsilon:.3}");
}

#[test]
fn a_layer_cut_to_the_clip_box_stays_cut_while_the_other_is_whole_and_render_camera_cuts_it_again() {
    let dir = tempfile::tempdir().unwrap();
    let shots = dir.path().join("shots");
    let mode = RenderMode::TwoPass;
    let (mut h, west, east) = two_tiles(dir.path(), mode);
    wait_for(&mut h, "both tiles framed", settled_in(mode));

    // The clip box's +x face dragged to the middle of the east tile.
    h.get_by_label("clip box").click();
    wait_for(&mut h, "the clip box", |app| app.is_settled() && app.inspection().clip_box.is_some());
    let handle = h.state().clip_handle(1).expect("the +x handle is on screen");
    let to = h.state().screen_position(DVec3::new(1049.0, 2015.0, 50.0)).unwrap();
    drag(&mut h, handle, to, 8);
    wait_for(&mut h, "the clipped frame", |app| {
        settled_in(mode)(app) && app.shown_frame().is_some_and(|(_, k)| !k.settings.clip.is_empty())
    });
    let clip_box = h.state().inspection().clip_box.unwrap();
    let east_cut = |app: &ViewerApp| app.model().and_then(|m| m.scene.objects.get(1).and_then(|o| o.clip_box()));
    h.get_by_role_and_label(Role::CheckBox, "clip 2").click();
    wait_for(&mut h, "the east tile cut", |app| settled_in(mode)(app) && east_cut(app) == Some(clip_box));
    h.get_by_label("clip box").click();
    wait_for(&mut h, "the clip switched off", |app| {
        settled_in(mode)(app) && app.shown_frame().is_some_and(|(_, k)| k.settings.clip.is_empty())
    });

    let model = h.state().model().unwrap();
    let inside =
        |p: &common::lidar::LidarPoint| (0..3).all(|a| (clip_box.min[a]..=clip_box.max[a]).contains(&p.xyz[a]));
    let expected = tile(EAST_X).iter().filter(|p| inside(p)).count();
    assert!(expected > 0 && expected < 3600, "the box holds part of the east tile: {expected} points");
    assert_eq!(model.scene.objects[1].cloud.len(), expected, "the east tile keeps the points inside the box");
    assert_eq!(model.scene.objects[0].cloud.len(), 3600, "the west tile stays whole");
    assert_eq!(model.scene.objects[0].clip_box(), None);
    let (west_edge, east_edge) = (DVec3::new(1029.0, 2015.0, 50.0), DVec3::new(1063.0, 2015.0, 50.0));
    assert!(drawn_at(h.state(), west_edge), "the west tile is drawn to its east edge");
    assert!(!drawn_at(h.state(), east_edge), "the east tile's far half is cut");

    let png = save_screenshot(&mut h, &shots);
    let sidecar = png.with_extension("json");
    let recorded: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&sidecar).unwrap()).unwrap();
    assert_eq!(
        recorded["looks"][1]["clip"]["max"][0],
        serde_json::json!(clip_box.max[0]),
        "the sidecar records the cut"
    );
    assert!(recorded["looks"][0].get("clip").is_none(), "and the whole layer without one");
    // The screenshot, for people to look at (target/tmp).
    std::fs::copy(&png, std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("viewer-layer-cut.png")).unwrap();
    let shot = image::open(&png).unwrap().to_rgba8();
    let rendered = common::viewer::render_again(&[&west, &east], &sidecar, dir.path());
    let epsilon = common::mean_difference(&shot, &rendered);
    eprintln!("{expected} of 3600 east points kept; render --camera ε = {epsilon:.4}");
    assert!(epsilon <= 0.05, "render --camera draws the screenshot again: ε = {epsilon:.3}");
}

/// Two COPC tiles side by side in x (west, east) of 115,600 points each, several nodes a tile.
fn copc_tiles(dir: &std::path::Path) -> [std::path::PathBuf; 2] {
    let (side, spacing, origin) = (340, 0.3, [431_000.0, 5_012_000.0, 80.0]);
    ["west", "east"].map(|name| {
        let k = if name == "west" { 0.0 } else { 1.0 };
        let from = [origin[0] + k * side as f64 * spacing, origin[1], origin[2]];
        let laz = write(&dir.join(format!("{name}.laz")), &tilted_grid(side, spacing, 0.02, from), from, None);
        let copc = dir.join(format!("{name}.copc.laz"));
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
            .args(["convert".as_ref(), laz.as_os_str(), copc.as_os_str()])
            .output()
            .unwrap();
        assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
        copc
    })
}

/// The east tile comes from a real HTTP server, its URL typed in the Model section.
#[test]
fn streamed_layers_share_the_windows_one_budget_and_the_statistics_give_each_share() {
    let dir = tempfile::tempdir().unwrap();
    let [west, _] = copc_tiles(dir.path());
    let server = common::nginx::Nginx::serve(dir.path());
    let budget = 60_000;
    let parameters = vec![(pointblend::frame::Parameter::PointBudget, budget.to_string())];
    let viewer = ViewerOptions { file: Some(west), mode: Some(RenderMode::TwoPass), parameters, ..options(dir.path()) };
    let mut h = harness_sized(viewer, TALL);
    wait_for(&mut h, "the west tile", settled_in(RenderMode::TwoPass));
    h.get_by_label("URL").focus();
    h.step();
    h.get_by_label("URL").type_text(&server.url("east.copc.laz"));
    h.step();
    h.get_by_label("open URL").click();
    h.step();
    let shares = |app: &ViewerApp| app.stream_status().map(|s| s.layers).unwrap_or_default();
    wait_for(&mut h, "both tiles streamed", |app| settled_in(RenderMode::TwoPass)(app) && shares(app).len() == 2);
    h.key_press(egui::Key::Home);
    wait_for(&mut h, "both tiles framed", |app| {
        settled_in(RenderMode::TwoPass)(app)
            && app.stream_status().is_some_and(|s| s.view.is_some_and(|v| v.camera == app.camera()))
    });
    let layers = shares(h.state());
    let names: Vec<&str> = layers.iter().map(|(name, _, _)| name.as_str()).collect();
    assert_eq!(names, ["west.copc.laz", "east.copc.laz"]);
    let total: usize = layers.iter().map(|(_, points, _)| points).sum();
    assert!(layers.iter().all(|(_, points, nodes)| *points > 0 && *nodes > 0), "each tile drawn: {layers:?}");
    assert!(total <= budget && total > budget / 2, "{total} points drawn under the one budget of {budget}: {layers:?}");
    assert_eq!(h.state().model().map(|m| m.scene.objects.len()), Some(2), "one object per file");
    for (name, _, nodes) in &layers {
        let share = [format!("{name}: "), format!(" points of {nodes} nodes")];
        assert!(share.iter().all(|part| h.query_by_label_contains(part).is_some()), "the statistics give {share:?}");
    }
}
