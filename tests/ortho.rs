//! Orthographic views (crates/core/src/frame/projection.rs): parallel rays in
//! `two-pass`, `tiled` and the reference. A generated survey tile, flat
//! ground with two equal square roofs 3 m and 12 m above it, seen from
//! above: the roofs cover equal areas in orthographic and unequal ones in
//! perspective; `tiled` stays the reference's image in orthographic.

mod common;

use common::tolerances::*;
use glam::Vec3;
use pointblend::cloud::PointCloud;
use pointblend::frame::{Camera, CameraRequest, NamedView, Projection, RenderSettings, View, resolve};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::scene::{Scene, primitives};

const RED: [u8; 3] = [220, 30, 30];
const BLUE: [u8; 3] = [30, 30, 220];

/// A 40 m tile, z up: grey ground, a red roof at 3 m and a blue one at 12 m, each 8 m square.
fn tile(opacity: f32) -> Scene {
    let mut cloud = PointCloud { z_up: true, ..Default::default() };
    let parts = [
        (primitives::plane(6400, 40.0, Vec3::ZERO, Vec3::Z), [128, 128, 128]),
        (primitives::plane(900, 8.0, Vec3::new(-10.0, 0.0, 3.0), Vec3::Z), RED),
        (primitives::plane(900, 8.0, Vec3::new(10.0, 0.0, 12.0), Vec3::Z), BLUE),
    ];
    for (part, colour) in parts {
        let n = part.len();
        cloud.positions.extend(part.positions);
        cloud.normals.extend(part.normals);
        cloud.radii.extend(part.radii);
        cloud.colours.extend(vec![colour; n]);
        cloud.opacity.extend(vec![opacity; n]);
    }
    Scene::from(cloud)
}

/// The tile from above in `projection`, fitted to the view.
fn from_above(scene: &Scene, projection: Projection) -> Camera {
    let request = CameraRequest { projection: Some(projection), view: Some(NamedView::Top), ..Default::default() };
    request.camera(&scene.flattened(), 1.0).expect("a camera")
}

fn render(scene: &Scene, camera: &Camera, mode: &str, size: u32) -> image::RgbaImage {
    let settings = RenderSettings { mode: mode.parse().unwrap(), lighting: false, ..Default::default() };
    if !settings.mode.is_gpu() {
        return reference::render(scene, camera, &ReferenceOptions::matching(&settings, scene), size, size);
    }
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload(scene, None);
    let spec = resolve(&settings, &gpu.facts(), &View::still((size, size)));
    renderer.render_spec(&mut gpu, camera, &spec, true).expect("render").0
}

/// Pixels of each roof: (red, blue).
fn roof_pixels(image: &image::RgbaImage) -> (usize, usize) {
    let near = |p: &image::Rgba<u8>, c: [u8; 3]| p.0.iter().zip(c).all(|(a, b)| (*a as i32 - b as i32).abs() < 40);
    let red = image.pixels().filter(|p| near(p, RED)).count();
    let blue = image.pixels().filter(|p| near(p, BLUE)).count();
    (red, blue)
}

fn difference((a, b): (usize, usize)) -> f64 {
    (a as f64 - b as f64).abs() / a.max(b).max(1) as f64
}

#[test]
fn equal_roofs_at_different_heights_cover_equal_areas_from_above_in_ortho_only() {
    let scene = tile(1.0);
    let ortho = from_above(&scene, Projection::Ortho);
    let perspective = from_above(&scene, Projection::Perspective);
    for mode in ["two-pass", "tiled", "reference"] {
        let roofs = roof_pixels(&render(&scene, &ortho, mode, 192));
        assert!(roofs.0 > 1000, "{mode}: the red roof covers {} pixels", roofs.0);
        assert!(
            difference(roofs) <= MAX_ORTHO_ROOF_AREA_DIFFERENCE,
            "{mode} in ortho: roofs of {} and {} pixels",
            roofs.0,
            roofs.1
        );
        let roofs = roof_pixels(&render(&scene, &perspective, mode, 192));
        assert!(roofs.1 as f64 > 1.2 * roofs.0 as f64, "{mode} in perspective: the nearer roof is larger: {roofs:?}");
    }
}

#[test]
fn tiled_is_the_reference_in_ortho_on_a_translucent_tile_and_the_lion() {
    let lion = Scene::from(pointblend::cloud::load(&common::bundled_model()).expect("the lion").0);
    for (scene, view) in [(tile(0.5), NamedView::Iso), (lion, NamedView::Front), (tile(0.5), NamedView::Top)] {
        let request = CameraRequest { projection: Some(Projection::Ortho), view: Some(view), ..Default::default() };
        let camera = request.camera(&scene.flattened(), 1.0).unwrap();
        let got = render(&scene, &camera, "tiled", 160);
        let want = render(&scene, &camera, "reference", 160);
        let error = reference::compare(&got, &want).unwrap();
        assert!(error.eps <= MAX_TILED_EPS, "{view:?}: ε {}", error.eps);
        let shown = common::foreground(&want, common::background_rgb()).iter().filter(|f| **f).count();
        assert!(shown > (160 * 160) / 5, "{view:?}: the view shows the scene ({shown} pixels)");
    }
}

#[test]
fn a_pick_in_ortho_meets_the_roof_under_the_pixel_at_its_height() {
    let scene = tile(0.5);
    let camera = from_above(&scene, Projection::Ortho);
    let size = 192;
    // The pixel over a point of the high roof, off its centre.
    let at = Vec3::new(11.5, 2.0, 12.0);
    let clip = camera.projection(1.0) * camera.view_matrix() * at.extend(1.0);
    let ndc = clip.truncate() / clip.w;
    let pixel = (((ndc.x + 1.0) * 0.5 * size as f32) as u32, ((1.0 - ndc.y) * 0.5 * size as f32) as u32);
    let settings = RenderSettings::default();
    let layers = pointblend::reference::pick::pick(
        &scene,
        &camera,
        &pointblend::reference::pick::options(&settings, &scene),
        (size, size),
        pixel,
    );
    assert_eq!(layers.len(), 2, "the roof and the ground under it: {layers:?}");
    let (roof, ground) = (layers[0].position, layers[1].position);
    // One pixel is 2·half_y/size wide; the ray is vertical, so both layers lie under it.
    let pixel_side = 2.0 * camera.half_extent_y() as f64 / size as f64;
    assert!((roof.z - 12.0).abs() < 1e-4 && ground.z.abs() < 1e-4, "{roof} {ground}");
    assert!((roof.truncate() - at.truncate().as_dvec2()).length() <= pixel_side, "{roof} under {at}");
    assert!((roof.truncate() - ground.truncate()).length() < 1e-4, "parallel rays: {roof} over {ground}");
}
