//! The status line's coordinates in the viewer, driven with egui_kittest:
//! over a known point of a UTM tile (EPSG:32611, 500 km and 4,100 km from
//! the origin, 1 mm scale) they are that point's position to the file's
//! scale. They come from the frame's depth: a mode without one says so. The
//! wheel zooms about the point under the cursor, which stays under it.

mod common;

use common::lidar::{CrsRecord, tilted_grid, write_with_crs};
use common::viewer::{harness, options, settled_in, settled_ortho_top, to_ortho_top, wait_for};
use egui_kittest::kittest::Queryable;
use glam::DVec3;
use pointblend::frame::UpAxis;
use pointblend::render::RenderMode;
use pointblend::viewer::{ViewerApp, ViewerOptions};

const OFFSET: [f64; 3] = [500_000.0, 4_100_000.0, 0.0];
const SCALE: f64 = 0.001;

/// A 60 m tile rising 1 in 10 eastwards, in UTM zone 11N (EPSG:32611), and the grid point (70, 50) as stored.
fn utm_tile(dir: &std::path::Path) -> (std::path::PathBuf, DVec3) {
    let points = tilted_grid(120, 0.5, 0.1, [OFFSET[0] + 0.25, OFFSET[1] + 0.25, 100.0]);
    let path = write_with_crs(&dir.join("utm.las"), &points, OFFSET, CrsRecord::GeoTiffKeys(&[(3072, 32611)]));
    let stored = |v: f64, o: f64| ((v - o) / SCALE).round() * SCALE + o;
    let p = points[70 * 120 + 50].xyz;
    (path, DVec3::new(stored(p[0], OFFSET[0]), stored(p[1], OFFSET[1]), stored(p[2], OFFSET[2])))
}

fn hover(h: &mut egui_kittest::Harness<'_, ViewerApp>, at: egui::Pos2) {
    h.input_mut().events.push(egui::Event::PointerMoved(at));
    h.step();
}

/// Turns the wheel by `points` over the pointer, stepping until the camera has taken it all.
fn wheel(h: &mut egui_kittest::Harness<'_, ViewerApp>, points: f32) {
    let before = h.state().camera().distance;
    h.input_mut().events.push(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, points),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Wheel,
        modifiers: Default::default(),
    });
    // egui spreads a turn of the wheel over frames: step until the camera stops moving.
    let mut last = before;
    let mut still = 0;
    for _ in 0..400 {
        h.step();
        let now = h.state().camera().distance;
        still = if now == last { still + 1 } else { 0 };
        last = now;
        if still >= 5 && now != before {
            assert_eq!(points > 0.0, now < before, "the wheel zooms in when turned forward");
            return;
        }
    }
    panic!("the wheel did not settle: the distance went from {before} to {last}");
}

#[test]
fn the_status_line_gives_the_file_coordinates_under_the_cursor_to_the_files_scale() {
    let dir = tempfile::tempdir().unwrap();
    let (file, known) = utm_tile(dir.path());
    let mut h = harness(ViewerOptions { file: Some(file), mode: Some(RenderMode::TwoPass), ..options(dir.path()) });
    to_ortho_top(&mut h);
    assert_eq!(h.state().camera().up, UpAxis::PosZ, "a lidar tile is z up");

    // Zoomed in about the known point: a pixel's footprint (the depth is
    // read per pixel) becomes a few millimetres across.
    let at = h.state().screen_position(known).expect("the known point is in view");
    hover(&mut h, at);
    wheel(&mut h, 1500.0);
    let still = h.state().screen_position(known).unwrap();
    assert!(still.distance(at) < 0.5, "the wheel zoomed about the cursor: the point moved from {at:?} to {still:?}");
    wait_for(&mut h, "the zoomed view", settled_ortho_top);
    hover(&mut h, at);
    let read = h.state().cursor_coordinates().expect("a surface under the cursor");
    let off = read - known;
    assert!(off.abs().max_element() <= SCALE, "read {read:.4}, the point is {known:.4}: off by {off:.4}");
    let line = h.state().status_line();
    assert!(line.contains(&format!("x {:.3}", read.x)) && line.ends_with("(metre; EPSG:32611)"), "{line}");

    // Off the tile, nothing; in a mode whose frame keeps no depth, it says so.
    wheel(&mut h, -1500.0);
    wait_for(&mut h, "the zoomed-out view", settled_ortho_top);
    let corner = h.state().view_rect().left_top() + egui::vec2(3.0, 3.0);
    hover(&mut h, corner);
    assert_eq!(h.state().status_line(), "no surface under the cursor");
    h.get_by_label("tiled").click();
    wait_for(&mut h, "tiled", settled_in(RenderMode::Tiled));
    let over_the_tile = h.state().screen_position(known).unwrap();
    hover(&mut h, over_the_tile);
    assert!(h.state().cursor_coordinates().is_none());
    assert!(h.state().status_line().starts_with("no coordinates"), "{}", h.state().status_line());
}
