//! `deferred`: Zhang & Pajarola 2007's deferred blending (§3, §5.1).
//!
//! The splats come grouped so that splats of one group barely overlap (§4).
//! One geometry traversal draws group k into layer k of 2D array targets, each
//! layer with its own z-buffer (so K is not bounded by the colour attachments
//! a pass may have): in each pixel the group's nearest splat writes w·rgb, w,
//! w·n and its true view depth (Fig. 11; Voronoi depth, Eq. 14, separates
//! surface layers by the Eq. 10 low-precision depth and picks the nearest
//! centre within one). A full-screen pass then takes d = min_k depth_k, sums
//! the layers within d + ε, normalises and shades (Fig. 6).
//!
//! With `--edl` the composite shades into an image of its own, and eye-dome
//! lighting (`super::eye_dome`) reads it with the group images' depths.

use super::eye_dome::{self, FrontDepth};
use super::{FrameDesc, GpuMode, depth_step_note, per_group};
use crate::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, SplatPass};
use crate::plan::{Layout, RenderPlan, Step, TargetId};
use crate::shaders::Variant;
use crate::targets::{ACCUM_FORMAT, DEPTH_FORMAT, VIEW_DEPTH_FORMAT, colour_format};

pub struct Deferred;

const COLOUR: TargetId = TargetId("group colour");
const WEIGHT: TargetId = TargetId("group weight");
const NORMAL: TargetId = TargetId("group normal");
const VIEW_DEPTH: TargetId = TargetId("group depth");
const Z_BUFFER: TargetId = TargetId("group z-buffer");

/// Group layers K: at least one, so an ungrouped scene is one group.
fn groups(frame: &FrameDesc<'_>) -> u32 {
    frame.groups.len().max(1) as u32
}

fn colour(frame: &FrameDesc<'_>) -> TargetId {
    if frame.weight_only() { WEIGHT } else { COLOUR }
}

/// What the group layers hold, in the order of the geometry pass's outputs.
fn layer_outputs(frame: &FrameDesc<'_>) -> Vec<TargetId> {
    let mut outputs = vec![colour(frame)];
    if frame.normals() {
        outputs.push(NORMAL);
    }
    outputs.push(VIEW_DEPTH);
    outputs
}

/// What the compositing pass reads, in the order of its bindings.
fn composite_inputs(frame: &FrameDesc<'_>) -> Vec<TargetId> {
    let mut inputs = vec![colour(frame), VIEW_DEPTH];
    if frame.normals() {
        inputs.push(NORMAL);
    }
    inputs
}

/// The group passes, the first also drawing the mesh triangles: a triangle
/// wins group 0's z-test where it is nearest (its fragments have ρ = 0, the
/// Voronoi z of a splat's centre), and the compositing sums it with the
/// other groups' splats within ε, as it sums splats.
fn with_triangles_in_group_0(mut passes: Vec<Command>) -> Vec<Command> {
    if let Some(Command::Splats(first)) = passes.first_mut() {
        first.triangles = true;
    }
    passes
}

impl GpuMode for Deferred {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let k = groups(frame);
        let target = |id, format, why| frame.target(id, format, Layout::Array { layers: k }, why);
        let mut targets = vec![
            target(WEIGHT, colour_format(true), "Eq. 4's weight per group; the scene has one colour"),
            target(COLOUR, colour_format(false), "Eq. 4: each group's weighted colour w·rgb, w"),
            target(NORMAL, ACCUM_FORMAT, "w·n, w·α for deferred shading"),
            target(VIEW_DEPTH, VIEW_DEPTH_FORMAT, "true view depth for the ε-z test of Fig. 6"),
            target(Z_BUFFER, DEPTH_FORMAT, "z-test within each group (Voronoi depth if on)"),
        ];
        targets.extend(eye_dome::targets(frame));
        let variant = frame.shading_variant().with(Variant::WEIGHT_ONLY, frame.weight_only());
        let uniforms = |layer: u32| frame.uniforms(layer, k, frame.settings.voronoi as u32);
        let outputs: Vec<ColourOutput> =
            layer_outputs(frame).into_iter().map(|target| ColourOutput { target, blend: Blend::Replace }).collect();
        let z_test = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let geometry = SplatPass {
            label: "DeferredGeometry::pass",
            shader: "deferred_geometry.wgsl",
            entry: "fs_group",
            variant,
            colour: outputs,
            depth: Some((Z_BUFFER, z_test)),
            inputs: Vec::new(),
            layer: 0,
            splats: 0..0,
            back_to_front: false,
            uniforms: uniforms(0),
            triangles: false,
        };
        let composite = FullscreenPass {
            output: eye_dome::output(frame),
            ..FullscreenPass::into_frame(
                "Composite::pass",
                ("deferred_composite.wgsl", "fs_composite"),
                variant,
                composite_inputs(frame),
                uniforms(0),
            )
        };
        let mut steps = vec![
            Step::new(
                "group images",
                "splats of group k -> layer k: w·rgb, w (+ w·n) + depth; z-test per group",
                with_triangles_in_group_0(per_group(geometry, frame.groups, k, uniforms)),
            ),
            Step::new(
                "composite",
                "full screen: d = min_k depth_k, sum the layers within d + ε, normalise, shade",
                vec![Command::Fullscreen(composite)],
            ),
        ];
        let front = FrontDepth::Groups { colour: colour(frame), depth: VIEW_DEPTH, groups: k };
        steps.extend(eye_dome::step(frame, front));
        let variant = format!(
            "{}, {}, Voronoi {}{}",
            frame.settings.grouping,
            frame.lighting_name(),
            if frame.settings.voronoi { "on" } else { "off" },
            if frame.weight_only() { ", weights only" } else { "" }
        );
        let mut plan = frame.plan(variant, k as usize, steps, targets);
        plan.notes.extend(depth_step_note(frame, frame.settings.voronoi));
        plan
    }
}
