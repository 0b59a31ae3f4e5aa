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
use crate::gpu_data::PassUniforms;
use crate::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, SplatPass};
use crate::plan::{Layout, Step, TargetDesc, TargetId};
use crate::shaders::Variant;
use crate::targets::DEPTH_FORMAT;

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
    frame.shading_variant().with(Variant::WEIGHT_ONLY, frame.weight_only())
}

/// The colour sums target of one set of layer sums: (Σw·rgb, Σw), or Σw alone.
fn colour(frame: &FrameDesc<'_>, colour: TargetId, weight: TargetId) -> TargetId {
    if frame.weight_only() { weight } else { colour }
}

/// The sums of a layer, in the order of the accumulation's outputs and of
/// the layer shader's bindings: colour, opacity, normal (when lit).
pub fn sums(frame: &FrameDesc<'_>, [c, w, a, n]: [TargetId; 4]) -> Vec<TargetId> {
    let mut out = vec![colour(frame, c, w), a];
    if frame.normals() {
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
    if frame.normals() {
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

/// The uniforms of a pass of layer `layer`.
pub fn uniforms(frame: &FrameDesc<'_>, layer: u32) -> PassUniforms {
    frame.uniforms(layer, 0, 0)
}

/// The two splat passes of a peeled layer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LayerPass {
    /// The nearest fragment behind the previous layer, pushed back by ε.
    Visibility,
    /// The sums of every fragment within ε of that front.
    Accumulate,
}

/// A splat pass of the peeling shader: `pass` of layer `layer`, which reads
/// the previous layer's depth unless it is the first.
pub fn splat_pass(
    frame: &FrameDesc<'_>,
    layer: u32,
    pass: LayerPass,
    colour: Vec<ColourOutput>,
    depth: Option<(TargetId, DepthTest)>,
) -> SplatPass {
    let first = layer == 0;
    let (label, entry) = match (pass, first) {
        (LayerPass::Visibility, true) => ("PeelVisibility::pass", "fs_front_visibility"),
        (LayerPass::Visibility, false) => ("PeelVisibility::pass", "fs_peel_visibility"),
        (LayerPass::Accumulate, true) => ("PeelAccumulate::pass", "fs_front_accumulate"),
        (LayerPass::Accumulate, false) => ("PeelAccumulate::pass", "fs_peel_accumulate"),
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
        back_to_front: false,
        uniforms: uniforms(frame, layer),
        // Each layer peels the mesh's triangles with the splats.
        triangles: true,
    }
}

/// Additive outputs into `targets`.
pub fn additive(targets: Vec<TargetId>) -> Vec<ColourOutput> {
    targets.into_iter().map(|target| ColourOutput { target, blend: Blend::Add }).collect()
}

/// The steps of exact layers `0..layers`: three per layer.
pub fn layer_steps(frame: &FrameDesc<'_>, layers: u32) -> Vec<Step> {
    let mut out = Vec::new();
    for i in 0..layers {
        let depth = DEPTH[i as usize % 2];
        let nearest = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let within_epsilon = DepthTest { write: false, compare: wgpu::CompareFunction::LessEqual, clear: false };
        let visibility = splat_pass(frame, i, LayerPass::Visibility, Vec::new(), Some((depth, nearest)));
        let accumulate =
            splat_pass(frame, i, LayerPass::Accumulate, additive(layer_sums(frame)), Some((depth, within_epsilon)));
        // Blending under what the layers in front left (from layer 2 on) reads it.
        let composite = FullscreenPass::under(
            "PeelLayer::pass",
            ("peel_layer.wgsl", "fs_layer"),
            variant(frame),
            layer_sums(frame),
            (COMPOSITE, i == 0),
            uniforms(frame, i),
        );
        let n = i + 1;
        out.push(Step::new(
            "visibility",
            format!("layer {n}: splats behind layer {i} -> depth + ε"),
            vec![Command::Splats(visibility)],
        ));
        out.push(Step::new(
            "accumulate",
            format!("layer {n}: splats within ε of its front -> Σw·rgb, Σw, Σw·α (+ Σw·n)"),
            vec![Command::Splats(accumulate)],
        ));
        out.push(Step::new(
            "composite layer",
            format!("layer {n}: normalise, shade facing the viewer, composite under the layers in front"),
            vec![Command::Fullscreen(composite)],
        ));
    }
    out
}

/// The final step: the composite over the background.
pub fn final_step(frame: &FrameDesc<'_>) -> Step {
    let command = FullscreenPass::into_frame(
        "PeelFinal::pass",
        ("peel_final.wgsl", "fs_final"),
        Variant::NONE,
        vec![COMPOSITE],
        uniforms(frame, 0),
    );
    Step::new("final", "full screen: the composite over the background -> output", vec![Command::Fullscreen(command)])
}

/// The variant in words.
pub fn describe(frame: &FrameDesc<'_>, layers: u32) -> String {
    format!("{layers} layers, {}{}", frame.lighting_name(), if frame.weight_only() { ", weights only" } else { "" })
}

/// Layers k: the setting, or the registry's default; at least 2 (one layer
/// is not transparency; approx-peel needs one exact and one approximate).
pub fn peel_layers(frame: &FrameDesc<'_>) -> u32 {
    frame.settings.peel_layers_or_default().max(2)
}
