//! Driving the viewer in tests: a kittest harness rendered with wgpu on
//! lavapipe, options that keep screenshots and groupings in a test's
//! folder, waiting for the render thread, and pointer input.

use std::path::Path;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use pointblend::grouping::cache::Cache;
use pointblend::render::RenderMode;
use pointblend::viewer::{ViewerApp, ViewerOptions};

/// Frames of the 3D view come from a render thread: generous for lavapipe on a busy machine.
pub const PATIENCE: Duration = Duration::from_secs(180);

pub fn harness(options: ViewerOptions) -> Harness<'static, ViewerApp> {
    harness_sized(options, [900.0, 600.0])
}

/// [`harness`] in a window of `size` points (a tall one shows the whole left panel).
pub fn harness_sized(options: ViewerOptions, size: [f32; 2]) -> Harness<'static, ViewerApp> {
    Harness::builder().with_size(size).wgpu().build_eframe(move |cc| ViewerApp::new(cc, options))
}

/// Screenshots into `dir`, and groupings cached beside them, not in the user's cache.
pub fn options(dir: &Path) -> ViewerOptions {
    let cache = Some(Cache::in_dir(dir.join("grouping-cache")));
    ViewerOptions { screenshot_dir: dir.to_path_buf(), cache, ..Default::default() }
}

/// Steps the UI until `done` holds.
pub fn wait_for(harness: &mut Harness<'_, ViewerApp>, what: &str, done: impl Fn(&ViewerApp) -> bool) {
    let started = Instant::now();
    while !done(harness.state()) {
        assert!(started.elapsed() < PATIENCE, "timed out waiting for {what}");
        harness.step();
        std::thread::sleep(Duration::from_millis(20));
    }
}

pub fn settled_in(mode: RenderMode) -> impl Fn(&ViewerApp) -> bool {
    move |app| app.is_settled() && app.shown_frame().is_some_and(|(_, key)| key.settings.mode == mode)
}

fn press(pos: egui::Pos2, pressed: bool) -> egui::Event {
    egui::Event::PointerButton { pos, button: egui::PointerButton::Primary, pressed, modifiers: Default::default() }
}

/// A primary-button drag from `from` to `to` in `steps` moves.
pub fn drag(h: &mut Harness<'_, ViewerApp>, from: egui::Pos2, to: egui::Pos2, steps: u32) {
    drag_path(h, &[from, to], steps);
}

/// A primary drag through `path`'s points in turn, in `steps` moves between each two.
pub fn drag_path(h: &mut Harness<'_, ViewerApp>, path: &[egui::Pos2], steps: u32) {
    let (from, to) = (path[0], path[path.len() - 1]);
    h.input_mut().events.push(egui::Event::PointerMoved(from));
    h.input_mut().events.push(press(from, true));
    h.step();
    for leg in path.windows(2) {
        for k in 1..=steps {
            h.input_mut()
                .events
                .push(egui::Event::PointerMoved(leg[0] + (leg[1] - leg[0]) * (k as f32 / steps as f32)));
            h.step();
        }
    }
    h.input_mut().events.push(press(to, false));
    h.step();
}

/// A primary click at `at`.
pub fn click(h: &mut Harness<'_, ViewerApp>, at: egui::Pos2) {
    h.input_mut().events.push(egui::Event::PointerMoved(at));
    h.step();
    h.input_mut().events.push(press(at, true));
    h.step();
    h.input_mut().events.push(press(at, false));
    h.step();
    h.step();
}

/// Ctrl+S, then the PNG it saved in `shots`.
pub fn save_screenshot(h: &mut Harness<'_, ViewerApp>, shots: &Path) -> std::path::PathBuf {
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    wait_for(h, "the screenshot", |app| app.status().is_some_and(|s| s.starts_with("saved")));
    std::fs::read_dir(shots)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "png"))
        .expect("a PNG in the screenshot folder")
}

/// A file dropped on the window.
#[derive(Debug)]
pub struct Dropped(pub std::path::PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }
    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

/// Opens the combo box labelled `combo` and clicks its item `item`.
pub fn choose(h: &mut Harness<'_, ViewerApp>, combo: &str, item: &str) {
    use egui_kittest::kittest::Queryable;
    h.get_by_label(combo).click();
    for _ in 0..3 {
        h.step();
    }
    h.get_by_label(item).click();
}

/// Settled in two-pass, drawn orthographic from the top.
pub fn settled_ortho_top(app: &ViewerApp) -> bool {
    settled_in(RenderMode::TwoPass)(app)
        && app.shown_frame().is_some_and(|(_, k)| {
            k.camera.projection == pointblend::frame::Projection::Ortho && k.camera.elevation_deg == 90.0
        })
}

/// The model in two-pass, then keys 1 (top) and O (orthographic), until that view is drawn.
pub fn to_ortho_top(h: &mut Harness<'_, ViewerApp>) {
    wait_for(h, "the model in two-pass", settled_in(RenderMode::TwoPass));
    for key in [egui::Key::Num1, egui::Key::O] {
        h.key_press(key);
        h.step();
    }
    wait_for(h, "the orthographic top view", settled_ortho_top);
}

/// `render FILES --camera SIDECAR` into `dir`: the image it draws.
pub fn render_again(files: &[&Path], sidecar: &Path, dir: &Path) -> image::RgbaImage {
    let again = dir.join("again.png");
    let output = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("render")
        .args(files)
        .arg("--camera")
        .arg(sidecar)
        .arg("--out")
        .arg(&again)
        .env("POINTBLEND_CACHE", dir.join("cache"))
        .output()
        .unwrap();
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    image::open(&again).unwrap().to_rgba8()
}
