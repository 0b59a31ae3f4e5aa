//! `approx-peel`: Guennebaud's approximate depth peeling (SPBG'06 slides):
//! k - 1 exact layers (default k = 3), then every remaining fragment blended
//! in any order into one approximate last layer.
//!
//! The exact layers are those of `depth-peel` ([`super::peeling`]). One more
//! splat pass adds w·rgb, w, w·α and w·n (normals turned to the viewer) of
//! every fragment behind the last exact layer, with no depth test; a
//! full-screen pass makes it one layer (`shaders/peel_rest.wgsl` has the
//! blending heuristic and why) and composites it under the exact ones. So the
//! splats are drawn 2(k - 1) + 1 times, whatever the depth complexity.

use super::{FrameDesc, GpuMode, peeling};
use crate::passes::{Command, DepthTest, FullscreenPass};
use crate::plan::{RenderPlan, Step, TargetId};

pub struct ApproxPeel;

const REST: [TargetId; 4] =
    [TargetId("rest colour"), TargetId("rest weight"), TargetId("rest opacity"), TargetId("rest normal")];

impl GpuMode for ApproxPeel {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let k = peeling::peel_layers(frame);
        let exact = k - 1;
        let mut steps = peeling::layer_steps(frame, exact);
        // Layer `exact` peels what lies behind the last exact layer, with no depth test (the
        // free depth target is attached only because the shader writes depth).
        let any_depth = DepthTest { write: false, compare: wgpu::CompareFunction::Always, clear: false };
        let free = peeling::DEPTH[exact as usize % 2];
        let outputs = peeling::additive(peeling::sums(frame, REST));
        let rest = peeling::splat_pass(frame, exact, peeling::LayerPass::Accumulate, outputs, Some((free, any_depth)));
        // The rest's sums, then the last exact layer's colour sums (shaders/peel_rest.wgsl).
        let mut inputs = peeling::sums(frame, REST);
        inputs.push(peeling::layer_sums(frame)[0]);
        let composite = FullscreenPass::under(
            "PeelRest::pass",
            ("peel_rest.wgsl", "fs_rest"),
            peeling::variant(frame),
            inputs,
            (peeling::COMPOSITE, false),
            peeling::uniforms(frame, exact),
        );
        steps.push(Step::new(
            "accumulate rest",
            format!("splats behind layer {exact}: Σw·rgb, Σw, Σw·α (+ Σw·n), in any order"),
            vec![Command::Splats(rest)],
        ));
        steps.push(Step::new(
            "composite rest",
            "the rest as one layer of l = Σw_rest/Σw_layer layers: α = 1 - (1 - ᾱ)^l, under the exact ones",
            vec![Command::Fullscreen(composite)],
        ));
        steps.push(peeling::final_step(frame));
        let mut targets = peeling::targets(frame);
        targets.extend(peeling::sum_targets(frame, REST, "Σw·rgb, Σw of everything behind the exact layers"));
        frame.plan(format!("{}, the last approximate", peeling::describe(frame, k)), 1, steps, targets)
    }
}
