//! The splat passes' EWA prefilter (Guennebaud's tangent-vector stretch) and
//! the supersampled reference it is measured against.

mod common;

use common::tolerances::*;
use glam::Vec3;
use pointblend::cloud::{self, PointCloud};
use pointblend::frame::prefilter::LOW_PASS_RADIUS_PX;
use pointblend::frame::{Camera, Prefilter};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::render::RenderSettings;
use pointblend::scene::Scene;

const SIZE: u32 = 160;

/// A 2×2 plane of 40,000 splats coloured as a checkerboard of 4×4-splat
/// squares, black and white: detail far below a pixel when seen from afar.
fn checkerboard() -> PointCloud {
    let mut plane = pointblend::scene::primitives::plane(40_000, 2.0, Vec3::ZERO, Vec3::Y);
    let spacing = 2.0 / 200.0;
    for (colour, p) in plane.colours.iter_mut().zip(&plane.positions) {
        let square = |v: f32| ((v + 1.0) / (4.0 * spacing)).floor() as i32;
        *colour = if (square(p.x) + square(p.z)).rem_euclid(2) == 0 { [230; 3] } else { [25; 3] };
    }
    plane
}

/// The plane from `distance` at 20° above it: a grazing view where each
/// pixel holds several squares.
fn far_grazing(cloud: &PointCloud, distance: f32) -> Camera {
    let mut camera = Camera::default_for(cloud, 1.0);
    camera.elevation_deg = 20.0;
    camera.distance = distance;
    camera
}

fn render(cloud: &PointCloud, camera: &Camera, settings: &RenderSettings) -> image::RgbaImage {
    render_at(cloud, camera, settings, SIZE)
}

fn render_at(cloud: &PointCloud, camera: &Camera, settings: &RenderSettings, size: u32) -> image::RgbaImage {
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload_cloud(cloud, None);
    renderer.render_image(&mut gpu, camera, settings, size, size).expect("render").0
}

/// The bundled lion (94K splats).
fn lion() -> PointCloud {
    cloud::load(&common::bundled_model()).unwrap().0
}

/// The default view of `cloud` moved back until the model is about
/// `pixels` tall in a frame `size` pixels tall (the default view fits it to
/// the frame).
fn far(cloud: &PointCloud, pixels: u32, size: u32) -> Camera {
    let mut camera = Camera::default_for(cloud, 1.0);
    camera.distance *= size as f32 / pixels as f32;
    camera
}

fn settings(prefilter: Prefilter) -> RenderSettings {
    RenderSettings { prefilter, lighting: false, ..Default::default() }
}

fn supersampled(scene: &Scene, camera: &Camera, settings: &RenderSettings, n: u32, size: u32) -> image::RgbaImage {
    let options = ReferenceOptions { supersample: n, ..ReferenceOptions::matching(settings, scene) };
    reference::render(scene, camera, &options, size, size)
}

#[test]
fn a_far_checkerboard_is_closer_to_the_supersampled_reference_with_the_prefilter() {
    let cloud = checkerboard();
    let scene = Scene::from(cloud.clone());
    for distance in [5.0, 9.0] {
        let camera = far_grazing(&cloud, distance);
        let exact = supersampled(&scene, &camera, &settings(Prefilter::None), 4, SIZE);
        let eps = |p: Prefilter| reference::compare(&render(&cloud, &camera, &settings(p)), &exact).unwrap().eps;
        let (none, ewa) = (eps(Prefilter::None), eps(Prefilter::Ewa));
        println!("distance {distance}: ε none {none:.3}, ewa {ewa:.3}, ratio {:.3}", ewa / none);
        assert!(ewa <= MAX_EWA_ALIASING_RATIO * none, "distance {distance}: ε ewa {ewa} against none {none}");
    }
}

