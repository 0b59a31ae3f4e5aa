//! The viewer's panels, driven with egui_kittest (rendered with wgpu on
//! lavapipe): switching modes, a bad file, and a screenshot whose sidecar
//! reproduces it through `pointblend render --camera`.

mod common;

use common::viewer::{Dropped, drag, harness, options, save_screenshot, settled_in, wait_for};

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::Arc;
use std::time::Duration;

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use pointblend::grouping::cache::Cache;
use pointblend::render::{RenderMode, RenderSettings};
use pointblend::viewer::{ViewerApp, ViewerOptions};

/// Share of pixels whose largest channel differs by more than 8/255, over
/// the images' common centre: the panel's width follows its rows (a slower
/// frame's times, a wider row), so two frames may differ in width by a few
/// pixels, at the same height and field of view.
fn changed_share(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    assert_eq!(a.height(), b.height());
    let width = a.width().min(b.width());
    assert!(a.width().abs_diff(b.width()) <= 8, "the view changed its width: {} and {}", a.width(), b.width());
    let centre =
        |i: &image::RgbaImage| image::imageops::crop_imm(i, (i.width() - width) / 2, 0, width, i.height()).to_image();
    let (a, b) = (centre(a), centre(b));
    let changed = a.pixels().zip(b.pixels()).filter(|(p, q)| (0..3).any(|c| p[c].abs_diff(q[c]) > 8)).count();
    changed as f64 / (a.width() * a.height()) as f64
}

#[test]
fn switching_the_mode_changes_the_image() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(options(dir.path()));
    wait_for(&mut h, "the lion in two-pass", settled_in(RenderMode::TwoPass));
    let two_pass = h.state().shown_frame().unwrap().0.clone();
    let window = h.render().expect("the window renders with wgpu");
    assert_eq!(window.width(), 900);

    // Unfiltered two-pass draws hard-edged splats: a visible change.
    h.get_by_label("unfiltered").click();
    wait_for(&mut h, "unfiltered two-pass", |app| {
        app.is_settled()
            && app.shown_frame().is_some_and(|(_, k)| k.settings.quality == pointblend::frame::Quality::Unfiltered)
    });
    let unfiltered = h.state().shown_frame().unwrap().0.clone();
    let share = changed_share(&two_pass, &unfiltered);
    assert!(share > 0.01, "unfiltered changed only {:.3}% of the pixels", 100.0 * share);

    h.get_by_label("reference").click();
    wait_for(&mut h, "the reference", settled_in(RenderMode::Reference));
    let reference = h.state().shown_frame().unwrap().0.clone();
    assert!(changed_share(&unfiltered, &reference) > 0.01);

    // The mode's parameters follow the registry: deferred shows its grouping.
    h.get_by_label("deferred").click();
    h.step();
    assert!(h.query_by_label("Voronoi rasterisation (Eq. 14)").is_some());
    assert!(h.query_by_label("unfiltered").is_none(), "two-pass's quality radio belongs to two-pass only");
    wait_for(&mut h, "the deferred frame", settled_in(RenderMode::Deferred));
    let deferred = h.state().shown_frame().unwrap().0.clone();
    let share = changed_share(&reference, &deferred);
    assert!(share > 0.0005, "deferred equals the reference on all but {:.4}% of the pixels", 100.0 * share);
}

#[test]
fn a_bad_file_shows_its_error_and_keeps_the_model() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("broken.ply");
    std::fs::write(
        &bad,
        b"ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\nend_header\n\0\0",
    )
    .unwrap();
    let mut h = harness(options(dir.path()));
    wait_for(&mut h, "the lion", settled_in(RenderMode::TwoPass));
    let before = h.state().shown_frame().unwrap().0.clone();
    h.input_mut().dropped_files.push(Arc::new(Dropped(bad.clone())));
    h.step();
    wait_for(&mut h, "the load to fail", |app| !app.is_loading());
    let app = h.state();
    let error = app.load_error().expect("an error for the broken file");
    assert!(error.contains("broken.ply"), "the error names the file: {error}");
    assert_eq!(app.model().map(|m| m.name.as_str()), Some("lion.ply"), "the old model stays");
    assert!(h.query_by_label_contains("Could not open").is_some(), "the error is shown in the window");
    h.step();
    assert_eq!(h.state().shown_frame().unwrap().0, &before, "the old image stays");
}

