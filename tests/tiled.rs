//! `tiled`, the exact reference on the GPU, against closed forms and the CPU
//! reference: parallel planes, a closed sphere from outside and from inside,
//! coincident splats by the thousand and the hundred thousand, thousands of
//! layers over one tile, edge-on planes, a floor crossing the near plane,
//! and the bundled lion in three views, opaque and transparent.

mod common;

use common::tolerances::*;
use glam::Vec3;
use pointblend::cloud::{self, PointCloud};
use pointblend::frame::{Camera, RenderSettings, View, resolve};
use pointblend::reference::{self, ReferenceOptions};
use pointblend::render::RenderMode;
use pointblend::scene::{Material, Scene, primitives};

fn tiled() -> RenderMode {
    "tiled".parse().unwrap()
}

fn settings(lighting: bool) -> RenderSettings {
    RenderSettings { mode: tiled(), lighting, ..Default::default() }
}

/// Renders with `tiled`; also returns how many pixels overflowed their window of waiting hits.
fn render(scene: &Scene, camera: &Camera, settings: &RenderSettings, size: u32) -> (image::RgbaImage, u32) {
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload(scene, None);
    let spec = resolve(settings, &gpu.facts(), &View::still((size, size)));
    let (image, plan, report) = renderer.render_spec(&mut gpu, camera, &spec, true).expect("render");
    assert!(plan.compute_passes() > 0, "tiled ran its own plan: {plan}");
    (image, report.window_overflows.expect("the tile pipeline counts its overflows"))
}

fn exact(scene: &Scene, camera: &Camera, settings: &RenderSettings, size: u32) -> (image::RgbaImage, Vec<u32>) {
    reference::render_with_layers(scene, camera, &ReferenceOptions::matching(settings, scene), size, size)
}

/// `tiled` and the reference of `scene`, lit, from (`azimuth`, `elevation`)
/// with the model fitted to the view: the error, and the pixels whose
/// window overflowed.
fn against_reference(scene: &Scene, (azimuth, elevation): (f32, f32), size: u32) -> (reference::ImageError, u32) {
    let flat = scene.flattened();
    let mut camera = Camera::default_for(&flat, 1.0);
    (camera.azimuth_deg, camera.elevation_deg) = (azimuth, elevation);
    camera.distance = camera.fit_distance(&flat.positions, 1.0);
    let (image, overflows) = render(scene, &camera, &settings(true), size);
    let (want, _) = exact(scene, &camera, &settings(true), size);
    (reference::compare(&image, &want).unwrap(), overflows)
}

/// The worst channel difference over the pixels where `want` gives a colour.
fn worst(image: &image::RgbaImage, want: impl Fn(u32, u32) -> Option<[f64; 3]>) -> f64 {
    let mut worst = 0.0f64;
    for (x, y, p) in image.enumerate_pixels() {
        if let Some(w) = want(x, y) {
            for (got, want) in p.0.iter().zip(w) {
                worst = worst.max((*got as f64 - want).abs());
            }
        }
    }
    worst
}

/// Layers front to back, each (colour, opacity), composited over the background, unlit.
fn composite(layers: &[([u8; 3], f32)]) -> [f64; 3] {
    let bg = common::background_rgb();
    let mut out = [0.0f64; 3];
    let mut through = 1.0f64;
    for (colour, alpha) in layers {
        for k in 0..3 {
            out[k] += through * *alpha as f64 * colour[k] as f64;
        }
        through *= 1.0 - *alpha as f64;
    }
    [0, 1, 2].map(|k| out[k] + through * bg[k] as f64)
}

/// Square planes of splats facing the camera (`looking_down_z`), each
/// (depth z, colour, opacity), covering the whole view.
fn planes(planes: &[(f32, [u8; 3], f32)], normal: Vec3) -> Scene {
    let (n, half) = (60, 2.2f32);
    let spacing = 2.0 * half / n as f32;
    let mut cloud = PointCloud::default();
    for &(z, colour, opacity) in planes {
        for i in 0..=n {
            for j in 0..=n {
                cloud.positions.push(Vec3::new(-half + i as f32 * spacing, -half + j as f32 * spacing, z));
                cloud.normals.push(normal);
                cloud.radii.push(1.5 * spacing);
                cloud.colours.push(colour);
                cloud.opacity.push(opacity);
            }
        }
    }
    let mut scene = Scene::from(cloud);
    scene.objects[0].material.two_sided = true;
    scene
}

