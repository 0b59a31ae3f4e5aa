//! Picking and measuring (crates/core/src/reference/pick.rs,
//! crates/core/src/inspect): a pick lands within one radius of the splat
//! under the pixel and reads its attributes; three transparent planes list
//! three layers and opaque ones one; measured distances, angles and heights
//! match the closed forms of a plane and a sphere; and the `pick` and
//! `measure` commands print the same answers as JSON.

mod common;

use glam::{DVec3, Vec2, Vec3, Vec4Swizzles};
use pointblend::cloud::{PointCloud, Values};
use pointblend::frame::{Camera, RenderSettings};
use pointblend::inspect::{PickReport, measure};
use pointblend::reference::{ReferenceOptions, pick::pick};
use pointblend::scene::{Scene, primitives};

const SIZE: u32 = 128;

fn options(scene: &Scene) -> ReferenceOptions {
    let settings = RenderSettings { mode: "reference".parse().unwrap(), ..Default::default() };
    ReferenceOptions::matching(&settings, scene)
}

/// The pixel whose square holds the world point `p`.
fn pixel_of(camera: &Camera, p: Vec3) -> (u32, u32) {
    let clip = camera.projection(1.0) * camera.view_matrix() * p.extend(1.0);
    let ndc = clip.xy() / clip.w;
    (((ndc.x + 1.0) * 0.5 * SIZE as f32) as u32, ((1.0 - ndc.y) * 0.5 * SIZE as f32) as u32)
}

/// The world ray through the centre of pixel (x, y): origin and unit direction.
fn pixel_ray(camera: &Camera, (x, y): (u32, u32)) -> (DVec3, DVec3) {
    let tan_y = (camera.fov_y_deg.to_radians() * 0.5).tan();
    let ndc = Vec2::new((x as f32 + 0.5) / SIZE as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / SIZE as f32 * 2.0);
    let eye_dir = (ndc * tan_y).extend(-1.0);
    let to_world = camera.view_matrix().inverse();
    let origin = to_world.transform_point3(Vec3::ZERO).as_dvec3();
    (origin, to_world.transform_vector3(eye_dir).as_dvec3().normalize())
}

/// Five discs apart from one another, with an intensity each.
fn five_discs() -> Scene {
    let positions = vec![
        Vec3::ZERO,
        Vec3::new(0.8, 0.5, 0.0),
        Vec3::new(-0.9, 0.4, 0.2),
        Vec3::new(0.3, -0.8, -0.3),
        Vec3::new(-0.6, -0.6, 0.1),
    ];
    let mut cloud = PointCloud::facing_z(positions, 0.15, [200, 100, 50]);
    cloud.attributes.push("intensity", Values::U16((0..cloud.len() as u16).map(|k| 1000 + k).collect()));
    Scene::from(cloud)
}

#[test]
fn a_pick_lands_within_one_radius_of_the_splat_under_the_pixel_and_reads_its_attributes() {
    let scene = five_discs();
    let camera = common::looking_down_z();
    let cloud = scene.flattened();
    for (i, centre) in cloud.positions.iter().enumerate() {
        let pixel = pixel_of(&camera, *centre);
        let layers = pick(&scene, &camera, &options(&scene), (SIZE, SIZE), pixel);
        assert_eq!(layers.len(), 1, "splat {i}: an opaque disc is one layer");
        let layer = &layers[0];
        assert_eq!(layer.splats, vec![i as u32], "splat {i} is the one picked");
        let off = layer.position.distance(centre.as_dvec3());
        assert!(off < cloud.radii[i] as f64, "splat {i}: picked {} is {off} from its centre", layer.position);
        assert!((layer.radius - 0.15).abs() < 1e-6 && layer.colour == [200, 100, 50] && layer.opacity == 1.0);
        assert!(layer.normal.distance(Vec3::Z) < 1e-5, "{}", layer.normal);
        let report = PickReport::new([pixel.0, pixel.1], layers, &cloud);
        assert_eq!(report.attributes[0], vec![("intensity".to_string(), 1000.0 + i as f64)]);
        assert_eq!(report.json()["layers"][0]["attributes"]["intensity"], 1000.0 + i as f64);
    }
    let empty = pick(&scene, &camera, &options(&scene), (SIZE, SIZE), (0, 0));
    assert!(empty.is_empty(), "a corner pixel meets nothing");
}

