//! Eye-dome lighting as the last step of an opaque frame (the formula is
//! `crate::frame::eye_dome`'s; the pass is shaders/eye_dome.wgsl).
//!
//! A mode that reads `--edl` shades into [`SHADED_IMAGE`] instead of the
//! frame, and this one full-screen pass multiplies that image by the
//! shading of the nearest surface's depth, which the mode already keeps:
//! `two-pass` in its visibility buffer (pushed back by ε when filtered),
//! `deferred` in its K group images' true view depths. No splat is drawn
//! again, and the step is in the plan only when asked for.

use super::FrameDesc;
use crate::passes::{Command, FullscreenPass, Output};
use crate::plan::{Layout, Step, TargetDesc, TargetId};
use crate::shaders::Variant;
use crate::targets::ACCUM_FORMAT;

/// The mode's shaded image, before eye-dome lighting.
pub const SHADED_IMAGE: TargetId = TargetId("shaded image");

/// Where the pass reads the nearest surface's view depth.
pub enum FrontDepth {
    /// A visibility buffer (linear depth mapped to 0..1) pushed back by `push` (ε, or 0).
    Buffer { target: TargetId, push: f32 },
    /// K group images: the nearest of their true view depths where their colour has weight.
    Groups { colour: TargetId, depth: TargetId, groups: u32 },
}

/// Where a mode that would write the frame writes instead: the shaded image under eye-dome lighting.
pub fn output(frame: &FrameDesc<'_>) -> Output {
    if frame.eye_dome().is_some() { Output::Target(SHADED_IMAGE) } else { Output::Frame }
}

/// The shaded image's target, when eye-dome lighting is on.
pub fn targets(frame: &FrameDesc<'_>) -> Vec<TargetDesc> {
    let image = frame.target(SHADED_IMAGE, ACCUM_FORMAT, Layout::Single, "the shaded image, before eye-dome lighting");
    frame.eye_dome().map(|_| image).into_iter().collect()
}

/// The eye-dome step, when eye-dome lighting is on; `depth` says where the
/// mode keeps the nearest surface's depth.
pub fn step(frame: &FrameDesc<'_>, depth: FrontDepth) -> Option<Step> {
    let edl = frame.eye_dome()?;
    let (variant, inputs, push, groups) = match depth {
        FrontDepth::Buffer { target, push } => (Variant::NONE, vec![SHADED_IMAGE, target], push, 1),
        FrontDepth::Groups { colour, depth, groups } => (
            Variant::GROUP_DEPTH.with(Variant::WEIGHT_ONLY, frame.weight_only()),
            vec![SHADED_IMAGE, colour, depth],
            0.0,
            groups,
        ),
    };
    let mut uniforms = frame.uniforms(0, groups, 0);
    uniforms.effect = [edl.strength, edl.radius_px, push, 0.0];
    let pass = FullscreenPass::into_frame("EyeDome::pass", ("eye_dome.wgsl", "fs_eye_dome"), variant, inputs, uniforms);
    Some(Step::new(
        "eye-dome lighting",
        format!(
            "full screen: the shaded image × exp(-300·{}·log-depth steps to 8 neighbours at {} px) -> output",
            edl.strength, edl.radius_px
        ),
        vec![Command::Fullscreen(pass)],
    ))
}
