//! Moving scenes: deformations against closed forms, keyframes and sequences,
//! a still frame of a moving scene against the still scene, bad input, and
//! `bench --animate`'s per-frame rows.

mod common;

use std::path::Path;
use std::process::Command;
use std::sync::Arc;

use glam::Vec3;
use pointblend::cloud::PointCloud;
use pointblend::frame::{Camera, RenderMode, RenderSettings};
use pointblend::grouping::GroupingSpec;
use pointblend::render::PreparedScene;
use pointblend::scene::animation::{Deform, DeformFrame, DeformKind};
use pointblend::scene::{self, Scene};

/// Two parallel square grids of splats with normal +y at heights ±`gap`/2,
/// longer along x (the bend's axis) than along z.
fn two_planes(gap: f32) -> PointCloud {
    let mut cloud = PointCloud::default();
    for h in [-gap / 2.0, gap / 2.0] {
        for i in 0..=60 {
            for j in 0..=20 {
                cloud.positions.push(Vec3::new(-0.3 + i as f32 * 0.01, h, -0.1 + j as f32 * 0.01));
                cloud.normals.push(Vec3::Y);
                cloud.radii.push(0.008);
                cloud.colours.push([200, 200, 200]);
                cloud.opacity.push(1.0);
            }
        }
    }
    cloud
}

#[test]
fn a_plane_bent_into_a_cylinder_segment_has_the_analytic_positions_normals_and_radii() {
    let gap = 0.04f32;
    let cloud = two_planes(gap);
    let frame = DeformFrame::of(&cloud, Vec3::Y);
    assert_eq!((frame.u, frame.up), (glam::DVec3::X, glam::DVec3::Y), "bends along the longest axis across up");
    let (amount, period) = (1.2f32, 2.0f32);
    let bend = Deform { kind: DeformKind::Bend, amount, period, wavelength: None };
    // A quarter period: the full angle, θ = amount, over the length L = 0.6.
    let bent = bend.apply(&frame, period as f64 / 4.0, &cloud);
    let kappa = amount as f64 / frame.length;
    let radius = 1.0 / kappa;
    let mut worst = (0.0f64, 0.0f64, 0.0f64);
    for i in 0..cloud.len() {
        let p = cloud.positions[i].as_dvec3();
        let (x, h) = (p.x, p.y);
        let phi = kappa * x;
        let expected = glam::DVec3::new((radius - h) * phi.sin(), radius - (radius - h) * phi.cos(), p.z);
        let normal = glam::DVec3::new(-phi.sin(), phi.cos(), 0.0);
        // Along the arc the surface stretches by (R - h)κ = 1 - κh, across it not at all:
        // the radius keeps the area, √(1 - κh).
        let stretch = (1.0 - kappa * h).sqrt();
        let position_error = (bent.positions[i].as_dvec3() - expected).length();
        let normal_error = (bent.normals[i].as_dvec3() - normal).length();
        let radius_error = (bent.radii[i] as f64 / (cloud.radii[i] as f64 * stretch) - 1.0).abs();
        worst = (worst.0.max(position_error), worst.1.max(normal_error), worst.2.max(radius_error));
    }
    println!("bend: worst position {:.2e} m, normal {:.2e}, relative radius {:.2e}", worst.0, worst.1, worst.2);
    assert!(worst.0 < 1e-6, "positions off the cylinder by {}", worst.0);
    assert!(worst.1 < 1e-5, "normals off the radial direction by {}", worst.1);
    assert!(worst.2 < 1e-5, "radii off the analytic area stretch by {}", worst.2);
    // The outer plane (h < 0, farther from the axis at h = R) grows, the inner one shrinks.
    let (outer, inner) = (bent.radii[0] / cloud.radii[0], bent.radii[cloud.len() - 1] / cloud.radii[0]);
    let half_gap = gap as f64 / 2.0;
    assert!((outer as f64 - (1.0 + kappa * half_gap).sqrt()).abs() < 1e-5, "outer stretch {outer}");
    assert!((inner as f64 - (1.0 - kappa * half_gap).sqrt()).abs() < 1e-5, "inner stretch {inner}");
}

