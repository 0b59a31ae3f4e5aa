//! `alg1`: Zhang & Pajarola 2007's Algorithm-1 (§5.2.1): transparent point
//! surfaces in one geometry traversal plus one compositing pass.
//!
//! The splats come in groups that each cover the surface with little overlap
//! (§4.4.2: duplication or radius enlargement; by default WGC with K = 4 and
//! radius enlargement, see `RenderSettings::grouping_for_mode`). Each group is drawn back to front
//! (the scene's instances are re-sorted per view, `render::instance_order`)
//! into its own layer I_k of a 2D array, α-blended with each splat's opacity
//! and culled by a z-test on Eq. 10's low-precision depth so that one surface
//! layer is blended once per group (`shaders/alg1_group.wgsl`; the step is
//! `RenderSettings::depth_step` × ε, and a fragment facing away from the
//! viewer counts half a step farther, so the two sides of a thin shell stay
//! two layers). A full-screen pass averages the K images over the
//! background (`shaders/alg1_average.wgsl`): groups that left a pixel empty
//! are left out, and the opacity is a trimmed mean without the most and the
//! least opaque group, which are the ones that blended a layer twice (its
//! fragments straddled a step) or missed one (a hole in the group).
//! In a scene of transparent and opaque splats, the opaque ones are drawn
//! first, apart and in high quality (`two-pass`, `super::opaque_part`): the group
//! passes cull fragments behind their depth and the average goes over their
//! image instead of the background (Fig. 18/19).

use super::covering::{describe, groups, variant};
use super::opaque_part::{self, OPAQUE_DEPTH, OPAQUE_IMAGE, with_opaque};
use super::{FrameDesc, GpuMode, depth_step_note, per_group};
use crate::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, SplatPass};
use crate::plan::{Layout, RenderPlan, Step, TargetId};
use crate::shaders::Variant;
use crate::targets::{ACCUM_FORMAT, DEPTH_FORMAT};

pub struct Alg1;

const IMAGES: TargetId = TargetId("group images I_k");
const Z_BUFFER: TargetId = TargetId("group Eq. 10 z-buffer");

impl GpuMode for Alg1 {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let k = groups(frame);
        let target = |id, format, why| frame.target(id, format, Layout::Array { layers: k }, why);
        let (mut targets, mut steps) = opaque_part::plan(frame);
        targets.extend([
            target(IMAGES, ACCUM_FORMAT, "I_k: group k blended back to front, premultiplied colour and α"),
            target(Z_BUFFER, DEPTH_FORMAT, "Eq. 10 low-precision depth per group: one blend per surface layer"),
        ]);
        let uniforms = |layer: u32| frame.uniforms(layer, k, 0);
        let z_test = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let group_pass = SplatPass {
            label: "Alg1Group::pass",
            shader: "alg1_group.wgsl",
            entry: "fs_alg1_group",
            variant: variant(frame),
            colour: vec![ColourOutput { target: IMAGES, blend: Blend::Over }],
            depth: Some((Z_BUFFER, z_test)),
            inputs: with_opaque(frame, Vec::new(), OPAQUE_DEPTH),
            layer: 0,
            splats: 0..0,
            back_to_front: true,
            uniforms: uniforms(0),
            triangles: false,
        };
        let average = FullscreenPass::into_frame(
            "Alg1Average::pass",
            ("alg1_average.wgsl", "fs_alg1_average"),
            Variant::NONE.with(Variant::OPAQUE_APART, opaque_part::present(frame)),
            with_opaque(frame, vec![IMAGES], OPAQUE_IMAGE),
            uniforms(0),
        );
        steps.extend([
            Step::new(
                "group layers",
                "group k back to front -> I_k: shaded rgb·α, α, over; z-test on Eq. 10 depth",
                per_group(group_pass, frame.transparent_groups, k, uniforms),
            ),
            Step::new(
                "average",
                "full screen: mean of the I_k that cover the pixel, over the background (or opaque image)",
                vec![Command::Fullscreen(average)],
            ),
        ]);
        let mut plan = frame.plan(describe(frame), k as usize, steps, targets);
        plan.notes.extend(depth_step_note(frame, true));
        plan
    }
}
