//! Render tests on lavapipe at 128-256 px: coverage, holes, background, NaN, filtering.

mod common;

use common::tolerances::*;
use glam::Vec3;
use pointblend::cloud::{self, PointCloud};
use pointblend::frame::Camera;
use pointblend::render::{Quality, RenderSettings};

const SIZE: u32 = 192;

fn render(cloud: &PointCloud, camera: &Camera, settings: &RenderSettings, size: u32) -> image::RgbaImage {
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload_cloud(cloud, None);
    renderer.render_image(&mut gpu, camera, settings, size, size).expect("render").0
}

/// The bundled torus knot as its vertices' splats (25,920, radii estimated
/// from neighbours, as the Stanford bunny's were made from its mesh) and the
/// triangles of the mesh, in the same frame.
fn knot_and_mesh() -> (PointCloud, Vec<[Vec3; 3]>) {
    let (cloud, triangles, _) = cloud::load_mesh(&common::bundled_mesh(), &Default::default()).unwrap();
    let triangles = triangles.iter().map(|t| t.map(|i| cloud.positions[i as usize])).collect();
    (cloud, triangles)
}

fn views(cloud: &PointCloud) -> Vec<Camera> {
    [(0.0, 0.0), (90.0, 20.0), (200.0, -15.0), (300.0, 60.0)]
        .into_iter()
        .map(|(az, el)| {
            let mut c = Camera::default_for(cloud, 1.0);
            c.azimuth_deg = az;
            c.elevation_deg = el;
            c.distance = c.fit_distance(&cloud.positions, 1.0);
            c
        })
        .collect()
}

fn count(mask: &[bool]) -> usize {
    mask.iter().filter(|&&b| b).count()
}

#[test]
fn the_knot_covers_its_mesh_silhouette_and_nothing_else() {
    let (cloud, triangles) = knot_and_mesh();
    let bg = common::background_rgb();
    for camera in views(&cloud) {
        let image = render(&cloud, &camera, &RenderSettings::default(), SIZE);
        let fg = common::foreground(&image, bg);
        let silhouette = common::silhouette(&triangles, &camera, SIZE, SIZE);
        let inner = common::morph(&silhouette, SIZE, SIZE, -1);
        let covered =
            count(&inner.iter().zip(&fg).map(|(s, f)| *s && *f).collect::<Vec<_>>()) as f64 / count(&inner) as f64;
        let spill = count(&fg.iter().zip(&silhouette).map(|(f, s)| *f && !*s).collect::<Vec<_>>()) as f64
            / count(&silhouette) as f64;
        println!("az {} el {}: coverage {covered:.4}, spill {spill:.4}", camera.azimuth_deg, camera.elevation_deg);
        assert!(covered >= MIN_SILHOUETTE_COVERAGE, "az {}: coverage {covered}", camera.azimuth_deg);
        assert!(spill <= MAX_SILHOUETTE_SPILL, "az {}: spill {spill}", camera.azimuth_deg);
        // Background stays background: away from the silhouette every pixel is exactly the background.
        let near = common::morph(&silhouette, SIZE, SIZE, BOUNDARY_RIM_PIXELS + 1);
        for (i, p) in image.pixels().enumerate() {
            if !near[i] {
                assert_eq!(p.0[..3], bg, "pixel {i} far from the knot is not background");
            }
        }
    }
}

#[test]
fn the_knot_has_no_holes_compared_with_a_dense_render() {
    let (cloud, _) = knot_and_mesh();
    let mut dense = cloud.clone();
    dense.radii.iter_mut().for_each(|r| *r *= 2.0);
    let max_radius = cloud.radii.iter().copied().fold(0.0f32, f32::max);
    let bg = common::background_rgb();
    for camera in views(&cloud) {
        for quality in [Quality::Filtered, Quality::Unfiltered] {
            let settings = RenderSettings { quality, ..Default::default() };
            let normal = common::foreground(&render(&cloud, &camera, &settings, SIZE), bg);
            let reference = common::foreground(&render(&dense, &camera, &settings, SIZE), bg);
            // The dense render's outline lies one (largest) splat radius further out.
            let nearest = camera.distance - camera.scene_radius;
            let growth = (max_radius * camera.focal_pixels(SIZE) / nearest).ceil() as i32;
            let inside = common::morph(&reference, SIZE, SIZE, -(BOUNDARY_RIM_PIXELS + growth));
            let holes = inside.iter().zip(&normal).filter(|(i, n)| **i && !**n).count();
            assert_eq!(holes, 0, "{quality:?} az {}: {holes} hole pixels", camera.azimuth_deg);
        }
    }
}

/// Mean absolute Laplacian of the luminance over `mask`.
fn roughness(image: &image::RgbaImage, mask: &[bool]) -> f64 {
    let (w, h) = image.dimensions();
    let lum = |x: u32, y: u32| {
        let p = image.get_pixel(x, y).0;
        0.299 * p[0] as f64 + 0.587 * p[1] as f64 + 0.114 * p[2] as f64
    };
    let (mut sum, mut n) = (0.0, 0usize);
    for y in 1..h - 1 {
        for x in 1..w - 1 {
            if mask[(y * w + x) as usize] {
                sum += (4.0 * lum(x, y) - lum(x - 1, y) - lum(x + 1, y) - lum(x, y - 1) - lum(x, y + 1)).abs();
                n += 1;
            }
        }
    }
    sum / n.max(1) as f64
}

