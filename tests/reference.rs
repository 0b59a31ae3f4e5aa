//! The exact reference on scenes with known answers, and two-pass against it.

mod common;

use common::tolerances::*;
use glam::{Vec2, Vec3};
use pointblend::cloud::{self, PointCloud};
use pointblend::frame::{Camera, RenderSettings, Shading, SplatKernel, UpAxis};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::scene::{Material, Scene, SceneObject};

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
        min_pixel_radius: 0.0,
        transparent: true,
        progress: false,
        environment: Default::default(),
        lights: Default::default(),
        supersample: 1,
        clip: Default::default(),
        eye_dome: None,
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
        projection: Default::default(),
    }
}

/// Discs given as (centre, normal, radius, colour).
fn discs(list: &[(Vec3, Vec3, f32, [u8; 3])]) -> Scene {
    Scene::from(PointCloud {
        positions: list.iter().map(|d| d.0).collect(),
        normals: list.iter().map(|d| d.1.normalize()).collect(),
        radii: list.iter().map(|d| d.2).collect(),
        colours: list.iter().map(|d| d.3).collect(),
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
fn two_pass_matches_the_reference_on_the_lion() {
    let (cloud, _) = cloud::load(&common::bundled_model()).unwrap();
    let settings = RenderSettings::default();
    let size = 256;
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload_cloud(&cloud, None);
    let scene = Scene::from(cloud.clone());
    for (az, el) in [(0.0, 10.0), (90.0, 25.0), (200.0, 40.0)] {
        let mut camera = Camera::default_for(&cloud, 1.0);
        camera.azimuth_deg = az;
        camera.elevation_deg = el;
        camera.distance = camera.fit_distance(&cloud.positions, 1.0);
        let (image, _) = renderer.render_image(&mut gpu, &camera, &settings, size, size).unwrap();
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

/// A square plane of overlapping splats at depth `z` (world z, facing the
/// camera), of one colour, as a scene object with `opacity`.
fn plane(z: f32, half: f32, colour: [u8; 3], opacity: f32) -> SceneObject {
    let n = 40;
    let spacing = 2.0 * half / n as f32;
    let mut cloud = PointCloud::default();
    for i in 0..=n {
        for j in 0..=n {
            cloud.positions.push(Vec3::new(-half + i as f32 * spacing, -half + j as f32 * spacing, z));
            cloud.normals.push(Vec3::Z);
            cloud.radii.push(1.5 * spacing);
            cloud.colours.push(colour);
            cloud.opacity.push(1.0);
        }
    }
    let mut object = Scene::from(cloud).objects.remove(0);
    object.material = Material::with_opacity(opacity);
    object
}

fn unlit_transparent(epsilon: f32) -> ReferenceOptions {
    ReferenceOptions { lighting: false, backface_culling: false, ..options(epsilon) }
}

/// α₁c₁ + (1 − α₁)(α₂c₂ + (1 − α₂)(… + bg)), in 0..255, front layer first.
fn over(layers: &[([u8; 3], f32)], background: [u8; 3]) -> [f32; 3] {
    let mut colour = background.map(|c| c as f32);
    for (c, a) in layers.iter().rev() {
        colour = [0, 1, 2].map(|k| a * c[k] as f32 + (1.0 - a) * colour[k]);
    }
    colour
}

#[test]
fn parallel_transparent_planes_composite_exactly_front_to_back() {
    let bg = background();
    let cases: Vec<Vec<(f32, [u8; 3], f32)>> = vec![
        vec![(1.0, [250, 30, 20], 0.5), (0.0, [20, 40, 240], 0.6)],
        vec![(1.0, [250, 30, 20], 0.3), (0.0, [20, 200, 40], 0.5), (-1.0, [40, 40, 250], 0.8)],
        vec![(1.0, [200, 200, 200], 1.0), (0.0, [20, 200, 40], 0.5)],
        vec![(1.0, [200, 100, 0], 0.0), (0.0, [20, 200, 40], 0.5)],
    ];
    for layers in cases {
        let mut scene = Scene::default();
        for &(z, c, a) in &layers {
            scene.objects.push(plane(z, 3.0, c, a));
        }
        let (image, counts) = reference::render_with_layers(&scene, &camera(), &unlit_transparent(0.3), SIZE, SIZE);
        let visible: Vec<([u8; 3], f32)> = layers.iter().filter(|l| l.2 > 0.0).map(|&(_, c, a)| (c, a)).collect();
        let want = over(&visible, bg);
        let centre = (SIZE / 2 - 8)..(SIZE / 2 + 8);
        for y in centre.clone() {
            for x in centre.clone() {
                let got = image.get_pixel(x, y).0;
                for k in 0..3 {
                    assert!((got[k] as f32 - want[k]).abs() <= 1.0, "{layers:?}: pixel {x},{y}: {got:?} vs {want:?}");
                }
                // Every plane is a layer, up to the first opaque one, which ends the ray.
                let met = layers.iter().position(|l| l.2 >= 1.0).map_or(layers.len(), |i| i + 1) as u32;
                assert_eq!(counts[(y * SIZE + x) as usize], met, "{layers:?}");
            }
        }
    }
}

#[test]
fn a_closed_transparent_sphere_has_two_layers_inside_its_outline() {
    let mut sphere = Scene::from(pointblend::scene::primitives::sphere(20_000, 1.0, Vec3::ZERO)).objects.remove(0);
    sphere.material = Material::with_opacity(0.4);
    let scene = Scene { objects: vec![sphere], ..Default::default() };
    let eps = 0.05;
    let (_, counts) = reference::render_with_layers(&scene, &camera(), &unlit_transparent(eps), SIZE, SIZE);
    let (mut inside, mut outside) = (0, 0);
    for y in 0..SIZE {
        for x in 0..SIZE {
            // The ray's closest approach to the centre, against the radius.
            let on_plane = pixel_on_plane(x, y, 0.0);
            let ray = on_plane.extend(-DISTANCE).normalize();
            let miss = Vec3::new(0.0, 0.0, DISTANCE).cross(ray).length();
            let count = counts[(y * SIZE + x) as usize];
            if miss < 0.9 {
                assert_eq!(count, 2, "pixel {x},{y} (ray passes {miss:.3} from the centre)");
                inside += 1;
            } else if miss > 1.1 {
                assert_eq!(count, 0, "pixel {x},{y} misses the sphere");
                outside += 1;
            }
        }
    }
    assert!(inside > 1000 && outside > 1000);
}

#[test]
fn an_opaque_ball_inside_a_transparent_sphere_shows_through_it_dimmed() {
    let mut shell = Scene::from(pointblend::scene::primitives::sphere(20_000, 1.0, Vec3::ZERO)).objects.remove(0);
    shell.material = Material { colour: Some([40, 80, 240]), ..Material::with_opacity(0.5) };
    let mut ball = Scene::from(pointblend::scene::primitives::sphere(4_000, 0.4, Vec3::ZERO)).objects.remove(0);
    ball.material = Material { colour: Some([240, 200, 40]), ..Material::default() };
    let scene = Scene { objects: vec![shell, ball], ..Default::default() };
    let (image, counts) = reference::render_with_layers(&scene, &camera(), &unlit_transparent(0.05), SIZE, SIZE);
    let c = SIZE / 2;
    let want = over(&[([40, 80, 240], 0.5), ([240, 200, 40], 1.0)], background());
    let got = image.get_pixel(c, c).0;
    for k in 0..3 {
        assert!((got[k] as f32 - want[k]).abs() <= 1.0, "{got:?} vs {want:?}");
    }
    // The ball is opaque: the ray ends there, and the shell's back layer is not met.
    assert_eq!(counts[(c * SIZE + c) as usize], 2);
}
