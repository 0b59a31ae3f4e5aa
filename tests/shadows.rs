//! Scene lights and translucent shadows (Gunjee et al. §4.1): the shadow
//! coefficients of TSM and of exact shadow rays against closed forms (one
//! and two translucent planes, an opaque one, a light inside a closed
//! translucent sphere), the same light in the images of the reference and
//! of GPU modes, stiff cases (a light on a splat, a light 10⁶ radii away,
//! 10,000 coincident splats, a 1×1 table, no lights) and bad input.

mod common;

use common::tolerances::*;
use glam::{Vec3, Vec4Swizzles};
use pointblend::cloud::PointCloud;
use pointblend::frame::{Camera, Light, Lights, RenderSettings, Shading, ShadowMethod};
use pointblend::render::{PreparedScene, RenderMode};
use pointblend::scene::{Scene, SceneObject, primitives};
use pointblend::shadow::{self, ShadowInput};
use std::sync::Arc;

/// The floor: z = 0, facing +z (towards `common::looking_down_z`), 4 wide.
fn floor() -> PointCloud {
    primitives::plane(20_000, 4.0, Vec3::ZERO, Vec3::Z)
}

/// A translucent square 0.4 wide, facing +z, centred at (-1.2, 0, z).
fn square(z: f32, opacity: f32) -> PointCloud {
    let mut p = primitives::plane(2_500, 0.4, Vec3::new(-1.2, 0.0, z), Vec3::Z);
    p.opacity.fill(opacity);
    p.colours.fill([90, 150, 230]);
    p
}

/// The light the squares shadow the floor from: their shadows overlap on
/// x in [-0.5, 0], y in [-0.4, 0.4], which the camera sees past them.
const LIGHT: Vec3 = Vec3::new(-2.0, 0.0, 2.0);

/// Floor points surely inside every square's shadow, and surely outside any.
fn in_shadow(p: Vec3) -> bool {
    p.z == 0.0 && (-0.4..=-0.1).contains(&p.x) && p.y.abs() <= 0.25
}
fn in_light(p: Vec3) -> bool {
    p.z == 0.0 && p.x >= 0.6 && p.x <= 1.2 && p.y.abs() <= 0.5
}

/// The floor and `squares` (their z and opacity), as one scene.
fn scene(squares: &[(f32, f32)]) -> Scene {
    let mut parts = vec![floor()];
    parts.extend(squares.iter().map(|&(z, a)| square(z, a)));
    let mut scene = Scene::from(parts.remove(0));
    for (k, part) in parts.into_iter().enumerate() {
        let mut object: SceneObject = Scene::from(part).objects.remove(0);
        object.name = format!("square {k}");
        object.material.two_sided = object.cloud.opacity[0] < 1.0;
        scene.objects.push(object);
    }
    scene
}

fn lit(mode: &str, method: ShadowMethod, light: Vec3) -> RenderSettings {
    let mut settings = RenderSettings {
        mode: mode.parse().unwrap(),
        lights: Lights::new(&[Light::point(light)]).unwrap(),
        // No highlight: the closed form is ambient + diffuse · T · cos.
        shading: Shading { specular: 0.0, ..Shading::default() },
        ..Default::default()
    };
    settings.shadows.method = method;
    settings
}

/// The coefficients of `cloud`'s splats for one light, read with opacity.
fn coefficients(cloud: &PointCloud, light: Light, method: ShadowMethod, cells: [u32; 2]) -> Vec<f32> {
    let settings = RenderSettings::default();
    let input = ShadowInput::new(cloud, &settings, true);
    let c = shadow::coefficients(&input, &[light], method, cells).expect("coefficients");
    c.per_light.into_iter().next().unwrap()
}

/// The worst |coefficient - want| over the floor splats where `region` holds.
fn worst(scene: &Scene, t: &[f32], region: fn(Vec3) -> bool, want: f32) -> (f32, usize) {
    let cloud = scene.flattened();
    let picked: Vec<f32> = (0..cloud.len()).filter(|&i| region(cloud.positions[i])).map(|i| t[i]).collect();
    assert!(picked.len() > 50, "the region holds floor splats");
    (picked.iter().map(|v| (v - want).abs()).fold(0.0, f32::max), picked.len())
}

#[test]
fn one_two_and_opaque_planes_pass_one_minus_a_its_square_and_nothing() {
    let a = 0.4;
    for method in [ShadowMethod::Tsm, ShadowMethod::Exact] {
        for (squares, want) in
            [(vec![(1.0, a)], 1.0 - a), (vec![(1.0, a), (1.2, a)], (1.0 - a) * (1.0 - a)), (vec![(1.0, 1.0)], 0.0)]
        {
            let scene = scene(&squares);
            let t = coefficients(&scene.flattened(), Light::point(LIGHT), method, [512, 512]);
            let (shadowed, n) = worst(&scene, &t, in_shadow, want);
            let (unshadowed, _) = worst(&scene, &t, in_light, 1.0);
            assert!(
                shadowed <= MAX_SHADOW_COEFFICIENT_ERROR && unshadowed <= MAX_SHADOW_COEFFICIENT_ERROR,
                "{method:?}, {} square(s): {n} floor splats under them off {want} by up to {shadowed}, lit ones off 1 by {unshadowed}",
                squares.len()
            );
        }
    }
}

