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
//! A scene with nothing transparent runs the opaque two-pass plan.

use super::two_pass::TwoPass;
use super::{FrameDesc, GpuMode, peeling};
use crate::render::gpu_data::PassUniforms;
use crate::render::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, Output, Recorded, SplatPass};
use crate::render::plan::{Layout, PlannedPass, RenderPlan, TargetDesc, TargetId};
use crate::render::shaders::Variant;
use crate::render::targets::{ACCUM_FORMAT, DEPTH_FORMAT};

pub struct Alg1;

const IMAGES: TargetId = TargetId("group images I_k");
const Z_BUFFER: TargetId = TargetId("group Eq. 10 z-buffer");

/// Group images K: at least one (also alg2's).
pub(super) fn groups(frame: &FrameDesc<'_>) -> u32 {
    frame.groups.len().max(1) as u32
}

/// The shader variant (also alg2's): lit or not; colours are always full.
pub(super) fn variant(frame: &FrameDesc<'_>) -> Variant {
    Variant::NONE.with(Variant::LIT, frame.settings.lighting)
}

/// The plan's variant in words (also alg2's): the grouping drawn, lit or not.
pub(super) fn describe(frame: &FrameDesc<'_>) -> String {
    format!("{}, {}", frame.settings.grouping_for_mode(), if frame.settings.lighting { "lit" } else { "unlit" })
}

impl GpuMode for Alg1 {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        if !frame.transparent {
            return peeling::opaque_fallback(frame, TwoPass.plan(frame));
        }
        let k = groups(frame);
        let target = |id, format, why| TargetDesc {
            id,
            format,
            width: frame.width,
            height: frame.height,
            layout: Layout::Array { layers: k },
            why,
        };
        let targets = vec![
            target(IMAGES, ACCUM_FORMAT, "I_k: group k blended back to front, premultiplied colour and α"),
            target(Z_BUFFER, DEPTH_FORMAT, "Eq. 10 low-precision depth per group: one blend per surface layer"),
        ];
        let passes = vec![
            PlannedPass {
                name: "group layers",
                what: "group k back to front -> I_k: shaded rgb·α, α, over; z-test on Eq. 10 depth".into(),
                reads: Vec::new(),
                writes: vec![IMAGES, Z_BUFFER],
                draws_splats: true,
                render_passes: k as usize,
            },
            PlannedPass {
                name: "average",
                what: "full screen: mean of the I_k that cover the pixel, over the background".into(),
                reads: vec![IMAGES],
                writes: Vec::new(),
                draws_splats: false,
                render_passes: 1,
            },
        ];
        RenderPlan {
            mode: frame.settings.mode,
            variant: describe(frame),
            width: frame.width,
            height: frame.height,
            splats: frame.splats,
            epsilon: frame.epsilon,
            groups: k as usize,
            passes,
            targets,
            notes: Vec::new(),
        }
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
        let mut commands: Vec<Recorded> = (0..k)
            .map(|layer| {
                let pass = SplatPass {
                    label: "Alg1Group::pass",
                    shader: "alg1_group.wgsl",
                    entry: "fs_alg1_group",
                    variant: variant(frame),
                    colour: vec![ColourOutput { target: IMAGES, blend: Blend::Over }],
                    depth: Some((Z_BUFFER, z_test)),
                    inputs: Vec::new(),
                    layer,
                    splats: frame.groups.get(layer as usize).cloned().unwrap_or(0..0),
                    uniforms: uniforms(layer),
                };
                Recorded { pass: 0, command: Command::Splats(pass) }
            })
            .collect();
        let average = FullscreenPass {
            label: "Alg1Average::pass",
            shader: "alg1_average.wgsl",
            entry: "fs_alg1_average",
            variant: Variant::NONE,
            inputs: vec![IMAGES],
            output: Output::Frame,
            blend: Blend::Replace,
            clear: true,
            uniforms: uniforms(0),
        };
        commands.push(Recorded { pass: 1, command: Command::Fullscreen(average) });
        commands
    }

    fn blends_in_order(&self, frame: &FrameDesc<'_>) -> bool {
        frame.transparent
    }
}
