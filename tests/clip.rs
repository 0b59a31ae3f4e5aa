//! Clipping per pixel (crates/core/src/frame/clip.rs): a plane through a
//! splat's centre leaves exactly half its disc in every mode, as the exact
//! reference draws it; a box that cuts half a caster away leaves half its
//! shadow, by translucent shadow mapping and by exact shadow rays; and the
//! command line's flags and a scene file's `[clip]` cut the same region.

mod common;

use common::tolerances::*;
use glam::{DVec3, Vec3};
use pointblend::cloud::PointCloud;
use pointblend::frame::clip::{ClipBox, ClipRegion, Hidden};
use pointblend::frame::{Light, RenderSettings, ShadowMethod};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::render::RenderMode;
use pointblend::scene::{Scene, primitives};
use pointblend::shadow::{self, ShadowInput};

/// One disc of radius 0.8 at the origin, facing the camera of `common::looking_down_z`.
fn one_disc(opacity: f32) -> Scene {
    let cloud = PointCloud {
        positions: vec![Vec3::ZERO],
        normals: vec![Vec3::Z],
        radii: vec![0.8],
        colours: vec![[220, 120, 40]],
        opacity: vec![opacity],
        ..Default::default()
    };
    let mut scene = Scene::from(cloud);
    scene.objects[0].material.two_sided = opacity < 1.0;
    scene
}

/// Keeps x ≥ 0: a plane through the disc's centre.
fn right_half() -> ClipRegion {
    ClipRegion { clip_box: None, planes: vec![[1.0, 0.0, 0.0, 0.0]] }
}

#[test]
fn a_plane_through_a_splat_centre_shows_half_its_disc_in_every_mode() {
    const SIZE: u32 = 128;
    let centre = SIZE as f32 / 2.0;
    // The disc's radius in pixels: 0.8 at distance 5 under a 30° field.
    let radius_px = 0.8 / (5.0 * 15f32.to_radians().tan()) * centre;
    for mode in RenderMode::ALL {
        let transparent = mode.info().transparent;
        let scene = one_disc(if transparent { 0.6 } else { 1.0 });
        let mut settings = RenderSettings { mode, lighting: false, ..Default::default() };
        settings.clip = scene.clip_in_frame(&right_half());
        let image = common::render_mode(&scene, &settings, SIZE);
        let background = image.get_pixel(2, 2).0;
        let want = reference::render(
            &scene,
            &common::looking_down_z(),
            &ReferenceOptions::matching(&settings, &scene),
            SIZE,
            SIZE,
        );
        let error = reference::compare(&image, &want).unwrap();
        let (mut left, mut right, mut right_pixels, mut drawn) = (0, 0, 0, 0);
        for (x, y, p) in image.enumerate_pixels() {
            let (dx, dy) = (x as f32 + 0.5 - centre, y as f32 + 0.5 - centre);
            let shown = p.0 != background;
            drawn += shown as u32;
            if (dx * dx + dy * dy).sqrt() < radius_px - 2.0 {
                if dx < -1.0 {
                    left += shown as u32;
                } else if dx > 1.0 {
                    right_pixels += 1;
                    right += shown as u32;
                }
            }
        }
        let half_area = std::f32::consts::PI * radius_px * radius_px / 2.0;
        assert_eq!(left, 0, "{mode}: {left} pixels left of the plane are drawn");
        assert_eq!(
            right,
            right_pixels,
            "{mode}: {} of {right_pixels} pixels right of it are empty",
            right_pixels - right
        );
        assert!(
            (drawn as f32 - half_area).abs() < 0.05 * half_area,
            "{mode}: {drawn} pixels drawn, half the disc is {half_area:.0}"
        );
        assert!(
            error.eps <= MAX_CLIP_EPS,
            "{mode}: ε {:.3} against the clipped reference (bad pixels {:.4})",
            error.eps,
            error.bad_pixel_share
        );
    }
}

/// Floor splats at z = 0 (4 wide), and an opaque square 0.8 wide at z = 1 above its centre.
fn floor_and_caster() -> (PointCloud, usize) {
    let mut cloud = primitives::plane(20_000, 4.0, Vec3::ZERO, Vec3::Z);
    let floor = cloud.len();
    let caster = primitives::plane(2_500, 0.8, Vec3::new(0.0, 0.0, 1.0), Vec3::Z);
    cloud.positions.extend(&caster.positions);
    cloud.normals.extend(&caster.normals);
    cloud.radii.extend(&caster.radii);
    cloud.colours.extend(&caster.colours);
    cloud.opacity.extend(&caster.opacity);
    (cloud, floor)
}