/// Planes facing +z at `zs`, of opacity `opacity`, two-sided, 2 wide.
fn planes(zs: &[f32], opacity: f32) -> Scene {
    let mut cloud = PointCloud::default();
    for &z in zs {
        let p = primitives::plane(2_000, 2.0, Vec3::new(0.0, 0.0, z), Vec3::Z);
        cloud.positions.extend(&p.positions);
        cloud.normals.extend(&p.normals);
        cloud.radii.extend(&p.radii);
        cloud.colours.extend(&p.colours);
        cloud.opacity.extend(std::iter::repeat_n(opacity, p.len()));
    }
    let mut scene = Scene::from(cloud);
    scene.objects[0].material.two_sided = opacity < 1.0;
    scene
}

#[test]
fn three_transparent_planes_list_three_layers_and_opaque_ones_one() {
    let camera = common::looking_down_z();
    let zs = [0.6, 0.0, -0.6];
    let pixel = (SIZE / 2 + 3, SIZE / 2 - 5);
    let (origin, dir) = pixel_ray(&camera, pixel);
    let see_through = planes(&zs, 0.5);
    let layers = pick(&see_through, &camera, &options(&see_through), (SIZE, SIZE), pixel);
    assert_eq!(layers.len(), 3, "{layers:?}");
    for (layer, z) in layers.iter().zip(zs) {
        // The closed form: where the pixel's ray meets the plane z.
        let exact = origin + dir * ((z as f64 - origin.z) / dir.z);
        assert!(layer.position.distance(exact) < 1e-4, "the layer at z = {z}: {} against {exact}", layer.position);
        assert!((layer.opacity - 0.5).abs() < 1e-6);
    }
    assert!(layers.windows(2).all(|w| w[0].depth < w[1].depth), "nearest first");
    let opaque = planes(&zs, 1.0);
    let layers = pick(&opaque, &camera, &options(&opaque), (SIZE, SIZE), pixel);
    assert_eq!(layers.len(), 1, "an opaque layer ends the ray");
    assert!((layers[0].position.z - 0.6).abs() < 1e-4);
}

#[test]
fn distances_angles_and_heights_match_a_plane_and_a_sphere() {
    let camera = Camera { elevation_deg: 35.0, azimuth_deg: 20.0, ..common::looking_down_z() };
    // A floor y = -0.5 seen from above at an angle: three picks on it.
    let floor = Scene::from(primitives::plane(40_000, 4.0, Vec3::new(0.0, -0.5, 0.0), Vec3::Y));
    let pixels = [(40, 90), (70, 100), (100, 60)];
    let exact: Vec<DVec3> = pixels
        .iter()
        .map(|&p| {
            let (o, d) = pixel_ray(&camera, p);
            o + d * ((-0.5 - o.y) / d.y)
        })
        .collect();
    let picked: Vec<DVec3> =
        pixels.iter().map(|&p| pick(&floor, &camera, &options(&floor), (SIZE, SIZE), p)[0].position).collect();
    let m = measure(&picked, DVec3::Y);
    let want = measure(&exact, DVec3::Y);
    assert!((m.distance - want.distance).abs() < 1e-4, "polyline {} against {}", m.distance, want.distance);
    assert!(
        (m.angles_deg[0] - want.angles_deg[0]).abs() < 0.01,
        "angle {} against {}",
        m.angles_deg[0],
        want.angles_deg[0]
    );
    assert!(m.height.abs() < 1e-4, "a floor has no height difference: {}", m.height);
    // The closed form of the angle itself, from the vectors between the exact points.
    let (a, b) = (exact[0] - exact[1], exact[2] - exact[1]);
    let cos = a.dot(b) / (a.length() * b.length());
    assert!((want.angles_deg[0] - cos.acos().to_degrees()).abs() < 1e-9);

    // A sphere of radius 1: the picked point lies on it (within the tangent
    // discs' bulge), and two picks are as far apart as the ray-sphere hits.
    let ball = Scene::from(primitives::sphere(60_000, 1.0, Vec3::ZERO));
    let r_splat = ball.flattened().radii[0] as f64;
    let hits: Vec<(DVec3, DVec3)> = [(64, 64), (50, 40), (80, 85)]
        .iter()
        .map(|&p| {
            let (o, d) = pixel_ray(&camera, p);
            let b = o.dot(d);
            let t = -b - (b * b - (o.length_squared() - 1.0)).sqrt();
            (pick(&ball, &camera, &options(&ball), (SIZE, SIZE), p)[0].position, o + d * t)
        })
        .collect();
    for (got, want) in &hits {
        assert!(got.distance(*want) < r_splat, "picked {got} against the sphere's {want}");
        assert!((got.length() - 1.0).abs() < r_splat * r_splat, "|p| = {}", got.length());
    }
    let got = measure(&[hits[1].0, hits[2].0], DVec3::Y);
    let want = measure(&[hits[1].1, hits[2].1], DVec3::Y);
    assert!((got.distance - want.distance).abs() < 2.0 * r_splat, "{} against {}", got.distance, want.distance);
    assert!((got.height - want.height).abs() < 2.0 * r_splat, "height {} against {}", got.height, want.height);
}

