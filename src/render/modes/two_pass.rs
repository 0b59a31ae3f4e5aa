//! `two-pass`: Botsch & Kobbelt 2003's standard pipeline.
//!
//! Filtered (2+1 passes): a visibility pass writes each pixel's nearest depth
//! pushed back by ε (§3.3); an accumulation pass adds w·colour, w and w·normal
//! of every fragment within ε of it (Eq. 3 weights, additive blending); a
//! full-screen pass divides by Σw and shades (§3.4). Unfiltered (1+1, §5): the
//! nearest splat wins each pixel with weight 1, then the same normalisation.

use super::{FrameDesc, GpuMode};
use crate::render::gpu_data::PassUniforms;
use crate::render::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, Output, Recorded, SplatPass};
use crate::render::plan::{Layout, PlannedPass, RenderPlan, TargetDesc, TargetId};
use crate::render::shaders::Variant;
use crate::render::targets::{ACCUM_FORMAT, DEPTH_FORMAT, colour_format};
use crate::view::Quality;

pub struct TwoPass;

const DEPTH: TargetId = TargetId("depth");
const COLOUR: TargetId = TargetId("accumulated colour");
const WEIGHT: TargetId = TargetId("accumulated weight");
const NORMAL: TargetId = TargetId("accumulated normal");

/// The colour target: (Σw·rgb, Σw), or Σw alone for a scene of one colour.
fn colour(frame: &FrameDesc<'_>) -> TargetId {
    if frame.weight_only() { WEIGHT } else { COLOUR }
}

fn lit(frame: &FrameDesc<'_>) -> bool {
    frame.settings.lighting
}

impl GpuMode for TwoPass {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let (w, h) = (frame.width, frame.height);
        let target = |id, format, why| TargetDesc { id, format, width: w, height: h, layout: Layout::Single, why };
        let mut targets = vec![
            target(DEPTH, DEPTH_FORMAT, "linear view depth for the ε test"),
            if frame.weight_only() {
                target(WEIGHT, colour_format(true), "additive Σw; the scene has one colour")
            } else {
                target(COLOUR, colour_format(false), "additive Σw·rgb, Σw")
            },
        ];
        let mut sums = vec![colour(frame)];
        if lit(frame) {
            targets.push(target(NORMAL, ACCUM_FORMAT, "Σw·n, Σw·α for deferred shading"));
            sums.push(NORMAL);
        }
        let mut written = sums.clone();
        let filtered = frame.settings.quality == Quality::Filtered;
        let mut passes = Vec::new();
        if filtered {
            passes.push(PlannedPass {
                name: "visibility",
                what: "splats -> depth (linear f32, +ε)".into(),
                reads: Vec::new(),
                writes: vec![DEPTH],
                draws_splats: true,
                render_passes: 1,
            });
            passes.push(PlannedPass {
                name: "accumulate",
                what: "splats within ε of the front -> additive Σw·rgb, Σw (+ Σw·n when lit)".into(),
                reads: vec![DEPTH],
                writes: written,
                draws_splats: true,
                render_passes: 1,
            });
        } else {
            written.push(DEPTH);
            passes.push(PlannedPass {
                name: "nearest-splat",
                what: "splats -> rgb, 1 (+ n when lit); depth test and write, no blending".into(),
                reads: Vec::new(),
                writes: written,
                draws_splats: true,
                render_passes: 1,
            });
        }
        passes.push(PlannedPass {
            name: "normalize",
            what: "full screen: divide by Σw, Phong shading -> output".into(),
            reads: sums,
            writes: Vec::new(),
            draws_splats: false,
            render_passes: 1,
        });
        let variant = format!(
            "{}, {}{}",
            if filtered { "filtered" } else { "unfiltered" },
            if lit(frame) { "lit" } else { "unlit" },
            if frame.weight_only() { ", weights only" } else { "" }
        );
        RenderPlan {
            mode: frame.settings.mode,
            variant,
            width: w,
            height: h,
            splats: frame.splats,
            epsilon: frame.epsilon,
            groups: 1,
            passes,
            targets,
            notes: Vec::new(),
        }
    }

    fn record(&self, frame: &FrameDesc<'_>, plan: &RenderPlan) -> Vec<Recorded> {
        let variant = Variant::NONE.with(Variant::LIT, lit(frame)).with(Variant::WEIGHT_ONLY, frame.weight_only());
        let uniforms = PassUniforms {
            uniform_colour: frame.uniform_colour_rgba(),
            depth: [frame.epsilon, frame.depth_steps, 0.0, 0.0],
            layers: [0, 1, 0, 0],
        };
        let outputs = |blend| {
            let mut out = vec![ColourOutput { target: colour(frame), blend }];
            if lit(frame) {
                out.push(ColourOutput { target: NORMAL, blend });
            }
            out
        };
        let splats = |label, shader, entry, variant, colour, depth| SplatPass {
            label,
            shader,
            entry,
            variant,
            colour,
            depth: Some((DEPTH, depth)),
            inputs: Vec::new(),
            layer: 0,
            splats: 0..frame.splats as u32,
            uniforms,
        };
        let mut commands = Vec::new();
        let filtered = frame.settings.quality == Quality::Filtered;
        if filtered {
            let visibility = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
            let within_epsilon = DepthTest { write: false, compare: wgpu::CompareFunction::LessEqual, clear: false };
            let first =
                splats("Visibility::pass", "visibility.wgsl", "fs_visibility", Variant::NONE, Vec::new(), visibility);
            let second = splats(
                "Accumulate::pass",
                "accumulate.wgsl",
                "fs_accumulate",
                variant,
                outputs(Blend::Add),
                within_epsilon,
            );
            commands.push(Recorded { pass: 0, command: Command::Splats(first) });
            commands.push(Recorded { pass: 1, command: Command::Splats(second) });
        } else {
            let nearest = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
            let only = splats(
                "NearestSplat::pass",
                "accumulate.wgsl",
                "fs_unfiltered",
                variant,
                outputs(Blend::Replace),
                nearest,
            );
            commands.push(Recorded { pass: 0, command: Command::Splats(only) });
        }
        let inputs = plan.passes.last().map(|p| p.reads.clone()).unwrap_or_default();
        let normalize = FullscreenPass {
            label: "Normalize::pass",
            shader: "normalize.wgsl",
            entry: "fs_normalize",
            variant,
            inputs,
            output: Output::Frame,
            blend: Blend::Replace,
            clear: true,
            uniforms,
        };
        commands.push(Recorded { pass: plan.passes.len() - 1, command: Command::Fullscreen(normalize) });
        commands
    }
}