#[test]
fn the_filtered_level_is_smoother_than_the_unfiltered_one() {
    let (cloud, triangles) = knot_and_mesh();
    for camera in views(&cloud) {
        let inside =
            common::morph(&common::silhouette(&triangles, &camera, SIZE, SIZE), SIZE, SIZE, -BOUNDARY_RIM_PIXELS);
        let filtered = render(&cloud, &camera, &RenderSettings::default(), SIZE);
        let unfiltered =
            render(&cloud, &camera, &RenderSettings { quality: Quality::Unfiltered, ..Default::default() }, SIZE);
        let (f, u) = (roughness(&filtered, &inside), roughness(&unfiltered, &inside));
        println!("az {}: roughness filtered {f:.3}, unfiltered {u:.3}", camera.azimuth_deg);
        assert!(u >= MIN_SMOOTHING_RATIO * f, "az {}: unfiltered {u} vs filtered {f}", camera.azimuth_deg);
    }
}

/// No NaN reaches the image: a NaN colour or weight ends as black (or
/// background inside the object); shading keeps every lit pixel above black.
fn assert_no_nan(image: &image::RgbaImage, what: &str) {
    let black = image.pixels().filter(|p| p.0[..3] == [0, 0, 0]).count();
    assert_eq!(black, 0, "{what}: {black} black (NaN) pixels");
}

/// No NaN, and the object is framed: some of the frame is object, some background.
fn assert_sane(image: &image::RgbaImage, what: &str) {
    assert_no_nan(image, what);
    let fg = common::foreground(image, common::background_rgb());
    let fg_share = count(&fg) as f64 / fg.len() as f64;
    assert!(fg_share > 0.01, "{what}: the frame is empty ({fg_share})");
    assert!(fg_share < 0.999, "{what}: no background left");
}

#[test]
fn every_test_scan_renders() {
    for path in common::real_scans() {
        let name = &path.display().to_string();
        let (cloud, _) = cloud::load(&path).unwrap();
        let camera = Camera::default_for(&cloud, 1.0);
        let image = render(&cloud, &camera, &RenderSettings::default(), 128);
        assert_sane(&image, name);
    }
}

/// A sphere of `n` splats (Fibonacci lattice), radii chosen to close it.
fn sphere(n: usize, radius: f32) -> PointCloud {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    let positions: Vec<Vec3> = (0..n)
        .map(|i| {
            let y = 1.0 - 2.0 * (i as f32 + 0.5) / n as f32;
            let r = (1.0 - y * y).sqrt();
            let phi = golden * i as f32;
            Vec3::new(r * phi.cos(), y, r * phi.sin()) * radius
        })
        .collect();
    let spacing = radius * (4.0 * std::f32::consts::PI / n as f32).sqrt();
    PointCloud {
        normals: positions.iter().map(|p| p.normalize()).collect(),
        radii: vec![spacing * 1.2; n],
        colours: vec![[180, 120, 90]; n],
        opacity: vec![1.0; n],
        positions,
        ..Default::default()
    }
}

#[test]
fn a_cloud_of_2_3_million_splats_renders_as_a_closed_disc() {
    let cloud = sphere(2_300_000, 1.0);
    let camera = Camera::default_for(&cloud, 1.0);
    let image = render(&cloud, &camera, &RenderSettings::default(), 128);
    assert_sane(&image, "2.3M sphere");
    // The sphere's outline, from its own triangles-free geometry: project the centre and radius.
    let fg = common::foreground(&image, common::background_rgb());
    let (w, c) = (128.0f32, 64.0f32);
    let angular = (1.0 / camera.distance).asin();
    let radius_px = angular.tan() * camera.focal_pixels(128);
    let mut missing = 0;
    for y in 0..128u32 {
        for x in 0..128u32 {
            let d = ((x as f32 + 0.5 - c).powi(2) + (y as f32 + 0.5 - c).powi(2)).sqrt();
            if d < radius_px - BOUNDARY_RIM_PIXELS as f32 && !fg[(y as f32 * w + x as f32) as usize] {
                missing += 1;
            }
        }
    }
    assert_eq!(missing, 0, "{missing} hole pixels in the 2.3M-splat sphere");
}