#[test]
fn deformations_that_collapse_or_vanish_stay_finite() {
    let cloud = two_planes(0.04);
    let frame = DeformFrame::of(&cloud, Vec3::Y);
    // A bend so tight that its axis (1/κ) lies between the planes: a circle of splats collapses onto it.
    let tight = Deform { kind: DeformKind::Bend, amount: 30.0, period: 1.0, wavelength: None };
    for kind in [DeformKind::Wave, DeformKind::Twist, DeformKind::Bend] {
        for t in [0.0, 0.13, 0.25, 0.5, 0.77] {
            let d = if kind == DeformKind::Bend { tight } else { Deform { kind, ..tight } };
            let out = d.apply(&frame, t, &cloud);
            let finite = out.positions.iter().all(|p| p.is_finite())
                && out.normals.iter().all(|n| n.is_finite() && (n.length() - 1.0).abs() < 1e-3)
                && out.radii.iter().all(|r| r.is_finite() && *r > 0.0);
            assert!(finite, "{kind:?} at {t}: a non-finite or zero splat");
        }
    }
}

/// A scene file in `dir` with `body` after a camera block, returned as its path.
fn scene_file(dir: &Path, name: &str, body: &str) -> std::path::PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, body).unwrap();
    path
}

/// A scene file's line naming the bundled lion.
fn lion_line() -> String {
    format!("ply = {:?}", common::bundled_model().display().to_string())
}

/// The lion framed whole (it stands 4.6 units tall), as the default view frames it.
fn lion_camera() -> Camera {
    let (lion, _) = pointblend::cloud::load(&common::bundled_model()).unwrap();
    Camera::default_for(&lion, 1.0)
}

fn render_both(
    still: &Scene,
    moving: &Scene,
    mode: RenderMode,
    grouping: &str,
) -> (image::RgbaImage, image::RgbaImage) {
    let camera = lion_camera();
    let settings = RenderSettings { mode, grouping: grouping.parse::<GroupingSpec>().unwrap(), ..Default::default() };
    let mut gpu = common::renderer();
    let mut still_frames = PreparedScene::of(Arc::new(still.clone()));
    let a = still_frames.render(Some(&mut gpu), &camera, &settings, (128, 128), false).unwrap().image;
    let at = moving.at_time(0.0).unwrap();
    let mut moving_frames = PreparedScene::of(Arc::new(at.scene)).moving();
    let b = moving_frames.render(Some(&mut gpu), &camera, &settings, (128, 128), false).unwrap().image;
    (a, b)
}

#[test]
fn a_deformation_of_amount_zero_or_a_keyframed_object_at_its_first_key_renders_as_the_still_scene() {
    let dir = tempfile::tempdir().unwrap();
    let lion = lion_line();
    let still = scene_file(
        dir.path(),
        "still.toml",
        &format!("[[object]]\n{lion}\nopacity = 0.5\ntranslate = [0.3, 0.0, 0.0]\n"),
    );
    let moving = scene_file(
        dir.path(),
        "moving.toml",
        &format!(
            "[[object]]\n{lion}\nopacity = 0.5\ndeform = {{ kind = \"wave\", amount = 0.0, period = 2.0 }}\n\
             [[object.keyframe]]\ntime = 0.0\ntranslate = [0.3, 0.0, 0.0]\n\
             [[object.keyframe]]\ntime = 1.0\ntranslate = [0.9, 0.6, 0.0]\nrotate = [0, 40, 0]\n"
        ),
    );
    let (still, _) = scene::open(&still, &Default::default()).unwrap();
    let (moving, _) = scene::open(&moving, &Default::default()).unwrap();
    assert!(moving.is_animated() && moving.animation_period() == 2.0);
    for (mode, grouping) in
        [(RenderMode::TwoPass, "mgc-c0.4"), (RenderMode::Deferred, "hash-k8"), (RenderMode::Alg2, "hash-k8-est")]
    {
        let (a, b) = render_both(&still, &moving, mode, grouping);
        let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
        println!("{mode}: {differing} pixels differ");
        assert_eq!(differing, 0, "{mode}: the moving scene at its first key differs from the still one");
    }
    // Half way between the keys the object has moved: the same comparison now differs.
    let half = moving.at_time(0.5).unwrap().scene;
    let (a, b) = render_both(&still, &half, RenderMode::TwoPass, "mgc-c0.4");
    assert!(a.pixels().zip(b.pixels()).any(|(p, q)| p != q), "a keyframed object does not move");
}

