//! The exact reference on scenes with known answers, and two-pass against it.

mod common;

use common::tolerances::*;
use glam::{Vec2, Vec3};
use pointblend::cloud::{self, PointCloud};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::scene::Scene;
use pointblend::view::{Camera, RenderSettings, Shading, SplatKernel, UpAxis};

const SIZE: u32 = 128;
const DISTANCE: f32 = 10.0;

/// Unlit shading: a pixel shows its normalised albedo exactly.
fn flat() -> Shading {
    Shading { ambient: 1.0, diffuse: 0.0, specular: 0.0, ..Shading::default() }
}

fn options(epsilon: f32) -> ReferenceOptions {
    ReferenceOptions {
        epsilon,
        backface_culling: true,
        kernel: SplatKernel::default(),
        shading: flat(),
        lighting: true,
        radius_scale: 1.0,
        progress: false,
    }
}

/// Looks down -z at the origin from z = DISTANCE.
fn camera() -> Camera {
    Camera {
        target: Vec3::ZERO,
        distance: DISTANCE,
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        fov_y_deg: 30.0,
        up: UpAxis::PosY,
        scene_radius: 4.0,
    }
}

/// Discs given as (centre, normal, radius, colour).
fn discs(list: &[(Vec3, Vec3, f32, [u8; 3])]) -> Scene {
    Scene::from(PointCloud {
        positions: list.iter().map(|d| d.0).collect(),
        normals: list.iter().map(|d| d.1.normalize()).collect(),
        radii: list.iter().map(|d| d.2).collect(),
        colors: list.iter().map(|d| d.3).collect(),
        opacity: vec![1.0; list.len()],
        ..Default::default()
    })
}

