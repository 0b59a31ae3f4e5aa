//! The GPU modes, one file each. A mode turns a frame's description
//! ([`FrameDesc`]: settings, size, what the uploaded scene holds) into its
//! [`RenderPlan`] (passes and targets) and records the plan as commands; the
//! renderer allocates the plan's targets and runs the commands.
//!
//! A new mode is a new file here with a [`GpuMode`] implementation, one line
//! in [`gpu_mode`], and its entry in the registry (`src/view/modes.rs`).

mod alg1;
mod alg2;
mod alpha_blend;
mod approx_peel;
mod deferred;
mod depth_peel;
mod peeling;
mod two_pass;

use std::ops::Range;

use super::passes::Recorded;
use super::plan::RenderPlan;
use crate::view::{RenderMode, RenderSettings};

/// Everything a mode needs to know to plan and record a frame.
#[derive(Debug, Clone)]
pub struct FrameDesc<'a> {
    pub settings: &'a RenderSettings,
    pub width: u32,
    pub height: u32,
    pub splats: usize,
    /// Instance ranges of the groups (one range over everything when ungrouped).
    pub groups: &'a [Range<u32>],
    /// The transparent splats of each group (the groups themselves unless the
    /// scene mixes opaque and transparent splats; see `GpuScene`).
    pub transparent_groups: &'a [Range<u32>],
    /// Instances of the scene's opaque splats drawn apart, under the
    /// transparent layers (empty unless grouped and mixed).
    pub opaque: Range<u32>,
    /// The scene's one colour, when every splat has it: colour targets then hold only weights.
    pub uniform_colour: Option<[u8; 3]>,
    /// ε in view-depth units.
    pub epsilon: f32,
    /// Low-precision depth steps n over the depth range (Zhang & Pajarola Eq. 10): (far - near)/ε.
    pub depth_steps: f32,
    /// Whether some splat is less than opaque (transparent modes draw an opaque scene opaquely).
    pub transparent: bool,
    /// The scene's environment map on the GPU, when it has one.
    pub environment: Option<&'a super::environment::EnvTexture>,
    /// How targets that sum every fragment of a pixel store their sums.
    pub sums: super::targets::SumPrecision,
}

impl FrameDesc<'_> {
    /// Whether colour targets hold only weights (a scene of one colour).
    pub fn weight_only(&self) -> bool {
        self.uniform_colour.is_some()
    }

    /// The format of a target that sums every fragment of a pixel, of four
    /// channels or one (see [`super::targets::SumPrecision`]).
    pub fn sum_format(&self, one_channel: bool) -> wgpu::TextureFormat {
        self.sums.format(one_channel)
    }

    /// The plan of this frame: its size, splats and ε, with the mode's
    /// variant in words, its group count, passes and targets.
    pub fn plan(
        &self,
        variant: String,
        groups: usize,
        passes: Vec<super::plan::PlannedPass>,
        targets: Vec<super::plan::TargetDesc>,
    ) -> RenderPlan {
        RenderPlan {
            mode: self.settings.mode,
            variant,
            width: self.width,
            height: self.height,
            splats: self.splats,
            epsilon: self.epsilon,
            groups,
            passes,
            // Every plan says when sums can saturate; modes append their own notes.
            notes: self.sums.note().into_iter().collect(),
            targets,
        }
    }

    /// A target of the frame's size.
    pub fn target(
        &self,
        id: super::plan::TargetId,
        format: wgpu::TextureFormat,
        layout: super::plan::Layout,
        why: &'static str,
    ) -> super::plan::TargetDesc {
        super::plan::TargetDesc { id, format, width: self.width, height: self.height, layout, why }
    }

    /// The instances of group `k` among `groups` (none past the last group).
    pub fn group(groups: &[Range<u32>], k: u32) -> Range<u32> {
        groups.get(k as usize).cloned().unwrap_or(0..0)
    }

    /// The one colour as a uniform (rgb 0..1), zero when there is none.
    pub fn uniform_colour_rgba(&self) -> [f32; 4] {
        match self.uniform_colour {
            Some([r, g, b]) => [r as f32 / 255.0, g as f32 / 255.0, b as f32 / 255.0, 1.0],
            None => [0.0; 4],
        }
    }
}

/// `pass` once per group layer 0..k, in plan pass `plan_pass`: each copy
/// draws its layer, that group's instances among `groups`, with
/// `uniforms(layer)` (the geometry passes of deferred, alg1 and alg2).
pub fn per_group(
    pass: super::passes::SplatPass,
    groups: &[Range<u32>],
    k: u32,
    plan_pass: usize,
    uniforms: impl Fn(u32) -> super::gpu_data::PassUniforms,
) -> Vec<Recorded> {
    (0..k)
        .map(|layer| {
            let pass = super::passes::SplatPass {
                layer,
                splats: FrameDesc::group(groups, layer),
                uniforms: uniforms(layer),
                ..pass.clone()
            };
            Recorded { pass: plan_pass, command: super::passes::Command::Splats(pass) }
        })
        .collect()
}

/// Says so when Eq. 10's depth steps had to be capped for f32 precision, so
/// that surface layers closer than a step share one (deferred's Voronoi
/// z-test, alg1's and alg2's Eq. 10 culling).
pub fn depth_step_note(frame: &FrameDesc<'_>, uses_steps: bool) -> Vec<String> {
    use crate::render::depth_steps::MAX_DEPTH_STEPS;
    if !uses_steps || frame.depth_steps < MAX_DEPTH_STEPS {
        return Vec::new();
    }
    vec![format!(
        "the depth range is more than {MAX_DEPTH_STEPS} × ε deep: Eq. 10's low-precision depth is capped at \
         {MAX_DEPTH_STEPS} steps (f32 precision), so surface layers closer than a step are not separated"
    )]
}

/// A render mode that runs on the GPU.
pub trait GpuMode: Sync {
    /// The passes and targets of a frame.
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan;
    /// The frame's render passes, in order, each tagged with its plan pass.
    fn record(&self, frame: &FrameDesc<'_>, plan: &RenderPlan) -> Vec<Recorded>;
    /// Whether the frame draws each group back to front (the renderer then
    /// sorts the scene's instances for the view first).
    fn blends_in_order(&self, _frame: &FrameDesc<'_>) -> bool {
        false
    }
}

/// The GPU implementation of `mode`, or `None` for a mode that runs on the CPU.
pub fn gpu_mode(mode: RenderMode) -> Option<&'static dyn GpuMode> {
    match mode {
        RenderMode::TwoPass => Some(&two_pass::TwoPass),
        RenderMode::Deferred => Some(&deferred::Deferred),
        RenderMode::DepthPeel => Some(&depth_peel::DepthPeel),
        RenderMode::ApproxPeel => Some(&approx_peel::ApproxPeel),
        RenderMode::Alg1 => Some(&alg1::Alg1),
        RenderMode::Alg2 => Some(&alg2::Alg2),
        RenderMode::AlphaBlend => Some(&alpha_blend::AlphaBlend),
        RenderMode::Reference => None,
    }
}
