//! `two-pass`: Botsch & Kobbelt 2003's standard pipeline.
//!
//! Filtered (2+1 passes): a visibility pass writes each pixel's nearest depth
//! pushed back by ε (§3.3); an accumulation pass adds w·colour, w and w·normal
//! of every fragment within ε of it (Eq. 3 weights, additive blending); a
//! full-screen pass divides by Σw and shades (§3.4). Unfiltered (1+1, §5): the
//! nearest splat wins each pixel with weight 1, then the same normalisation.
//!
//! The transparent grouped modes draw a scene's opaque splats with the same
//! passes ([`OpaquePart`]) into an image of their own, under their layers.

use super::{FrameDesc, GpuMode};
use crate::render::gpu_data::PassUniforms;
use crate::render::passes::{Blend, ColourOutput, Command, DepthTest, FullscreenPass, Output, Recorded, SplatPass};
use crate::render::plan::{Layout, PlannedPass, RenderPlan, TargetDesc, TargetId};
use crate::render::shaders::Variant;
use crate::render::targets::{ACCUM_FORMAT, DEPTH_FORMAT};
use crate::view::Quality;
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

/// `two-pass` itself: into the frame.
const OWN: Targets = Targets {
    depth: TargetId("depth"),
    colour: TargetId("accumulated colour"),
    weight: TargetId("accumulated weight"),
    normal: TargetId("accumulated normal"),
    image: None,
};

/// The opaque splats of a transparent scene, drawn apart into [`OPAQUE_IMAGE`].
pub(super) const OPAQUE: Targets = Targets {
    depth: TargetId("opaque depth"),
    colour: TargetId("opaque colour"),
    weight: TargetId("opaque weight"),
    normal: TargetId("opaque normal"),
    image: Some(OPAQUE_IMAGE),
};

/// The opaque splats shaded over the background: what the transparent layers go over.
pub(super) const OPAQUE_IMAGE: TargetId = TargetId("opaque image");
/// Their front + ε: transparent fragments behind it are culled.
pub(super) const OPAQUE_DEPTH: TargetId = OPAQUE.depth;

impl Targets {
    /// The colour target: (Σw·rgb, Σw), or Σw alone for a scene of one colour.
    fn colour(&self, frame: &FrameDesc<'_>) -> TargetId {
        if frame.weight_only() { self.weight } else { self.colour }
    }

    /// What the normalisation reads.
    fn sums(&self, frame: &FrameDesc<'_>) -> Vec<TargetId> {
        let mut sums = vec![self.colour(frame)];
        if lit(frame) {
            sums.push(self.normal);
        }
        sums
    }
}

fn lit(frame: &FrameDesc<'_>) -> bool {
    frame.settings.lighting
}

/// Whether `ids` are drawn filtered: `two-pass` as its quality says; the
/// opaque part of a transparent frame always (the transparent passes cull
/// behind its front + ε, which only the visibility pass leaves).
fn filtered(frame: &FrameDesc<'_>, ids: &Targets) -> bool {
    ids.image.is_some() || frame.settings.quality == Quality::Filtered
}

/// The targets and planned passes of a two-pass rendering into `ids`.
pub(super) fn plan_parts(frame: &FrameDesc<'_>, ids: &Targets) -> (Vec<TargetDesc>, Vec<PlannedPass>) {
    let target = |id, format, why| frame.target(id, format, Layout::Single, why);
    let mut targets = vec![
        target(ids.depth, DEPTH_FORMAT, "linear view depth for the ε test"),
        if frame.weight_only() {
            target(ids.weight, frame.sum_format(true), "additive Σw; the scene has one colour")
        } else {
            target(ids.colour, frame.sum_format(false), "additive Σw·rgb, Σw")
        },
    ];
    if lit(frame) {
        targets.push(target(ids.normal, frame.sum_format(false), "Σw·n, Σw·α for deferred shading"));
    }
    if let Some(image) = ids.image {
        targets.push(target(image, ACCUM_FORMAT, "the opaque splats shaded over the background"));
    }
    let sums = ids.sums(frame);
    let mut written = sums.clone();
    let mut passes = Vec::new();
    if filtered(frame, ids) {
        passes.push(PlannedPass {
            name: "visibility",
            what: "splats -> depth (linear f32, +ε)".into(),
            reads: Vec::new(),
            writes: vec![ids.depth],
            draws_splats: true,
            render_passes: 1,
        });
        passes.push(PlannedPass {
            name: "accumulate",
            what: "splats within ε of the front -> additive Σw·rgb, Σw (+ Σw·n when lit)".into(),
            reads: vec![ids.depth],
            writes: written,
            draws_splats: true,
            render_passes: 1,
        });
    } else {
        written.push(ids.depth);
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
        what: format!(
            "full screen: divide by Σw, Phong shading -> {}",
            if ids.image.is_some() { "opaque image" } else { "output" }
        ),
        reads: sums,
        writes: ids.image.into_iter().collect(),
        draws_splats: false,
        render_passes: 1,
    });
    (targets, passes)
}

