//! Transparent modes on lavapipe against the exact reference, and the stiff
//! cases: opacity 0 and 1, a thousand coincident splats, a camera inside.

mod common;

use common::tolerances::*;
use glam::Vec3;
use pointblend::cloud::{self, PointCloud};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::render::RenderMode;
use pointblend::scene::{Material, Scene, primitives};
use pointblend::view::{Camera, RenderSettings};

fn transparent_bunny(opacity: f32) -> Scene {
    let (cloud, _) = cloud::load(&common::bundled_bunny()).unwrap();
    let mut scene = Scene::from(cloud);
    scene.set_opacity(opacity);
    scene
}

fn mode(name: &str) -> RenderMode {
    name.parse().unwrap()
}

fn settings(name: &str, layers: u32) -> RenderSettings {
    RenderSettings { mode: mode(name), layers, ..Default::default() }
}

fn view(scene: &Scene, azimuth: f32, elevation: f32) -> Camera {
    let cloud = scene.flattened();
    let mut camera = Camera::default_for(&cloud, 1.0);
    camera.azimuth_deg = azimuth;
    camera.elevation_deg = elevation;
    camera.distance = camera.fit_distance(&cloud.positions, 1.0);
    camera
}

fn render(scene: &Scene, camera: &Camera, settings: &RenderSettings, size: u32) -> image::RgbaImage {
    let mut renderer = common::renderer();
    let gpu = renderer.upload(scene, None);
    renderer.render_image(&gpu, camera, settings, size, size).expect("render").0
}

fn exact(scene: &Scene, camera: &Camera, settings: &RenderSettings, size: u32) -> (image::RgbaImage, Vec<u32>) {
    reference::render_with_layers(scene, camera, &ReferenceOptions::matching(settings, scene), size, size)
}

#[test]
fn depth_peel_with_enough_layers_matches_the_reference_on_the_transparent_bunny() {
    let scene = transparent_bunny(0.5);
    let size = 160;
    for (az, el) in [(0.0, 10.0), (90.0, 25.0), (200.0, 40.0)] {
        let camera = view(&scene, az, el);
        let probe = settings("depth-peel", 0);
        let (want, counts) = exact(&scene, &camera, &probe, size);
        let deepest = counts.iter().copied().max().unwrap();
        assert!(deepest >= 2, "az {az}: the bunny is seen through ({deepest} layers)");
        let settings = settings("depth-peel", deepest);
        let got = render(&scene, &camera, &settings, size);
        let error = reference::compare(&got, &want).unwrap();
        println!("az {az}: {deepest} layers, ε {:.3}, PSNR {:.2} dB", error.eps, error.psnr);
        assert!(error.eps <= MAX_DEPTH_PEEL_EPS, "az {az}: ε {}", error.eps);
    }
}

#[test]
fn fewer_peeled_layers_cost_accuracy_and_approximate_peeling_recovers_most_of_it() {
    let scene = transparent_bunny(0.5);
    let camera = view(&scene, 20.0, 10.0);
    let size = 160;
    let (want, _) = exact(&scene, &camera, &settings("depth-peel", 0), size);
    let eps = |name: &str, layers: u32| {
        let got = render(&scene, &camera, &settings(name, layers), size);
        reference::compare(&got, &want).unwrap().eps
    };
    let (peel2, peel8, approx3) = (eps("depth-peel", 2), eps("depth-peel", 8), eps("approx-peel", 3));
    println!("depth-peel k=2 ε {peel2:.3}, k=8 ε {peel8:.3}, approx-peel k=3 ε {approx3:.3}");
    assert!(peel8 < peel2, "more layers, less error");
    assert!(approx3 < peel2, "the approximate last layer beats dropping the rest");
    assert!(approx3 <= MAX_APPROX_PEEL_EPS, "approx-peel k=3: ε {approx3}");
}

#[test]
fn opacity_zero_shows_only_the_background_in_every_transparent_mode() {
    let scene = transparent_bunny(0.0);
    let camera = view(&scene, 0.0, 10.0);
    let bg = common::background_rgb();
    for name in ["depth-peel", "approx-peel", "reference"] {
        let settings = settings(name, 0);
        let image = if name == "reference" {
            exact(&scene, &camera, &settings, 96).0
        } else {
            render(&scene, &camera, &settings, 96)
        };
        let off = image.pixels().filter(|p| p.0[..3] != bg).count();
        assert_eq!(off, 0, "{name}: {off} pixels are not the background");
    }
}

