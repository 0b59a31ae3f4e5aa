//! `alg1`: Zhang & Pajarola 2007's Algorithm-1 (§5.2.1): transparent point
//! surfaces in one geometry traversal plus one compositing pass.
//!
//! The splats come in groups that each cover the surface with little overlap
//! (§4.4.2: duplication or radius enlargement; by default WGC with K = 4 and
//! radius enlargement, see `RenderSettings::grouping_for_mode`). Each group is drawn back to front
//! (the scene's instances are re-sorted per view, `render::instance_order`)
//! into its own layer I_k of a 2D array, α-blended with each splat's opacity
//! and culled by a z-test on Eq. 10's low-precision depth so that one surface
//! layer is blended once per group (`shaders/alg1_group.wgsl`). A full-screen
//! pass averages the K images over the background; groups that left a pixel
//! empty are left out of its average (`shaders/alg1_average.wgsl`).
//! In a scene of transparent and opaque splats, the opaque ones are drawn
//! first, apart and in high quality (`two-pass`, [`OpaquePart`]): the group
//! passes cull fragments behind their depth and the average goes over their
//! image instead of the background (Fig. 18/19).
//! A scene with nothing transparent runs the opaque two-pass plan.

use super::two_pass::{OPAQUE_DEPTH, OPAQUE_IMAGE, OpaquePart, TwoPass};
use super::{FrameDesc, GpuMode, depth_step_note, peeling, per_group};
use crate::render::gpu_data::PassUniforms;
use crate::render::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, Output, Recorded, SplatPass};
use crate::render::plan::{Layout, PlannedPass, RenderPlan, TargetId};
use crate::render::shaders::Variant;
use crate::render::targets::{ACCUM_FORMAT, DEPTH_FORMAT};

pub struct Alg1;

const IMAGES: TargetId = TargetId("group images I_k");
const Z_BUFFER: TargetId = TargetId("group Eq. 10 z-buffer");

/// Group images K: at least one (also alg2's).
pub(super) fn groups(frame: &FrameDesc<'_>) -> u32 {
    frame.transparent_groups.len().max(1) as u32
}

/// The shader variant (also alg2's): lit or not, opaque splats drawn apart
/// or not; colours are always full.
pub(super) fn variant(frame: &FrameDesc<'_>) -> Variant {
    Variant::NONE.with(Variant::LIT, frame.settings.lighting).with(Variant::OPAQUE_APART, OpaquePart::present(frame))
}

/// `reads` and, when the opaque splats are drawn apart, `opaque` (also alg2's).
pub(super) fn with_opaque(frame: &FrameDesc<'_>, mut reads: Vec<TargetId>, opaque: TargetId) -> Vec<TargetId> {
    if OpaquePart::present(frame) {
        reads.push(opaque);
    }
    reads
}

/// The plan's variant in words (also alg2's): the grouping drawn, lit or
/// not, and how opaque splats are drawn.
pub(super) fn describe(frame: &FrameDesc<'_>) -> String {
    format!(
        "{}, {}{}",
        frame.settings.grouping_for_mode(),
        if frame.settings.lighting { "lit" } else { "unlit" },
        if OpaquePart::present(frame) { ", opaque splats apart (two-pass)" } else { "" }
    )
}

impl GpuMode for Alg1 {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        if !frame.transparent {
            return peeling::opaque_fallback(frame, TwoPass.plan(frame));
        }
        let k = groups(frame);
        let target = |id, format, why| frame.target(id, format, Layout::Array { layers: k }, why);
        let (mut targets, mut passes) = OpaquePart::plan(frame);
        targets.extend([
            target(IMAGES, ACCUM_FORMAT, "I_k: group k blended back to front, premultiplied colour and α"),
            target(Z_BUFFER, DEPTH_FORMAT, "Eq. 10 low-precision depth per group: one blend per surface layer"),
        ]);
        passes.extend([
            PlannedPass {
                name: "group layers",
                what: "group k back to front -> I_k: shaded rgb·α, α, over; z-test on Eq. 10 depth".into(),
                reads: with_opaque(frame, Vec::new(), OPAQUE_DEPTH),
                writes: vec![IMAGES, Z_BUFFER],
                draws_splats: true,
                render_passes: k as usize,
            },
            PlannedPass {
                name: "average",
                what: "full screen: mean of the I_k that cover the pixel, over the background (or opaque image)".into(),
                reads: with_opaque(frame, vec![IMAGES], OPAQUE_IMAGE),
                writes: Vec::new(),
                draws_splats: false,
                render_passes: 1,
            },
        ]);
        let mut plan = frame.plan(describe(frame), k as usize, passes, targets);
        plan.notes.extend(depth_step_note(frame, true));
        plan
    }

    fn record(&self, frame: &FrameDesc<'_>, plan: &RenderPlan) -> Vec<Recorded> {
        if !frame.transparent {
            return TwoPass.record(frame, plan);
        }
        let k = groups(frame);
        let uniforms = |layer: u32| PassUniforms {
            uniform_colour: frame.uniform_colour_rgba(),
            depth: [frame.epsilon, frame.depth_steps, 0.0, 0.0],
            layers: [layer, k, 0, 0],
        };
        let z_test = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let mut commands = OpaquePart::record(frame);
        let first = plan.passes.len() - 2;
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
            uniforms: uniforms(0),
        };
        commands.extend(per_group(group_pass, frame.transparent_groups, k, first, uniforms));
        let average = FullscreenPass {
            label: "Alg1Average::pass",
            shader: "alg1_average.wgsl",
            entry: "fs_alg1_average",
            variant: Variant::NONE.with(Variant::OPAQUE_APART, OpaquePart::present(frame)),
            inputs: with_opaque(frame, vec![IMAGES], OPAQUE_IMAGE),
            output: Output::Frame,
            blend: Blend::Replace,
            clear: true,
            uniforms: uniforms(0),
        };
        commands.push(Recorded { pass: first + 1, command: Command::Fullscreen(average) });
        commands
    }

    fn blends_in_order(&self, frame: &FrameDesc<'_>) -> bool {
        frame.transparent
    }
}
