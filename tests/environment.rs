//! Environment maps (Zhang & Pajarola §5.2.3): the bundled default and the
//! shared maps load, their DWAB residue is cleaned, and bad files give one
//! line naming the file.

mod common;

use std::path::PathBuf;

use glam::Vec3;
use pointblend::scene::environment::EnvironmentMap;

fn bundled() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/venice.exr")
}

#[test]
fn the_bundled_and_shared_maps_load_clean_with_a_full_mip_chain() {
    let mut paths = vec![bundled()];
    paths.extend(["sky.exr", "studio.exr", "venice.exr"].map(|n| common::data(&format!("env/{n}"))));
    for path in paths {
        let map = EnvironmentMap::load(&path).unwrap_or_else(|e| panic!("{e}"));
        println!(
            "{}: {}x{}, {} levels, {} texels cleaned",
            map.name,
            map.width(),
            map.height(),
            map.levels.len(),
            map.cleaned
        );
        assert_eq!((map.width(), map.height()), (512, 256), "{}", path.display());
        // 512x256 halves nine times to 1x1.
        assert_eq!(map.levels.len(), 10);
        for level in &map.levels {
            assert!(level.texels.iter().flatten().all(|v| v.is_finite() && *v >= 0.0), "{}", path.display());
        }
        // Not a black map: the mean of the last level is the map's mean.
        let mean = map.levels.last().unwrap().texels[0];
        assert!(mean.iter().any(|&v| v > 0.05), "{}: mean {mean:?}", path.display());
        let sample = map.sample(Vec3::new(0.3, 0.2, -0.9), (Vec3::Y, Vec3::Z), 2.5);
        assert!(sample.iter().all(|v| v.is_finite()), "{sample:?}");
    }
}

#[test]
fn bad_maps_give_one_line_naming_the_file() {
    let dir = tempfile::Builder::new().prefix("pointblend-env-").tempdir().unwrap();
    let corrupt = dir.path().join("corrupt.exr");
    std::fs::write(&corrupt, b"v/1\x01not an exr at all").unwrap();
    let tiny = dir.path().join("one-pixel.png");
    image::RgbImage::from_pixel(1, 1, image::Rgb([200, 100, 50])).save(&tiny).unwrap();
    let empty = dir.path().join("empty.hdr");
    std::fs::write(&empty, b"").unwrap();
    let missing = dir.path().join("missing.exr");
    for path in [corrupt, tiny, empty, missing] {
        let error = EnvironmentMap::load(&path).expect_err("a bad map");
        let line = error.to_string();
        println!("{line}");
        assert!(line.contains(&*path.file_name().unwrap().to_string_lossy()), "{line}");
        assert!(!line.contains('\n'), "one line: {line}");
    }
}

#[test]
fn an_hdr_map_with_huge_and_zero_values_stays_finite() {
    // A Radiance map with a 1e5 sun and black texels, written by the image
    // crate and read back through the loader.
    let dir = tempfile::Builder::new().prefix("pointblend-env-").tempdir().unwrap();
    let path = dir.path().join("sun.hdr");
    let mut image = image::Rgb32FImage::from_pixel(16, 8, image::Rgb([0.0, 0.0, 0.0]));
    image.put_pixel(3, 2, image::Rgb([1e5, 1e5, 1e5]));
    image.put_pixel(4, 2, image::Rgb([0.5, 0.25, 1.0]));
    image::DynamicImage::ImageRgb32F(image).save(&path).unwrap();
    let map = EnvironmentMap::load(&path).unwrap();
    for level in &map.levels {
        assert!(level.texels.iter().flatten().all(|v| v.is_finite() && *v >= 0.0));
    }
    let sun = map.levels[0].texels[2 * 16 + 3];
    assert!(sun[0] > 50.0 && sun[0] < 1000.0, "the sun encodes large but finite: {sun:?}");
    assert_eq!(map.levels[0].texels[0], [0.0; 3]);
}

/// A plane of splats facing +z at depth `z` (a grid of spacing 0.1 over
/// ±2.2, discs of radius 0.15: no holes), of one colour and opacity.
fn plane(z: f32, colour: [u8; 3], opacity: f32) -> pointblend::cloud::PointCloud {
    let mut cloud = pointblend::cloud::PointCloud::default();
    for i in 0..=44 {
        for j in 0..=44 {
            cloud.positions.push(Vec3::new(-2.2 + i as f32 * 0.1, -2.2 + j as f32 * 0.1, z));
            cloud.normals.push(Vec3::Z);
            cloud.radii.push(0.15);
            cloud.colors.push(colour);
            cloud.opacity.push(opacity);
        }
    }
    cloud
}