/// The commands of a two-pass rendering of `splats` into `ids`, its plan
/// passes numbered from `first_pass`.
pub(super) fn record_parts(
    frame: &FrameDesc<'_>,
    ids: &Targets,
    splats: Range<u32>,
    first_pass: usize,
) -> Vec<Recorded> {
    let variant = Variant::NONE.with(Variant::LIT, lit(frame)).with(Variant::WEIGHT_ONLY, frame.weight_only());
    let uniforms = PassUniforms {
        uniform_colour: frame.uniform_colour_rgba(),
        depth: [frame.epsilon, frame.depth_steps, 0.0, 0.0],
        layers: [0, 1, 0, 0],
    };
    let outputs = |blend| {
        let mut out = vec![ColourOutput { target: ids.colour(frame), blend }];
        if lit(frame) {
            out.push(ColourOutput { target: ids.normal, blend });
        }
        out
    };
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
        uniforms,
    };
    let mut commands = Vec::new();
    if filtered(frame, ids) {
        let visibility = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let within_epsilon = DepthTest { write: false, compare: wgpu::CompareFunction::LessEqual, clear: false };
        let first = pass("Visibility::pass", "visibility.wgsl", "fs_visibility", Variant::NONE, Vec::new(), visibility);
        let second =
            pass("Accumulate::pass", "accumulate.wgsl", "fs_accumulate", variant, outputs(Blend::Add), within_epsilon);
        commands.push(Recorded { pass: first_pass, command: Command::Splats(first) });
        commands.push(Recorded { pass: first_pass + 1, command: Command::Splats(second) });
    } else {
        let nearest = DepthTest { write: true, compare: wgpu::CompareFunction::Less, clear: true };
        let only =
            pass("NearestSplat::pass", "accumulate.wgsl", "fs_unfiltered", variant, outputs(Blend::Replace), nearest);
        commands.push(Recorded { pass: first_pass, command: Command::Splats(only) });
    }
    let normalize = FullscreenPass {
        label: "Normalize::pass",
        shader: "normalize.wgsl",
        entry: "fs_normalize",
        // Into the opaque image, α says where an opaque splat was drawn.
        variant: variant.with(Variant::OPAQUE_APART, ids.image.is_some()),
        inputs: ids.sums(frame),
        output: ids.image.map_or(Output::Frame, Output::Target),
        blend: Blend::Replace,
        clear: true,
        uniforms,
    };
    let normalize_pass = first_pass + if filtered(frame, ids) { 2 } else { 1 };
    commands.push(Recorded { pass: normalize_pass, command: Command::Fullscreen(normalize) });
    commands
}

/// The opaque splats of a transparent scene drawn apart (when it has some):
/// two-pass into [`OPAQUE_IMAGE`] and [`OPAQUE_DEPTH`], which the transparent
/// passes then read.
pub(super) struct OpaquePart;

impl OpaquePart {
    /// Whether the frame draws its opaque splats apart.
    pub fn present(frame: &FrameDesc<'_>) -> bool {
        !frame.opaque.is_empty()
    }

    /// Its targets and planned passes, none when there are no opaque splats.
    pub fn plan(frame: &FrameDesc<'_>) -> (Vec<TargetDesc>, Vec<PlannedPass>) {
        if Self::present(frame) { plan_parts(frame, &OPAQUE) } else { Default::default() }
    }

    /// Its commands (plan passes from 0), none when there are no opaque splats.
    pub fn record(frame: &FrameDesc<'_>) -> Vec<Recorded> {
        if Self::present(frame) { record_parts(frame, &OPAQUE, frame.opaque.clone(), 0) } else { Vec::new() }
    }
}

impl GpuMode for TwoPass {
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan {
        let (targets, passes) = plan_parts(frame, &OWN);
        let variant = format!(
            "{}, {}{}",
            if filtered(frame, &OWN) { "filtered" } else { "unfiltered" },
            if lit(frame) { "lit" } else { "unlit" },
            if frame.weight_only() { ", weights only" } else { "" }
        );
        frame.plan(variant, 1, passes, targets)
    }

    fn record(&self, frame: &FrameDesc<'_>, _plan: &RenderPlan) -> Vec<Recorded> {
        record_parts(frame, &OWN, 0..frame.splats as u32, 0)
    }
}
