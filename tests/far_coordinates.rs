//! Picks and measures keep the file's millimetres at any extent: on a
//! generated LAS file 100 km wide (a plane z = 3x, in UTM-like coordinates,
//! with pairs of points 1 mm apart at both ends), `pick` reports the stored
//! position of the splat it hit exactly as the file holds it, and `measure`
//! gives hit points within 0.5 mm of the exact ray-plane intersections
//! (computed here in f64 from the camera's own values) and their distance
//! within 0.1 mm. f32 positions alone are 4 mm coarse 50 km from the centre.

mod common;

use common::lidar::{LidarPoint, write};
use glam::{DVec3, Vec3, Vec4Swizzles};
use pointblend::frame::{Camera, CameraRequest};

const WIDTH: u32 = 256;
const HEIGHT: u32 = 128;
/// The plane z = 3x about this corner, in metres (the file's scale is 0.001).
const CORNER: [f64; 3] = [500_000.0, 4_000_000.0, 0.0];
const LENGTH: f64 = 100_000.0;

fn point(xyz: [f64; 3]) -> LidarPoint {
    LidarPoint { xyz, intensity: 0, class: 2, return_number: 1, returns: 1, gps_time: 0.0, rgb: [0; 3] }
}

/// The plane's points every 100 m along x and 250 m along y, 2 km across, each moved by a few
/// millimetres (so that f32 holds none of them), and a point 1 mm beside
/// each end's middle one.
fn plane_points() -> Vec<LidarPoint> {
    let at = |x: f64, y: f64| point([CORNER[0] + x, CORNER[1] + y, CORNER[2] + 3.0 * x]);
    let mut points = Vec::new();
    for i in 0..=(LENGTH / 100.0) as usize {
        for j in 0..=8 {
            let jitter = |k: usize, m: usize| (k % m) as f64 * 0.001;
            points.push(at(i as f64 * 100.0 + jitter(i + j, 7), j as f64 * 250.0 + jitter(i, 5)));
        }
    }
    points.push(at(0.001, 1000.0));
    points.push(at(LENGTH - 0.001, 1000.0));
    points
}

/// The pixel whose square holds the frame point `p`.
fn pixel_of(camera: &Camera, p: Vec3) -> (u32, u32) {
    let clip = camera.projection(WIDTH as f32 / HEIGHT as f32) * camera.view_matrix() * p.extend(1.0);
    let ndc = clip.xy() / clip.w;
    (((ndc.x + 1.0) * 0.5 * WIDTH as f32) as u32, ((1.0 - ndc.y) * 0.5 * HEIGHT as f32) as u32)
}

/// Where the ray through pixel (x, y) meets the plane z = 3x (file
/// coordinates), computed here in f64: the eye and axes from the camera's
/// azimuth, elevation, distance and target, the plane in closed form.
fn exact_hit(camera: &Camera, origin: DVec3, (x, y): (u32, u32)) -> DVec3 {
    let (up, front) = camera.up.frame();
    let (up, front) = (up.as_dvec3(), front.as_dvec3());
    let right = up.cross(front);
    let (az, el) = ((camera.azimuth_deg as f64).to_radians(), (camera.elevation_deg as f64).to_radians());
    let back = (right * az.sin() * el.cos() + front * az.cos() * el.cos() + up * el.sin()).normalize();
    let eye = camera.target.as_dvec3() + back * camera.distance as f64 + origin;
    let forward = -back;
    let side = forward.cross(up).normalize();
    let top = side.cross(forward);
    let tan_y = ((camera.fov_y_deg as f64).to_radians() * 0.5).tan();
    let aspect = WIDTH as f64 / HEIGHT as f64;
    let ndc_x = (x as f64 + 0.5) / WIDTH as f64 * 2.0 - 1.0;
    let ndc_y = 1.0 - (y as f64 + 0.5) / HEIGHT as f64 * 2.0;
    let direction = forward + side * (ndc_x * tan_y * aspect) + top * (ndc_y * tan_y);
    // (eye + t d)·(3, 0, -1) = c, the plane z - CORNER.z = 3 (x - CORNER.x).
    let normal = DVec3::new(3.0, 0.0, -1.0);
    let c = 3.0 * CORNER[0] - CORNER[2];
    let t = (c - eye.dot(normal)) / direction.dot(normal);
    eye + direction * t
}

