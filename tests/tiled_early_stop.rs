//! `tiled` stops a pixel once its light is spent: at once behind an opaque
//! layer, and once less than 1/1024 of the light gets through a translucent
//! stack (shaders/tiled_raster.wgsl, `LAST_LIGHT`). These tests hold that
//! the stop changes nothing an 8-bit image can show: an opaque scene's image
//! is the same bit for bit as with every layer composited, and a translucent
//! one is within 1/255 per channel.

mod common;

use glam::Vec3;
use pointblend::cloud::PointCloud;
use pointblend::frame::{Camera, RenderSettings};
use pointblend::scene::Scene;

/// Square planes of splats facing +z, one per opacity, 0.5 apart in depth.
fn stack(opacities: &[f32]) -> Scene {
    let (n, half) = (40, 2.0f32);
    let spacing = 2.0 * half / n as f32;
    let mut cloud = PointCloud::default();
    for (k, &opacity) in opacities.iter().enumerate() {
        let colour = [(40 + 50 * k % 216) as u8, (200 - 23 * k % 160) as u8, (90 + 31 * k % 160) as u8];
        for i in 0..=n {
            for j in 0..=n {
                cloud.positions.push(Vec3::new(
                    -half + i as f32 * spacing,
                    -half + j as f32 * spacing,
                    -0.5 * k as f32,
                ));
                cloud.normals.push(Vec3::Z);
                cloud.radii.push(1.5 * spacing);
                cloud.colours.push(colour);
                cloud.opacity.push(opacity);
            }
        }
    }
    Scene::from(cloud)
}

/// The scene in `tiled`, lit, with and without the stop, from an oblique view.
fn with_and_without_the_stop(scene: &Scene) -> (image::RgbaImage, image::RgbaImage) {
    let flat = scene.flattened();
    let mut camera = Camera::default_for(&flat, 1.0);
    (camera.azimuth_deg, camera.elevation_deg) = (20.0, 25.0);
    let settings = RenderSettings { mode: "tiled".parse().unwrap(), lighting: true, ..Default::default() };
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload(scene, None);
    let stopped = renderer.render_image(&mut gpu, &camera, &settings, 128, 128).expect("render with the stop").0;
    renderer.stop_early(false);
    let every_layer = renderer.render_image(&mut gpu, &camera, &settings, 128, 128);
    renderer.stop_early(true);
    let built = renderer.renderer.modules_built();
    let raster = |every: bool| {
        built.iter().any(|(root, v)| *root == "tiled_raster.wgsl" && v.to_string().contains("EVERY_LAYER") == every)
    };
    assert!(raster(true) && raster(false), "both rasters ran: {built:?}");
    (stopped, every_layer.expect("render without the stop").0)
}

/// The largest difference of one channel between two images, and the pixels that differ.
fn difference(a: &image::RgbaImage, b: &image::RgbaImage) -> (u8, usize) {
    let mut worst = 0u8;
    let mut differing = 0;
    for (p, q) in a.pixels().zip(b.pixels()) {
        let most = p.0.iter().zip(q.0).map(|(x, y)| x.abs_diff(y)).max().unwrap_or(0);
        worst = worst.max(most);
        differing += (most > 0) as usize;
    }
    (worst, differing)
}

#[test]
fn an_opaque_scene_is_the_same_bit_for_bit_without_the_stop() {
    let lion = Scene::from(common::thinned_lion(2));
    for (what, scene) in [("three opaque planes", stack(&[1.0, 1.0, 1.0])), ("the lion", lion)] {
        let (stopped, every_layer) = with_and_without_the_stop(&scene);
        assert!(stopped.pixels().any(|p| p.0[..3] != common::background_rgb()), "{what}: something is drawn");
        let (worst, differing) = difference(&stopped, &every_layer);
        println!("{what}: {differing} pixels differ, by at most {worst}");
        assert_eq!(differing, 0, "{what}: {differing} pixels differ, by at most {worst}");
    }
}

#[test]
fn a_translucent_scene_is_within_one_step_of_255_without_the_stop() {
    // Eight layers of opacity 0.7: after six, 0.3^6 = 0.07 % of the light
    // gets through, less than 1/1024, so the pixel stops there and the last
    // two layers, which would add at most 0.2 of a step, are not drawn.
    let mut lion = Scene::from(common::thinned_lion(2));
    lion.set_opacity(0.9);
    for (what, scene) in [("eight planes at 0.7", stack(&[0.7; 8])), ("the lion at 0.9", lion)] {
        let (stopped, every_layer) = with_and_without_the_stop(&scene);
        assert!(stopped.pixels().any(|p| p.0[..3] != common::background_rgb()), "{what}: something is drawn");
        let (worst, differing) = difference(&stopped, &every_layer);
        println!("{what}: {differing} pixels differ, by at most {worst}");
        assert!(worst <= 1, "{what}: {differing} pixels differ, by up to {worst}");
    }
}