/// The frame bench draws of a sidecar's view: its timing path
/// ([`pointblend::bench::timing::time_frames`]) through `render_frame`.
fn bench_image(sidecar: &Path, cache: &Path) -> image::RgbaImage {
    let view = pointblend::frame::Sidecar::read(sidecar).unwrap();
    let settings = view.settings().unwrap();
    let (scene, _) = pointblend::scene::open(&common::bundled_model(), &Default::default()).unwrap();
    let mut frames = pointblend::render::PreparedScene::of(Arc::new(scene)).with_cache(Cache::in_dir(cache));
    let config = pointblend::bench::config::BenchConfig {
        variants: Vec::new(),
        settings,
        materials: Default::default(),
        width: view.size[0],
        height: view.size[1],
        frames: 1,
        warm_up: 1,
        views: 1,
        out: cache.to_path_buf(),
        progress: false,
        orders: false,
        animate: None,
        environment: None,
        stream: Default::default(),
        camera: Default::default(),
        time: None,
        path: None,
        stream_budget: Default::default(),
        ruler: None,
        no_reference: false,
    };
    let mut renderer = pointblend::render::GpuRenderer::new().unwrap();
    let spec = frames.resolve(&settings, pointblend::frame::View::still((config.width, config.height)));
    let timed = pointblend::bench::timing::time_frames(&mut renderer, &mut frames, &view.camera(), &spec, &config);
    timed.unwrap().0.image
}

/// The viewer, `render` and bench draw the same image of one view: all
/// three make it through `PreparedScene::render_frame`.
#[test]
fn a_screenshot_and_its_sidecar_reproduce_the_image_through_render_and_bench() {
    let dir = tempfile::tempdir().unwrap();
    let shots = dir.path().join("shots");
    let mut h = harness(ViewerOptions { mode: Some(RenderMode::Deferred), ..options(&shots) });
    wait_for(&mut h, "the deferred lion", settled_in(RenderMode::Deferred));
    let png = save_screenshot(&mut h, &shots);
    let sidecar = png.with_extension("json");
    assert!(sidecar.exists(), "{} has no sidecar", png.display());
    let shot = image::open(&png).unwrap().to_rgba8();
    assert_eq!(Some(shot.dimensions()), h.state().shown_frame().map(|(i, _)| i.dimensions()));

    let rendered = common::viewer::render_again(&[&common::bundled_model()], &sidecar, dir.path());
    assert_eq!(rendered.dimensions(), shot.dimensions());
    let differing = rendered.pixels().zip(shot.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "{differing} pixels differ between the screenshot and its re-render");
    let benched = bench_image(&sidecar, &dir.path().join("cache"));
    assert_eq!(benched.dimensions(), shot.dimensions());
    let differing = benched.pixels().zip(shot.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "{differing} pixels differ between the screenshot and bench's frame");
}

#[test]
fn resizing_down_to_one_pixel_and_back_keeps_drawing() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(options(dir.path()));
    wait_for(&mut h, "the lion", settled_in(RenderMode::TwoPass));
    for size in [[1.0, 1.0], [0.0, 0.0], [320.0, 1.0], [1.0, 240.0], [640.0, 360.0]] {
        h.set_size(egui::vec2(size[0], size[1]));
        h.step();
        wait_for(&mut h, "a frame at the new size", |app| app.is_settled());
        let (image, key) = h.state().shown_frame().unwrap();
        assert!(image.width() >= 1 && image.height() >= 1 && image.dimensions() == key.size, "{size:?}");
    }
    let (image, _) = h.state().shown_frame().unwrap();
    assert!(image.width() > 100, "the view grows back: {:?}", image.dimensions());
}

