//! The cache of reference images, keyed by everything that decides them.
//!
//! The key hashes (FNV-1a, stable across runs and builds) the model file's
//! path, size and modification time, the camera, the image size and every
//! render parameter; the image is stored as `cache/reference-KEY.png` with the
//! time it took to render in `cache/reference-KEY.ms`.

use std::path::{Path, PathBuf};

use crate::view::{Camera, RenderSettings};

/// A cache entry's files.
pub struct CacheEntry {
    pub image: PathBuf,
    pub millis: PathBuf,
}

use crate::grouping::cache::{FNV_OFFSET, fnv1a};

/// Where the reference image for these inputs is (or would be) cached.
pub fn entry(dir: &Path, model: &Path, camera: &Camera, settings: &RenderSettings, size: (u32, u32)) -> CacheEntry {
    let meta = std::fs::metadata(model).ok();
    let stamp = meta.as_ref().and_then(|m| m.modified().ok()).map(|t| format!("{t:?}")).unwrap_or_default();
    let file_len = meta.map(|m| m.len()).unwrap_or(0);
    let key = format!(
        "v1|{}|{file_len}|{stamp}|{camera:?}|{size:?}|{:?}|{:?}|{}|{}|{}|{}",
        model.display(),
        settings.kernel,
        settings.shading,
        settings.epsilon_scale,
        settings.backface_culling,
        settings.lighting,
        settings.radius_scale
    );
    let name = format!("reference-{:016x}", fnv1a(FNV_OFFSET, key.as_bytes()));
    let dir = dir.join("cache");
    CacheEntry { image: dir.join(format!("{name}.png")), millis: dir.join(format!("{name}.ms")) }
}

impl CacheEntry {
    /// The cached image and its render time, if both are there and readable.
    pub fn load(&self) -> Option<(image::RgbaImage, f64)> {
        let ms = std::fs::read_to_string(&self.millis).ok()?.trim().parse().ok()?;
        let image = image::open(&self.image).ok()?.to_rgba8();
        Some((image, ms))
    }
}
