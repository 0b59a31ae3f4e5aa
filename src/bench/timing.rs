//! Timing one variant from one view through the one frame path
//! ([`PreparedScene::render_frame`], as `render` and the viewer draw it):
//! warm-up frames, then timed frames
//! (wall time until the GPU is idle, and per-pass GPU timestamps where the
//! adapter has them; where it has none for compute passes, each step waited
//! for alone in frames of their own), and the last frame's image and plan.

use std::time::Instant;

use super::config::BenchConfig;
use crate::frame::{Camera, FrameSpec};
use crate::render::{Frame, FrameError, GpuRenderer, PreparedScene, Readback};

/// Warm-up and timed frames of one variant (its frame `variant`, decided
/// once) from one view: the last frame read back (image, plan and report),
/// wall times and GPU times per plan pass.
#[allow(clippy::type_complexity)]
pub fn time_frames(
    renderer: &mut GpuRenderer,
    frames: &mut PreparedScene,
    camera: &Camera,
    variant: &FrameSpec,
    config: &BenchConfig,
) -> Result<(Frame, Vec<f64>, Vec<Vec<f64>>, bool), FrameError> {
    let mut wall = Vec::new();
    let mut per_pass: Vec<Vec<f64>> = Vec::new();
    for frame in 0..config.warm_up + config.frames {
        let t = Instant::now();
        // Under a point budget the frame selects its splats first (part of its time).
        let plan = frames.render_frame(Some(renderer), camera, variant, Readback::Nothing)?.plan;
        renderer.ctx.wait_idle()?;
        let ms = t.elapsed().as_secs_f64() * 1e3;
        if frame >= config.warm_up {
            wall.push(ms);
            if let Some(times) = renderer.renderer.pass_times(&renderer.ctx, &plan)? {
                per_pass.resize(times.len(), Vec::new());
                for (i, t) in times.into_iter().enumerate() {
                    per_pass[i].push(t);
                }
            }
        }
    }
    let profiled = per_pass.is_empty();
    if profiled {
        // No GPU timestamps for these steps (compute passes on a software
        // adapter): time each step on its own in frames of their own.
        renderer.renderer.profile_steps(true);
        for _ in 0..config.frames.min(3) {
            let profiled = frames.render_frame(Some(renderer), camera, variant, Readback::Nothing);
            let times = renderer.renderer.step_times().map(<[f64]>::to_vec);
            if let Err(e) = profiled {
                renderer.renderer.profile_steps(false);
                return Err(e);
            }
            for (i, t) in times.unwrap_or_default().into_iter().enumerate() {
                per_pass.resize(per_pass.len().max(i + 1), Vec::new());
                per_pass[i].push(t);
            }
        }
        renderer.renderer.profile_steps(false);
    }
    let frame = frames.render_frame(Some(renderer), camera, variant, Readback::Image)?;
    Ok((frame, wall, per_pass, profiled))
}
