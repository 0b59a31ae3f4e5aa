//! Box and lasso selections in the viewer, driven with egui_kittest: a box
//! or a lasso dragged on the orthographic top view of a lidar tile selects
//! the points under it, and exporting it writes those points, and no other,
//! as `convert` writes a subset: the format, the scale and every field
//! kept, extra bytes too. Kept or hidden, a selection cuts the view, and a
//! lasso hidden in a perspective view is drawn again by `render --camera`.

mod common;

use common::lidar::{ExtraField, tilted_grid, write, write_fields};
use common::viewer::{
    drag, drag_path, harness_sized, options, save_screenshot, settled_in, settled_ortho_top, to_ortho_top, wait_for,
};
use egui_kittest::kittest::Queryable;
use glam::DVec3;
use pointblend::render::RenderMode;
use pointblend::viewer::{ViewerApp, ViewerOptions};

const TALL: [f32; 2] = [900.0, 1300.0];

/// Every point of a LAS file as it reads back.
fn points_of(path: &std::path::Path) -> (las::Header, Vec<las::Point>) {
    let mut reader = las::Reader::from_path(path).unwrap();
    let header = reader.header().clone();
    (header, reader.read_all().unwrap().points().map(Result::unwrap).collect())
}

#[test]
fn a_box_selection_exports_the_points_inside_it_with_every_field() {
    let dir = tempfile::tempdir().unwrap();
    let points = tilted_grid(60, 0.5, 0.0, [1000.0, 2000.0, 50.0]);
    let extra = [ExtraField { name: "height", scale: None }];
    let file = write_fields(&dir.path().join("tile.las"), &points, [0.0; 3], &extra);
    let viewer = ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(dir.path()) };
    let mut h = harness_sized(viewer, TALL);
    to_ortho_top(&mut h);
    h.get_by_label("select").click();
    h.step();
    let (lo, hi) = (DVec3::new(1010.2, 2010.2, 50.0), DVec3::new(1021.3, 2018.3, 50.0));
    let (from, to) = (h.state().screen_position(lo).unwrap(), h.state().screen_position(hi).unwrap());
    let camera = h.state().camera();
    drag(&mut h, from, to, 6);
    assert_eq!(h.state().camera(), camera, "the select tool's drag does not orbit");
    assert!(h.state().inspection().selection.is_some());

    let out = dir.path().join("selected.las");
    let ctx = h.ctx.clone();
    h.state_mut().export_selection(&ctx, &out);
    // A second export asked while the first runs waits its turn: the first is not dropped.
    let second = dir.path().join("second.las");
    h.state_mut().export_selection(&ctx, &second);
    assert!(h.state().status().is_some_and(|s| s.contains("under way")), "{:?}", h.state().status());
    wait_for(&mut h, "the export", |app| !app.is_exporting());
    assert!(h.state().status().is_some_and(|s| s.starts_with("exported")), "{:?}", h.state().status());
    assert!(!second.exists(), "the second export was not started");

    let (header_in, all) = points_of(&file);
    let (header_out, selected) = points_of(&out);
    assert_eq!(header_out.point_format(), header_in.point_format(), "the point format, extra bytes included");
    assert_eq!(header_out.transforms(), header_in.transforms(), "the scale and offset");
    // In the top view x runs right and y up: the box is this rectangle of the file.
    let inside = |p: &las::Point| (lo.x..=hi.x).contains(&p.x) && (lo.y..=hi.y).contains(&p.y);
    let want: Vec<&las::Point> = all.iter().filter(|p| inside(p)).collect();
    assert!(want.len() > 300, "{} points in the box", want.len());
    assert_eq!(selected.len(), want.len(), "the points inside the box, and no other");
    for (got, want) in selected.iter().zip(want) {
        assert_eq!(got, want, "every field of the point");
    }
}

/// Whether the frame on screen drew something at the file point `p`.
fn drawn_at(app: &ViewerApp, p: DVec3) -> bool {
    let (image, _) = app.shown_frame().unwrap();
    let view = app.view_rect();
    let at = (app.screen_position(p).unwrap() - view.min) * (image.width() as f32 / view.width());
    image.get_pixel(at.x as u32, at.y as u32).0[..3] != common::background_rgb()
}

#[test]
fn keep_only_clips_the_view_to_the_selection_and_hide_hides_one() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(&dir.path().join("tile.las"), &tilted_grid(60, 0.5, 0.0, [1000.0, 2000.0, 50.0]), [0.0; 3], None);
    let viewer = ViewerOptions { file: Some(file), mode: Some(RenderMode::TwoPass), ..options(dir.path()) };
    let mut h = harness_sized(viewer, TALL);
    to_ortho_top(&mut h);
    h.get_by_label("select").click();
    h.step();
    let on = |x: f64, y: f64| DVec3::new(x, y, 50.0);
    let select = |h: &mut egui_kittest::Harness<'_, ViewerApp>, lo: DVec3, hi: DVec3| {
        let (from, to) = (h.state().screen_position(lo).unwrap(), h.state().screen_position(hi).unwrap());
        drag(h, from, to, 6);
    };
    select(&mut h, on(1005.0, 2005.0), on(1025.0, 2025.0));
    h.get_by_label("keep only").click();
    wait_for(&mut h, "the view clipped to the box", |app| {
        settled_ortho_top(app) && app.shown_frame().is_some_and(|(_, k)| !k.settings.clip.is_empty())
    });
    assert!(drawn_at(h.state(), on(1015.0, 2015.0)), "inside the box is drawn");
    assert!(!drawn_at(h.state(), on(1027.0, 2015.0)) && !drawn_at(h.state(), on(1015.0, 2003.0)), "outside is clipped");

    select(&mut h, on(1010.0, 2010.0), on(1020.0, 2020.0));
    h.get_by_label("hide").click();
    wait_for(&mut h, "the second box hidden", |app| {
        settled_ortho_top(app) && app.inspection().selection.is_none() && !drawn_at(app, on(1015.0, 2015.0))
    });
    assert!(drawn_at(h.state(), on(1007.0, 2015.0)), "the rest of the first box stays");
    assert!(!drawn_at(h.state(), on(1027.0, 2015.0)), "and outside it stays clipped");
}

