//! Point sizes: `--radius-scale` and `--min-pixel-radius` (far splats drawn
//! at least that many pixels in radius, in their own plane), in every mode
//! against the reference and the closed form of a disc's area.

mod common;

use common::tolerances::*;
use glam::Vec3;
use pointblend::cloud::PointCloud;
use pointblend::frame::RenderSettings;
use pointblend::reference::{self, ReferenceOptions};
use pointblend::render::RenderMode;
use pointblend::scene::Scene;

const SIZE: u32 = 128;

/// Discs facing the camera of `common::looking_down_z` at the origin: one of
/// radius `tiny` and, 1 to its right, one of radius 0.1 (about 5 px).
fn two_discs(tiny: f32) -> Scene {
    Scene::from(PointCloud {
        positions: vec![Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)],
        normals: vec![Vec3::Z; 2],
        radii: vec![tiny, 0.1],
        colours: vec![[230, 200, 60]; 2],
        opacity: vec![1.0; 2],
        ..Default::default()
    })
}

/// The drawn pixels left and right of the image's middle (the two discs).
fn drawn_halves(image: &image::RgbaImage) -> (usize, usize) {
    let background = common::background_rgb();
    let drawn = |x: u32, y: u32| image.get_pixel(x, y).0[..3] != background;
    let mut halves = (0, 0);
    for y in 0..SIZE {
        for x in 0..SIZE {
            if drawn(x, y) {
                if x < SIZE / 2 + 12 { halves.0 += 1 } else { halves.1 += 1 }
            }
        }
    }
    halves
}

#[test]
fn a_minimum_pixel_radius_grows_a_tiny_splat_to_its_closed_form_area_in_every_mode() {
    const MIN_PX: f32 = 4.0;
    // 1e-4 at distance 5 under a 30° field is 0.005 px: nothing is drawn without the floor.
    let scene = two_discs(1e-4);
    let large_px = 0.1 / (5.0 * 15f32.to_radians().tan()) * (SIZE as f32 / 2.0);
    for mode in RenderMode::ALL {
        let unfloored = RenderSettings { mode, lighting: false, ..Default::default() };
        let floored = RenderSettings { min_pixel_radius: MIN_PX, ..unfloored };
        let (tiny_before, large_before) = drawn_halves(&common::render_mode(&scene, &unfloored, SIZE));
        let image = common::render_mode(&scene, &floored, SIZE);
        let (tiny, large) = drawn_halves(&image);
        let area = std::f32::consts::PI * MIN_PX * MIN_PX;
        assert!(tiny_before <= 1, "{mode}: a 0.005 px splat draws {tiny_before} pixels");
        assert!(
            (tiny as f32 - area).abs() <= 0.25 * area,
            "{mode}: the tiny splat covers {tiny} pixels at a {MIN_PX} px floor (π·r² = {area:.0})"
        );
        assert_eq!(large, large_before, "{mode}: a {large_px:.1} px splat is above the floor and unchanged");
        // Against the reference at the same floor; alg1 and alg2's covering
        // groups enlarge the lone large disc with or without a floor, so each
        // mode is held to its own error without one.
        let camera = common::looking_down_z();
        let error_of = |settings: &RenderSettings, image: &image::RgbaImage| {
            let want = reference::render(&scene, &camera, &ReferenceOptions::matching(settings, &scene), SIZE, SIZE);
            reference::compare(image, &want).unwrap().eps
        };
        let (with_floor, without) =
            (error_of(&floored, &image), error_of(&unfloored, &common::render_mode(&scene, &unfloored, SIZE)));
        assert!(
            with_floor <= without + MAX_POINT_SIZE_EPS,
            "{mode}: ε {with_floor:.3} against the reference at the same floor, {without:.3} without a floor"
        );
    }
}
