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

use super::two_pass::TwoPass;
use super::{FrameDesc, GpuMode, peeling};
use crate::render::passes::{Blend, Command, DepthTest, FullscreenPass, Output, Recorded};
use crate::render::plan::{PlannedPass, RenderPlan, TargetId};

pub struct ApproxPeel;

const REST: [TargetId; 4] =
    [TargetId("rest colour"), TargetId("rest weight"), TargetId("rest opacity"), TargetId("rest normal")];

impl GpuMode for ApproxPeel {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        if !frame.transparent {
            return peeling::opaque_fallback(frame, TwoPass.plan(frame));
        }
        let k = peeling::layers(frame);
        let mut passes = peeling::layer_passes(frame, k - 1);
        let last = peeling::DEPTH[(k as usize) % 2];
        passes.push(PlannedPass {
            name: "accumulate rest",
            what: format!("splats behind layer {}: Σw·rgb, Σw, Σw·α (+ Σw·n), in any order", k - 1),
            reads: vec![last],
            writes: peeling::sums(frame, REST),
            draws_splats: true,
            render_passes: 1,
        });
        let mut reads = peeling::sums(frame, REST);
        reads.insert(2, peeling::layer_sums(frame)[0]);
        reads.push(peeling::COMPOSITE); // blended under it
        passes.push(PlannedPass {
            name: "composite rest",
            what: "the rest as one layer of l = Σw_rest/Σw_layer layers: α = 1 - (1 - ᾱ)^l, under the exact ones"
                .into(),
            reads,
            writes: vec![peeling::COMPOSITE],
            draws_splats: false,
            render_passes: 1,
        });
        passes.push(peeling::final_pass());
        let mut targets = peeling::targets(frame);
        targets.extend(peeling::sum_targets(frame, REST, "Σw·rgb, Σw of everything behind the exact layers"));
        frame.plan(format!("{}, the last approximate", peeling::describe(frame, k)), 1, passes, targets)
    }

    fn record(&self, frame: &FrameDesc<'_>, plan: &RenderPlan) -> Vec<Recorded> {
        if !frame.transparent {
            return TwoPass.record(frame, plan);
        }
        let k = peeling::layers(frame);
        let exact = k - 1;
        let mut commands = peeling::record_layers(frame, exact);
        let first = 3 * exact as usize;
        // Layer `exact` peels what lies behind the last exact layer, with no depth test (the
        // free depth target is attached only because the shader writes depth).
        let any_depth = DepthTest { write: false, compare: wgpu::CompareFunction::Always, clear: false };
        let free = peeling::DEPTH[exact as usize % 2];
        let outputs = peeling::additive(peeling::sums(frame, REST));
        let rest = peeling::splat_pass(frame, exact, peeling::Step::Accumulate, outputs, Some((free, any_depth)));
        commands.push(Recorded { pass: first, command: Command::Splats(rest) });
        let mut inputs = peeling::sums(frame, REST);
        inputs.insert(2, peeling::layer_sums(frame)[0]);
        let composite = FullscreenPass {
            label: "PeelRest::pass",
            shader: "peel_rest.wgsl",
            entry: "fs_rest",
            variant: peeling::variant(frame),
            inputs,
            output: Output::Target(peeling::COMPOSITE),
            blend: Blend::Under,
            clear: false,
            uniforms: peeling::uniforms(frame, exact),
        };
        commands.push(Recorded { pass: first + 1, command: Command::Fullscreen(composite) });
        commands.push(peeling::record_final(frame, first + 2));
        commands
    }
}