fn run_json(args: &[&str]) -> serde_json::Value {
    let out =
        std::process::Command::new(env!("CARGO_BIN_EXE_pointblend")).args(args).output().expect("pointblend runs");
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("JSON")
}

#[test]
fn the_commands_print_the_layers_and_the_measurement_as_json() {
    let lion = common::bundled_model().display().to_string();
    let view = ["--size", "128x128", "--azimuth", "30"];
    let mut args = vec!["pick", lion.as_str(), "--at", "60,50", "--json"];
    args.extend(view);
    let one = run_json(&args);
    assert_eq!(one["pixel"], serde_json::json!([60, 50]));
    let layers = one["layers"].as_array().unwrap();
    assert_eq!(layers.len(), 1, "the lion is opaque");
    for key in ["depth", "position", "splats", "normal", "radius", "colour", "opacity", "attributes"] {
        assert!(layers[0].get(key).is_some(), "{key} is missing: {}", layers[0]);
    }
    // A translucent ball: each ray through it passes two layers.
    let dir = tempfile::tempdir().unwrap();
    let ball = dir.path().join("ball.toml");
    std::fs::write(
        &ball,
        "[[object]]\nsphere = { splats = 20000, radius = 1.0, centre = [0.0, 0.0, 0.0] }\nopacity = 0.5\n",
    )
    .unwrap();
    let ball = ball.display().to_string();
    let mut args = vec!["pick", ball.as_str(), "--at", "60,50", "--at", "70,90", "--json"];
    args.extend(view);
    let two = run_json(&args);
    let see_through = two.as_array().unwrap();
    assert_eq!(see_through.len(), 2, "one report per pixel");
    assert!(
        see_through.iter().all(|r| r["layers"].as_array().unwrap().len() == 2),
        "a translucent ball has two layers: {two}"
    );
    let position = |r: &serde_json::Value| {
        DVec3::from_slice(
            &r["layers"][0]["position"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect::<Vec<_>>(),
        )
    };
    let mut args = vec!["measure", ball.as_str(), "--at", "60,50", "--at", "70,90", "--json"];
    args.extend(view);
    let m = run_json(&args);
    let want = position(&see_through[0]).distance(position(&see_through[1]));
    assert!((m["distance"].as_f64().unwrap() - want).abs() < 1e-9, "{m} against {want}");
    assert_eq!(m["points"][1]["pixel"], serde_json::json!([70, 90]));
    assert!(m["angle_deg"].is_null(), "two points have no angle");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_pointblend"))
        .args(["measure", lion.as_str(), "--at", "0,0", "--at", "60,50", "--size", "128x128"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success() && stderr.contains("pixel 0,0 shows no surface"), "{stderr}");
}