#[test]
fn keyframes_interpolate_and_a_long_list_stays_cheap() {
    let dir = tempfile::tempdir().unwrap();
    let mut body = format!("[[object]]\n{}\n", lion_line());
    for k in 0..10_000 {
        body.push_str(&format!("[[object.keyframe]]\ntime = {}\ntranslate = [{}, 0.0, 0.0]\n", k as f32 * 0.01, k % 2));
    }
    let path = scene_file(dir.path(), "long.toml", &body);
    let started = std::time::Instant::now();
    let (scene, _) = scene::open(&path, &Default::default()).unwrap();
    let animation = scene.objects[0].animation.clone().unwrap();
    assert_eq!(animation.keyframes.len(), 10_000);
    // Between keys 4 (x = 0) and 5 (x = 1), a quarter of the way.
    let t = 0.0425;
    let x = animation.keyed(t).translation.x;
    assert!((x - 0.25).abs() < 1e-3, "linear interpolation gives {x} at {t} s");
    // A frame of the scene shares the still cloud and holds no per-key state.
    let at = scene.at_time(57.3).unwrap();
    assert!(Arc::ptr_eq(&at.scene.objects[0].cloud, &scene.objects[0].cloud));
    assert!(started.elapsed().as_secs() < 10, "10,000 keyframes took {:?}", started.elapsed());
}

/// A PLY of `cloud` (x y z nx ny nz radius), for sequence frames.
fn write_frame(path: &Path, cloud: &PointCloud) {
    pointblend::cloud::write::write_ply(cloud, path, &[]).unwrap();
}

#[test]
fn a_sequence_plays_its_frames_and_shows_the_one_before_an_unreadable_frame() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    let (lion, _) = pointblend::cloud::load(&common::bundled_model()).unwrap();
    let mut moved = lion.clone();
    moved.positions.iter_mut().for_each(|p| p.y += 1.5);
    moved.positions.truncate(20_000); // frames may differ in point count
    moved.normals.truncate(20_000);
    moved.radii.truncate(20_000);
    moved.colours.truncate(20_000);
    moved.opacity.truncate(20_000);
    write_frame(&frames.join("f_000.ply"), &lion);
    std::fs::write(frames.join("f_001.ply"), b"ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n").unwrap();
    write_frame(&frames.join("f_002.ply"), &moved);
    std::fs::write(frames.join("notes.txt"), "not a frame").unwrap();
    let path = scene_file(dir.path(), "seq.toml", "[[object]]\nsequence = \"frames/f_*.ply\"\nfps = 2\n");
    let (scene, _) = scene::open(&path, &Default::default()).unwrap();
    assert!((scene.animation_period() - 1.5).abs() < 1e-9, "3 frames at 2 fps");
    let shown = |t: f64| {
        let at = scene.at_time(t).unwrap();
        (at.frames[0], at.scene.objects[0].cloud.len())
    };
    assert_eq!(shown(0.0), (Some(0), lion.len()));
    assert_eq!(shown(0.6), (Some(0), lion.len()), "the unreadable frame 1 shows frame 0");
    assert_eq!(shown(1.2), (Some(2), 20_000));
    assert_eq!(shown(1.6), (Some(0), lion.len()), "the sequence loops");
    // A sequence of one frame, named as a folder.
    let single = dir.path().join("single");
    std::fs::create_dir(&single).unwrap();
    write_frame(&single.join("only.ply"), &moved);
    let path = scene_file(dir.path(), "one.toml", "[[object]]\nsequence = \"single\"\n");
    let (scene, _) = scene::open(&path, &Default::default()).unwrap();
    for t in [0.0, 0.5, 100.0] {
        assert_eq!(scene.at_time(t).unwrap().frames[0], Some(0));
    }
}