#[test]
fn the_opacity_slider_makes_a_transparent_mode_see_through_and_keeps_the_view() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(options(dir.path()));
    wait_for(&mut h, "the lion in two-pass", settled_in(RenderMode::TwoPass));
    h.get_by_label("depth-peel").click();
    wait_for(&mut h, "the opaque lion in depth-peel", settled_in(RenderMode::DepthPeel));
    let (opaque, key) = h.state().shown_frame().map(|(i, k)| (i.clone(), k.clone())).unwrap();
    assert!(h.query_all_by_label("opacity").next().is_some(), "the model panel has an opacity slider");

    let ctx = h.ctx.clone();
    h.state_mut().set_opacity(&ctx, 0.4);
    wait_for(&mut h, "the lion at opacity 0.4", |app| {
        settled_in(RenderMode::DepthPeel)(app)
            && app.model().is_some_and(|m| m.opacity() == (0.4, true))
            && app.shown_frame().is_some_and(|(_, k)| k.generation > key.generation)
    });
    let (seen_through, after) = h.state().shown_frame().map(|(i, k)| (i.clone(), k.clone())).unwrap();
    assert_eq!(after.camera, key.camera, "a new opacity keeps the view");
    let share = changed_share(&opaque, &seen_through);
    println!("{:.1}% of the pixels changed", 100.0 * share);
    assert!(share > 0.05, "the lion shows its back layers and the background through it: {share}");
}

#[test]
fn an_environment_map_picked_in_the_viewer_is_reflected_and_refracted_by_alg2() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = harness(options(dir.path()));
    wait_for(&mut h, "the lion in two-pass", settled_in(RenderMode::TwoPass));
    assert!(h.query_by_label("environment").is_some(), "the model panel has an environment picker");
    let ctx = h.ctx.clone();
    h.state_mut().set_opacity(&ctx, 0.4);
    wait_for(&mut h, "the lion at opacity 0.4", |app| app.model().is_some_and(|m| m.opacity() == (0.4, true)));
    h.get_by_label("alg2").click();
    wait_for(&mut h, "the glass lion in alg2", |app| {
        settled_in(RenderMode::Alg2)(app) && app.shown_frame().is_some_and(|(_, k)| k.settings.mode == RenderMode::Alg2)
    });
    let (plain, key) = h.state().shown_frame().map(|(i, k)| (i.clone(), k.clone())).unwrap();
    h.state_mut()
        .set_environment(&ctx, Some(pointblend::assets::path(pointblend::assets::BUNDLED_ENVIRONMENT).unwrap()));
    wait_for(&mut h, "the lion in the Venice map", |app| {
        settled_in(RenderMode::Alg2)(app)
            && app.model().is_some_and(|m| m.scene.environment.is_some())
            && app.shown_frame().is_some_and(|(_, k)| k.generation > key.generation)
    });
    let (in_venice, _) = h.state().shown_frame().map(|(i, k)| (i.clone(), k.clone())).unwrap();
    let share = changed_share(&plain, &in_venice);
    println!("{:.1}% of the pixels changed", 100.0 * share);
    // The skybox replaces the flat background and the lion reflects and refracts it.
    assert!(share > 0.5, "the map shows: {share}");
    assert!(in_venice.pixels().all(|p| p.0[..3] != [0, 0, 0]), "no black (NaN) pixels");
}

#[test]
fn a_scene_lights_the_view_and_lights_move_and_go() {
    let dir = tempfile::tempdir().unwrap();
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/shadow-floor.toml");
    let mut h = harness(ViewerOptions { file: Some(file), ..options(dir.path()) });
    let lit_by = |n: usize| {
        move |app: &ViewerApp| app.is_settled() && app.shown_frame().is_some_and(|(_, k)| k.settings.lights.len() == n)
    };
    wait_for(&mut h, "the floor scene lit by its light", lit_by(1));
    // The panel's width follows its rows, so frames are compared over their common centre.
    let centre = |image: &image::RgbaImage| {
        image::imageops::crop_imm(image, (image.width() - 400) / 2, 0, 400, image.height()).to_image()
    };
    let lit = centre(h.state().shown_frame().unwrap().0);
    assert!(h.query_by_label("light 1").is_some(), "the light's row is shown");
    assert!(h.query_by_label("TSM").is_some(), "the shadow method is offered");

    // Deleting it brings the headlight back: another image.
    h.get_by_label("delete").click();
    wait_for(&mut h, "the headlight", lit_by(0));
    let headlight = centre(h.state().shown_frame().unwrap().0);
    assert!(changed_share(&lit, &headlight) > 0.01, "the light and its shadow changed the image");

    // Adding one lights it again, with shadows.
    h.get_by_label("add a light").click();
    wait_for(&mut h, "a new light", lit_by(1));
    let again = centre(h.state().shown_frame().unwrap().0);
    assert!(changed_share(&headlight, &again) > 0.01);
}