#[test]
fn a_box_that_cuts_half_a_caster_away_leaves_half_its_shadow() {
    let (cloud, floor) = floor_and_caster();
    // The light above the square's centre: its shadow is 1.2 wide on the floor.
    let light = Light::point(Vec3::new(0.0, 0.0, 3.0));
    // The half x < 0 of the caster is cut away; the floor is not touched.
    let region = ClipRegion {
        clip_box: Some(ClipBox { min: [-1.0, -1.0, 0.5], max: [0.0, 1.0, 1.5], hide: Hidden::Inside }),
        planes: vec![],
    };
    let clip = region.in_frame(DVec3::ZERO, 1.0);
    for method in [ShadowMethod::Tsm, ShadowMethod::Exact] {
        let settings = RenderSettings { clip, ..Default::default() };
        let input = ShadowInput::new(&cloud, &settings, false);
        let t = shadow::coefficients(&input, &[light], method, [512, 512]).unwrap().per_light.remove(0);
        let under = |x: std::ops::RangeInclusive<f32>| -> Vec<f32> {
            (0..floor)
                .filter(|&i| x.contains(&cloud.positions[i].x) && cloud.positions[i].y.abs() < 0.4)
                .map(|i| t[i])
                .collect()
        };
        let (cut, kept) = (under(-0.5..=-0.1), under(0.1..=0.5));
        assert!(cut.len() > 50 && kept.len() > 50);
        let worst_cut = cut.iter().map(|v| (1.0 - v).abs()).fold(0.0, f32::max);
        let worst_kept = kept.iter().map(|v| v.abs()).fold(0.0, f32::max);
        assert!(
            worst_cut <= MAX_SHADOW_COEFFICIENT_ERROR && worst_kept <= MAX_SHADOW_COEFFICIENT_ERROR,
            "{method:?}: under the cut half the floor is lit (off 1 by up to {worst_cut}), under the kept half shadowed (off 0 by up to {worst_kept})"
        );
    }
}

#[test]
fn the_flags_and_a_scene_files_clip_cut_the_same_image() {
    let dir = tempfile::tempdir().unwrap();
    let model = common::bundled_model();
    let scene_file = dir.path().join("clipped.toml");
    std::fs::write(
        &scene_file,
        format!(
            "[[object]]\nply = {:?}\n\n[clip]\nbox = {{ min = [-1.0, 0.0, -3.0], max = [3.0, 3.0, 3.0], hide = \"inside\" }}\nplanes = [[0.0, 0.0, 1.0, 0.5]]\n",
            model.display().to_string()
        ),
    )
    .unwrap();
    let (by_flags, by_file, unclipped) =
        (dir.path().join("flags.png"), dir.path().join("file.png"), dir.path().join("all.png"));
    let common_args = ["--size", "96x96", "--mode", "reference"];
    let flags =
        [&common_args[..], &["--clip-box", "-1,0,-3,3,3,3", "--clip-hide", "inside", "--clip-plane", "0,0,1,0.5"]]
            .concat();
    let mut with_model: Vec<String> = vec![model.display().to_string()];
    with_model.extend(flags.iter().map(|s| s.to_string()));
    assert!(common::render_cli(&with_model, &by_flags).0);
    let mut with_file: Vec<String> = vec![scene_file.display().to_string()];
    with_file.extend(common_args.iter().map(|s| s.to_string()));
    assert!(common::render_cli(&with_file, &by_file).0);
    let mut plain: Vec<String> = vec![model.display().to_string()];
    plain.extend(common_args.iter().map(|s| s.to_string()));
    assert!(common::render_cli(&plain, &unclipped).0);
    let (a, b, c) = (image::open(&by_flags).unwrap(), image::open(&by_file).unwrap(), image::open(&unclipped).unwrap());
    assert_eq!(a.as_bytes(), b.as_bytes(), "the flags and the scene file cut the same region");
    assert_ne!(a.as_bytes(), c.as_bytes(), "the clip changes the image");
}

#[test]
fn bad_clip_regions_are_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("x.png");
    let model = common::bundled_model().display().to_string();
    for (args, what) in [
        (vec!["--clip-plane", "0,0,0,1"], "a zero normal"),
        (vec!["--clip-box", "1,0,0,0,1,1"], "a box with min > max"),
        (vec!["--clip-box", "0,0,0,1,1"], "a box of five numbers"),
        (vec!["--clip-hide", "inside"], "--clip-hide without a box"),
    ] {
        let args: Vec<&str> = std::iter::once(model.as_str()).chain(args).collect();
        common::refused_in_one_line(&args, &out, what);
    }
    let seven: Vec<String> = std::iter::once(model.clone())
        .chain((0..7).flat_map(|_| ["--clip-plane".to_string(), "1,0,0,0".to_string()]))
        .collect();
    let line = common::refused_in_one_line(&seven, &out, "seven planes");
    assert!(line.contains("at most 6"), "{line}");
    let scene_file = dir.path().join("bad.toml");
    std::fs::write(&scene_file, format!("[[object]]\nply = {model:?}\n[clip]\nplanes = [[0.0, 0.0, 0.0, 1.0]]\n"))
        .unwrap();
    let line = common::refused_in_one_line(&[scene_file.display().to_string()], &out, "a scene file's zero normal");
    assert!(line.contains("bad.toml:"), "{line}");
}
