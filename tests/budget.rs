//! Frames under a point budget: nodes of the multi-resolution hierarchy
//! chosen by screen-space error, in every GPU mode, measured against the
//! reference of the whole model.

mod common;

use std::sync::Arc;

use common::tolerances::{BOUNDARY_RIM_PIXELS, MAX_BUDGET_HOLES};
use pointblend::cloud;
use pointblend::frame::{Camera, Selection, View};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::render::{PreparedScene, Readback, RenderMode, RenderSettings};
use pointblend::scene::Scene;

const SIZE: u32 = 192;

/// The bundled lion (94K splats) in its default view.
fn lion() -> (Arc<Scene>, Camera) {
    let (cloud, _) = cloud::load(&common::bundled_model()).unwrap();
    let camera = Camera::default_for(&cloud, 1.0);
    (Arc::new(Scene::from(cloud)), camera)
}

fn frame(frames: &mut PreparedScene, camera: &Camera, settings: &RenderSettings) -> (image::RgbaImage, Vec<String>) {
    let mut renderer = common::renderer();
    let frame = frames.render(Some(&mut *renderer), camera, settings, (SIZE, SIZE), false).expect("render");
    (frame.image, frame.plan.notes.into_iter().chain(frame.report.lines()).collect())
}

#[test]
fn a_budget_of_the_whole_model_is_todays_image_and_a_budget_of_one_draws_the_root() {
    let (scene, camera) = lion();
    let mut frames = PreparedScene::of(Arc::clone(&scene));
    let all = RenderSettings::default();
    let (today, _) = frame(&mut frames, &camera, &all);
    let at_size = RenderSettings { point_budget: Some(scene.len() as u32), ..all };
    let (same, notes) = frame(&mut frames, &camera, &at_size);
    assert!(today == same, "a budget of every splat changed the image");
    assert!(!notes.iter().any(|n| n.contains("point budget")), "{notes:?}");
    // Through the budgeted path itself: a budget of every splat selects the
    // hierarchy's leaves, which hold every original splat, so the frame is
    // today's but for the order the splats are summed in.
    let (whole, stats) = {
        let mut renderer = common::renderer();
        // resolve draws such a frame whole; the spec is made to take the budgeted path here.
        let mut spec = frames.resolve(&at_size, View::still((SIZE, SIZE)));
        spec.selection = Selection::Budget(scene.len() as u32);
        let frame = frames.render_frame(Some(&mut *renderer), &camera, &spec, Readback::Image).expect("render");
        (frame.image, frame.report.budget.expect("a budgeted frame"))
    };
    assert_eq!(stats.splats, scene.len(), "{stats:?}");
    let error = reference::compare(&whole, &today).unwrap();
    let worst =
        whole.pixels().zip(today.pixels()).flat_map(|(a, b)| (0..3).map(move |c| a.0[c].abs_diff(b.0[c]))).max();
    println!(
        "a budget of every splat, budgeted: ε {:.4} against today's frame, largest channel difference {worst:?}",
        error.eps
    );
    assert!(worst <= Some(1), "the budgeted path with every splat differs from today's frame by {worst:?}");
    let one = RenderSettings { point_budget: Some(1), ..all };
    let (root, notes) = frame(&mut frames, &camera, &one);
    let note = notes.iter().find(|n| n.contains("point budget 1:")).expect("the plan states the budget");
    assert!(note.contains("of 1 nodes"), "{note}");
    let background = common::background_rgb();
    assert!(root.pixels().any(|p| p.0[..3] != background), "the root node draws something");
}

