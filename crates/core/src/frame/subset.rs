//! Splats chosen per view from what a scene holds, behind one trait: the
//! nodes of the multi-resolution hierarchy under a point budget
//! ([`crate::lod::subset::BudgetSubset`]), the splats drawn beside a hybrid
//! object's triangles (Guennebaud §4, [`crate::hybrid::subset::HybridSubset`]),
//! and a streamed file's nodes ([`crate::copc::subset::StreamSubset`]). Each
//! yields its splats in world space and a key that names them, so the
//! renderer keeps what it prepared for them (upload, per-frame grouping,
//! shadows) by key and never asks how they were chosen. A tree of nodes
//! prepared once can stand behind this trait for all three.

use super::{Camera, RenderSettings};
use crate::cloud::PointCloud;

/// What a frame's settings say about choosing its splats, in memory and
/// streamed alike: the radius scale the splats are drawn at, and whether
/// nodes outside the view are dropped (not when the frame is lit by scene
/// lights: off-screen splats still cast its shadows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Choosing {
    pub radius_scale: f32,
    pub cull: bool,
}

impl Choosing {
    /// How a frame drawn with `drawn` chooses its splats.
    pub fn of(drawn: &RenderSettings) -> Self {
        Choosing { radius_scale: drawn.radius_scale, cull: !drawn.lit_by_lights() }
    }
}

impl Default for Choosing {
    fn default() -> Self {
        Choosing::of(&Default::default())
    }
}

/// What a subset chose for one frame.
#[derive(Debug, Clone)]
pub struct Choice {
    /// The splats in world space when the choice changed since the last
    /// frame (`None`: the last splats again).
    pub cloud: Option<PointCloud>,
    /// Names the splats chosen: the same key, the same splats.
    pub key: u64,
}

/// Splats chosen per view.
pub trait Subset {
    type Error;

    /// Chooses the splats of a frame from `camera` at `size`, as its
    /// settings say ([`Choosing`]: the radius scale that sizes them, and
    /// whether what is off screen is left out).
    fn choose(&mut self, camera: &Camera, size: (u32, u32), choosing: Choosing) -> Result<Choice, Self::Error>;
}
