//! The opaque splats of a transparent scene, drawn apart (Zhang & Pajarola
//! Fig. 18/19): `alg1` and `alg2` draw them first with `two-pass`'s steps,
//! in high quality, into [`OPAQUE_IMAGE`] and [`OPAQUE_DEPTH`]; the
//! transparent passes then cull fragments behind that depth and composite
//! over that image instead of the background.

use super::FrameDesc;
use super::two_pass::{self, OPAQUE_TARGETS};
use crate::plan::{Step, TargetDesc, TargetId};

pub(super) use super::two_pass::{OPAQUE_DEPTH, OPAQUE_IMAGE};

/// Whether the frame draws its opaque splats apart.
pub(super) fn present(frame: &FrameDesc<'_>) -> bool {
    !frame.opaque.is_empty()
}

/// Its targets and steps, none when there are no opaque splats.
pub(super) fn plan(frame: &FrameDesc<'_>) -> (Vec<TargetDesc>, Vec<Step>) {
    if present(frame) {
        (two_pass::targets(frame, &OPAQUE_TARGETS), two_pass::steps(frame, &OPAQUE_TARGETS, frame.opaque.clone()))
    } else {
        Default::default()
    }
}

/// `reads` and, when the opaque splats are drawn apart, `opaque`.
pub(super) fn with_opaque(frame: &FrameDesc<'_>, mut reads: Vec<TargetId>, opaque: TargetId) -> Vec<TargetId> {
    if present(frame) {
        reads.push(opaque);
    }
    reads
}