fn slab(planes: &[(f32, [u8; 3], f32)], env: [f32; 3]) -> pointblend::scene::Scene {
    let mut cloud = pointblend::cloud::PointCloud::default();
    for &(z, colour, opacity) in planes {
        let p = plane(z, colour, opacity);
        cloud.positions.extend(p.positions);
        cloud.normals.extend(p.normals);
        cloud.radii.extend(p.radii);
        cloud.colors.extend(p.colors);
        cloud.opacity.extend(p.opacity);
    }
    let mut scene = pointblend::scene::Scene::from(cloud);
    scene.objects[0].material.two_sided = true;
    scene.environment = Some(std::sync::Arc::new(EnvironmentMap::constant(env)));
    scene
}

#[test]
fn a_transparent_slab_in_a_constant_environment_matches_the_closed_form() {
    use pointblend::reference::{ReferenceOptions, render_with_layers};
    use pointblend::view::environment::{EnvironmentSettings, LayerEffects};
    use pointblend::view::{Camera, RenderSettings, UpAxis};
    // The camera looks down -z from z = 5 (30° field): every ray meets the
    // planes, at cos θ_I = -d·z of its pixel. In a constant environment E
    // every lookup is E whatever the direction, so per channel
    //   I = F·E + (1 − F)·(α₁c₁ + (1 − α₁)·B),
    // F = F0 + (1 − F0)(1 − cos θ_I)^5, F0 = ((η − 1)/(η + 1))², and B the
    // layers behind over E: α₂c₂ + a·E for a second transparent plane, with
    // a its exact transmittance 1 − α₂ (single-layer) or Eq. 15's absorption
    // (1 − α₁)^l with l = 1 layer behind and the nearest layer's α₁
    // (multi-layer: the paper assumes one opacity throughout); c₂ for an
    // opaque plane (E is not seen). Bound: the colours are exact, the normal is
    // exactly +z, so only the final 8-bit rounding (0.5) remains: 0.5/255
    // per channel, within 1 unit.
    let camera = Camera {
        target: Vec3::ZERO,
        distance: 5.0,
        azimuth_deg: 0.0,
        elevation_deg: 0.0,
        fov_y_deg: 30.0,
        up: UpAxis::PosY,
        scene_radius: 3.0,
    };
    let env = [0.2, 0.7, 0.9];
    let (red, blue) = ([240u8, 40, 30], [30u8, 60, 230]);
    let size = 48u32;
    let tan = (15f32).to_radians().tan();
    for layers in [LayerEffects::Single, LayerEffects::Multi] {
        for (behind_opacity, what) in [(0.6, "two transparent planes"), (1.0, "transparent over opaque")] {
            let scene = slab(&[(0.5, red, 0.5), (0.0, blue, behind_opacity)], env);
            let settings = RenderSettings {
                mode: "reference".parse().unwrap(),
                lighting: false,
                environment: EnvironmentSettings { eta: 1.5, dispersion: 0.0, layers, skybox: true },
                ..Default::default()
            };
            let options = ReferenceOptions::matching(&settings, &scene);
            let (image, _) = render_with_layers(&scene, &camera, &options, size, size);
            let f0 = (0.5f32 / 2.5).powi(2);
            let mut worst = 0.0f32;
            for (x, y, p) in image.enumerate_pixels() {
                let ndc = [(x as f32 + 0.5) / size as f32 * 2.0 - 1.0, 1.0 - (y as f32 + 0.5) / size as f32 * 2.0];
                let d = Vec3::new(ndc[0] * tan, ndc[1] * tan, -1.0).normalize();
                let fresnel = f0 + (1.0 - f0) * (1.0 + d.z).powi(5);
                for k in 0..3 {
                    let (c1, c2) = (red[k] as f32 / 255.0, blue[k] as f32 / 255.0);
                    let reaching = match layers {
                        LayerEffects::Single => 1.0 - behind_opacity,
                        LayerEffects::Multi => 1.0 - 0.5,
                    };
                    let behind = if behind_opacity < 1.0 { behind_opacity * c2 + reaching * env[k] } else { c2 };
                    let want = fresnel * env[k] + (1.0 - fresnel) * (0.5 * c1 + 0.5 * behind);
                    worst = worst.max((p.0[k] as f32 - want * 255.0).abs());
                }
            }
            println!("{layers}, {what}: worst channel error {worst:.2}");
            assert!(worst <= 1.0, "{layers}, {what}: off by {worst}");
        }
    }
}