#[test]
fn two_and_three_planes_of_opacity_zero_half_and_one_composite_to_the_closed_form() {
    // Each plane is one ε-layer of normalised colour c and opacity α (Eq. 1:
    // every splat of it has both), so a pixel is Σ T_k α_k c_k + T·bg. The
    // raster composites in f32 and stores f32; the frame rounds once to 8
    // bits: at most 0.5 off, plus f32 error far below 1/255.
    let colours = [[240u8, 40, 30], [30, 200, 60], [40, 60, 230]];
    let camera = common::looking_down_z();
    let mut cases: Vec<Vec<f32>> = Vec::new();
    for a in [0.0, 0.5, 1.0] {
        for b in [0.0, 0.5, 1.0] {
            cases.push(vec![a, b]);
        }
    }
    cases.extend([vec![0.5, 0.5, 0.5], vec![0.3, 0.0, 0.8], vec![0.5, 1.0, 0.5], vec![0.0, 0.0, 1.0]]);
    for opacities in cases {
        let layers: Vec<(f32, [u8; 3], f32)> =
            opacities.iter().enumerate().map(|(k, &a)| (1.0 - k as f32, colours[k], a)).collect();
        let mut scene = planes(&layers, Vec3::Z);
        if !scene.has_transparency() {
            scene.set_opacity(1.0); // all opaque: the opaque pipeline
        }
        let want = composite(&layers.iter().map(|&(_, c, a)| (c, a)).collect::<Vec<_>>());
        let (image, _) = render(&scene, &camera, &settings(false), 64);
        let off = worst(&image, |_, _| Some(want));
        println!("planes {opacities:?}: worst channel error {off:.2} (want {want:?})");
        assert!(off <= MAX_TILED_CLOSED_FORM_CHANNEL_ERROR, "planes {opacities:?}: off by {off} from {want:?}");
    }
}

#[test]
fn a_thousand_and_a_hundred_thousand_coincident_splats_are_one_layer() {
    // One ε-layer of normalised opacity 0.5 over the background (Eq. 1). A
    // hundred thousand entries in one tile's list take the sort's path in
    // place in the entry buffer (longer than its workgroup memory).
    let colour = [240, 120, 30];
    let want = composite(&[(colour, 0.5)]);
    for count in [1000, 100_000] {
        let scene = common::coincident(count, 0.5, colour);
        let camera = Camera {
            target: Vec3::ZERO,
            distance: 1.0,
            azimuth_deg: 0.0,
            elevation_deg: 0.0,
            ..Camera::default_for(&scene.flattened(), 1.0)
        };
        let (image, _) = render(&scene, &camera, &settings(false), 64);
        let off = worst(&image, |x, y| ((26..39).contains(&x) && (26..39).contains(&y)).then_some(want));
        println!("{count} coincident splats: worst channel error {off:.2}");
        assert!(off <= MAX_TILED_CLOSED_FORM_CHANNEL_ERROR, "{count}: off by {off} from {want:?}");
    }
}