#[test]
fn a_moving_scene_plays_and_pauses_and_states_its_regroup_cost() {
    let dir = tempfile::tempdir().unwrap();
    let file = common::asset("lion-wave.toml");
    let mut h = harness(ViewerOptions { file: Some(file), mode: Some(RenderMode::Deferred), ..options(dir.path()) });
    let shown_at = |app: &ViewerApp| app.shown_frame().and_then(|(_, k)| k.time);
    wait_for(&mut h, "the first frame of the moving scene", |app| shown_at(app) == Some(0.0));
    let first = h.state().shown_frame().unwrap().0.clone();
    h.get_by_label("play").click();
    wait_for(&mut h, "a later frame", |app| shown_at(app).is_some_and(|t| t > 0.2));
    let later = h.state().shown_frame().unwrap().0.clone();
    assert!(changed_share(&first, &later) > 0.005, "the lion moved");
    assert!(h.query_all_by_label_contains("regrouped").next().is_some(), "the statistics state the regroup cost");
    h.get_by_label("pause").click();
    h.step();
    let paused = shown_at(h.state());
    for _ in 0..20 {
        h.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    wait_for(&mut h, "the paused frame", |app| app.is_settled());
    let still = shown_at(h.state());
    assert!(still.is_some() && still >= paused, "paused at {paused:?}, shown {still:?}");
    let settled = h.state().shown_frame().unwrap().0.clone();
    for _ in 0..10 {
        h.step();
        std::thread::sleep(Duration::from_millis(20));
    }
    assert_eq!(shown_at(h.state()), still, "a paused animation stays where it is");
    assert_eq!(changed_share(&settled, h.state().shown_frame().unwrap().0), 0.0);

    // A screenshot names its time, and `render --camera` draws that frame again.
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    wait_for(&mut h, "the screenshot", |app| app.status().is_some_and(|s| s.starts_with("saved")));
    let png = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "png"))
        .expect("a PNG in the screenshot folder");
    let sidecar: serde_json::Value =
        serde_json::from_slice(&std::fs::read(png.with_extension("json")).unwrap()).unwrap();
    assert_eq!(sidecar["time"].as_f64(), still, "the sidecar's time");
    let again = dir.path().join("again.png");
    let wave = common::asset("lion-wave.toml");
    let output = Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("render")
        .arg(&wave)
        .arg("--camera")
        .arg(png.with_extension("json"))
        .arg("--out")
        .arg(&again)
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let (shot, rendered) = (image::open(&png).unwrap().to_rgba8(), image::open(&again).unwrap().to_rgba8());
    let differing = rendered.pixels().zip(shot.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "{differing} pixels differ between the screenshot and its re-render at its time");
}

/// Drags across the 3D view (the right part of the window): an orbit.
fn orbit(h: &mut Harness<'_, ViewerApp>) {
    let start = egui::pos2(700.0, 300.0);
    drag(h, start, start + egui::vec2(72.0, 24.0), 6);
}

