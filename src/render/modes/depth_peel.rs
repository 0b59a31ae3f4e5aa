//! `depth-peel`: exact depth peeling with k layers (default 8), the baseline
//! Zhang & Pajarola's Fig. 17 measures transparency against.
//!
//! Each of the k layers is a full splat render (visibility, accumulation,
//! shading) of what lies behind the layer before, composited front to back
//! (see [`super::peeling`]): k × (2 + 1) passes and a final one. With k at
//! least the number of layers a pixel's ray meets, the image is the exact
//! transparent blend up to two-pass's own error. A scene with nothing
//! transparent runs the opaque `two-pass` plan instead.

use super::two_pass::TwoPass;
use super::{FrameDesc, GpuMode, peeling};
use crate::render::passes::Recorded;
use crate::render::plan::RenderPlan;

pub struct DepthPeel;

impl GpuMode for DepthPeel {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        if !frame.transparent {
            return peeling::opaque_fallback(frame, TwoPass.plan(frame));
        }
        let k = peeling::layers(frame);
        let mut passes = peeling::layer_passes(frame, k);
        passes.push(peeling::final_pass());
        frame.plan(peeling::describe(frame, k), 1, passes, peeling::targets(frame))
    }

    fn record(&self, frame: &FrameDesc<'_>, plan: &RenderPlan) -> Vec<Recorded> {
        if !frame.transparent {
            return TwoPass.record(frame, plan);
        }
        let k = peeling::layers(frame);
        let mut commands = peeling::record_layers(frame, k);
        commands.push(peeling::record_final(frame, 3 * k as usize));
        commands
    }
}
