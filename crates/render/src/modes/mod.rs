//! The GPU modes, one file each. A mode turns a frame's description
//! ([`FrameDesc`]: settings, size, what the uploaded scene holds) into its
//! [`RenderPlan`]: one list of steps, each the render passes it records. The
//! renderer allocates the targets those passes bind and runs them in order.
//!
//! Policy that holds for every mode lives here, once: a transparent mode
//! (the registry's `transparent`) given a scene with nothing transparent
//! runs the opaque two-pass plan and says so ([`plan`]); the pass uniforms
//! are made by one constructor ([`FrameDesc::uniforms`]).
//!
//! A new mode is a new file here with a [`GpuMode`] implementation and its
//! line in [`gpu_mode`], plus its entry in the registry (`crates/core/src/frame/modes.rs`);
//! docs/ADDING_A_MODE.md shows the whole diff.

mod alg1;
mod alg2;
mod alpha_blend;
mod approx_peel;
mod covering;
mod deferred;
mod depth_peel;
mod eye_dome;
mod opaque_part;
mod peeling;
mod tiled;
mod two_pass;

use std::ops::Range;

use super::gpu_data::PassUniforms;
use super::passes::Command;
use super::plan::{RenderPlan, Step};
use crate::frame::{FrameSpec, RenderMode, RenderSettings};

/// Everything a mode needs to know to plan and record a frame.
#[derive(Debug, Clone)]
pub struct FrameDesc<'a> {
    /// The settings the passes read (the spec's `drawn`).
    pub settings: &'a RenderSettings,
    /// The frame as [`crate::frame::resolve`] decided it.
    pub spec: &'a FrameSpec,
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
    pub environment: Option<&'a super::environment_texture::EnvTexture>,
    /// How targets that sum every fragment of a pixel store their sums.
    pub sums: super::targets::SumPrecision,
    /// Lit by scene lights: the splats are lit once each with their shadow
    /// coefficients (uploaded beside them), and the passes blend lit colours.
    pub lights: bool,
    /// Mesh triangles the frame draws beside its splats (the passes that
    /// draw them say so with `SplatPass::triangles`; `tiled` bins them).
    pub triangles: u32,
}

impl FrameDesc<'_> {
    /// Whether normals are kept and shaded per pixel (the headlight): lighting on, no scene lights.
    pub fn normals(&self) -> bool {
        self.settings.lighting && !self.lights
    }

    /// The shading names of a pass's variant: `LIT` (the headlight, per
    /// pixel), `LIGHTS` (scene lights, per splat) or neither (unlit).
    pub fn shading_variant(&self) -> super::shaders::Variant {
        use super::shaders::Variant;
        Variant::NONE.with(Variant::LIT, self.normals()).with(Variant::LIGHTS, self.lights)
    }

    /// The lighting, in words, for the plan's variant.
    pub fn lighting_name(&self) -> &'static str {
        match (self.lights, self.settings.lighting) {
            (true, _) => "lit by scene lights",
            (false, true) => "lit",
            (false, false) => "unlit",
        }
    }

    /// Whether the splat passes low-pass filter (the EWA prefilter, in a mode that reads it).
    pub fn prefiltered(&self) -> bool {
        self.spec.low_pass_px > 0.0
    }

    /// The eye-dome lighting the frame draws, if any.
    pub fn eye_dome(&self) -> Option<crate::frame::EyeDome> {
        self.spec.eye_dome
    }

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
    /// variant in words, its group count, steps and the targets they may bind.
    pub fn plan(
        &self,
        variant: String,
        groups: usize,
        steps: Vec<Step>,
        targets: Vec<super::plan::TargetDesc>,
    ) -> RenderPlan {
        let size = (self.width, self.height);
        let mut plan =
            RenderPlan::new(self.settings.mode, variant, size, self.splats, self.epsilon, groups, steps, targets);
        // Every plan says when sums can saturate; modes append their own notes.
        plan.notes.extend(self.sums.note());
        let clip = &self.settings.clip;
        plan.clipped = !clip.is_empty();
        if plan.clipped {
            let boxed = if clip.clip_box.is_some() { " and a box" } else { "" };
            plan.notes.push(format!("clipped per pixel by {} plane(s){boxed}", clip.plane_count));
        }
        plan
    }

    /// The uniforms of one render pass: the frame's one colour, ε and depth
    /// steps, with the pass's `layer`, a `count` (K for the group modes) and
    /// a mode's `flag` (Voronoi depth).
    pub fn uniforms(&self, layer: u32, count: u32, flag: u32) -> PassUniforms {
        PassUniforms {
            uniform_colour: self.uniform_colour_rgba(),
            depth: [self.epsilon, self.depth_steps, 0.0, 0.0],
            layers: [layer, count, flag, 0],
            effect: [0.0; 4],
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
        super::plan::TargetDesc { id, format, width: self.width, height: self.height, layout, why, storage: false }
    }

    /// A single image of the frame's size that a compute pass writes.
    pub fn storage_target(
        &self,
        id: super::plan::TargetId,
        format: wgpu::TextureFormat,
        why: &'static str,
    ) -> super::plan::TargetDesc {
        super::plan::TargetDesc { storage: true, ..self.target(id, format, super::plan::Layout::Single, why) }
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

/// `pass` once per group layer 0..k: each copy draws its layer, that
/// group's instances among `groups`, with `uniforms(layer)` (the geometry
/// steps of deferred, alg1 and alg2).
pub fn per_group(
    pass: super::passes::SplatPass,
    groups: &[Range<u32>],
    k: u32,
    uniforms: impl Fn(u32) -> PassUniforms,
) -> Vec<Command> {
    (0..k)
        .map(|layer| {
            Command::Splats(super::passes::SplatPass {
                layer,
                splats: FrameDesc::group(groups, layer),
                uniforms: uniforms(layer),
                ..pass.clone()
            })
        })
        .collect()
}

/// Says so when Eq. 10's depth steps had to be capped for f32 precision, so
/// that surface layers closer than a step share one (deferred's Voronoi
/// z-test, alg1's and alg2's Eq. 10 culling).
pub fn depth_step_note(frame: &FrameDesc<'_>, uses_steps: bool) -> Vec<String> {
    use crate::depth_steps::MAX_DEPTH_STEPS;
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
    /// The steps of a frame, each with the render passes it records, and
    /// the targets they bind.
    fn plan(&self, frame: &FrameDesc<'_>) -> RenderPlan;
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
        RenderMode::Tiled => Some(&tiled::Tiled),
        RenderMode::Reference => None,
    }
}

/// The plan of a frame in its settings' mode, `None` for a mode that runs on
/// the CPU. Under the spec's opaque fallback a transparent mode draws as
/// `two-pass` does (no layer, peel or group target); the spec's notes say so.
pub fn plan(frame: &FrameDesc<'_>) -> Option<RenderPlan> {
    let implementation = gpu_mode(frame.settings.mode)?;
    let mut plan = if frame.spec.opaque_fallback { two_pass::TwoPass.plan(frame) } else { implementation.plan(frame) };
    plan.notes.extend(frame.spec.note_lines());
    Some(plan)
}