/// Runs `pointblend` with `args`; returns (success, stderr).
fn pointblend(args: &[&str]) -> (bool, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_pointblend")).args(args).env("WGPU_BACKEND", "vulkan").output().unwrap();
    (out.status.success(), String::from_utf8_lossy(&out.stderr).into_owned())
}

/// The error line of a failed run (the last line of stderr that is not a log line).
fn error_line(stderr: &str) -> String {
    stderr.lines().rfind(|l| !l.starts_with('[')).unwrap_or_default().to_string()
}

#[test]
fn bad_animation_input_is_one_clear_line_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let lion = format!("ply = {:?}", common::bundled_model().display().to_string());
    let cases = [
        (
            "nan.toml",
            format!("[[object]]\n{lion}\ndeform = {{ kind = \"wave\", amount = nan, period = 2.0 }}\n"),
            "deform amount",
        ),
        (
            "period.toml",
            format!("[[object]]\n{lion}\ndeform = {{ kind = \"twist\", amount = 1.0, period = 0.0 }}\n"),
            "period",
        ),
        (
            "kind.toml",
            format!("[[object]]\n{lion}\ndeform = {{ kind = \"wiggle\", amount = 1.0, period = 1.0 }}\n"),
            "wiggle",
        ),
        (
            "order.toml",
            format!("[[object]]\n{lion}\n[[object.keyframe]]\ntime = 1.0\n[[object.keyframe]]\ntime = 0.5\n"),
            "keyframes out of order",
        ),
        ("missing.toml", "[[object]]\nsequence = \"nowhere/*.ply\"\n".to_string(), "nowhere"),
        ("fps.toml", format!("[[object]]\n{lion}\nfps = 10\n"), "fps"),
    ];
    for (name, body, expected) in cases {
        let path = scene_file(dir.path(), name, &body);
        let out = dir.path().join(format!("{name}.png"));
        let (ok, stderr) =
            pointblend(&["render", path.to_str().unwrap(), "--size", "64x64", "--out", out.to_str().unwrap()]);
        let line = error_line(&stderr);
        println!("{name}: {line}");
        assert!(!ok && line.contains(expected) && line.contains(name), "{name}: {stderr}");
        assert!(!out.exists(), "{name}: an image was written");
    }
    let wave = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/lion-wave.toml");
    for time in ["-1", "NaN"] {
        let out = dir.path().join(format!("t{time}.png"));
        let args =
            ["render", wave.to_str().unwrap(), "--time", time, "--size", "64x64", "--out", out.to_str().unwrap()];
        let (ok, stderr) = pointblend(&args);
        let line = error_line(&stderr);
        println!("--time {time}: {line}");
        assert!(!ok && line.contains("--time"), "--time {time}: {stderr}");
        assert!(!out.exists(), "--time {time}: an image was written");
    }
}

#[test]
fn bench_animate_records_each_frames_regroup_upload_and_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let wave = common::asset("lion-wave.toml");
    let args = [
        "bench",
        wave.to_str().unwrap(),
        "--animate",
        "3",
        "--modes",
        "deferred,alg2",
        "--views",
        "1",
        "--frames",
        "1",
        "--warm-up",
        "0",
        "--loads",
        "1",
        "--size",
        "96x96",
        "--out",
        out.to_str().unwrap(),
    ];
    let (ok, stderr) = pointblend(&args);
    assert!(ok, "{stderr}");
    assert!(out.join("animation.png").is_file());
    let rows: Vec<serde_json::Value> = serde_json::from_slice(&std::fs::read(out.join("bench.json")).unwrap()).unwrap();
    // 3 frames x (reference + deferred + alg2).
    assert_eq!(rows.len(), 9);
    for row in rows.iter().filter(|r| r["ruler"] == false) {
        let frame = row["frame"].as_u64().unwrap();
        let time = row["time"].as_f64().unwrap();
        assert!((time - frame as f64 * 2.0 / 3.0).abs() < 1e-9, "frames spread over the 2 s period: {row}");
        assert!(row["regroup_ms"].as_f64().unwrap() > 0.0, "{row}");
        assert_eq!(row["upload_ms"].is_null(), frame == 0, "an upload is timed from frame 1 on: {row}");
        assert!(row["eps"].as_f64().unwrap().is_finite());
    }
    let (ok, stderr) = pointblend(&["bench", common::bundled_model().to_str().unwrap(), "--animate", "2"]);
    assert!(!ok && error_line(&stderr).contains("nothing in the scene moves"), "{stderr}");
}

