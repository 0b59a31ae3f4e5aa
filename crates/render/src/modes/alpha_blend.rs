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
//! background (`shaders/alg1_average.wgsl` with K = 1).

use super::{FrameDesc, GpuMode};
use crate::passes::{Blend, ColourOutput, Command, FullscreenPass, SplatPass};
use crate::plan::{Layout, RenderPlan, Step, TargetId};
use crate::shaders::Variant;
use crate::targets::ACCUM_FORMAT;

pub struct AlphaBlend;

const IMAGE: TargetId = TargetId("blended image");

impl GpuMode for AlphaBlend {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let targets = vec![frame.target(
            IMAGE,
            ACCUM_FORMAT,
            Layout::Array { layers: 1 },
            "every splat back to front: shaded rgb·α, α, over; no culling",
        )];
        let uniforms = frame.uniforms(0, 1, 0);
        let blend = SplatPass {
            label: "AlphaBlend::pass",
            shader: "alpha_blend.wgsl",
            entry: "fs_alpha_blend",
            variant: frame.shading_variant(),
            colour: vec![ColourOutput { target: IMAGE, blend: Blend::Over }],
            depth: None,
            inputs: Vec::new(),
            layer: 0,
            splats: 0..frame.splats as u32,
            back_to_front: true,
            uniforms,
            triangles: false,
        };
        let over = FullscreenPass::into_frame(
            "AlphaBlendOver::pass",
            ("alg1_average.wgsl", "fs_alg1_average"),
            Variant::NONE,
            vec![IMAGE],
            uniforms,
        );
        let steps = vec![
            Step::new(
                "blend",
                "all splats back to front -> image: rgb·α, α, over; no depth test",
                vec![Command::Splats(blend)],
            ),
            Step::new("over background", "full screen: the image over the background", vec![Command::Fullscreen(over)]),
        ];
        frame.plan(frame.lighting_name().into(), 1, steps, targets)
    }
}
