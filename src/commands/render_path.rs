//! `pointblend render FILE --path views.json --path-frames N --out frames/f.png`:
//! a flight through bookmarked views (crates/core/src/frame/view_path.rs),
//! written as a numbered image sequence (`f-0000.png` ...) and an animated
//! GIF (`f.gif`) through the `image` crate, each file atomically. The scene,
//! its grouping and the GPU are set up once; every frame is an ordinary
//! frame of the same settings from the path's camera.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result};
use pointblend::frame::{RenderSettings, ViewPath};
use pointblend::render::{Frame, GpuRenderer, PreparedScene, Readback};

use super::stream_args::StreamedFlight;

/// Frames per second of the animated GIF.
const GIF_FPS: u32 = 25;

/// `frames/f.png` → `frames/f-0007.png`.
pub fn frame_path(out: &Path, k: u32) -> PathBuf {
    let stem = out.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_else(|| "frame".into());
    let extension = out.extension().map(|e| e.to_string_lossy().into_owned()).unwrap_or_else(|| "png".into());
    out.with_file_name(format!("{stem}-{k:04}.{extension}"))
}

/// What a flight writes: the input's name (for the report), the `--out` pattern and the frame count.
pub struct Flight<'a> {
    pub file: &'a Path,
    pub out: &'a Path,
    pub frames: u32,
}

/// Flies `args` through `views`: each frame drawn from `frames` on `gpu`
/// (none for the reference); a streamed file's frames each select their
/// own nodes from `restream` (shown in the same prepared scene: the nodes
/// two frames share stay on the GPU).
pub fn run(
    args: &Flight<'_>,
    views: &ViewPath,
    frames: &mut PreparedScene,
    (mut gpu, mut restream): (Option<&mut GpuRenderer>, Option<StreamedFlight>),
    settings: &RenderSettings,
    size: (u32, u32),
) -> Result<()> {
    let n = args.frames;
    let gif_path = args.out.with_extension("gif");
    let started = Instant::now();
    // One frame decided once, drawn from every view of the path (again for each new selection).
    let mut spec = frames.resolve(settings, pointblend::frame::View::still(size));
    let bar = pointblend::progress::bar(n as u64, "camera path", true);
    let mut gif_bytes = Vec::new();
    {
        let mut gif = image::codecs::gif::GifEncoder::new_with_speed(&mut gif_bytes, 10);
        gif.set_repeat(image::codecs::gif::Repeat::Infinite).context("the animated GIF")?;
        for k in 0..n {
            let camera = views.camera_at(k as f32 / (n - 1) as f32);
            if let Some(flight) = restream.as_mut() {
                let shown = Arc::clone(frames.scene());
                if let Some(next) = flight.next_scene(&camera, &shown)? {
                    let next = Arc::new(next);
                    frames.show_selection(gpu.as_deref(), Arc::clone(&next), next.flattened())?;
                    spec = frames.resolve(settings, pointblend::frame::View::still(size));
                }
            }
            let Frame { image, .. } = frames.render_frame(gpu.as_deref_mut(), &camera, &spec, Readback::Image)?;
            super::shared::write_image(&image, &frame_path(args.out, k))?;
            let delay = image::Delay::from_numer_denom_ms(1000, GIF_FPS);
            gif.encode_frame(image::Frame::from_parts(image, 0, 0, delay))
                .with_context(|| format!("{}: frame {k}", gif_path.display()))?;
            bar.inc(1);
        }
    }
    bar.finish();
    pointblend::output::write_atomically(&gif_path, &gif_bytes)
        .with_context(|| format!("{}: cannot write the animation", gif_path.display()))?;
    println!(
        "{}: {} frames through {} views in {:.1} s -> {} .. {} and {}",
        super::shared::shown_path(args.file),
        n,
        views.views.len(),
        started.elapsed().as_secs_f64(),
        frame_path(args.out, 0).display(),
        frame_path(args.out, n - 1).display(),
        gif_path.display()
    );
    Ok(())
}