#[test]
fn a_scene_moved_on_frame_by_frame_draws_what_a_fresh_upload_of_that_frame_draws() {
    let (scene, _) = scene::open(&common::asset("lion-wave.toml"), &Default::default()).unwrap();
    let camera = lion_camera();
    let mut gpu = common::renderer();
    for mode in [RenderMode::Deferred, RenderMode::Alg2, RenderMode::DepthPeel, RenderMode::Tiled] {
        let settings = RenderSettings { mode, ..Default::default() };
        let first = scene.at_time(0.0).unwrap().scene;
        let mut moved = PreparedScene::of(Arc::new(first)).moving();
        moved.render(Some(&mut gpu), &camera, &settings, (128, 128), false).unwrap();
        for t in [0.3, 0.7, 1.9] {
            let at = Arc::new(scene.at_time(t).unwrap().scene);
            let update = moved.advance(Some(&gpu), Arc::clone(&at), at.flattened()).unwrap();
            let a = moved.render(Some(&mut gpu), &camera, &settings, (128, 128), false).unwrap().image;
            // The same groups (the moved copy's lattice is the first frame's), uploaded afresh.
            let mut fresh = PreparedScene::of(Arc::clone(&at)).moving();
            if let Some(drawn) = moved.resolve(&settings, pointblend::frame::View::still((128, 128))).grouping {
                fresh.add_grouping(moved.grouping(drawn.spec).unwrap().clone());
            }
            let b = fresh.render(Some(&mut gpu), &camera, &settings, (128, 128), false).unwrap().image;
            let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
            println!(
                "{mode} at {t} s: regroup {:.1} ms, upload {:.1} ms ({} bytes); {differing} pixels differ from a fresh upload",
                update.regroup_ms, update.upload_ms, update.uploaded_bytes
            );
            assert!(update.uploaded_bytes > 0, "{mode}: nothing was written for a moved frame");
            assert_eq!(differing, 0, "{mode} at {t} s: the rewritten copy draws something else");
        }
    }
}

/// The goal for per-frame grouping: the groups a deforming model is given
/// frame after frame (on the rest pose's lattice, incrementally) overlap no
/// more than the still model's hash groups, or a one-off hash grouping of the
/// same frame, plus 10 % (§6.1's overlap factor).
const MAX_PER_FRAME_OVERLAP_GROWTH: f64 = 1.10;

#[test]
fn per_frame_hash_groups_of_the_waving_lion_overlap_about_as_little_as_the_still_ones() {
    use pointblend::grouping::hash::{Collisions, HashOptions};
    use pointblend::grouping::metrics;
    use pointblend::grouping::regroup::{HashRegrouper, Lattice};
    let (scene, _) = scene::open(&common::asset("lion-wave.toml"), &Default::default()).unwrap();
    let rest = Arc::clone(&scene.objects[0].cloud);
    let options = HashOptions { k: 8, collisions: Collisions::All };
    let mut regrouper = HashRegrouper::new(Lattice::of(&rest), options).unwrap();
    let still = metrics::measure(&rest, &regrouper.regroup(&rest)).overlap_factor;
    for t in [0.25, 0.5, 1.0, 1.5, 1.75] {
        let cloud = Arc::clone(&scene.at_time(t).unwrap().scene.objects[0].cloud);
        let per_frame = metrics::measure(&cloud, &regrouper.regroup(&cloud)).overlap_factor;
        let one_off = metrics::measure(&cloud, &pointblend::grouping::hash::group(&cloud, &options).unwrap().0);
        let one_off = one_off.overlap_factor;
        println!("t {t}: overlap factor per frame {per_frame:.4}, one-off {one_off:.4} (the still lion {still:.4})");
        assert!(per_frame <= one_off * MAX_PER_FRAME_OVERLAP_GROWTH, "t {t}: per frame {per_frame}, one-off {one_off}");
        assert!(per_frame <= still * MAX_PER_FRAME_OVERLAP_GROWTH, "t {t}: per frame {per_frame}, still {still}");
    }
}