/// Where the ray of pixel (x, y) meets the plane z = `z` (world = eye space shifted by DISTANCE).
fn pixel_on_plane(x: u32, y: u32, z: f32) -> Vec2 {
    let tan_y = (camera().fov_y_deg.to_radians() * 0.5).tan();
    let ndc = Vec2::new((x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / SIZE as f32 * 2.0);
    ndc * tan_y * (DISTANCE - z)
}

fn background() -> [u8; 3] {
    let b = flat().background;
    [b.x, b.y, b.z].map(|c| (c * 255.0).round() as u8)
}

#[test]
fn a_disc_facing_the_camera_covers_exactly_its_circle() {
    let radius = 1.5;
    let cloud = discs(&[(Vec3::ZERO, Vec3::Z, radius, [200, 100, 50])]);
    let image = reference::render(&cloud, &camera(), &options(0.1), SIZE, SIZE);
    let mut inside_pixels = 0;
    for (x, y, p) in image.enumerate_pixels() {
        let r = pixel_on_plane(x, y, 0.0).length() / radius;
        if r < 1.0 - 1e-4 {
            inside_pixels += 1;
            assert_eq!(p.0[..3], [200, 100, 50], "pixel {x},{y} inside the disc");
        } else if r > 1.0 + 1e-4 {
            assert_eq!(p.0[..3], background(), "pixel {x},{y} outside the disc");
        }
    }
    assert!(inside_pixels > 100);
}

#[test]
fn overlapping_coplanar_discs_blend_with_normalised_gaussian_weights() {
    let (a, b, radius) = (Vec3::new(-0.6, 0.0, 0.0), Vec3::new(0.6, 0.1, 0.0), 1.4);
    let cloud = discs(&[(a, Vec3::Z, radius, [255, 0, 0]), (b, Vec3::Z, radius, [0, 0, 255])]);
    let kernel = SplatKernel::default();
    let image = reference::render(&cloud, &camera(), &options(0.1), SIZE, SIZE);
    let mut blended = 0;
    for (x, y, p) in image.enumerate_pixels() {
        let q = pixel_on_plane(x, y, 0.0);
        let rho2 = |c: Vec3| (q - c.truncate()).length_squared() / (radius * radius);
        let (wa, wb) = (kernel.weight(rho2(a)), kernel.weight(rho2(b)));
        let margin = |c: Vec3| (rho2(c) - 1.0).abs() > 1e-3;
        if !(margin(a) && margin(b)) || wa + wb == 0.0 {
            continue;
        }
        let want_red = 255.0 * wa / (wa + wb);
        let want_blue = 255.0 * wb / (wa + wb);
        assert!((p.0[0] as f32 - want_red).abs() <= 0.5 + 1e-3, "pixel {x},{y}: red {} vs {want_red}", p.0[0]);
        assert!((p.0[2] as f32 - want_blue).abs() <= 0.5 + 1e-3, "pixel {x},{y}: blue {} vs {want_blue}", p.0[2]);
        assert_eq!(p.0[1], 0);
        blended += (wa > 0.0 && wb > 0.0) as usize;
    }
    assert!(blended > 100, "the discs overlap on {blended} pixels");
}

#[test]
fn of_two_parallel_discs_further_apart_than_epsilon_the_front_one_wins() {
    let cloud =
        discs(&[(Vec3::new(0.0, 0.0, 1.0), Vec3::Z, 1.0, [255, 0, 0]), (Vec3::ZERO, Vec3::Z, 2.0, [0, 0, 255])]);
    let image = reference::render(&cloud, &camera(), &options(0.5), SIZE, SIZE);
    let (mut red, mut blue) = (0, 0);
    for (x, y, p) in image.enumerate_pixels() {
        let front = pixel_on_plane(x, y, 1.0).length();
        let back = pixel_on_plane(x, y, 0.0).length() / 2.0;
        if front < 1.0 - 1e-3 {
            assert_eq!(p.0[..3], [255, 0, 0], "pixel {x},{y} in front of the blue disc");
            red += 1;
        } else if front > 1.0 + 1e-3 && back < 1.0 - 1e-3 {
            assert_eq!(p.0[..3], [0, 0, 255], "pixel {x},{y} shows only the back disc");
            blue += 1;
        }
    }
    assert!(red > 100 && blue > 100);
    // Closer than ε, the same discs blend instead.
    let image = reference::render(&cloud, &camera(), &options(1.5), SIZE, SIZE);
    let centre = image.get_pixel(SIZE / 2, SIZE / 2).0;
    assert!(centre[0] > 0 && centre[2] > 0, "within ε the discs blend: {centre:?}");
}

#[test]
fn a_disc_seen_at_89_degrees_gives_no_nan() {
    for degrees in [89.0f32, 89.99, 90.0] {
        let tilt = degrees.to_radians();
        let normal = Vec3::new(0.0, tilt.sin(), tilt.cos());
        let cloud = discs(&[(Vec3::ZERO, normal, 3.0, [120, 200, 80])]);
        let shading = Shading::default();
        let opts = ReferenceOptions { shading, backface_culling: false, ..options(0.1) };
        let image = reference::render(&cloud, &camera(), &opts, SIZE, SIZE);
        let bg = [shading.background.x, shading.background.y, shading.background.z].map(|c| (c * 255.0).round() as u8);
        for p in image.pixels() {
            assert!(p.0[..3] == bg || p.0[..3] != [0, 0, 0], "{degrees}°: a NaN (black) pixel");
        }
        if degrees <= 89.0 {
            assert!(image.pixels().any(|p| p.0[..3] != bg), "{degrees}°: the sliver of the disc is visible");
        }
    }
}

#[test]
fn two_pass_matches_the_reference_on_the_bunny() {
    let (cloud, _) = cloud::load(&common::bundled_bunny()).unwrap();
    let settings = RenderSettings::default();
    let size = 256;
    let mut renderer = common::renderer();
    let gpu = renderer.upload_cloud(&cloud, None);
    let scene = Scene::from(cloud.clone());
    for (az, el) in [(0.0, 10.0), (90.0, 25.0), (200.0, 40.0)] {
        let mut camera = Camera::default_for(&cloud, 1.0);
        camera.azimuth_deg = az;
        camera.elevation_deg = el;
        camera.distance = camera.fit_distance(&cloud.positions, 1.0);
        let (image, _) = renderer.render_image(&gpu, &camera, &settings, size, size).unwrap();
        let exact = reference::render(&scene, &camera, &ReferenceOptions::matching(&settings, &scene), size, size);
        let error = reference::compare(&image, &exact).unwrap();
        println!(
            "az {az}: ε {:.3}, PSNR {:.2} dB, bad pixels {:.2}%",
            error.eps,
            error.psnr,
            100.0 * error.bad_pixel_share
        );
        assert!(error.eps <= MAX_TWO_PASS_EPS, "az {az}: ε {}", error.eps);
        assert!(error.bad_pixel_share <= MAX_TWO_PASS_BAD_PIXELS, "az {az}: bad {}", error.bad_pixel_share);
    }
}