#[test]
fn a_large_model_is_drawn_under_the_point_budget_while_the_camera_moves_then_in_full() {
    let dir = tempfile::tempdir().unwrap();
    // Two lions side by side: 188,826 splats, a still model above the default moving budget.
    let lion = common::bundled_model().display().to_string();
    let file = dir.path().join("two-lions.toml");
    std::fs::write(
        &file,
        format!("[[object]]\nply = {lion:?}\n\n[[object]]\nply = {lion:?}\ntranslate = [5.0, 0.0, 0.0]\n"),
    )
    .unwrap();
    let mut h = harness(ViewerOptions { file: Some(file), ..options(dir.path()) });
    wait_for(&mut h, "the two lions in two-pass", settled_in(RenderMode::TwoPass));
    let total = h.state().model().unwrap().cloud.len();
    assert_eq!(h.state().shown_splats(), Some(total), "a still frame draws every splat");
    let hierarchy = h.state().model().unwrap().hierarchy.clone().expect("built while loading");
    assert_eq!(hierarchy.originals, total);
    orbit(&mut h);
    // 188,826 splats are over the default budget while moving: the frames drawn then keep to it.
    wait_for(&mut h, "a preview under the budget", |app| {
        app.shown_frame().is_some_and(|(_, key)| key.preview.is_some())
    });
    let budget = h.state().shown_frame().unwrap().1.preview.unwrap().budget as usize;
    let drawn = h.state().shown_splats().unwrap();
    assert!(drawn <= budget && drawn * 2 > budget, "{drawn} splats drawn under a budget of {budget}");
    assert!(budget < total);
    // When the camera stops, the full frame follows.
    wait_for(&mut h, "the full frame after the orbit", |app| {
        settled_in(RenderMode::TwoPass)(app) && app.shown_frame().is_some_and(|(_, key)| key.preview.is_none())
    });
    assert_eq!(h.state().shown_splats(), Some(total));
    assert!(h.state().shown_frame().unwrap().1.settings.point_budget.is_none());
}

#[test]
fn the_viewer_draws_a_hybrid_mesh_as_its_triangles() {
    // The bundled knot mesh in the viewer's default view, where its splats
    // are several pixels wide and every leaf is triangles: the view is the
    // reference's exact triangles, not the vertex splats.
    let dir = tempfile::tempdir().unwrap();
    let file = common::asset("knot-hybrid.toml");
    let mut h =
        harness(ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(dir.path()) });
    wait_for(&mut h, "the hybrid knot in two-pass", settled_in(RenderMode::TwoPass));
    let (image, key) = h.state().shown_frame().map(|(i, k)| (i.clone(), k.clone())).unwrap();
    let (scene, _) = pointblend::scene::open(&file, &Default::default()).unwrap();
    let options = pointblend::reference::ReferenceOptions::matching(&key.settings, &scene);
    let exact = pointblend::reference::render(&scene, &key.camera, &options, key.size.0, key.size.1);
    let splats = RenderSettings { hybrid_pixels: f32::INFINITY, ..key.settings };
    let mut frames = pointblend::render::PreparedScene::of(Arc::new(scene));
    let mut renderer = common::renderer();
    let vertex_splats = frames.render(Some(&mut *renderer), &key.camera, &splats, key.size, false).unwrap().image;
    let eps = pointblend::reference::compare(&image, &exact).unwrap().eps;
    let splat_eps = pointblend::reference::compare(&vertex_splats, &exact).unwrap().eps;
    println!("viewer: ε {eps:.3} against the triangles; the vertex splats {splat_eps:.3}");
    assert!(eps <= common::tolerances::MAX_HYBRID_EPS_RATIO * splat_eps, "ε {eps} against {splat_eps}");
}

#[test]
fn a_copc_file_streams_its_view_and_the_point_budget_reselects_it() {
    let dir = tempfile::tempdir().unwrap();
    // 2 x 400² points: a root and its children (the writer's leaves hold at most 100,000).
    let laz = common::lidar::two_planes(&dir.path().join("tile.laz"), 400, 0.2, [500_000.0, 4_000_000.0, 10.0], 3.0);
    let copc = dir.path().join("tile.copc.laz");
    pointblend::copc::write::write_copc(&laz, &copc, false).unwrap();
    let mut h = harness(ViewerOptions { file: Some(copc), ..options(dir.path()) });
    let streamed = |app: &ViewerApp| app.is_settled() && app.model().is_some_and(|m| m.streamed.is_some());
    wait_for(&mut h, "the streamed view", streamed);
    let all = h.state().shown_splats().unwrap();
    assert!(h.query_by_label_contains("streaming:").is_some(), "the statistics have a streaming line");
    assert!(h.query_by_label_contains("node cache:").is_some(), "and the cache's");
    // The panel's budget (250,000 when switched on) is below the default (1M): fewer nodes.
    h.get_by_label("point budget").click();
    wait_for(&mut h, "the view reselected", |app| streamed(app) && app.shown_splats().is_some_and(|n| n < all));
    let fewer = h.state().shown_splats().unwrap();
    println!("streamed: {all} splats under the default budget, {fewer} under the panel's");
    assert!(fewer <= 250_000 && all > 250_000, "{fewer} of {all}");
}

