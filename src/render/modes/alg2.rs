//! `alg2`: Zhang & Pajarola 2007's Algorithm-2 (§5.2.2): the nearest
//! transparent layer in high quality, the layers behind it as Algorithm-1
//! draws them; two geometry passes and one compositing pass.
//!
//! Pass 1 is `deferred`'s geometry pass (group k into I_k: w·rgb, w, w·n,
//! w·α, true depth; nearest splat per group by Voronoi depth,
//! `shaders/alg2_nearest.wgsl`). Pass 2 is Algorithm-1's geometry pass into
//! O_k (each group back to front, α-blended, Eq. 10 culling), which drops
//! every fragment within ε of the nearest layer's depth read from pass 1
//! (`shaders/alg2_other.wgsl`). The compositing pass does the three blends of
//! §5.2.2 at once (`shaders/alg2_composite.wgsl`): C_F, the ε-z composited,
//! normalised and shaded nearest layer with its opacity α = Σw·α/Σw; C_O, the
//! average of the O_k over the background; and I = α·C_F + (1 - α)·C_O. The
//! groups are those of `alg1` (covering, `RenderSettings::grouping_for_mode`).
//! A scene with nothing transparent runs the opaque two-pass plan.

use super::alg1::{describe, groups, variant};
use super::two_pass::TwoPass;
use super::{FrameDesc, GpuMode, peeling};
use crate::render::gpu_data::PassUniforms;
use crate::render::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, Output, Recorded, SplatPass};
use crate::render::plan::{Layout, PlannedPass, RenderPlan, TargetDesc, TargetId};
use crate::render::targets::{ACCUM_FORMAT, DEPTH_FORMAT, VIEW_DEPTH_FORMAT};

pub struct Alg2;

const NEAR_COLOUR: TargetId = TargetId("nearest layer I_k: w·rgb, w");
const NEAR_NORMAL: TargetId = TargetId("nearest layer I_k: w·n, w·α");
const NEAR_DEPTH: TargetId = TargetId("nearest layer I_k: depth");
const NEAR_Z: TargetId = TargetId("nearest layer z-buffer");
const OTHERS: TargetId = TargetId("other layers O_k");
const OTHERS_Z: TargetId = TargetId("other layers Eq. 10 z-buffer");

impl GpuMode for Alg2 {
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
            target(NEAR_COLOUR, ACCUM_FORMAT, "pass 1 (deferred): each group's nearest splat, Eq. 4 weight"),
            target(NEAR_NORMAL, ACCUM_FORMAT, "pass 1: w·n for deferred shading, w·α for the nearest layer's opacity"),
            target(NEAR_DEPTH, VIEW_DEPTH_FORMAT, "pass 1: true view depth for ε-z compositing and pass 2's culling"),
            target(NEAR_Z, DEPTH_FORMAT, "pass 1: z-test within each group (Voronoi depth)"),
            target(OTHERS, ACCUM_FORMAT, "pass 2 (Algorithm-1): the layers behind the nearest, per group"),
            target(OTHERS_Z, DEPTH_FORMAT, "pass 2: Eq. 10 low-precision depth per group"),
        ];
        let passes = vec![
            PlannedPass {
                name: "nearest layer",
                what: "group k -> I_k as deferred draws it: w·rgb, w, w·n, w·α, depth; Voronoi z-test".into(),
                reads: Vec::new(),
                writes: vec![NEAR_COLOUR, NEAR_NORMAL, NEAR_DEPTH, NEAR_Z],
                draws_splats: true,
                render_passes: k as usize,
            },
            PlannedPass {
                name: "other layers",
                what: "group k back to front -> O_k, without fragments within ε of the nearest layer".into(),
                reads: vec![NEAR_COLOUR, NEAR_DEPTH],
                writes: vec![OTHERS, OTHERS_Z],
                draws_splats: true,
                render_passes: k as usize,
            },
            PlannedPass {
                name: "composite",
                what: "full screen: C_F (ε-z, normalise, shade), C_O (mean of O_k), I = α·C_F + (1-α)·C_O".into(),
                reads: vec![NEAR_COLOUR, NEAR_DEPTH, NEAR_NORMAL, OTHERS],
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
            layers: [layer, k, frame.settings.voronoi as u32, 0],
        };
        let z_test = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let replace = |target| ColourOutput { target, blend: Blend::Replace };
        let group = |layer: u32| frame.groups.get(layer as usize).cloned().unwrap_or(0..0);
        let mut commands = Vec::new();
        for layer in 0..k {
            let pass = SplatPass {
                label: "Alg2Nearest::pass",
                shader: "alg2_nearest.wgsl",
                entry: "fs_alg2_nearest",
                variant: variant(frame),
                colour: vec![replace(NEAR_COLOUR), replace(NEAR_NORMAL), replace(NEAR_DEPTH)],
                depth: Some((NEAR_Z, z_test)),
                inputs: Vec::new(),
                layer,
                splats: group(layer),
                uniforms: uniforms(layer),
            };
            commands.push(Recorded { pass: 0, command: Command::Splats(pass) });
        }
        for layer in 0..k {
            let pass = SplatPass {
                label: "Alg2Other::pass",
                shader: "alg2_other.wgsl",
                entry: "fs_alg2_other",
                variant: variant(frame),
                colour: vec![ColourOutput { target: OTHERS, blend: Blend::Over }],
                depth: Some((OTHERS_Z, z_test)),
                inputs: vec![NEAR_COLOUR, NEAR_DEPTH],
                layer,
                splats: group(layer),
                uniforms: uniforms(layer),
            };
            commands.push(Recorded { pass: 1, command: Command::Splats(pass) });
        }
        let composite = FullscreenPass {
            label: "Alg2Composite::pass",
            shader: "alg2_composite.wgsl",
            entry: "fs_alg2_composite",
            variant: variant(frame),
            inputs: vec![NEAR_COLOUR, NEAR_DEPTH, NEAR_NORMAL, OTHERS],
            output: Output::Frame,
            blend: Blend::Replace,
            clear: true,
            uniforms: uniforms(0),
        };
        commands.push(Recorded { pass: 2, command: Command::Fullscreen(composite) });
        commands
    }

    fn blends_in_order(&self, frame: &FrameDesc<'_>) -> bool {
        frame.transparent
    }
}