#[test]
fn a_light_inside_a_closed_translucent_sphere_passes_one_minus_a_once() {
    let a = 0.4;
    let mut ball = primitives::sphere(8_000, 0.3, Vec3::new(0.0, 0.0, 0.6));
    ball.opacity.fill(a);
    let mut cloud = floor();
    let n_floor = cloud.len();
    cloud.positions.extend(&ball.positions);
    cloud.normals.extend(&ball.normals);
    cloud.radii.extend(&ball.radii);
    cloud.colours.extend(&ball.colours);
    cloud.opacity.extend(&ball.opacity);
    let light = Light::point(Vec3::new(0.0, 0.0, 0.6));
    for method in [ShadowMethod::Tsm, ShadowMethod::Exact] {
        let t = coefficients(&cloud, light, method, [512, 512]);
        let near_floor: Vec<f32> =
            (0..n_floor).filter(|&i| cloud.positions[i].truncate().length() < 1.0).map(|i| t[i]).collect();
        let off = near_floor.iter().map(|v| (v - (1.0 - a)).abs()).fold(0.0, f32::max);
        assert!(
            off <= MAX_SHADOW_COEFFICIENT_ERROR,
            "{method:?}: the floor outside the ball receives 1 - a = {} once; off by up to {off} over {} splats",
            1.0 - a,
            near_floor.len()
        );
    }
}

/// The pixel of world point `p` (inside the image) for `camera` at `size`².
fn pixel_of(camera: &Camera, p: Vec3, size: u32) -> (u32, u32) {
    let clip = camera.projection(1.0) * camera.view_matrix() * p.extend(1.0);
    let ndc = clip.xy() / clip.w;
    (((ndc.x * 0.5 + 0.5) * size as f32) as u32, ((0.5 - ndc.y * 0.5) * size as f32) as u32)
}

/// The closed form of a floor point at `p` (albedo 1 grey as loaded) receiving `t` of the light.
fn closed_form(settings: &RenderSettings, albedo: Vec3, p: Vec3, t: f32) -> Vec3 {
    let l = (LIGHT - p).normalize();
    let s = &settings.shading;
    albedo * (s.ambient + s.diffuse * t * l.z.max(0.0))
}

#[test]
fn the_reference_and_gpu_modes_show_the_closed_form_on_the_floor() {
    let a = 0.4;
    let scene = Arc::new(scene(&[(1.0, a)]));
    let camera = common::looking_down_z();
    let size = 128;
    let albedo = Vec3::from_array(scene.flattened().colours[0].map(|c| c as f32 / 255.0));
    let points = [Vec3::new(-0.25, 0.0, 0.0), Vec3::new(-0.25, 0.15, 0.0), Vec3::new(0.8, 0.0, 0.0)];
    let mut frames = PreparedScene::of(Arc::clone(&scene));
    let mut renderer = common::renderer();
    // Transparent modes see the square as it is; opaque ones draw it opaque.
    for (mode, t_shadow) in [("reference", 1.0 - a), ("tiled", 1.0 - a), ("alg2", 1.0 - a), ("two-pass", 0.0)] {
        for method in [ShadowMethod::Exact, ShadowMethod::Tsm] {
            let settings = lit(mode, method, LIGHT);
            let frame = frames.render(Some(&mut renderer), &camera, &settings, (size, size), false).expect("render");
            for p in points {
                let t = if in_shadow(p) { t_shadow } else { 1.0 };
                let want = closed_form(&settings, albedo, p, t) * 255.0;
                let (x, y) = pixel_of(&camera, p, size);
                let got = frame.image.get_pixel(x, y).0;
                let off = (0..3).map(|c| (got[c] as f32 - want[c]).abs()).fold(0.0, f32::max);
                assert!(
                    off <= MAX_LIT_FLOOR_ERROR_8BIT,
                    "{mode} ({method:?}) at {p}: {got:?} against the closed form {want} (T = {t})"
                );
            }
            if mode != "reference" {
                assert!(frame.plan.variant.contains("lit by scene lights"), "{mode}: {}", frame.plan.variant);
            }
        }
    }
}

