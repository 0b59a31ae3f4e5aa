//! `alg2`: Zhang & Pajarola 2007's Algorithm-2 (§5.2.2): the nearest
//! transparent layer in high quality, the layers behind it as Algorithm-1
//! draws them; two geometry passes and one compositing pass.
//!
//! Pass 1 is `deferred`'s geometry pass (group k into I_k: w·rgb, w, w·n,
//! w·α, true depth; nearest splat per group by Voronoi depth,
//! `shaders/alg2_nearest.wgsl`). A full-screen pass then finds the nearest
//! layer's depth d = min_k depth_k once per pixel (`shaders/alg2_front.wgsl`),
//! so that neither pass 2's fragments nor the composite read all K layers
//! for it. Pass 2 is Algorithm-1's geometry pass into O_k (each group back
//! to front, α-blended, Eq. 10 culling), which drops every fragment within ε
//! of d (`shaders/alg2_other.wgsl`). The compositing pass does the three blends of
//! §5.2.2 at once (`shaders/alg2_composite.wgsl`): C_F, the ε-z composited,
//! normalised and shaded nearest layer with its opacity α = Σw·α/Σw; C_O, the
//! average of the O_k over the background (with Algorithm-1's trimmed
//! opacity); and I = α·C_F + (1 - α)·C_O. The
//! groups are those of `alg1` (covering, `RenderSettings::grouping_for_mode`).
//! Opaque splats of a mixed scene are drawn apart first as in `alg1`: both
//! geometry passes cull behind them, and C_O goes over their image.

use super::covering::{describe, groups, variant};
use super::opaque_part::{self, OPAQUE_DEPTH, OPAQUE_IMAGE, with_opaque};
use super::{FrameDesc, GpuMode, depth_step_note, per_group};
use crate::frame::environment_effects::LayerEffects;
use crate::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, SplatPass};
use crate::plan::{Layout, RenderPlan, Step, TargetId};
use crate::shaders::Variant;
use crate::targets::{ACCUM_FORMAT, DEPTH_FORMAT, VIEW_DEPTH_FORMAT};

pub struct Alg2;

const NEAR_COLOUR: TargetId = TargetId("nearest layer I_k: w·rgb, w");
const NEAR_NORMAL: TargetId = TargetId("nearest layer I_k: w·n, w·α");
const NEAR_DEPTH: TargetId = TargetId("nearest layer I_k: depth");
const NEAR_Z: TargetId = TargetId("nearest layer z-buffer");
const FRONT: TargetId = TargetId("nearest layer depth d and facing");
/// d in f32 (the ε-z test's precision) and the facing (0/1).
const FRONT_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rg32Float;
const OTHERS: TargetId = TargetId("other layers O_k");
const OTHERS_Z: TargetId = TargetId("other layers Eq. 10 z-buffer");

/// Whether the other layers count themselves for the multi-layer
/// environment effects (an environment map, `--env-layers multi`).
fn multi_layer(frame: &FrameDesc<'_>) -> bool {
    frame.environment.is_some() && frame.settings.environment.layer_effects == LayerEffects::Multi
}

/// Says which environment map the composite samples and how.
fn environment_note(frame: &FrameDesc<'_>) -> Option<String> {
    let map = frame.environment?;
    let env = &frame.settings.environment;
    Some(format!(
        "environment map {} {}x{}, {} levels ({} bytes, uploaded with the scene), sampled by the composite: reflection, refraction (η {}, dispersion {}), Fresnel, {}-layer{}",
        map.name,
        map.width,
        map.height,
        map.levels,
        map.bytes(),
        env.eta,
        env.dispersion,
        env.layer_effects,
        if multi_layer(frame) { "; O_k sum their opacities (Eq. 15-16's layer count)" } else { "" }
    ))
}

