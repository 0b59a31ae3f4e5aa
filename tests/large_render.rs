//! Frames larger than a render may take (crates/render/src/subframe.rs): a
//! frame drawn a sub-frame at a time is the frame drawn whole, in every GPU
//! mode and with the passes that read neighbouring pixels (eye-dome
//! lighting, the prefilter's coverage); and an 8192² render of the bundled
//! model is drawn in sub-frames whose memory is bounded by their budget,
//! not by the frame; a frame bench times without reading it back is drawn in
//! the sub-frames its saved image is drawn in.

mod common;

use common::tolerances::{MAX_WINDOWED_CHANGED_PIXELS, MAX_WINDOWED_PIXEL_DIFF};
use pointblend::frame::{Camera, EyeDome, Prefilter, RenderSettings, View};
use pointblend::render::{GpuRenderer, PreparedScene, Readback, RenderMode};
use pointblend::scene::Scene;
use std::sync::Arc;

/// Renders `scene` in `settings` at `size`, with a window budget of `budget` bytes.
fn render(
    renderer: &mut GpuRenderer,
    scene: &Arc<Scene>,
    settings: &RenderSettings,
    size: (u32, u32),
    budget: u64,
) -> (image::RgbaImage, pointblend::render::RenderPlan, Vec<String>) {
    renderer.set_subframe_budget(budget);
    let mut frames = PreparedScene::of(Arc::clone(scene));
    let camera = Camera::default_for(frames.cloud(), size.0 as f32 / size.1 as f32);
    let frame = frames.render(Some(renderer), &camera, settings, size, false).expect("the frame renders");
    (frame.image, frame.plan, frame.report.lines())
}

#[test]
fn a_frame_drawn_in_windows_is_the_frame_drawn_whole_in_every_gpu_mode() {
    let opaque = Arc::new(Scene::from(common::thinned_lion(3)));
    let mut transparent = Scene::from(common::thinned_lion(3));
    transparent.set_opacity(0.5);
    let transparent = Arc::new(transparent);
    let size = (320, 240);
    let mut renderer = common::renderer();
    let edl = Some(EyeDome::default());
    let mut cases: Vec<(String, RenderSettings, &Arc<Scene>)> = Vec::new();
    for mode in RenderMode::ALL.into_iter().filter(|m| m.is_gpu()) {
        let scene = if mode.info().transparent { &transparent } else { &opaque };
        cases.push((mode.to_string(), RenderSettings { mode, ..Default::default() }, scene));
    }
    let two_pass = RenderSettings { mode: RenderMode::TwoPass, ..Default::default() };
    cases.push(("two-pass, EWA coverage".into(), RenderSettings { prefilter: Prefilter::Ewa, ..two_pass }, &opaque));
    cases.push(("two-pass, eye-dome".into(), RenderSettings { eye_dome: edl, ..two_pass }, &opaque));
    let deferred = RenderSettings { mode: RenderMode::Deferred, eye_dome: edl, ..Default::default() };
    cases.push(("deferred, eye-dome".into(), deferred, &opaque));
    for (what, settings, scene) in cases {
        let (whole, plan, report) = render(&mut renderer, scene, &settings, size, u64::MAX);
        assert!(!report.iter().any(|n| n.starts_with("drawn in")), "{what}: the whole frame fits");
        // A budget of a quarter of the whole frame's memory: several windows.
        let per_pixel = plan.target_bytes() / (size.0 * size.1) as u64 + 8;
        let (windowed, plan, report) = render(&mut renderer, scene, &settings, size, per_pixel * 160 * 160);
        let note = report.iter().find(|n| n.starts_with("drawn in")).unwrap_or_else(|| panic!("{what}: not windowed"));
        assert!(plan.width < size.0 && plan.height < size.1, "{what}: {note}");
        let (mut changed, mut largest) = (0, 0);
        for (x, y, a) in whole.enumerate_pixels() {
            let b = windowed.get_pixel(x, y);
            let most = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap();
            assert!(most <= MAX_WINDOWED_PIXEL_DIFF, "{what}: ({x}, {y}) is {:?} whole, {:?} in sub-frames", a.0, b.0);
            changed += (most > 0) as usize;
            largest = largest.max(most);
        }
        let share = changed as f64 / (size.0 * size.1) as f64;
        println!("{what}: {note}; {changed} pixels differ, by at most {largest}");
        assert!(share <= MAX_WINDOWED_CHANGED_PIXELS, "{what}: {share:.4} of the pixels differ");
    }
}