#[test]
fn stiff_cases_give_finite_coefficients_and_images() {
    let a = 0.5;
    let base = scene(&[(1.0, a)]);
    let cloud = base.flattened();
    let radius = 2.0f32 * 2f32.sqrt();
    let on_a_splat = Light::point(cloud.positions[cloud.len() / 2]);
    let far_above = Light::point(Vec3::new(0.0, 0.0, 1e6 * radius));
    for (name, light, cells) in [
        ("on a splat", on_a_splat, [512, 512]),
        ("1e6 radii away", far_above, [512, 512]),
        ("1x1 table", Light::point(LIGHT), [1, 1]),
    ] {
        for method in [ShadowMethod::Tsm, ShadowMethod::Exact] {
            let t = coefficients(&cloud, light, method, cells);
            assert!(
                t.iter().all(|v| (0.0..=1.0).contains(v)),
                "{name}, {method:?}: a coefficient is NaN or outside 0..1"
            );
        }
    }
    // Nearly directional, straight down: the floor under the square keeps 1 - a.
    let t = coefficients(&cloud, far_above, ShadowMethod::Tsm, [512, 512]);
    let under = |p: Vec3| p.z == 0.0 && (p.x + 1.2).abs() < 0.15 && p.y.abs() < 0.15;
    let (off, _) = worst(&base, &t, under, 1.0 - a);
    assert!(off <= MAX_SHADOW_COEFFICIENT_ERROR, "a light 1e6 radii above: off 1 - a by {off}");

    // Directional light straight down, tables not square: the same 1 - a under the square.
    let sun = Light::directional(Vec3::new(0.0, 0.0, -1.0));
    for cells in [[128, 512], [512, 128]] {
        let t = coefficients(&cloud, sun, ShadowMethod::Tsm, cells);
        let (off, _) = worst(&base, &t, under, 1.0 - a);
        assert!(off <= MAX_SHADOW_COEFFICIENT_ERROR, "a directional light, {cells:?} cells: off 1 - a by {off}");
    }

    // 10,000 coincident translucent splats are one layer, not 10,000.
    let mut stack = common::coincident(10_000, a, [200, 100, 50]).flattened().as_ref().clone();
    // A probe splat under the stack.
    stack.positions.push(Vec3::new(0.0, 0.0, -1.0));
    stack.normals.push(Vec3::Z);
    stack.radii.push(0.05);
    stack.colours.push([255; 3]);
    stack.opacity.push(1.0);
    stack.two_sided.push(false);
    let last = stack.len() - 1;
    for method in [ShadowMethod::Tsm, ShadowMethod::Exact] {
        let t = coefficients(&stack, Light::point(Vec3::new(0.0, 0.0, 3.0)), method, [256, 256]);
        assert!(
            (t[last] - (1.0 - a)).abs() <= MAX_SHADOW_COEFFICIENT_ERROR,
            "{method:?}: {} behind the stack",
            t[last]
        );
    }

    // Lights on a splat and far away render without failing or a black frame, on the GPU and the reference.
    let scene = Arc::new(base.clone());
    let mut frames = PreparedScene::of(Arc::clone(&scene));
    let mut renderer = common::renderer();
    for light in [on_a_splat, far_above] {
        for mode in ["two-pass", "alg2", "reference"] {
            let settings =
                RenderSettings { lights: Lights::new(&[light]).unwrap(), ..lit(mode, ShadowMethod::Tsm, LIGHT) };
            let frame =
                frames.render(Some(&mut renderer), &common::looking_down_z(), &settings, (64, 64), false).unwrap();
            assert!(frame.image.pixels().any(|p| p.0[..3].iter().any(|&c| c > 40)), "{mode}: a black frame");
        }
    }
}

#[test]
fn no_lights_plan_allocate_and_upload_no_shadow_work() {
    let scene = Arc::new(scene(&[(1.0, 0.5)]));
    let mut frames = PreparedScene::of(Arc::clone(&scene));
    let mut renderer = common::renderer();
    let settings = RenderSettings { mode: RenderMode::DEFAULT, ..Default::default() };
    let frame = frames.render(Some(&mut renderer), &common::looking_down_z(), &settings, (64, 64), false).unwrap();
    assert!(frame.report.shadows.is_empty() && frame.report.shadow_ms.is_none(), "no coefficients were computed");
    let spec = frames.resolve(&settings, pointblend::frame::View::still((64, 64)));
    assert!(frames.gpu_scene(&renderer, &spec).unwrap().light_chunks().is_none(), "no buffer was made");
    assert!(!frame.plan.to_string().contains("light"), "the plan names no lights: {}", frame.plan);
    // With a light, the frame's report states the tables.
    let lit = lit("two-pass", ShadowMethod::Tsm, LIGHT);
    let frame = frames.render(Some(&mut renderer), &common::looking_down_z(), &lit, (64, 64), false).unwrap();
    let text = frame.report.to_string();
    assert!(text.contains("TSM table of light 1: 512x512 cells") && text.contains("MiB"), "{text}");
}