/// A COPC file of two `side`² grids 3 m apart (made by `convert`'s writer),
/// served by nginx as `tile.copc.laz` (and `slow/tile.copc.laz`).
fn served_copc(dir: &Path, side: usize) -> common::nginx::Nginx {
    let laz = common::lidar::two_planes(&dir.join("tile.laz"), side, 0.2, [500_000.0, 4_000_000.0, 10.0], 3.0);
    let served = dir.join("served");
    std::fs::create_dir_all(&served).unwrap();
    pointblend::copc::write::write_copc(&laz, &served.join("tile.copc.laz"), false).unwrap();
    common::nginx::Nginx::serve(&served)
}

#[test]
fn the_viewer_streams_a_url_from_a_real_server_with_the_command_lines_camera_and_cache() {
    let dir = tempfile::tempdir().unwrap();
    let server = served_copc(dir.path(), 200);
    let url = PathBuf::from(server.url("tile.copc.laz"));
    let asked = pointblend::frame::CameraRequest { azimuth: Some(70.0), elevation: Some(25.0), ..Default::default() };
    let stream = pointblend::copc::StreamOptions { cache_bytes: 64_000_000, ..Default::default() };
    let mut h = harness(ViewerOptions { file: Some(url), camera: asked, stream, ..options(dir.path()) });
    let streamed = |app: &ViewerApp| app.is_settled() && app.model().is_some_and(|m| m.streamed.is_some());
    wait_for(&mut h, "the streamed view of the URL", streamed);
    assert!(h.state().shown_splats().unwrap() > 1000, "the URL's points are drawn");
    let camera = h.state().camera();
    assert_eq!((camera.azimuth_deg, camera.elevation_deg), (70.0, 25.0), "the command line's camera");
    assert!(h.query_by_label_contains(" of 64 MB (").is_some(), "the node cache's line shows the bound given");
}

/// The render thread does not wait on loading, and a view refines in
/// steps: over a slow server (64 KB/s a request), while the nodes a larger
/// budget adds load, an orbit draws frames at the new camera with the
/// nodes already there, and the nodes loaded so far are shown before the
/// last one arrives, more at each step (coarse first, never fewer).
#[test]
fn frames_keep_coming_while_a_slow_server_sends_the_new_nodes_which_appear_step_by_step() {
    let dir = tempfile::tempdir().unwrap();
    let server = served_copc(dir.path(), 600);
    let url = PathBuf::from(server.url("slow/tile.copc.laz"));
    // A budget that holds the root alone.
    let parameters = vec![(pointblend::frame::Parameter::PointBudget, "40000".to_string())];
    let mut h = harness(ViewerOptions { file: Some(url), parameters, ..options(dir.path()) });
    let streamed = |app: &ViewerApp| app.is_settled() && app.model().is_some_and(|m| m.streamed.is_some());
    wait_for(&mut h, "the root's view", streamed);
    let coarse = h.state().shown_splats().unwrap();
    // The budget switched off: every node (1M by default), from the slow server.
    h.get_by_label("point budget").click();
    wait_for(&mut h, "the other nodes' loading", |app| app.is_loading());
    let shown_while_loading = std::cell::RefCell::new(Vec::new());
    wait_for(&mut h, "a step shown while the rest load", |app| {
        let mut shown = shown_while_loading.borrow_mut();
        if let Some(n) = app.shown_splats().filter(|n| shown.last() != Some(n)) {
            shown.push(n);
        }
        app.is_loading() && app.shown_splats().is_some_and(|n| n > coarse)
    });
    let steps = shown_while_loading.into_inner();
    assert!(steps.windows(2).all(|w| w[0] <= w[1]), "a step never shows fewer splats: {steps:?}");
    let before = h.state().camera();
    let centre = h.state().view_rect().center();
    drag(&mut h, centre, centre + egui::vec2(120.0, 0.0), 4);
    let turned = h.state().camera();
    assert_ne!(turned.azimuth_deg, before.azimuth_deg, "the drag orbits");
    wait_for(&mut h, "a frame at the new camera", |app| app.shown_frame().is_some_and(|(_, k)| k.camera == turned));
    assert!(h.state().is_loading(), "the frame came before the nodes");
    wait_for(&mut h, "the new nodes drawn", |app| streamed(app) && app.shown_splats().is_some_and(|n| n > coarse));
    let status = h.state().model().unwrap().streamed.as_ref().unwrap().status();
    let all = h.state().shown_splats().unwrap();
    println!(
        "slow server: {coarse} splats, then {all} of {} nodes; shown while loading: {steps:?}",
        status.nodes_shown
    );
}