#[test]
fn a_sequence_with_an_empty_frame_plays_through_it_in_every_grouped_mode() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    std::fs::create_dir(&frames).unwrap();
    let lion = common::thinned_lion(3);
    write_frame(&frames.join("f_0.ply"), &lion);
    let empty =
        "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
    std::fs::write(frames.join("f_1.ply"), empty).unwrap();
    write_frame(&frames.join("f_2.ply"), &lion);
    let path = scene_file(dir.path(), "seq.toml", "[[object]]\nsequence = \"frames\"\nfps = 1\nopacity = 0.5\n");
    let (scene, _) = scene::open(&path, &Default::default()).unwrap();
    let camera = lion_camera();
    let mut gpu = common::renderer();
    for mode in [RenderMode::Deferred, RenderMode::Alg2, RenderMode::Tiled] {
        let settings = RenderSettings { mode, ..Default::default() };
        let mut frames = PreparedScene::of(Arc::new(scene.at_time(0.0).unwrap().scene)).moving();
        for t in [0.0, 1.0, 2.0, 1.0] {
            let at = scene.at_time(t).unwrap();
            println!("{mode} at {t} s: frame {:?} of {} splats", at.frames[0], at.scene.len());
            let at = Arc::new(at.scene);
            frames.advance(Some(&gpu), Arc::clone(&at), at.flattened()).unwrap();
            let image = frames.render(Some(&mut gpu), &camera, &settings, (64, 64), false).unwrap().image;
            let drawn = image.pixels().filter(|p| p.0 != image.get_pixel(0, 0).0).count();
            assert_eq!(drawn > 0, !at.is_empty(), "{mode} at {t} s: {drawn} pixels drawn of {} splats", at.len());
        }
    }
}

#[test]
fn a_copy_sorted_back_to_front_and_then_moved_draws_the_moved_frame_in_a_mode_that_does_not_sort() {
    let dir = tempfile::tempdir().unwrap();
    let body = format!(
        "[[object]]\n{}\nopacity = 0.5\n\n[[object]]\nsphere = {{ splats = 2000, radius = 0.5, centre = [0.0, 2.2, -0.6] }}\n\
         [[object.keyframe]]\ntime = 0.0\n[[object.keyframe]]\ntime = 1.0\ntranslate = [0.0, 0.9, 0.0]\n",
        lion_line()
    );
    let (scene, _) = scene::open(&scene_file(dir.path(), "still-and-moving.toml", &body), &Default::default()).unwrap();
    let lattice = pointblend::render::rest_lattice(&scene).unwrap();
    let camera = lion_camera();
    let sorted = RenderSettings { mode: RenderMode::AlphaBlend, ..Default::default() };
    let unsorted = RenderSettings { mode: RenderMode::DepthPeel, ..Default::default() };
    let mut gpu = common::renderer();
    let mut frames = PreparedScene::of(Arc::new(scene.at_time(0.0).unwrap().scene)).moving_on(lattice);
    // Two moves, each after a sorted frame: the second one writes only what changed.
    for t in [0.25, 0.5] {
        frames.render(Some(&mut gpu), &camera, &sorted, (128, 128), false).unwrap();
        let at = Arc::new(scene.at_time(t).unwrap().scene);
        frames.advance(Some(&gpu), Arc::clone(&at), at.flattened()).unwrap();
    }
    let at = Arc::new(scene.at_time(0.5).unwrap().scene);
    let a = frames.render(Some(&mut gpu), &camera, &unsorted, (128, 128), false).unwrap().image;
    let mut fresh = PreparedScene::of(Arc::clone(&at)).moving_on(lattice);
    let b = fresh.render(Some(&mut gpu), &camera, &unsorted, (128, 128), false).unwrap().image;
    let differing = a.pixels().zip(b.pixels()).filter(|(p, q)| p != q).count();
    assert_eq!(differing, 0, "{differing} pixels differ: the moved copy kept records of the sorted view");
}