#[test]
fn thousands_of_layers_over_one_tile_are_all_composited() {
    // 5000 screen-filling splats at 5000 depths (more than an ε apart), each
    // its own layer of opacity 0.0012 and its own colour: 0.9988^5000 = 0.25%
    // of the background still shows, so every layer counts, and no cap may
    // cut the list. Every tile holds all 5000 splats, more than one
    // invocation sorts (SHORT_LIST), so the workgroup's sort orders them.
    let count = 5000;
    let alpha = 0.0012;
    assert!(count > pointblend::render::tile_engine::SHORT_LIST as usize);
    let mut cloud = PointCloud::default();
    let mut layers = Vec::new();
    for k in 0..count {
        let colour = [(k * 7 % 256) as u8, (k * 13 % 256) as u8, (255 - k % 256) as u8];
        cloud.positions.push(Vec3::new(0.0, 0.0, -(k as f32) * 0.05));
        cloud.normals.push(Vec3::Z);
        cloud.radii.push(400.0);
        cloud.colours.push(colour);
        cloud.opacity.push(alpha);
        layers.push((colour, alpha));
    }
    let mut scene = Scene::from(cloud);
    scene.objects[0].material.two_sided = true;
    let camera = Camera {
        target: Vec3::new(0.0, 0.0, -125.0),
        distance: 130.0,
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        fov_y_deg: 30.0,
        up: pointblend::frame::UpAxis::PosY,
        scene_radius: 130.0,
        projection: Default::default(),
    };
    // ε is in units of the mean radius (400): 0.0001 makes it 0.04, less
    // than the 0.05 between two layers.
    let settings = RenderSettings { epsilon_scale: 0.0001, ..settings(false) };
    let want = composite(&layers);
    let (image, _) = render(&scene, &camera, &settings, 64);
    let off = worst(&image, |_, _| Some(want));
    let (reference, counts) = exact(&scene, &camera, &settings, 64);
    assert!(counts.iter().all(|&c| c == count as u32), "the reference meets every layer");
    println!("{count} layers: worst channel error {off:.2} (want {want:?})");
    assert!(off <= MAX_TILED_CLOSED_FORM_CHANNEL_ERROR, "off by {off} from {want:?}");
    let error = reference::compare(&image, &reference).unwrap();
    assert!(error.eps <= MAX_TILED_EPS, "against the reference: ε {}", error.eps);
}

#[test]
fn a_closed_sphere_shows_two_layers_from_outside_and_one_from_inside() {
    let colour = [60, 160, 220];
    let alpha = 0.4;
    let mut object = Scene::from(primitives::sphere(20_000, 1.0, Vec3::ZERO)).objects.remove(0);
    object.material = Material { colour: Some(colour), ..Material::with_opacity(alpha) };
    let scene = Scene { objects: vec![object], ..Default::default() };
    let outside = Camera { target: Vec3::ZERO, distance: 4.0, ..Camera::default_for(&scene.flattened(), 1.0) };
    let inside = Camera { distance: 0.3, elevation_deg: 20.0, azimuth_deg: 30.0, ..outside };
    // Unlit, a pixel whose ray meets the front and the back of the shell is
    // the closed form of two layers; lit, the reference is the ruler.
    let two = composite(&[(colour, alpha), (colour, alpha)]);
    let size = 96;
    let (image, _) = render(&scene, &outside, &settings(false), size);
    let (_, counts) = exact(&scene, &outside, &settings(false), size);
    let twos = counts.iter().filter(|&&c| c == 2).count();
    assert!(twos > (size * size / 4) as usize, "most of the disc is two layers: {twos}");
    let off = worst(&image, |x, y| (counts[(y * size + x) as usize] == 2).then_some(two));
    println!("sphere from outside: {twos} two-layer pixels, worst channel error {off:.2}");
    assert!(off <= MAX_TILED_CLOSED_FORM_CHANNEL_ERROR, "off by {off} from {two:?}");
    for (what, camera) in [("outside", outside), ("inside", inside)] {
        let (image, _) = render(&scene, &camera, &settings(true), size);
        let (want, counts) = exact(&scene, &camera, &settings(true), size);
        if what == "inside" {
            assert!(counts.iter().all(|&c| c == 1), "from inside every ray meets the shell once");
        }
        let error = reference::compare(&image, &want).unwrap();
        println!("sphere, lit, from {what}: ε {:.4}", error.eps);
        assert!(error.eps <= MAX_TILED_EPS, "from {what}: ε {}", error.eps);
    }
}

