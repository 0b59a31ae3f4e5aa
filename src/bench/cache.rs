//! The cache of reference images, keyed by everything that decides them.
//!
//! The key hashes (FNV-1a, stable across runs and builds) the scene's content
//! (its files' bytes, transforms and materials), the camera, the image size,
//! every render parameter and whether opacity was read; the image is stored as
//! `cache/reference-KEY.png` with the time it took to render in
//! `cache/reference-KEY.ms` and the number of ε-layers each pixel's ray met
//! in `cache/reference-KEY.layers` (little-endian u32, row-major).

use std::path::{Path, PathBuf};

use crate::frame::{Camera, RenderSettings};

/// A cache entry's files.
pub struct CacheEntry {
    pub image: PathBuf,
    pub millis: PathBuf,
    pub layers: PathBuf,
}

/// A reference image, the milliseconds it took, and its layers per pixel.
#[derive(Debug, Clone)]
pub struct Ruler {
    pub image: image::RgbaImage,
    pub ms: f64,
    pub layers: Vec<u32>,
}

use crate::hash::{FNV_OFFSET, fnv1a};

/// Where the reference image for these inputs is (or would be) cached.
pub fn entry(
    dir: &Path,
    scene_hash: u64,
    camera: &Camera,
    settings: &RenderSettings,
    transparent: bool,
    size: (u32, u32),
    environment: Option<&crate::scene::environment_map::EnvironmentMap>,
) -> CacheEntry {
    let environment = match environment.filter(|_| transparent && settings.draws_environment()) {
        Some(map) => format!("{:016x}|{:?}", map.hash, settings.environment),
        None => "-".into(),
    };
    let key = format!(
        "v2|{scene_hash:016x}|{transparent}|{camera:?}|{size:?}|{environment}|{:?}|{:?}|{}|{}|{}|{}|{:?}{}",
        settings.kernel,
        settings.shading,
        settings.epsilon_scale,
        settings.backface_culling,
        settings.lighting,
        settings.radius_scale,
        settings.lights,
        // One ray per pixel keeps the key it had before supersampling was a choice.
        if settings.supersample > 1 { format!("|ss{}", settings.supersample) } else { String::new() },
    );
    // Likewise without eye-dome lighting.
    let key = match settings.eye_dome_drawn() {
        Some(edl) => format!("{key}|edl{edl:?}"),
        None => key,
    };
    let name = format!("reference-{:016x}", fnv1a(FNV_OFFSET, key.as_bytes()));
    let dir = dir.join("cache");
    CacheEntry {
        image: dir.join(format!("{name}.png")),
        millis: dir.join(format!("{name}.ms")),
        layers: dir.join(format!("{name}.layers")),
    }
}

impl CacheEntry {
    /// The cached ruler, if its three files are there, readable and of one size.
    pub fn load(&self) -> Option<Ruler> {
        let ms = std::fs::read_to_string(&self.millis).ok()?.trim().parse().ok()?;
        let image = image::open(&self.image).ok()?.to_rgba8();
        let bytes = std::fs::read(&self.layers).ok()?;
        let layers: Vec<u32> = bytes.chunks_exact(4).map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])).collect();
        (bytes.len() == 4 * image.width() as usize * image.height() as usize).then_some(Ruler { image, ms, layers })
    }
}