/// A lit view's sidecar records its lights, so `render --camera` lights it
/// again: the scene file's light here (headlit, the image would differ).
#[test]
fn a_lit_screenshot_is_rendered_again_with_its_lights() {
    let dir = tempfile::tempdir().unwrap();
    let shots = dir.path().join("shots");
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/shadow-floor.toml");
    let mut h = harness(ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(&shots) });
    let lit =
        |app: &ViewerApp| app.is_settled() && app.shown_frame().is_some_and(|(_, k)| k.settings.lights.len() == 1);
    wait_for(&mut h, "the floor scene lit by its light", lit);
    let png = save_screenshot(&mut h, &shots);
    let sidecar = pointblend::frame::Sidecar::read(&png.with_extension("json")).unwrap();
    let lights = sidecar.lights().unwrap();
    assert_eq!(lights.len(), 1, "the sidecar records the light");
    let pointblend::frame::LightKind::Point(at) = lights[0].kind else { panic!("a point light") };
    assert!(
        at.distance(glam::Vec3::new(-3.0, 8.5, 3.5)) < 1e-4,
        "in file coordinates, as the scene file gives it: {at}"
    );
    let shot = image::open(&png).unwrap().to_rgba8();
    let rendered = common::viewer::render_again(&[&file], &png.with_extension("json"), dir.path());
    assert_eq!(rendered.dimensions(), shot.dimensions());
    let differing = rendered.pixels().zip(shot.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "{differing} pixels differ between the lit screenshot and its re-render");
}

/// A screenshot of a view coloured by attribute carries the legend, where
/// the view draws it (the lower left corner), and the frame unchanged elsewhere.
#[test]
fn a_screenshot_of_a_view_coloured_by_class_carries_its_legend() {
    let dir = tempfile::tempdir().unwrap();
    let shots = dir.path().join("shots");
    let file = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/lidar-classes.toml");
    let mut h = harness(ViewerOptions { file: Some(file), mode: Some(RenderMode::TwoPass), ..options(&shots) });
    wait_for(&mut h, "the lidar demo", settled_in(RenderMode::TwoPass));
    let legend = h.state().legend_shown().expect("the lidar demo is coloured by class");
    let png = save_screenshot(&mut h, &shots);
    let shot = image::open(&png).unwrap().to_rgba8();
    let frame = h.state().shown_frame().unwrap().0.clone();
    assert_eq!(shot.dimensions(), frame.dimensions());
    let (height, width) = legend.size();
    let (w, h_px) = shot.dimensions();
    let in_corner = |x: u32, y: u32| x < width as u32 + 20 && y + height as u32 + 20 > h_px;
    let changed: Vec<(u32, u32)> = (0..h_px)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| shot.get_pixel(x, y) != frame.get_pixel(x, y))
        .collect();
    println!("{} pixels carry the legend {legend:?}", changed.len());
    assert!(changed.len() > 500, "the legend is drawn in: {} pixels", changed.len());
    assert!(changed.iter().all(|&(x, y)| in_corner(x, y)), "only the corner changes");
    // Its swatches are the classes' colours.
    let pointblend::viewer::Legend::Classes { rows, .. } = legend else { panic!("a class legend") };
    for (colour, label) in rows {
        let swatch = changed.iter().filter(|&&(x, y)| shot.get_pixel(x, y).0[..3] == colour).count();
        assert!(swatch >= 50, "{label}'s swatch: {swatch} pixels");
    }
}