#[test]
fn edge_on_planes_and_a_floor_through_the_near_plane_match_the_reference() {
    // Planes seen exactly edge-on are drawn as slivers (the footprint is
    // tilted to the foreshortening bound, as in the reference), and a floor
    // whose splats cross the near plane keeps the part in front of it.
    let edge_on = planes(&[(0.0, [200, 200, 40], 0.5), (1.0, [40, 200, 200], 0.5)], Vec3::X);
    let camera = common::looking_down_z();
    let (floor, floor_camera) = common::floor_crossing_the_near_plane();
    let mut floor = Scene::from(floor);
    floor.set_opacity(0.6);
    for (what, scene, camera) in [("edge-on planes", edge_on, camera), ("floor", floor, floor_camera)] {
        for lighting in [false, true] {
            let (image, _) = render(&scene, &camera, &settings(lighting), 96);
            assert!(image.pixels().any(|p| p.0[..3] != common::background_rgb()), "{what}: something is drawn");
            let (want, _) = exact(&scene, &camera, &settings(lighting), 96);
            let error = reference::compare(&image, &want).unwrap();
            println!("{what}, lit {lighting}: ε {:.4}, bad pixels {:.4}%", error.eps, 100.0 * error.bad_pixel_share);
            assert!(error.eps <= MAX_TILED_EPS, "{what}: ε {}", error.eps);
        }
    }
}

/// Two translucent sheets of large, dense splats (radius 5 spacings), 1.6 ε
/// apart, each splat's depth jittered by up to ±0.45 ε, seen at a grazing
/// and a steep angle: dozens of discs wait on each pixel at once, more than
/// its window holds. Released early, a hit that is not the nearest would
/// open the front layer too deep, and its reach would swallow the sheet
/// behind. Such pixels are finished a layer at a time and must match the reference
/// as exactly as the rest.
#[test]
fn pixels_whose_window_overflows_are_still_exact() {
    let (n, half) = (50, 2.0f32);
    let spacing = 2.0 * half / n as f32;
    let radius = 5.0 * spacing;
    let epsilon = radius; // ε = epsilon_scale (1) × the mean radius
    let mut jitter = 0x2545_f491_4f6c_dd1du64;
    let mut cloud = PointCloud::default();
    for (sheet, colour) in [(0.0, [230, 90, 40]), (1.6 * epsilon, [40, 120, 230])] {
        for i in 0..=n {
            for j in 0..=n {
                jitter ^= jitter << 13;
                jitter ^= jitter >> 7;
                jitter ^= jitter << 17;
                let offset = ((jitter >> 40) as f32 / (1u64 << 24) as f32 - 0.5) * 0.9 * epsilon;
                cloud.positions.push(Vec3::new(-half + i as f32 * spacing, sheet + offset, -half + j as f32 * spacing));
                cloud.normals.push(Vec3::Y);
                cloud.radii.push(radius);
                cloud.colours.push(colour);
                cloud.opacity.push(0.5);
            }
        }
    }
    let mut scene = Scene::from(cloud);
    scene.objects[0].material.two_sided = true;
    for (view, elevation) in [("grazing", 12.0), ("steep", 60.0)] {
        let (error, overflows) = against_reference(&scene, (30.0, elevation), 128);
        println!(
            "dense sheets, {view}: ε {:.4}, bad pixels {:.4}%, {overflows} window overflows",
            error.eps,
            100.0 * error.bad_pixel_share
        );
        assert!(overflows > 100, "{view}: the case overflows windows ({overflows} pixels)");
        assert!(error.eps <= MAX_TILED_EPS, "{view}: ε {}", error.eps);
        assert!(error.bad_pixel_share <= MAX_TILED_BAD_PIXELS, "{view}: bad pixels {}", error.bad_pixel_share);
    }
}

/// The raster reads its lists a subgroup at a time where the device has
/// subgroup operations, else each pixel on its own: both release the same
/// hits in the same order, so they give the same image, bit for bit, on the
/// bundled lion (opaque and transparent) and on mesh triangles.
#[test]
fn reading_lists_by_subgroup_or_by_pixel_gives_the_same_image() {
    let assets = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets");
    let lion = Scene::from(common::thinned_lion(2));
    let mut glass_lion = lion.clone();
    glass_lion.set_opacity(0.5);
    let knot = pointblend::scene::open(&assets.join("glass-mesh.toml"), &Default::default()).unwrap().0;
    let mut renderer = common::renderer();
    if !renderer.use_subgroups(true) {
        println!("this device has no subgroup operations: only one way to read the lists");
        return;
    }
    for (what, scene) in [("lion", lion), ("lion at 0.5", glass_lion), ("glass knot and lion", knot)] {
        let flat = scene.flattened();
        let camera = Camera::default_for(&flat, 1.0);
        let mut gpu = renderer.upload(&scene, None);
        renderer.use_subgroups(false);
        let by_pixel = renderer.render_image(&mut gpu, &camera, &settings(true), 96, 96);
        renderer.use_subgroups(true);
        let by_subgroup = renderer.render_image(&mut gpu, &camera, &settings(true), 96, 96);
        let (by_pixel, by_subgroup) = (by_pixel.expect("render").0, by_subgroup.expect("render").0);
        let differing = by_subgroup.pixels().zip(by_pixel.pixels()).filter(|(a, b)| a != b).count();
        assert!(by_subgroup.pixels().any(|p| p.0[..3] != common::background_rgb()), "{what}: something is drawn");
        assert_eq!(differing, 0, "{what}: {differing} pixels differ between the two ways of reading the lists");
    }
}