impl GpuMode for Alg2 {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let k = groups(frame);
        let target = |id, format, why| frame.target(id, format, Layout::Array { layers: k }, why);
        let (mut targets, mut steps) = opaque_part::plan(frame);
        targets.extend([
            target(NEAR_COLOUR, ACCUM_FORMAT, "pass 1 (deferred): each group's nearest splat, Eq. 4 weight"),
            target(NEAR_NORMAL, ACCUM_FORMAT, "pass 1: w·n for deferred shading, w·α for the nearest layer's opacity"),
            target(NEAR_DEPTH, VIEW_DEPTH_FORMAT, "pass 1: true view depth for ε-z compositing and pass 2's culling"),
            target(NEAR_Z, DEPTH_FORMAT, "pass 1: z-test within each group (Voronoi depth)"),
            frame.target(
                FRONT,
                FRONT_FORMAT,
                Layout::Single,
                "d = min_k depth_k of pass 1 and its facing, once per pixel: what pass 2 culls and C_F sums",
            ),
            target(OTHERS, ACCUM_FORMAT, "pass 2 (Algorithm-1): the layers behind the nearest, per group"),
            target(OTHERS_Z, DEPTH_FORMAT, "pass 2: Eq. 10 low-precision depth per group"),
        ]);
        let uniforms = |layer: u32| frame.uniforms(layer, k, frame.settings.voronoi as u32);
        let z_test = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let replace = |target| ColourOutput { target, blend: Blend::Replace };
        let others_blend = if multi_layer(frame) { Blend::OverSumAlpha } else { Blend::Over };
        let nearest = SplatPass {
            label: "Alg2Nearest::pass",
            shader: "alg2_nearest.wgsl",
            entry: "fs_alg2_nearest",
            variant: variant(frame),
            colour: vec![replace(NEAR_COLOUR), replace(NEAR_NORMAL), replace(NEAR_DEPTH)],
            depth: Some((NEAR_Z, z_test)),
            inputs: with_opaque(frame, Vec::new(), OPAQUE_DEPTH),
            layer: 0,
            splats: 0..0,
            back_to_front: false,
            uniforms: uniforms(0),
            triangles: false,
        };
        let others = SplatPass {
            label: "Alg2Other::pass",
            shader: "alg2_other.wgsl",
            entry: "fs_alg2_other",
            colour: vec![ColourOutput { target: OTHERS, blend: others_blend }],
            depth: Some((OTHERS_Z, z_test)),
            inputs: with_opaque(frame, vec![FRONT], OPAQUE_DEPTH),
            back_to_front: true,
            ..nearest.clone()
        };
        let composite = FullscreenPass::into_frame(
            "Alg2Composite::pass",
            ("alg2_composite.wgsl", "fs_alg2_composite"),
            variant(frame).with(Variant::ENVIRONMENT, frame.environment.is_some()),
            with_opaque(frame, vec![NEAR_COLOUR, NEAR_DEPTH, NEAR_NORMAL, OTHERS, FRONT], OPAQUE_IMAGE),
            uniforms(0),
        );
        let front = FullscreenPass::into_target(
            "Alg2Front::pass",
            ("alg2_front.wgsl", "fs_alg2_front"),
            variant(frame),
            vec![NEAR_COLOUR, NEAR_DEPTH, NEAR_NORMAL],
            FRONT,
            uniforms(0),
        );
        steps.extend([
            Step::new(
                "nearest layer",
                "group k -> I_k as deferred draws it: w·rgb, w, w·n, w·α, depth; Voronoi z-test",
                per_group(nearest, frame.transparent_groups, k, uniforms),
            ),
            Step::new(
                "nearest depth",
                "full screen: d = min_k depth_k of the groups that drew, and its facing, once per pixel",
                vec![Command::Fullscreen(front)],
            ),
            Step::new(
                "other layers",
                "group k back to front -> O_k, without the nearest layer's fragments (within ε of d, its facing)",
                per_group(others, frame.transparent_groups, k, uniforms),
            ),
            Step::new(
                "composite",
                "full screen: C_F (ε-z, normalise, shade), C_O (mean of O_k), I = α·C_F + (1-α)·C_O",
                vec![Command::Fullscreen(composite)],
            ),
        ]);
        let mut plan = frame.plan(describe(frame), k as usize, steps, targets);
        plan.notes.extend(depth_step_note(frame, true));
        plan.notes.extend(environment_note(frame));
        plan
    }
}