#[test]
fn opacity_one_draws_the_opaque_picture_without_peeling() {
    let scene = transparent_bunny(1.0);
    assert!(!scene.has_transparency());
    let camera = view(&scene, 30.0, 10.0);
    let opaque = render(&scene, &camera, &settings("two-pass", 0), 128);
    let mut renderer = common::renderer();
    let gpu = renderer.upload(&scene, None);
    for name in ["depth-peel", "approx-peel"] {
        let settings = settings(name, 0);
        let (image, plan) = renderer.render_image(&gpu, &camera, &settings, 128, 128).unwrap();
        assert!(plan.notes.iter().any(|n| n.contains("opaque")), "{name}: the plan says it fell back\n{plan}");
        assert!(!plan.passes.iter().any(|p| p.name.contains("peel")), "{name} peels an opaque scene\n{plan}");
        assert_eq!(image, opaque, "{name}: not the two-pass picture");
    }
}

/// `count` splats at one point facing the camera, each of `opacity`.
fn coincident(count: usize, opacity: f32, colour: [u8; 3]) -> Scene {
    let mut cloud = PointCloud::default();
    for _ in 0..count {
        cloud.positions.push(Vec3::ZERO);
        cloud.normals.push(Vec3::Z);
        cloud.radii.push(0.1);
        cloud.colors.push(colour);
        cloud.opacity.push(opacity);
    }
    let mut scene = Scene::from(cloud);
    scene.objects[0].material.two_sided = true;
    scene
}

#[test]
fn a_thousand_coincident_transparent_splats_blend_as_one_layer_without_overflow() {
    let colour = [240, 120, 30];
    let scene = coincident(1000, 0.5, colour);
    assert!(scene.has_transparency());
    let camera =
        Camera { target: Vec3::ZERO, distance: 1.0, azimuth_deg: 0.0, elevation_deg: 0.0, ..view(&scene, 0.0, 0.0) };
    let bg = common::background_rgb();
    // Eq. 1: one layer of normalised opacity 0.5 over the background.
    let want = [0, 1, 2].map(|k| 0.5 * colour[k] as f32 + 0.5 * bg[k] as f32);
    for name in ["depth-peel", "approx-peel", "reference"] {
        let settings = RenderSettings { lighting: false, ..settings(name, 0) };
        let image = if name == "reference" {
            exact(&scene, &camera, &settings, 64).0
        } else {
            render(&scene, &camera, &settings, 64)
        };
        // Inside the disc every pixel is the closed form: no NaN-black, no
        // saturated speck where a thousand weights add up.
        let mut worst = 0.0f32;
        for (x, y) in (26..39).flat_map(|y| (26..39).map(move |x| (x, y))) {
            let got = image.get_pixel(x, y).0;
            for k in 0..3 {
                worst = worst.max((got[k] as f32 - want[k]).abs());
            }
        }
        println!("{name}: worst channel error {worst}");
        assert!(worst <= MAX_COINCIDENT_CHANNEL_ERROR, "{name}: off by {worst} from {want:?}");
    }
}

#[test]
fn a_camera_inside_a_transparent_sphere_sees_its_inside_as_the_reference_does() {
    let mut object = Scene::from(primitives::sphere(20_000, 1.0, Vec3::ZERO)).objects.remove(0);
    object.material = Material { colour: Some([60, 160, 220]), ..Material::with_opacity(0.4) };
    let scene = Scene { objects: vec![object], ..Default::default() };
    let mut camera = view(&scene, 30.0, 20.0);
    camera.target = Vec3::ZERO;
    camera.distance = 0.3;
    let bg = common::background_rgb();
    let size = 128;
    for name in ["depth-peel", "approx-peel"] {
        let settings = settings(name, 0);
        let (want, counts) = exact(&scene, &camera, &settings, size);
        assert!(counts.iter().all(|&c| c == 1), "from inside every ray meets the shell once");
        let got = render(&scene, &camera, &settings, size);
        assert!(got.pixels().all(|p| p.0[..3] != bg), "{name}: the shell covers the whole frame");
        let error = reference::compare(&got, &want).unwrap();
        println!("{name} inside the sphere: ε {:.3}", error.eps);
        assert!(error.eps <= MAX_DEPTH_PEEL_EPS, "{name}: ε {}", error.eps);
    }
}
