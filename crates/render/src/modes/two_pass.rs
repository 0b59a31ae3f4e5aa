//! `two-pass`: Botsch & Kobbelt 2003's standard pipeline.
//!
//! Filtered (2+1 passes): a visibility pass writes each pixel's nearest depth
//! pushed back by ε (§3.3); an accumulation pass adds w·colour, w and w·normal
//! of every fragment within ε of it (Eq. 3 weights, additive blending); a
//! full-screen pass divides by Σw and shades (§3.4). Unfiltered (1+1, §5): the
//! nearest splat wins each pixel with weight 1, then the same normalisation.
//!
//! With the EWA prefilter (filtered, into the frame) the accumulation also
//! antialiases edges (`covered`): it makes the ε test itself against the
//! visibility depth, sums the fragments behind the front apart, and adds each
//! fragment's coverage of its pixel; the normalisation lays the front over
//! what is behind it by that coverage.
//!
//! The transparent grouped modes draw a scene's opaque splats with the same
//! steps (`super::opaque_part`) into an image of their own, under their layers.
//!
//! With `--edl` the normalisation shades into an image of its own, and eye-dome
//! lighting (`super::eye_dome`) reads it with the visibility depth.

use super::eye_dome::{self, FrontDepth};
use super::{FrameDesc, GpuMode};
use crate::frame::Quality;
use crate::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, Output, SplatPass};
use crate::plan::{FrontDepthTarget, Layout, RenderPlan, Step, TargetDesc, TargetId};
use crate::shaders::Variant;
use crate::targets::{ACCUM_FORMAT, DEPTH_FORMAT};
use std::ops::Range;

pub struct TwoPass;

/// The targets of one two-pass rendering, and where its result goes.
pub(super) struct Targets {
    depth: TargetId,
    colour: TargetId,
    weight: TargetId,
    normal: TargetId,
    /// The shaded image's target, or `None` for the frame.
    image: Option<TargetId>,
}

/// The prefilter's edge antialiasing: the stretched fragments' shaded
/// colours (lit), the fragments behind the front, and their coverage.
const SHADED: TargetId = TargetId("shaded colour");
const BEHIND: TargetId = TargetId("behind colour");
const COVERAGE: TargetId = TargetId("coverage");

/// `two-pass` itself: into the frame.
const OWN: Targets = Targets {
    depth: TargetId("depth"),
    colour: TargetId("accumulated colour"),
    weight: TargetId("accumulated weight"),
    normal: TargetId("accumulated normal"),
    image: None,
};

/// The opaque splats of a transparent scene, drawn apart into [`OPAQUE_IMAGE`].
pub(super) const OPAQUE_TARGETS: Targets = Targets {
    depth: TargetId("opaque depth"),
    colour: TargetId("opaque colour"),
    weight: TargetId("opaque weight"),
    normal: TargetId("opaque normal"),
    image: Some(OPAQUE_IMAGE),
};

/// The opaque splats shaded over the background: what the transparent layers go over.
pub(super) const OPAQUE_IMAGE: TargetId = TargetId("opaque image");
/// Their front + ε: transparent fragments behind it are culled.
pub(super) const OPAQUE_DEPTH: TargetId = OPAQUE_TARGETS.depth;

impl Targets {
    /// The colour target: (Σw·rgb, Σw), or Σw alone for a scene of one colour.
    fn colour(&self, frame: &FrameDesc<'_>) -> TargetId {
        if weight_only(frame, self) { self.weight } else { self.colour }
    }

    /// What the normalisation reads.
    fn sums(&self, frame: &FrameDesc<'_>) -> Vec<TargetId> {
        let mut sums = vec![self.colour(frame)];
        if lit(frame) {
            sums.push(self.normal);
        }
        sums.extend(apart(frame, self));
        sums
    }
}

fn lit(frame: &FrameDesc<'_>) -> bool {
    frame.normals()
}

/// Whether `ids` are drawn filtered: `two-pass` as its quality says; the
/// opaque part of a transparent frame always (the transparent passes cull
/// behind its front + ε, which only the visibility pass leaves).
fn filtered(frame: &FrameDesc<'_>, ids: &Targets) -> bool {
    ids.image.is_some() || frame.settings.quality == Quality::Filtered
}

/// Whether the accumulation antialiases edges by coverage: the EWA
/// prefilter is on, filtered, drawn into the frame (the opaque part of a
/// transparent frame keeps the hardware ε test: its depth is what the
/// layers are culled by).
fn covered(frame: &FrameDesc<'_>, ids: &Targets) -> bool {
    ids.image.is_none() && filtered(frame, ids) && frame.prefiltered()
}

/// The targets the accumulation writes apart when it keeps coverage, in
/// the order it writes and the normalisation reads them (none otherwise).
fn apart(frame: &FrameDesc<'_>, ids: &Targets) -> Vec<TargetId> {
    match (covered(frame, ids), lit(frame)) {
        (false, _) => Vec::new(),
        (true, true) => vec![SHADED, BEHIND, COVERAGE],
        (true, false) => vec![BEHIND, COVERAGE],
    }
}

/// Whether the colour targets hold weights alone (a scene of one colour),
/// except where coverage is kept: a stretched splat's colour is shaded per
/// fragment, so its sums are of colours however uniform the albedo.
fn weight_only(frame: &FrameDesc<'_>, ids: &Targets) -> bool {
    frame.weight_only() && !covered(frame, ids)
}