#[test]
fn the_bundled_lion_matches_the_reference_opaque_and_transparent_in_three_views() {
    let (cloud, _) = cloud::load(&common::bundled_model()).unwrap();
    for opacity in [1.0, 0.5] {
        let mut scene = Scene::from(cloud.clone());
        scene.set_opacity(opacity);
        for (azimuth, elevation) in [(0.0, 0.0), (90.0, 20.0), (200.0, -30.0)] {
            let (error, early) = against_reference(&scene, (azimuth, elevation), 160);
            println!(
                "lion at {opacity}, view ({azimuth}, {elevation}): ε {:.4}, bad pixels {:.4}%, {early} window overflows",
                error.eps,
                100.0 * error.bad_pixel_share
            );
            assert!(error.eps <= MAX_TILED_EPS, "opacity {opacity}, view ({azimuth}, {elevation}): ε {}", error.eps);
            assert!(error.bad_pixel_share <= MAX_TILED_BAD_PIXELS, "bad pixels {}", error.bad_pixel_share);
        }
    }
}

#[test]
fn the_glass_lion_reflects_and_refracts_as_the_reference_does() {
    let scene = pointblend::scene::open(&common::asset("glass.toml"), &Default::default()).unwrap().0;
    let camera = Camera::default_for(&scene.flattened(), 1.0);
    for layers in ["single", "multi"] {
        let mut settings = settings(true);
        settings.environment.layer_effects = layers.parse().unwrap();
        let (image, _) = render(&scene, &camera, &settings, 128);
        let (want, _) = exact(&scene, &camera, &settings, 128);
        let error = reference::compare(&image, &want).unwrap();
        println!("glass lion, {layers}-layer effects: ε {:.4}", error.eps);
        assert!(error.eps <= MAX_TILED_ENVIRONMENT_EPS, "{layers}: ε {}", error.eps);
    }
}

#[test]
fn an_opaque_scene_runs_the_tile_pipeline_and_the_plan_states_its_memory() {
    let (cloud, _) = cloud::load(&common::bundled_model()).unwrap();
    let scene = Scene::from(cloud);
    let camera = Camera::default_for(&scene.flattened(), 1.0);
    let mut renderer = common::renderer();
    let mut gpu = renderer.upload(&scene, None);
    let spec = resolve(&settings(true), &gpu.facts(), &View::still((96, 96)));
    let (_, plan, report) = renderer.render_spec(&mut gpu, &camera, &spec, true).unwrap();
    let text = format!("{plan}{report}");
    assert!(plan.compute_passes() == 4 && !text.contains("two-pass plan"), "{text}");
    let engine = renderer.renderer.tile_engine().unwrap();
    let entries = engine.last.entries;
    assert!(entries >= scene.len() as u64 / 2, "most splats are binned: {entries}");
    assert!(engine.entry_capacity() >= entries, "room for every entry");
    let lists = report.tile_lists.expect("the report states the tile lists");
    let stated = lists.buffers.iter().find(|b| b.name == "tile entries").unwrap().bytes;
    assert_eq!(stated, engine.entry_capacity() * pointblend::render::tile_engine::ENTRY_BYTES, "{text}");
    let reported: u64 = lists.buffers.iter().map(|b| b.bytes).sum();
    assert!(engine.bytes() <= reported + (1 << 16), "the report states what the engine holds: {text}");
    assert!(text.contains("GPU memory of the frame"), "{text}");
}
