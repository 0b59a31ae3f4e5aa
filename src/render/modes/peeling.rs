//! What `depth-peel` and `approx-peel` share: exact layers peeled front to
//! back and composited under each other, and the final pass over the
//! background.
//!
//! Layer i is a full splat render of what lies behind layer i-1: a visibility
//! pass keeps the nearest fragment deeper than the previous layer's front + ε
//! (read from the previous layer's depth buffer; two depth targets alternate),
//! an accumulation pass adds w·rgb, w, w·α (and w·n) of every such fragment
//! within ε of it, and a full-screen pass normalises the sums, shades them
//! facing the viewer and composites the layer premultiplied under the ones
//! in front: C += (1 - A)·α·c, A += (1 - A)·α. A final pass puts the composite
//! over the background. An opaque layer makes A = 1, after which nothing
//! behind it shows, as in the exact reference.

use super::FrameDesc;
use crate::render::gpu_data::PassUniforms;
use crate::render::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, Output, Recorded, SplatPass};
use crate::render::plan::{Layout, PlannedPass, TargetDesc, TargetId};
use crate::render::shaders::Variant;
use crate::render::targets::DEPTH_FORMAT;

/// The two depth buffers layers alternate between.
pub const DEPTH: [TargetId; 2] = [TargetId("peel depth (even layers)"), TargetId("peel depth (odd layers)")];
pub const COLOUR: TargetId = TargetId("layer colour");
pub const WEIGHT: TargetId = TargetId("layer weight");
pub const OPACITY: TargetId = TargetId("layer opacity");
pub const NORMAL: TargetId = TargetId("layer normal");
pub const COMPOSITE: TargetId = TargetId("composite");

/// Format of the premultiplied composite of the layers.
const COMPOSITE_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// The shader variant of a frame: lighting, and colours or weights only.
pub fn variant(frame: &FrameDesc<'_>) -> Variant {
    Variant::NONE.with(Variant::LIT, frame.settings.lighting).with(Variant::WEIGHT_ONLY, frame.weight_only())
}

/// The colour sums target of one set of layer sums: (Σw·rgb, Σw), or Σw alone.
fn colour(frame: &FrameDesc<'_>, colour: TargetId, weight: TargetId) -> TargetId {
    if frame.weight_only() { weight } else { colour }
}

/// The sums of a layer, in the order of the accumulation's outputs and of
/// the layer shader's bindings: colour, opacity, normal (when lit).
pub fn sums(frame: &FrameDesc<'_>, [c, w, a, n]: [TargetId; 4]) -> Vec<TargetId> {
    let mut out = vec![colour(frame, c, w), a];
    if frame.settings.lighting {
        out.push(n);
    }
    out
}

/// The exact layers' sums.
pub fn layer_sums(frame: &FrameDesc<'_>) -> Vec<TargetId> {
    sums(frame, [COLOUR, WEIGHT, OPACITY, NORMAL])
}

/// A target of the view's size.
pub fn target(frame: &FrameDesc<'_>, id: TargetId, format: wgpu::TextureFormat, why: &'static str) -> TargetDesc {
    frame.target(id, format, Layout::Single, why)
}

/// The targets of one set of layer sums.
pub fn sum_targets(frame: &FrameDesc<'_>, ids: [TargetId; 4], what: &'static str) -> Vec<TargetDesc> {
    let [c, w, a, n] = ids;
    let mut out = vec![if frame.weight_only() {
        target(frame, w, frame.sum_format(true), what)
    } else {
        target(frame, c, frame.sum_format(false), what)
    }];
    out.push(target(frame, a, frame.sum_format(true), "Σw·α: the layer's opacity"));
    if frame.settings.lighting {
        out.push(target(frame, n, frame.sum_format(false), "Σw·n, turned to the viewer, for shading"));
    }
    out
}

/// The targets every peeling frame needs.
pub fn targets(frame: &FrameDesc<'_>) -> Vec<TargetDesc> {
    let mut out = vec![
        target(frame, DEPTH[0], DEPTH_FORMAT, "front + ε of even layers; read by the next layer"),
        target(frame, DEPTH[1], DEPTH_FORMAT, "front + ε of odd layers; read by the next layer"),
    ];
    out.extend(sum_targets(frame, [COLOUR, WEIGHT, OPACITY, NORMAL], "Σw·rgb, Σw of one layer"));
    out.push(target(frame, COMPOSITE, COMPOSITE_FORMAT, "the layers composited front to back, premultiplied"));
    out
}

/// The planned passes of exact layers `0..layers`.
pub fn layer_passes(frame: &FrameDesc<'_>, layers: u32) -> Vec<PlannedPass> {
    let mut out = Vec::new();
    for i in 0..layers {
        let (depth, previous) = (DEPTH[i as usize % 2], DEPTH[(i as usize + 1) % 2]);
        let reads = if i == 0 { Vec::new() } else { vec![previous] };
        let mut written = layer_sums(frame);
        out.push(PlannedPass {
            name: "visibility",
            what: format!("layer {}: splats behind layer {i} -> depth + ε", i + 1),
            reads: reads.clone(),
            writes: vec![depth],
            draws_splats: true,
            render_passes: 1,
        });
        let mut reads_depth = reads;
        reads_depth.push(depth);
        out.push(PlannedPass {
            name: "accumulate",
            what: format!("layer {}: splats within ε of its front -> Σw·rgb, Σw, Σw·α (+ Σw·n)", i + 1),
            reads: reads_depth,
            writes: std::mem::take(&mut written),
            draws_splats: true,
            render_passes: 1,
        });
        out.push(PlannedPass {
            name: "composite layer",
            what: format!("layer {}: normalise, shade facing the viewer, composite under the layers in front", i + 1),
            // Blending under what the layers in front left (from layer 2 on) reads it.
            reads: if i == 0 { layer_sums(frame) } else { [layer_sums(frame), vec![COMPOSITE]].concat() },
            writes: vec![COMPOSITE],
            draws_splats: false,
            render_passes: 1,
        });
    }
    out
}