fn run_json(args: &[&str]) -> serde_json::Value {
    let out =
        std::process::Command::new(env!("CARGO_BIN_EXE_pointblend")).args(args).output().expect("pointblend runs");
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    serde_json::from_slice(&out.stdout).expect("JSON")
}

fn vector(value: &serde_json::Value) -> DVec3 {
    let v: Vec<f64> = value.as_array().unwrap().iter().map(|c| c.as_f64().unwrap()).collect();
    DVec3::new(v[0], v[1], v[2])
}

#[test]
fn picks_and_measures_keep_the_files_millimetres_100_km_from_one_another() {
    let dir = tempfile::tempdir().unwrap();
    let points = plane_points();
    let file = write(&dir.path().join("wide.las"), &points, CORNER, None);
    // The camera the commands make: the scene as `pick` opens it, framed from
    // the side the plane faces.
    let (scene, _) = pointblend::scene::open(&file, &Default::default()).unwrap();
    let flat = scene.flatten();
    assert_eq!(flat.cloud.len(), points.len(), "points 1 mm apart stay two splats, however far out");
    let origin = DVec3::from_array(flat.cloud.origin);
    let asked = CameraRequest { azimuth: Some(-60.0), ..Default::default() };
    let camera = asked.camera(&flat.cloud, WIDTH as f32 / HEIGHT as f32).unwrap();
    let frame = |p: [f64; 3]| (DVec3::from_array(p) - origin).as_vec3();
    // Pixels on the plane near both ends, where f32 positions are 4 mm coarse.
    let on_plane = |x: f64| frame([CORNER[0] + x, CORNER[1] + 1000.0, CORNER[2] + 3.0 * x]);
    // Pixels on the plane from one end to the other, where f32 positions are up to 16 mm coarse.
    let pixels: Vec<(u32, u32)> = (0..8).map(|k| pixel_of(&camera, on_plane(2000.0 + k as f64 * 13_700.0))).collect();
    let file_arg = file.display().to_string();
    let common = ["--size", "256x128", "--azimuth", "-60", "--json"];
    let mut args = vec!["measure".to_string(), file_arg.clone()];
    for (x, y) in &pixels {
        args.extend(["--at".to_string(), format!("{x},{y}")]);
    }
    args.extend(common.iter().map(|a| a.to_string()));
    let measured = run_json(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let hits: Vec<DVec3> = measured["points"].as_array().unwrap().iter().map(|p| vector(&p["position"])).collect();
    let exact: Vec<DVec3> = pixels.iter().map(|p| exact_hit(&camera, origin, *p)).collect();
    for (hit, want) in hits.iter().zip(&exact) {
        let off = hit.distance(*want);
        println!("hit {hit:?}, exact {want:?}: {:.4} mm", off * 1e3);
        assert!(off < 0.5e-3, "a hit point {:.3} mm from the exact ray-plane point", off * 1e3);
    }
    let distance = measured["distance"].as_f64().unwrap();
    let want: f64 = exact.windows(2).map(|w| w[0].distance(w[1])).sum();
    println!("measured {distance:.6} m, exact {want:.6} m");
    assert!(want > 90_000.0 && (distance - want).abs() < 0.1e-3, "{distance} against {want}");
    // Each picked layer names its splat's stored position exactly as the
    // file holds it: whole millimetres, and one of the file's points.
    for end in [300.0, LENGTH - 300.0] {
        let (x, y) = pixel_of(&camera, on_plane(end));
        let picked = run_json(&[&["pick", file_arg.as_str(), "--at", &format!("{x},{y}")], &common[..]].concat());
        let stored = vector(&picked["layers"][0]["stored_position"]);
        let in_file = points.iter().any(|p| DVec3::from_array(p.xyz).distance(stored) < 1e-7);
        println!("pixel {x},{y}: stored at {stored:?}");
        assert!(in_file, "the stored position {stored:?} is none of the file's points");
        let millimetres = stored * 1e3;
        assert!((millimetres - millimetres.round()).abs().max_element() < 1e-4, "{stored:?} is not the file's");
    }
}