/// Whether `p` is inside the triangle `t` (x and y), and its distance to the triangle's nearest edge.
fn in_triangle(t: &[DVec3; 3], p: DVec3) -> (bool, f64) {
    let side = |a: DVec3, b: DVec3| (b.x - a.x) * (p.y - a.y) - (b.y - a.y) * (p.x - a.x);
    let sides = [side(t[0], t[1]), side(t[1], t[2]), side(t[2], t[0])];
    let inside = sides.iter().all(|s| *s > 0.0) || sides.iter().all(|s| *s < 0.0);
    let near = (0..3)
        .map(|k| sides[k].abs() / t[k].truncate().distance(t[(k + 1) % 3].truncate()))
        .fold(f64::INFINITY, f64::min);
    (inside, near)
}

#[test]
fn a_lasso_selection_exports_the_points_inside_its_outline() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(&dir.path().join("tile.las"), &tilted_grid(60, 0.5, 0.0, [1000.0, 2000.0, 50.0]), [0.0; 3], None);
    let viewer = ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(dir.path()) };
    let mut h = harness_sized(viewer, TALL);
    to_ortho_top(&mut h);
    h.get_by_label("lasso").click();
    h.step();
    // A triangle no grid point lies near the edges of, drawn as a lasso around and back to its start.
    let triangle =
        [DVec3::new(1005.13, 2005.37, 50.0), DVec3::new(1025.21, 2007.39, 50.0), DVec3::new(1012.33, 2024.27, 50.0)];
    let path: Vec<egui::Pos2> = [0, 1, 2, 0].iter().map(|&k| h.state().screen_position(triangle[k]).unwrap()).collect();
    drag_path(&mut h, &path, 8);
    let selection = h.state().inspection().selection.clone().expect("the lasso is the selection");
    assert!(selection.lasso.len() > 20, "the outline follows the pointer: {} points", selection.lasso.len());

    let out = dir.path().join("lasso.las");
    let ctx = h.ctx.clone();
    h.state_mut().export_selection(&ctx, &out);
    wait_for(&mut h, "the export", |app| !app.is_exporting());
    assert!(h.state().status().is_some_and(|s| s.starts_with("exported")), "{:?}", h.state().status());
    let (_, all) = points_of(&file);
    let (_, selected) = points_of(&out);
    let at = |p: &las::Point| DVec3::new(p.x, p.y, p.z);
    assert!(all.iter().all(|p| in_triangle(&triangle, at(p)).1 > 1e-3), "no point on an edge");
    let want: Vec<&las::Point> = all.iter().filter(|p| in_triangle(&triangle, at(p)).0).collect();
    assert!(want.len() > 300, "{} points in the triangle", want.len());
    assert_eq!(selected.len(), want.len(), "the points inside the outline, and no other (not its box's)");
    assert!(selected.iter().zip(want).all(|(got, want)| got == want), "every field of every point");
}

#[test]
fn a_lasso_hidden_in_perspective_is_drawn_again_by_render_camera() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(&dir.path().join("tile.las"), &tilted_grid(60, 0.5, 0.0, [1000.0, 2000.0, 50.0]), [0.0; 3], None);
    let shots = dir.path().join("shots");
    let viewer = ViewerOptions { file: Some(file.clone()), mode: Some(RenderMode::TwoPass), ..options(&shots) };
    let mut h = harness_sized(viewer, TALL);
    wait_for(&mut h, "the tile in two-pass", settled_in(RenderMode::TwoPass));
    h.get_by_label("lasso").click();
    h.step();
    let on = |x: f64, y: f64| DVec3::new(x, y, 50.0);
    let (centre, outside) = (on(1015.0, 2015.0), on(1027.0, 2027.0));
    assert!(drawn_at(h.state(), centre) && drawn_at(h.state(), outside), "the tile is drawn there first");
    let corners = [on(1008.0, 2008.0), on(1022.0, 2009.0), on(1020.0, 2022.0), on(1009.0, 2020.0), on(1008.0, 2008.0)];
    let path: Vec<egui::Pos2> = corners.iter().map(|&c| h.state().screen_position(c).unwrap()).collect();
    drag_path(&mut h, &path, 6);
    h.get_by_label("hide").click();
    wait_for(&mut h, "the lasso hidden", |app| {
        settled_in(RenderMode::TwoPass)(app)
            && app.model().is_some_and(|m| m.style.as_ref().is_some_and(|s| s.regions.len() == 1))
    });
    assert!(!drawn_at(h.state(), centre), "inside the lasso is hidden");
    assert!(drawn_at(h.state(), outside), "outside it is drawn");

    let png = save_screenshot(&mut h, &shots);
    let sidecar = png.with_extension("json");
    let recorded: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&sidecar).unwrap()).unwrap();
    assert_eq!(recorded["style"]["regions"][0]["keep"], false, "the sidecar records the hidden lasso");
    let shot = image::open(&png).unwrap().to_rgba8();
    let rendered = common::viewer::render_again(&[&file], &sidecar, dir.path());
    let epsilon = common::mean_difference(&shot, &rendered);
    assert!(epsilon <= 0.05, "render --camera draws the screenshot again: ε = {epsilon:.3}");
}
