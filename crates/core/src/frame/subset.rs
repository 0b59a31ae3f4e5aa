//! Splats chosen per view from what a scene holds, behind one trait: the
//! nodes of the multi-resolution hierarchy under a point budget
//! ([`crate::lod::subset::BudgetSubset`]), the splats drawn beside a hybrid
//! object's triangles (Guennebaud §4, [`crate::hybrid::subset::HybridSubset`]),
//! and a streamed file's nodes ([`crate::copc::subset::StreamSubset`]). Each
//! yields its splats in world space and a key that names them, so the
//! renderer keeps what it prepared for them (upload, per-frame grouping,
//! shadows) by key and never asks how they were chosen. A tree of nodes
//! prepared once can stand behind this trait for all three.

use super::spec::per_node_hash;
use super::{Camera, RenderSettings};
use crate::cloud::PointCloud;
use crate::grouping::Grouping;
use crate::grouping::hash::HashOptions;

/// What a frame's settings say about choosing its splats, in memory and
/// streamed alike: the radius scale the splats are drawn at, whether
/// nodes outside the view are dropped (not when the frame is lit by scene
/// lights: off-screen splats still cast its shadows), and the hash grouping
/// a streamed file's nodes are labelled with when the mode draws groups.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Choosing {
    pub radius_scale: f32,
    pub cull: bool,
    /// Set when the frame's mode draws groups: a streamed node's labels
    /// ([`crate::frame::spec::per_node_hash`] of the mode's grouping).
    pub groups: Option<HashOptions>,
}

impl Choosing {
    /// How a frame drawn with `drawn` chooses its splats.
    pub fn of(drawn: &RenderSettings) -> Self {
        Choosing {
            radius_scale: drawn.radius_scale,
            cull: !drawn.lit_by_lights(),
            groups: drawn.mode.needs_grouping().then(|| per_node_hash(drawn.grouping_for_mode())).flatten(),
        }
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
    /// The splats' groups, when the subset labels them as they are chosen
    /// (a streamed file's nodes, each labelled once: [`NodeGrouping`]).
    pub grouping: Option<NodeGrouping>,
    /// Which splats each node holds, when the subset is a tree of nodes
    /// drawn whole (a streamed file's: [`NodeSpans`]).
    pub spans: Option<std::sync::Arc<NodeSpans>>,
}

/// Groups a subset gave its splats with the splats themselves (a streamed
/// file's nodes, each labelled once, on a world lattice per level): the
/// hash grouping of `options`, without §4.4.2's extension (the frame adds it).
#[derive(Debug, Clone)]
pub struct NodeGrouping {
    pub options: HashOptions,
    pub grouping: std::sync::Arc<Grouping>,
}

/// Which splats of a choice each of its nodes holds, in the splats' order:
/// node `n` of `(n, splats)` holds `splats`. The renderer keeps a node's
/// splats in the same GPU slots for as long as it stays drawn
/// (`node_pool.rs` of the render crate), so a new choice writes only the
/// nodes it adds.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct NodeSpans(pub Vec<(u32, std::ops::Range<u32>)>);

impl NodeSpans {
    /// The spans of nodes whose records (`(node, records)`, in record
    /// order) became splats `splat_of` (one per record, `u32::MAX` for one
    /// dropped; a copy merged into an earlier record's splat takes no new
    /// one): a node holds the splats its records were the first of.
    /// `None` when the records do not add up to `splat_of`.
    pub fn of_records(nodes: impl Iterator<Item = (u32, usize)>, splat_of: &[u32]) -> Option<Self> {
        let (mut spans, mut record, mut next) = (Vec::new(), 0usize, 0u32);
        for (node, records) in nodes {
            let start = next;
            for &splat in splat_of.get(record..record + records)? {
                if splat != u32::MAX && splat >= next {
                    next = splat + 1;
                }
            }
            record += records;
            spans.push((node, start..next));
        }
        (record == splat_of.len()).then_some(NodeSpans(spans))
    }

    /// The splats of all the nodes.
    pub fn splats(&self) -> u32 {
        self.0.iter().map(|(_, s)| s.len() as u32).sum()
    }
}

/// Splats chosen per view.
pub trait Subset {
    type Error;

    /// Chooses the splats of a frame from `camera` at `size`, as its
    /// settings say ([`Choosing`]: the radius scale that sizes them, and
    /// whether what is off screen is left out).
    fn choose(&mut self, camera: &Camera, size: (u32, u32), choosing: Choosing) -> Result<Choice, Self::Error>;
}