/// The process's peak resident memory so far (VmHWM), in bytes.
fn peak_resident_bytes() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").expect("/proc/self/status");
    let line = status.lines().find(|l| l.starts_with("VmHWM:")).expect("VmHWM");
    line.split_whitespace().nth(1).unwrap().parse::<u64>().unwrap() * 1024
}

#[test]
fn an_8192_square_render_of_the_bundled_model_takes_bounded_memory() {
    const SIDE: u32 = 8192;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/lion.ply");
    let scene = Arc::new(pointblend::scene::open(&path, &Default::default()).expect("the bundled lion").0);
    let settings = RenderSettings { mode: RenderMode::TwoPass, ..Default::default() };
    let mut renderer = common::renderer();
    let small = render(&mut renderer, &scene, &settings, (512, 512), u64::MAX).0;
    let before = peak_resident_bytes();
    let budget = pointblend::render::gpu_renderer::DEFAULT_SUBFRAME_BUDGET;
    let (image, plan, report) = render(&mut renderer, &scene, &settings, (SIDE, SIDE), budget);
    let grown = peak_resident_bytes().saturating_sub(before);
    let whole_targets = plan.target_bytes() / (plan.width as u64 * plan.height as u64) * (SIDE as u64 * SIDE as u64);
    let image_bytes = SIDE as u64 * SIDE as u64 * 4;
    let note = report.iter().find(|n| n.starts_with("drawn in")).expect("an 8192² frame is drawn in sub-frames");
    println!(
        "{note}; peak memory grew by {} MiB: the image is {} MiB, the window budget {} MiB, the whole frame's targets {} MiB",
        grown >> 20,
        image_bytes >> 20,
        budget >> 20,
        whole_targets >> 20
    );
    assert!(plan.target_bytes() <= budget, "a window's targets take {} bytes", plan.target_bytes());
    // What grows is the image, its PNG's worth of copies and one window's
    // targets: bounded by the budget, not by the whole frame's targets.
    assert!(
        grown < image_bytes * 2 + budget && grown < whole_targets,
        "peak memory grew by {grown} bytes (image {image_bytes}, budget {budget}, whole targets {whole_targets})"
    );
    // And it is the lion, as at 512²: box-filtered down 16×, the same picture.
    let down = image::imageops::resize(&image, 512, 512, image::imageops::FilterType::Triangle);
    let differing = down.pixels().zip(small.pixels()).filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) > 24)).count();
    let share = differing as f64 / (512.0 * 512.0);
    assert!(share < common::tolerances::MAX_LARGE_SHOT_CHANGED, "{share:.3} of the pixels differ from the 512² frame");
}

#[test]
fn a_timed_frame_is_drawn_in_the_sub_frames_its_saved_image_is_drawn_in() {
    // Bench times frames it does not read back: over the memory budget they
    // are drawn a sub-frame at a time too, so the frame timed is the frame saved.
    let scene = Arc::new(Scene::from(common::thinned_lion(3)));
    let size = (320, 240);
    let mut renderer = common::renderer();
    let mut frames = PreparedScene::of(Arc::clone(&scene));
    let camera = Camera::default_for(frames.cloud(), size.0 as f32 / size.1 as f32);
    let spec = frames.resolve(&RenderSettings::default(), View::still(size));
    renderer.set_subframe_budget(u64::MAX);
    let whole = frames.render_frame(Some(&mut *renderer), &camera, &spec, Readback::Image).unwrap();
    assert!(whole.report.subframes.is_none(), "the whole frame fits");
    let per_pixel = whole.plan.target_bytes() / (size.0 * size.1) as u64 + 8;
    renderer.set_subframe_budget(per_pixel * 160 * 160);
    let timed = frames.render_frame(Some(&mut *renderer), &camera, &spec, Readback::Nothing).unwrap();
    let saved = frames.render_frame(Some(&mut *renderer), &camera, &spec, Readback::Image).unwrap();
    renderer.set_subframe_budget(pointblend::render::gpu_renderer::DEFAULT_SUBFRAME_BUDGET);
    assert_eq!(timed.image.dimensions(), (0, 0), "a timed frame is not read back");
    let drawn_in = timed.report.subframes.expect("the timed frame is drawn in sub-frames");
    assert_eq!(Some(drawn_in), saved.report.subframes, "the timed and the saved frame run one plan");
    assert_eq!((timed.plan.width, timed.plan.height), (saved.plan.width, saved.plan.height));
    assert!(drawn_in.count > 1, "{drawn_in:?}");
}