#[test]
fn splats_larger_than_the_filter_are_drawn_as_without_it() {
    // The checkerboard from above, close: every disc is over a pixel in radius on screen.
    let cloud = checkerboard();
    let mut camera = far_grazing(&cloud, 1.2);
    camera.elevation_deg = 89.0;
    let (none, ewa) =
        (render(&cloud, &camera, &settings(Prefilter::None)), render(&cloud, &camera, &settings(Prefilter::Ewa)));
    let differing = none.pixels().zip(ewa.pixels()).filter(|(a, b)| a != b).count();
    assert_eq!(differing, 0, "a close-up (every splat above the low-pass radius) changed in {differing} pixels");
    // The bundled lion, lit, close at 320²: every splat is over the low-pass
    // radius on screen (checked below; at 160² its smallest splats are not,
    // and are rightly stretched), and those seen edge-on along its silhouette
    // (thin on screen) are not widened either.
    let lion = lion();
    let size = 320;
    let mut camera = Camera::default_for(&lion, 1.0);
    camera.distance = camera.fit_distance(&lion.positions, 1.0) * 0.5;
    let view = camera.view_matrix();
    let smallest = (0..lion.len())
        .map(|i| lion.radii[i] * camera.focal_pixels(size) / -view.transform_point3(lion.positions[i]).z)
        .fold(f32::INFINITY, f32::min);
    assert!(smallest > LOW_PASS_RADIUS_PX, "the smallest splat is {smallest} px: not a close-up");
    let lit = |p: Prefilter| RenderSettings { prefilter: p, ..Default::default() };
    let (none, ewa) =
        (render_at(&lion, &camera, &lit(Prefilter::None), size), render_at(&lion, &camera, &lit(Prefilter::Ewa), size));
    // A widened silhouette turns background pixels into surface, tens of
    // levels apart. Measured (2026-11-29, lavapipe): smallest splat 1.18 px,
    // 2 pixels off by 1/255 (the Stanford bunny: 2 pixels by 1/255 too).
    let worst = none.pixels().zip(ewa.pixels()).flat_map(|(a, b)| (0..3).map(|c| a[c].abs_diff(b[c]))).max();
    let changed = none.pixels().zip(ewa.pixels()).filter(|(a, b)| a != b).count();
    println!("the close lion: smallest splat {smallest:.2} px; {changed} pixels changed, by up to {worst:?}/255");
    assert!(worst <= Some(1), "the close lion changed by up to {worst:?}/255");
}

#[test]
fn a_supersampled_reference_is_the_box_filter_of_its_rays() {
    let cloud = lion();
    let scene = Scene::from(cloud.clone());
    let mut camera = Camera::default_for(&cloud, 1.0);
    camera.distance = camera.fit_distance(&cloud.positions, 1.0) * 3.0;
    let s = RenderSettings::default();
    let size = 48;
    let fine = supersampled(&scene, &camera, &s, 1, size * 3);
    let coarse = supersampled(&scene, &camera, &s, 3, size);
    let mut worst = 0u8;
    let mut blended = 0;
    for (x, y, p) in coarse.enumerate_pixels() {
        for c in 0..3 {
            let sum: u32 = (0..9).map(|k| fine.get_pixel(3 * x + k % 3, 3 * y + k / 3).0[c] as u32).sum();
            // The coarse pixel averages before quantising, the fine pixels after: ±1.
            worst = worst.max(
                (sum as f32 / 9.0).round().max(p.0[c] as f32) as u8
                    - (sum as f32 / 9.0).round().min(p.0[c] as f32) as u8,
            );
        }
        let corner = fine.get_pixel(3 * x, 3 * y);
        blended += (0..9).any(|k| fine.get_pixel(3 * x + k % 3, 3 * y + k / 3) != corner) as usize;
    }
    assert!(worst <= 1, "a supersampled pixel is off the mean of its rays by {worst}/255");
    assert!(blended > 50, "the view has too few pixels whose rays differ ({blended}) to test the filter");
    let one = supersampled(&scene, &camera, &s, 1, size);
    assert_ne!(one, coarse, "3×3 rays per pixel gave the one-ray image");
}