/// The targets a two-pass rendering into `ids` may bind.
pub(super) fn targets(frame: &FrameDesc<'_>, ids: &Targets) -> Vec<TargetDesc> {
    let target = |id, format, why| frame.target(id, format, Layout::Single, why);
    let mut targets = vec![
        target(ids.depth, DEPTH_FORMAT, "linear view depth for the ε test"),
        if weight_only(frame, ids) {
            target(ids.weight, frame.sum_format(true), "additive Σw; the scene has one colour")
        } else {
            target(ids.colour, frame.sum_format(false), "additive Σw·rgb, Σw")
        },
    ];
    if lit(frame) {
        targets.push(target(ids.normal, frame.sum_format(false), "Σw·n, Σw·α for deferred shading"));
    }
    for id in apart(frame, ids) {
        let why = match id {
            SHADED => "Σw·shaded rgb, Σw of the stretched splats",
            BEHIND => "Σw·shaded rgb, Σw behind the front + ε",
            _ => "Σ coverage front, behind; solid counts",
        };
        targets.push(target(id, frame.sum_format(false), why));
    }
    match ids.image {
        Some(image) => targets.push(target(image, ACCUM_FORMAT, "the opaque splats shaded over the background")),
        None => targets.extend(eye_dome::targets(frame)),
    }
    targets
}

/// The steps of a two-pass rendering of `splats` into `ids`.
pub(super) fn steps(frame: &FrameDesc<'_>, ids: &Targets, splats: Range<u32>) -> Vec<Step> {
    let variant = frame.shading_variant().with(Variant::WEIGHT_ONLY, weight_only(frame, ids));
    let uniforms = frame.uniforms(0, 1, 0);
    let outputs = |blend| {
        let mut out = vec![ColourOutput { target: ids.colour(frame), blend }];
        if lit(frame) {
            out.push(ColourOutput { target: ids.normal, blend });
        }
        out
    };
    let covered = covered(frame, ids);
    let pass = |label, shader, entry, variant, colour, depth| SplatPass {
        label,
        shader,
        entry,
        variant,
        colour,
        depth: Some((ids.depth, depth)),
        inputs: Vec::new(),
        layer: 0,
        splats: splats.clone(),
        back_to_front: false,
        uniforms,
        triangles: true,
    };
    let mut steps = Vec::new();
    if filtered(frame, ids) {
        let visibility = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let within_epsilon = DepthTest { write: false, compare: wgpu::CompareFunction::LessEqual, clear: false };
        steps.push(Step::new(
            "visibility",
            "splats -> depth (linear f32, +ε)",
            vec![Command::Splats(pass(
                "Visibility::pass",
                "visibility.wgsl",
                "fs_visibility",
                Variant::NONE,
                Vec::new(),
                visibility,
            ))],
        ));
        let mut accumulate = pass(
            "Accumulate::pass",
            "accumulate.wgsl",
            "fs_accumulate",
            variant.with(Variant::COVERAGE, covered),
            outputs(Blend::Add),
            within_epsilon,
        );
        let mut what = "splats within ε of the front -> additive Σw·rgb, Σw (+ Σw·n when lit)".to_string();
        if covered {
            // The ε test is made in the shader, against the visibility depth as an input.
            let apart = apart(frame, ids).into_iter().map(|target| ColourOutput { target, blend: Blend::Add });
            accumulate.colour.extend(apart);
            (accumulate.depth, accumulate.inputs) = (None, vec![ids.depth]);
            what += "; the stretched ones shaded apart, those behind apart, Σ coverage and solid counts";
        }
        steps.push(Step::new("accumulate", what, vec![Command::Splats(accumulate)]));
    } else {
        let nearest = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        steps.push(Step::new(
            "nearest-splat",
            "splats -> rgb, 1 (+ n when lit); depth test and write, no blending",
            vec![Command::Splats(pass(
                "NearestSplat::pass",
                "accumulate.wgsl",
                "fs_unfiltered",
                variant,
                outputs(Blend::Replace),
                nearest,
            ))],
        ));
    }
    let normalize = FullscreenPass {
        label: "Normalize::pass",
        shader: "normalize.wgsl",
        entry: "fs_normalize",
        // Into the opaque image, α says where an opaque splat was drawn.
        variant: variant.with(Variant::OPAQUE_APART, ids.image.is_some()).with(Variant::COVERAGE, covered),
        inputs: ids.sums(frame),
        output: ids.image.map_or(eye_dome::output(frame), Output::Target),
        blend: Blend::Replace,
        clear: true,
        uniforms,
    };
    let into = match (ids.image, frame.eye_dome()) {
        (Some(_), _) => "opaque image",
        (None, Some(_)) => "shaded image",
        (None, None) => "output",
    };
    let cover = if covered { ", the front over what is behind it by coverage" } else { "" };
    steps.push(Step::new(
        "normalize",
        format!("full screen: divide by Σw, Phong shading{cover} -> {into}"),
        vec![Command::Fullscreen(normalize)],
    ));
    if ids.image.is_none() {
        // The visibility pass pushed the front back by ε; the nearest-splat pass wrote it as it is.
        let push = if filtered(frame, ids) { frame.epsilon } else { 0.0 };
        steps.extend(eye_dome::step(frame, FrontDepth::Buffer { target: ids.depth, push }));
    }
    steps
}

impl GpuMode for TwoPass {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let variant = format!(
            "{}, {}{}",
            if filtered(frame, &OWN) { "filtered" } else { "unfiltered" },
            frame.lighting_name(),
            if weight_only(frame, &OWN) { ", weights only" } else { "" }
        );
        let steps = steps(frame, &OWN, 0..frame.splats as u32);
        let mut plan = frame.plan(variant, 1, steps, targets(frame, &OWN));
        // The visibility pass pushed the front back by ε; the nearest-splat pass wrote it as it is.
        let push = if filtered(frame, &OWN) { frame.epsilon } else { 0.0 };
        plan.front_depth = Some(FrontDepthTarget { target: OWN.depth, push });
        plan
    }
}
