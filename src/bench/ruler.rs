//! The ruler a bench row is measured against: the exact reference of the
//! view (CPU ray casting, Zhang & Pajarola 2007 §6.3's ground truth),
//! reading the scene's opacity or every splat opaque, supersampled when
//! asked, and cached in the output folder ([`super::cache`]).

use std::time::Instant;

use super::cache::{self, Ruler};
use super::config::{BenchConfig, BenchError, io_error, save_png};
use crate::frame::{Camera, RenderSettings};
use crate::output::write_atomically;
use crate::reference::{self, ReferenceOptions};
use crate::scene::Scene;

/// What a row's error is measured against.
pub fn ruler_name(transparent: bool, supersample: u32) -> String {
    let what = if transparent { "reference with the scene's opacity" } else { "reference with every splat opaque" };
    match supersample {
        0 | 1 => what.to_string(),
        n => format!("{what}, {n}×{n} rays per pixel"),
    }
}

/// The exact reference of `scene` from `camera`, reading opacity or not,
/// from the cache when it is there; the milliseconds it took and its layers per pixel.
pub fn ruler(
    config: &BenchConfig,
    scene: &Scene,
    settings: &RenderSettings,
    camera: &Camera,
    transparent: bool,
) -> Result<Ruler, BenchError> {
    let size = (config.width, config.height);
    let environment = scene.environment.as_deref();
    let entry = cache::entry(&config.out, scene.content_hash(), camera, settings, transparent, size, environment);
    if let Some(cached) = entry.load() {
        return Ok(cached);
    }
    let options = ReferenceOptions { transparent, ..ReferenceOptions::matching(settings, scene) };
    let t = Instant::now();
    let (image, layers) = reference::render_with_layers(scene, camera, &options, size.0, size.1);
    let ms = t.elapsed().as_secs_f64() * 1e3;
    save_png(&image, &entry.image)?;
    let bytes: Vec<u8> = layers.iter().flat_map(|l| l.to_le_bytes()).collect();
    write_atomically(&entry.layers, &bytes).map_err(io_error(&entry.layers))?;
    write_atomically(&entry.millis, format!("{ms}").as_bytes()).map_err(io_error(&entry.millis))?;
    Ok(Ruler { image, ms, layers })
}