#[test]
fn bad_supersample_and_prefilter_values_are_one_line_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("never.png");
    let lion = common::bundled_model();
    for bad in [
        ["--mode", "reference", "--supersample", "0"],
        ["--mode", "reference", "--supersample", "17"],
        ["--mode", "reference", "--supersample", "two"],
        ["--mode", "two-pass", "--prefilter", "gauss"],
    ] {
        let args: Vec<std::ffi::OsString> =
            std::iter::once(lion.clone().into_os_string()).chain(bad.iter().map(|a| a.into())).collect();
        let error = common::refused_in_one_line(&args, &out, &format!("{bad:?}"));
        assert!(error.contains(bad[2]), "{bad:?}: the error names the option: {error}");
    }
    let good = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .arg("render")
        .arg(&lion)
        .args(["--mode", "reference", "--supersample", "2", "--size", "64x48", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(good.status.success(), "{}", String::from_utf8_lossy(&good.stderr));
    assert_eq!(image::open(&out).unwrap().width(), 64);
}

/// The Stanford bunny far away (about 24 px tall, lit, on black): every
/// splat is below the low-pass radius and stretched, across the outline
/// too. The stretched part of a silhouette splat lies in its plane continued
/// past the disc, in front of the surface, and once set the visibility
/// depth: the splats facing the viewer were culled and the outline was
/// shaded by edge-on normals, a dark rim; deferred's within-group z-test
/// did the same. The outline's pixels must be no darker with the filter
/// than without it, in two-pass and in deferred.
///
/// Kept on the bunny: the property does not carry to the lion. There the
/// prefiltered two-pass outline is 3-9 % darker at 24, 32 and 48 px tall
/// (mean r+g+b 255 against 281 at 24 px; deferred's is brighter), with its
/// scanned colours or in one colour alike (measured 2026-11-29, lavapipe).
#[test]
fn a_far_prefiltered_outline_is_no_darker_than_an_unfiltered_one() {
    let (bunny, _) = cloud::load(&require!(common::stanford_bunny())).unwrap();
    let mut camera = Camera::default_for(&bunny, 1.0);
    camera.distance = 2.6;
    let shading = pointblend::frame::Shading { background: Vec3::ZERO, ..Default::default() };
    for mode in ["two-pass", "deferred"] {
        let lit = |prefilter| RenderSettings {
            mode: mode.parse().unwrap(),
            prefilter,
            lighting: true,
            shading,
            ..Default::default()
        };
        let (none, ewa) =
            (render(&bunny, &camera, &lit(Prefilter::None)), render(&bunny, &camera, &lit(Prefilter::Ewa)));
        outline_no_darker(&none, &ewa, mode);
    }
}

/// The mean r+g+b of the outline (covered pixels of `none` next to
/// background) is no lower in `ewa`.
fn outline_no_darker(none: &image::RgbaImage, ewa: &image::RgbaImage, mode: &str) {
    let covered = |x: u32, y: u32| none.get_pixel(x, y).0[..3] != [0, 0, 0];
    // The outline: covered pixels of the unfiltered image next to background.
    let mut sums = (0.0f64, 0.0f64, 0usize);
    for y in 1..SIZE - 1 {
        for x in 1..SIZE - 1 {
            let edge = !covered(x - 1, y) || !covered(x + 1, y) || !covered(x, y - 1) || !covered(x, y + 1);
            if covered(x, y) && edge {
                let luminance =
                    |image: &image::RgbaImage| image.get_pixel(x, y).0[..3].iter().map(|&c| c as f64).sum::<f64>();
                sums = (sums.0 + luminance(none), sums.1 + luminance(ewa), sums.2 + 1);
            }
        }
    }
    let (none_mean, ewa_mean) = (sums.0 / sums.2 as f64, sums.1 / sums.2 as f64);
    println!("{mode}: outline of {} pixels: mean r+g+b {none_mean:.1} unfiltered, {ewa_mean:.1} prefiltered", sums.2);
    assert!(sums.2 > 40, "{mode}: the bunny is drawn with an outline ({} pixels)", sums.2);
    assert!(ewa_mean >= none_mean, "{mode}: the prefiltered outline is darker: {ewa_mean:.1} against {none_mean:.1}");
}

/// Mean |ΔR|+|ΔG|+|ΔB| of `image` against `exact` over the bounding box of
/// the pixels that are not background (black) in `exact` or in `unfiltered`.
fn eps_over_model(image: &image::RgbaImage, exact: &image::RgbaImage, unfiltered: &image::RgbaImage) -> f64 {
    let drawn = |x, y| exact.get_pixel(x, y).0[..3] != [0, 0, 0] || unfiltered.get_pixel(x, y).0[..3] != [0, 0, 0];
    let (mut low, mut high) = ((u32::MAX, u32::MAX), (0, 0));
    for (x, y, _) in exact.enumerate_pixels().filter(|&(x, y, _)| drawn(x, y)) {
        (low, high) = ((low.0.min(x), low.1.min(y)), (high.0.max(x), high.1.max(y)));
    }
    let mut sum = 0.0;
    for y in low.1..=high.1 {
        for x in low.0..=high.0 {
            let (a, b) = (image.get_pixel(x, y).0, exact.get_pixel(x, y).0);
            sum += (0..3).map(|c| a[c].abs_diff(b[c]) as f64).sum::<f64>();
        }
    }
    sum / ((high.0 - low.0 + 1) * (high.1 - low.1 + 1)) as f64
}

/// A model far away, about 48 px tall on black, every splat below the
/// low-pass radius: what aliases is its outline and its shading. The
/// prefilter's coverage blends the outline with what is behind it and its
/// stretched splats are shaded before they are averaged, so the error
/// against the 4×4-supersampled reference, over the model's box, is a share
/// of the unfiltered image's: at most `bound` lit and unlit. Without coverage
/// the filter widened the outline by half a pixel and tripled the error.
fn far_model_is_nearer_the_supersampled_reference_with_the_prefilter(
    what: &str,
    cloud: &PointCloud,
    camera: &Camera,
    bound: f64,
) {
    let scene = Scene::from(cloud.clone());
    let size = 256;
    let shading = pointblend::frame::Shading { background: Vec3::ZERO, ..Default::default() };
    for lighting in [true, false] {
        let settings = |prefilter| RenderSettings { prefilter, lighting, shading, ..Default::default() };
        let exact = supersampled(&scene, camera, &settings(Prefilter::None), 4, size);
        let none = render_at(cloud, camera, &settings(Prefilter::None), size);
        let ewa = render_at(cloud, camera, &settings(Prefilter::Ewa), size);
        let (eps_none, eps_ewa) = (eps_over_model(&none, &exact, &none), eps_over_model(&ewa, &exact, &none));
        let ratio = eps_ewa / eps_none;
        println!(
            "{what}, lighting {lighting}: ε none {eps_none:.2}, ewa {eps_ewa:.2}, ratio {ratio:.3} (bound {bound:.3})"
        );
        assert!(eps_none > 5.0, "{what}, lighting {lighting}: the unfiltered model aliases too little ({eps_none:.2})");
        assert!(ratio <= bound, "{what}, lighting {lighting}: ε ewa {eps_ewa:.2} against none {eps_none:.2}");
    }
}

/// The bundled lion about 48 px tall at 256²: a regression bound measured on it.
#[test]
fn a_far_lion_is_nearer_the_supersampled_reference_with_the_prefilter() {
    let lion = lion();
    let camera = far(&lion, 48, 256);
    far_model_is_nearer_the_supersampled_reference_with_the_prefilter(
        "far lion",
        &lion,
        &camera,
        MAX_EWA_FAR_LION_RATIO,
    );
}

/// The Stanford bunny at distance 1.3 (about 48 px tall at 256²): the
/// issue's goal, at most half the unfiltered error (measured: lit 4.28
/// against 10.18, unlit 5.29 against 12.68). Kept on the bunny because the
/// goal was set and met there and docs/BENCHMARKS.md reports its far view;
/// the lion, whose colours and varied splat sizes alias otherwise, has its
/// own measured bound above.
#[test]
fn a_far_bunny_is_at_least_twice_as_near_the_supersampled_reference_with_the_prefilter() {
    let (bunny, _) = cloud::load(&require!(common::stanford_bunny())).unwrap();
    let mut camera = Camera::default_for(&bunny, 1.0);
    camera.distance = 1.3;
    far_model_is_nearer_the_supersampled_reference_with_the_prefilter(
        "far bunny",
        &bunny,
        &camera,
        MAX_EWA_ALIASING_RATIO,
    );
}