/// The final pass.
pub fn final_pass() -> PlannedPass {
    PlannedPass {
        name: "final",
        what: "full screen: the composite over the background -> output".into(),
        reads: vec![COMPOSITE],
        writes: Vec::new(),
        draws_splats: false,
        render_passes: 1,
    }
}

/// The uniforms of a pass of layer `layer`.
pub fn uniforms(frame: &FrameDesc<'_>, layer: u32) -> PassUniforms {
    PassUniforms {
        uniform_colour: frame.uniform_colour_rgba(),
        depth: [frame.epsilon, frame.depth_steps, 0.0, 0.0],
        layers: [layer, 0, 0, 0],
    }
}

/// The two splat passes of a peeled layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Step {
    /// The nearest fragment behind the previous layer, pushed back by ε.
    Visibility,
    /// The sums of every fragment within ε of that front.
    Accumulate,
}

/// A splat pass of the peeling shader: `step` of layer `layer`, which reads
/// the previous layer's depth unless it is the first.
pub fn splat_pass(
    frame: &FrameDesc<'_>,
    layer: u32,
    step: Step,
    colour: Vec<ColourOutput>,
    depth: Option<(TargetId, DepthTest)>,
) -> SplatPass {
    let first = layer == 0;
    let (label, entry) = match (step, first) {
        (Step::Visibility, true) => ("PeelVisibility::pass", "fs_front_visibility"),
        (Step::Visibility, false) => ("PeelVisibility::pass", "fs_peel_visibility"),
        (Step::Accumulate, true) => ("PeelAccumulate::pass", "fs_front_accumulate"),
        (Step::Accumulate, false) => ("PeelAccumulate::pass", "fs_peel_accumulate"),
    };
    SplatPass {
        label,
        shader: "peel.wgsl",
        entry,
        variant: if colour.is_empty() { Variant::NONE } else { variant(frame) },
        colour,
        depth,
        inputs: if first { Vec::new() } else { vec![DEPTH[(layer as usize + 1) % 2]] },
        layer: 0,
        splats: 0..frame.splats as u32,
        uniforms: uniforms(frame, layer),
    }
}

/// Additive outputs into `targets`.
pub fn additive(targets: Vec<TargetId>) -> Vec<ColourOutput> {
    targets.into_iter().map(|target| ColourOutput { target, blend: Blend::Add }).collect()
}

/// Records exact layers `0..layers`, as planned passes `0..3·layers`.
pub fn record_layers(frame: &FrameDesc<'_>, layers: u32) -> Vec<Recorded> {
    let mut out = Vec::new();
    for i in 0..layers {
        let depth = DEPTH[i as usize % 2];
        let nearest = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let within_epsilon = DepthTest { write: false, compare: wgpu::CompareFunction::LessEqual, clear: false };
        let visibility = splat_pass(frame, i, Step::Visibility, Vec::new(), Some((depth, nearest)));
        let accumulate =
            splat_pass(frame, i, Step::Accumulate, additive(layer_sums(frame)), Some((depth, within_epsilon)));
        let composite = FullscreenPass {
            label: "PeelLayer::pass",
            shader: "peel_layer.wgsl",
            entry: "fs_layer",
            variant: variant(frame),
            inputs: layer_sums(frame),
            output: Output::Target(COMPOSITE),
            blend: Blend::Under,
            clear: i == 0,
            uniforms: uniforms(frame, i),
        };
        let first = 3 * i as usize;
        out.push(Recorded { pass: first, command: Command::Splats(visibility) });
        out.push(Recorded { pass: first + 1, command: Command::Splats(accumulate) });
        out.push(Recorded { pass: first + 2, command: Command::Fullscreen(composite) });
    }
    out
}

/// Records the final pass as planned pass `pass`.
pub fn record_final(frame: &FrameDesc<'_>, pass: usize) -> Recorded {
    let command = FullscreenPass {
        label: "PeelFinal::pass",
        shader: "peel_final.wgsl",
        entry: "fs_final",
        variant: Variant::NONE,
        inputs: vec![COMPOSITE],
        output: Output::Frame,
        blend: Blend::Replace,
        clear: true,
        uniforms: uniforms(frame, 0),
    };
    Recorded { pass, command: Command::Fullscreen(command) }
}

/// The variant in words.
pub fn describe(frame: &FrameDesc<'_>, layers: u32) -> String {
    format!(
        "{layers} layers, {}{}",
        if frame.settings.lighting { "lit" } else { "unlit" },
        if frame.weight_only() { ", weights only" } else { "" }
    )
}

/// Layers k: the setting, or the registry's default; at least 2 (one layer
/// is not transparency; approx-peel needs one exact and one approximate).
pub fn layers(frame: &FrameDesc<'_>) -> u32 {
    frame.settings.layers_or_default().max(2)
}

/// The opaque plan a transparent mode runs for a scene with nothing transparent, saying so.
pub fn opaque_fallback(
    frame: &FrameDesc<'_>,
    mut plan: crate::render::plan::RenderPlan,
) -> crate::render::plan::RenderPlan {
    plan.notes.push(format!(
        "nothing in the scene is transparent, so {} runs the opaque two-pass plan: no peeling pass, no layer target",
        frame.settings.mode
    ));
    plan.mode = frame.settings.mode;
    plan
}