#[test]
fn every_gpu_mode_draws_a_budgeted_frame_closer_to_the_reference_than_a_subsample_and_without_holes() {
    // Half of the bundled lion's splats, opaque for the opaque modes and at
    // opacity 0.5 for the transparent ones.
    let cloud = common::thinned_lion(2);
    let camera = Camera::default_for(&cloud, 1.0);
    let opaque = Arc::new(Scene::from(cloud));
    let mut glass = Scene::clone(&opaque);
    glass.set_opacity(0.5);
    let glass = Arc::new(glass);
    let mut opaque_frames = PreparedScene::of(Arc::clone(&opaque));
    let mut glass_frames = PreparedScene::of(Arc::clone(&glass));
    // A quarter of the splats, as the goal (250K of 1M).
    let budget = opaque.len() as u32 / 4;
    for mode in RenderMode::ALL.into_iter().filter(|m| m.is_gpu()) {
        let transparent = mode.info().transparent;
        let (scene, frames) = if transparent { (&glass, &mut glass_frames) } else { (&opaque, &mut opaque_frames) };
        let settings = RenderSettings { mode, point_budget: Some(budget), ..Default::default() };
        let (image, notes) = frame(frames, &camera, &settings);
        let note = notes.iter().find(|n| n.starts_with("point budget")).expect("the report states the budget");
        let drawn: usize = note.split(": ").nth(1).unwrap().split(' ').next().unwrap().parse().unwrap();
        assert!(drawn <= budget as usize && drawn > budget as usize / 2, "{mode}: {note}");
        let full = RenderSettings { point_budget: None, ..settings };
        let exact = reference::render(scene, &camera, &ReferenceOptions::matching(&full, scene), SIZE, SIZE);
        let (whole, _) = frame(frames, &camera, &full);
        let eps = reference::compare(&image, &exact).unwrap().eps;
        let whole_eps = reference::compare(&whole, &exact).unwrap().eps;
        // The same number of splats picked uniformly, radii grown to keep the area (a plain subsample).
        // Drawn as budgeted frames are: groups by hashing, redone for each set of splats.
        let mut sub_frames = PreparedScene::of(Arc::new(Scene::from(subsample(&scene.flattened(), drawn)))).moving();
        let (sub, _) = frame(&mut sub_frames, &camera, &full);
        let sub_eps = reference::compare(&sub, &exact).unwrap().eps;
        // No holes: inside the reference's silhouette (eroded) the budgeted frame shows the surface.
        let bg = common::background_rgb();
        let inside = common::morph(&common::foreground(&exact, bg), SIZE, SIZE, -BOUNDARY_RIM_PIXELS);
        let holes = inside.iter().zip(common::foreground(&image, bg)).filter(|(i, f)| **i && !*f).count();
        println!(
            "{mode}: {drawn} of {} splats, ε {eps:.3}; whole model {whole_eps:.3}; uniform subsample {sub_eps:.3}; {holes} holes",
            scene.len()
        );
        assert!(eps < sub_eps, "{mode}: the hierarchy's splats (ε {eps}) are no better than a subsample's ({sub_eps})");
        assert!(holes <= MAX_BUDGET_HOLES, "{mode}: {holes} background pixels inside");
    }
}

/// Every (n/count)-th splat, radii grown by sqrt(n/count) so that the total
/// disc area stays: what large models drew while the camera moved before
/// the hierarchy.
fn subsample(cloud: &cloud::PointCloud, count: usize) -> cloud::PointCloud {
    let n = cloud.len();
    let picks: Vec<usize> = (0..count).map(|i| i * n / count).collect();
    let grow = (n as f32 / count as f32).sqrt();
    cloud::PointCloud {
        positions: picks.iter().map(|&i| cloud.positions[i]).collect(),
        normals: picks.iter().map(|&i| cloud.normals[i]).collect(),
        radii: picks.iter().map(|&i| cloud.radii[i] * grow).collect(),
        colours: picks.iter().map(|&i| cloud.colours[i]).collect(),
        opacity: picks.iter().map(|&i| cloud.opacity[i]).collect(),
        two_sided: if cloud.two_sided.is_empty() {
            Vec::new()
        } else {
            picks.iter().map(|&i| cloud.two_sided[i]).collect()
        },
        ..Default::default()
    }
}

#[test]
fn a_budget_of_zero_is_one_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.png");
    for bad in ["0", "-5", "many"] {
        let args = [common::bundled_model().into_os_string(), "--point-budget".into(), bad.into()];
        let error = common::refused_in_one_line(&args, &out, &format!("--point-budget {bad}"));
        assert!(error.contains("--point-budget"), "{error}");
    }
}
