//! `depth-peel`: exact depth peeling with k layers (default 8), the baseline
//! Zhang & Pajarola's Fig. 17 measures transparency against.
//!
//! Each of the k layers is a full splat render (visibility, accumulation,
//! shading) of what lies behind the layer before, composited front to back
//! (see [`super::peeling`]): k × (2 + 1) passes and a final one. With k at
//! least the number of layers a pixel's ray meets, the image is the exact
//! transparent blend up to two-pass's own error.

use super::{FrameDesc, GpuMode, peeling};
use crate::plan::RenderPlan;

pub struct DepthPeel;

impl GpuMode for DepthPeel {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let k = peeling::peel_layers(frame);
        let mut steps = peeling::layer_steps(frame, k);
        steps.push(peeling::final_step(frame));
        frame.plan(peeling::describe(frame, k), 1, steps, peeling::targets(frame))
    }
}