#[test]
fn splats_crossing_the_near_plane_render_without_cracks() {
    let (floor, camera) = common::floor_crossing_the_near_plane();
    let crossing = common::splats_crossing_the_near_plane(&floor, &camera);
    assert!(crossing > 10, "the case must really cross the near plane: {crossing} splats do");
    let size = 160;
    let settings = RenderSettings::default();
    let image = render(&floor, &camera, &settings, size);
    assert_no_nan(&image, "near-plane crossing");
    // The floor fills the lower part of the view down to the last row: no crack where it meets the near plane.
    let bg = common::background_rgb();
    let bottom_gaps = (0..size).filter(|&x| image.get_pixel(x, size - 1).0[..3] == bg).count();
    assert_eq!(bottom_gaps, 0, "{bottom_gaps} background pixels in the bottom row");
    // And it agrees with the exact reference, which casts the same rays.
    let scene = pointblend::scene::Scene::from(floor);
    let options = pointblend::reference::ReferenceOptions::matching(&settings, &scene);
    let exact = pointblend::reference::render(&scene, &camera, &options, size, size);
    let bottom_gaps = (0..size).filter(|&x| exact.get_pixel(x, size - 1).0[..3] == bg).count();
    assert_eq!(bottom_gaps, 0, "the reference has {bottom_gaps} background pixels in the bottom row");
    let error = pointblend::reference::compare(&image, &exact).unwrap();
    println!(
        "near-plane floor: {crossing} crossing splats, ε {:.3}, bad {:.3}%",
        error.eps,
        100.0 * error.bad_pixel_share
    );
    assert!(error.eps <= NEAR_PLANE_EPS, "ε {}", error.eps);
    assert!(error.bad_pixel_share <= NEAR_PLANE_BAD_PIXELS, "bad {}", error.bad_pixel_share);
}

#[test]
fn extreme_views_and_sizes_give_sane_images() {
    let base = sphere(20_000, 1.0);
    // Edge-on splats: every normal perpendicular to the view axis, culling off.
    let mut edge_on = base.clone();
    edge_on.normals.iter_mut().for_each(|n| *n = Vec3::X);
    let camera = Camera::default_for(&edge_on, 1.0);
    let no_cull = RenderSettings { backface_culling: false, ..Default::default() };
    assert_sane(&render(&edge_on, &camera, &no_cull, 128), "edge-on splats");

    // Tiny and huge models: radii from 1e-6 to 1e5 units.
    for scale in [1e-6f32, 1e-3, 1e3, 1e5] {
        let mut scaled = base.clone();
        scaled.positions.iter_mut().for_each(|p| *p *= scale);
        scaled.radii.iter_mut().for_each(|r| *r *= scale);
        let camera = Camera::default_for(&scaled, 1.0);
        assert_sane(&render(&scaled, &camera, &RenderSettings::default(), 128), &format!("scale {scale}"));
    }

    // A single splat: the bounds have no extent.
    let mut single = base.clone();
    single.positions.truncate(1);
    single.normals.truncate(1);
    single.colours.truncate(1);
    single.opacity.truncate(1);
    single.radii = vec![0.5];
    let camera = Camera::default_for(&single, 1.0);
    assert_sane(&render(&single, &camera, &RenderSettings::default(), 128), "one splat");
}

#[test]
fn a_model_a_millionth_of_its_distance_away_renders_in_every_mode() {
    // The depth range around a tiny model far away is a few f32 steps wide
    // (at 1e-8 of the distance, none: far − near rounds to 0 and 1/(far −
    // near) to infinity). Every mode must still show the sphere's disc, of
    // the size its distance gives, without a NaN pixel.
    use pointblend::frame::RenderMode;
    let mut cloud = sphere(20_000, 1.0);
    cloud.opacity.iter_mut().for_each(|a| *a = 0.5); // the transparent modes draw their own passes
    for ratio in [1e-6f32, 1e-8] {
        let mut camera = Camera::default_for(&cloud, 1.0);
        camera.distance = 1.0 / ratio;
        // The sphere's angular radius asin(1/d), 0.4 of the half field.
        camera.fov_y_deg = 2.0 * (ratio.asin() / 0.4).to_degrees();
        let (near, far) = camera.near_far();
        assert!(far > near && (1.0 / (far - near)).is_finite(), "{ratio}: near {near}, far {far}");
        let size = 96u32;
        let radius_px = ratio.asin().tan() * camera.focal_pixels(size);
        let disc = std::f32::consts::PI * radius_px * radius_px;
        for mode in RenderMode::ALL {
            let settings = RenderSettings { mode, ..Default::default() };
            let image = if mode.is_gpu() {
                let grouping =
                    mode.needs_grouping().then(|| settings.grouping_for_mode().compute(&cloud).expect("grouping"));
                let mut renderer = common::renderer();
                let mut gpu = renderer.upload_cloud(&cloud, grouping.as_ref());
                renderer.render_image(&mut gpu, &camera, &settings, size, size).expect("render").0
            } else {
                let scene = pointblend::scene::Scene::from(cloud.clone());
                let options = pointblend::reference::ReferenceOptions::matching(&settings, &scene);
                pointblend::reference::render(&scene, &camera, &options, size, size)
            };
            let what = format!("{mode} at {ratio:e} of the distance");
            assert_no_nan(&image, &what);
            let shown = count(&common::foreground(&image, common::background_rgb())) as f32;
            println!("{what}: {shown} px against the disc's {disc:.0}");
            assert!((shown - disc).abs() <= 0.1 * disc, "{what}: {shown} px against the disc's {disc:.0}");
        }
    }
}
