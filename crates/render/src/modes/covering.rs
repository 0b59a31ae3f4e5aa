//! What Algorithm-1 and Algorithm-2 (Zhang & Pajarola §5.2.1-5.2.2) share:
//! K covering groups drawn each into its own layer, the shader variant, and
//! the plan's description.

use super::{FrameDesc, opaque_part};
use crate::shaders::Variant;

/// Group images K: at least one.
pub(super) fn groups(frame: &FrameDesc<'_>) -> u32 {
    frame.transparent_groups.len().max(1) as u32
}

/// The shader variant: lit or not, opaque splats drawn apart or not; colours are always full.
pub(super) fn variant(frame: &FrameDesc<'_>) -> Variant {
    frame.shading_variant().with(Variant::OPAQUE_APART, opaque_part::present(frame))
}

/// The plan's variant in words: the grouping drawn, lit or not, the
/// back-to-front order, and how opaque splats are drawn.
pub(super) fn describe(frame: &FrameDesc<'_>) -> String {
    format!(
        "{}, {}{}",
        frame.settings.grouping_for_mode(),
        frame.lighting_name(),
        if opaque_part::present(frame) { ", opaque splats apart (two-pass)" } else { "" }
    )
}
