//! `tiled` under a memory bound (crates/render/src/tile_engine.rs,
//! gpu_renderer.rs): a frame whose per-splat buffers and tile lists would
//! pass `POINTBLEND_GPU_MEMORY_MB` is drawn in parts of the screen, each
//! packing the splats that reach it into the slots the bound allows, and is
//! the frame drawn whole; the frame's GPU memory stays within the bound. A
//! part that cannot be cut small enough is one clear error and no image.

mod common;

use common::tolerances::{MAX_WINDOWED_CHANGED_PIXELS, MAX_WINDOWED_PIXEL_DIFF};
use std::path::Path;
use std::process::{Command, Output};

/// `pointblend render FILE --mode tiled --size SIZE --out OUT --explain` with
/// `more` arguments, under a memory bound of `mib` MiB when given.
fn render_tiled(file: &Path, size: &str, out: &Path, mib: Option<u32>, more: &[&str]) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_pointblend"));
    command.args(["render", file.to_str().unwrap(), "--mode", "tiled", "--size", size, "--explain", "--out"]);
    command.arg(out).args(more);
    if let Some(mib) = mib {
        command.env("POINTBLEND_GPU_MEMORY_MB", mib.to_string());
    }
    command.output().unwrap()
}

/// The MiB after "GPU memory of the frame: " in `--explain`'s plan.
fn frame_memory_mib(stdout: &str) -> f64 {
    let line = stdout.lines().find(|l| l.contains("GPU memory of the frame:")).expect("the plan states its memory");
    let after = line.split("GPU memory of the frame:").nth(1).unwrap();
    after.split_whitespace().next().unwrap().parse().unwrap()
}

#[test]
fn a_frame_over_the_memory_bound_is_drawn_in_parts_and_is_the_frame_drawn_whole() {
    // The lion at opacity 0.5 takes more than 2 MiB in eye records and
    // pixel boxes alone, so the bound holds neither those nor the lists.
    let dir = tempfile::tempdir().unwrap();
    let lion = common::bundled_model();
    let (whole_png, parts_png) = (dir.path().join("whole.png"), dir.path().join("parts.png"));
    let whole = render_tiled(&lion, "256x256", &whole_png, None, &["--opacity", "0.5"]);
    assert!(whole.status.success(), "{}", String::from_utf8_lossy(&whole.stderr));
    let whole_out = String::from_utf8_lossy(&whole.stdout);
    assert!(!whole_out.contains("drawn in"), "unbounded, the frame is drawn whole: {whole_out}");
    let bound = 2;
    let whole_mib = frame_memory_mib(&whole_out);
    assert!(whole_mib > bound as f64, "the whole frame takes more than the bound below: {whole_out}");

    let parts = render_tiled(&lion, "256x256", &parts_png, Some(bound), &["--opacity", "0.5"]);
    let stdout = String::from_utf8_lossy(&parts.stdout);
    assert!(parts.status.success(), "{stdout}{}", String::from_utf8_lossy(&parts.stderr));
    let drawn_in = stdout.lines().find(|l| l.contains("drawn in")).unwrap_or_else(|| panic!("not in parts: {stdout}"));
    assert!(drawn_in.contains("tile lists of `tiled`"), "cut for the tile pipeline's memory: {drawn_in}");
    assert!(stdout.contains("packed into"), "the splats reaching a part are packed into fewer slots: {stdout}");
    let memory = frame_memory_mib(&stdout);
    assert!(memory <= bound as f64, "the frame took {memory} MiB, more than the {bound} MiB bound: {stdout}");

    let (a, b) = (image::open(&whole_png).unwrap().to_rgba8(), image::open(&parts_png).unwrap().to_rgba8());
    let (mut changed, mut largest) = (0usize, 0u8);
    for (x, y, p) in a.enumerate_pixels() {
        let most = (0..3).map(|c| p[c].abs_diff(b.get_pixel(x, y)[c])).max().unwrap();
        changed += (most > 0) as usize;
        largest = largest.max(most);
    }
    let share = changed as f64 / (256.0 * 256.0);
    println!("{drawn_in}; {memory} MiB; {changed} pixels differ from the whole frame, by at most {largest}");
    assert!(largest <= MAX_WINDOWED_PIXEL_DIFF, "a pixel differs by {largest}");
    assert!(share <= MAX_WINDOWED_CHANGED_PIXELS, "{share:.4} of the pixels differ");
    assert!(a.pixels().filter(|p| p[0] != a.get_pixel(0, 0)[0]).count() > 5000, "the lion is in the frame");
}

#[test]
fn a_part_too_small_to_cut_that_still_does_not_fit_is_one_clear_error_and_no_image() {
    // Twenty thousand splats on a spot a few pixels wide: a part of one tile
    // holds them all, and 1 MiB has slots for fewer than 8200.
    let dir = tempfile::tempdir().unwrap();
    let mut cloud = pointblend::cloud::PointCloud::default();
    for k in 0..20_000 {
        let t = k as f32 / 20_000.0;
        cloud.positions.push(glam::Vec3::new(0.001 * (t * 97.0).sin(), 0.001 * (t * 89.0).cos(), 0.0));
        cloud.normals.push(glam::Vec3::Z);
        cloud.radii.push(0.0005);
        cloud.colours.push([200, 100, 50]);
        cloud.opacity.push(0.5);
    }
    let ply = dir.path().join("spot.ply");
    pointblend::cloud::write::write_ply(&cloud, &ply, &[]).unwrap();
    let out = dir.path().join("never.png");
    let result = render_tiled(&ply, "64x64", &out, Some(1), &["--distance", "1"]);
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert!(!result.status.success(), "{stderr}");
    let errors: Vec<&str> = stderr.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{stderr}");
    assert!(errors[0].contains("even in a part of") && errors[0].contains("POINTBLEND_GPU_MEMORY_MB"), "{stderr}");
    assert!(!out.exists(), "no image from a failed render");
}
