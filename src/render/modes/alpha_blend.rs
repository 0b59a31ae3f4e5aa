//! `alpha-blend`: plain back-to-front α-blending of every splat, the baseline
//! that shows why Zhang & Pajarola (§5.2) group the splats.
//!
//! The splats are sorted back to front for the view (`render::instance_order`,
//! one group of everything) and each is blended over the image with its
//! opacity (premultiplied "over", `shaders/alpha_blend.wgsl`), with no depth
//! test and no fragment culling. Neighbouring discs of one surface overlap, so
//! each surface layer is blended as often as discs cover the pixel (about
//! 2-3 times on a scan): the double blending that Algorithm-1's groups and
//! Eq. 10 culling remove. A full-screen pass puts the image over the
//! background (`shaders/alg1_average.wgsl` with K = 1). A scene with nothing
//! transparent runs the opaque two-pass plan.

use super::two_pass::TwoPass;
use super::{FrameDesc, GpuMode, peeling};
use crate::render::gpu_data::PassUniforms;
use crate::render::passes::{Blend, ColourOutput, Command, FullscreenPass, Output, Recorded, SplatPass};
use crate::render::plan::{Layout, PlannedPass, RenderPlan, TargetId};
use crate::render::shaders::Variant;
use crate::render::targets::ACCUM_FORMAT;

pub struct AlphaBlend;

const IMAGE: TargetId = TargetId("blended image");

impl GpuMode for AlphaBlend {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        if !frame.transparent {
            return peeling::opaque_fallback(frame, TwoPass.plan(frame));
        }
        let targets = vec![frame.target(
            IMAGE,
            ACCUM_FORMAT,
            Layout::Array { layers: 1 },
            "every splat back to front: shaded rgb·α, α, over; no culling",
        )];
        let passes = vec![
            PlannedPass {
                name: "blend",
                what: "all splats back to front -> image: rgb·α, α, over; no depth test".into(),
                reads: Vec::new(),
                writes: vec![IMAGE],
                draws_splats: true,
                render_passes: 1,
            },
            PlannedPass {
                name: "over background",
                what: "full screen: the image over the background".into(),
                reads: vec![IMAGE],
                writes: Vec::new(),
                draws_splats: false,
                render_passes: 1,
            },
        ];
        frame.plan((if frame.settings.lighting { "lit" } else { "unlit" }).into(), 1, passes, targets)
    }

    fn record(&self, frame: &FrameDesc<'_>, plan: &RenderPlan) -> Vec<Recorded> {
        if !frame.transparent {
            return TwoPass.record(frame, plan);
        }
        let uniforms = PassUniforms {
            uniform_colour: frame.uniform_colour_rgba(),
            depth: [frame.epsilon, frame.depth_steps, 0.0, 0.0],
            layers: [0, 1, 0, 0],
        };
        let blend = SplatPass {
            label: "AlphaBlend::pass",
            shader: "alpha_blend.wgsl",
            entry: "fs_alpha_blend",
            variant: Variant::NONE.with(Variant::LIT, frame.settings.lighting),
            colour: vec![ColourOutput { target: IMAGE, blend: Blend::Over }],
            depth: None,
            inputs: Vec::new(),
            layer: 0,
            splats: 0..frame.splats as u32,
            uniforms,
        };
        let over = FullscreenPass {
            label: "AlphaBlendOver::pass",
            shader: "alg1_average.wgsl",
            entry: "fs_alg1_average",
            variant: Variant::NONE,
            inputs: vec![IMAGE],
            output: Output::Frame,
            blend: Blend::Replace,
            clear: true,
            uniforms,
        };
        vec![
            Recorded { pass: 0, command: Command::Splats(blend) },
            Recorded { pass: 1, command: Command::Fullscreen(over) },
        ]
    }

    fn blends_in_order(&self, frame: &FrameDesc<'_>) -> bool {
        frame.transparent
    }
}
