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
