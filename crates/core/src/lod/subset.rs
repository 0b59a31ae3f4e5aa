//! The nodes a frame draws under a point budget, as a [`Subset`]: chosen
//! from the scene's multi-resolution hierarchy by screen-space error
//! ([`super::select`]), gathered into one cloud only when the choice
//! changed, node after node, with the span each node holds in it
//! ([`NodeSpans`]), as a streamed file's nodes come: the renderer keeps a
//! node drawn in one view in its GPU slots for the next.

use std::sync::Arc;
use std::time::Instant;

use super::{Choosing, Hierarchy, SelectOptions, Selection, gather, select};
use crate::frame::Camera;
use crate::frame::subset::{Choice, NodeSpans, Subset};

/// What the last choice drew and cost.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct BudgetChoice {
    pub nodes: usize,
    pub splats: usize,
    /// Node selection, in milliseconds.
    pub select_ms: f64,
    pub changed: bool,
}

/// The nodes of `hierarchy` under a budget.
pub struct BudgetSubset {
    pub hierarchy: Arc<Hierarchy>,
    /// What the hierarchy's splats are (its cache key): choices are keyed by it and their nodes.
    key: u64,
    /// Most splats a frame draws; set per frame (the frame's spec says it).
    pub budget: u32,
    selected: Option<Selection>,
    /// The key of the last choice.
    chosen_key: u64,
    pub last: BudgetChoice,
}

impl BudgetSubset {
    /// Nothing chosen yet from `hierarchy`, whose splats `key` names.
    pub fn new(hierarchy: Arc<Hierarchy>, key: u64) -> Self {
        BudgetSubset {
            hierarchy,
            key,
            budget: u32::MAX,
            selected: None,
            chosen_key: key,
            last: BudgetChoice::default(),
        }
    }
}

impl Subset for BudgetSubset {
    type Error = std::convert::Infallible;

    fn choose(&mut self, camera: &Camera, size: (u32, u32), choosing: Choosing) -> Result<Choice, Self::Error> {
        let started = Instant::now();
        let options = SelectOptions::for_frame(self.budget as usize, choosing, 0.0);
        let selection = select(&self.hierarchy, camera, size, options);
        let select_ms = started.elapsed().as_secs_f64() * 1e3;
        let changed = self.selected.as_ref() != Some(&selection);
        let (cloud, spans) = if changed {
            // Keyed by what it is (the hierarchy and the nodes chosen), not by hashing every splat.
            let nodes: Vec<u8> = selection.nodes.iter().flat_map(|n| n.to_le_bytes()).collect();
            self.chosen_key = crate::hash::fnv1a(self.key, &nodes);
            (Some(gather(&self.hierarchy, &selection)), Some(Arc::new(spans_of(&self.hierarchy, &selection))))
        } else {
            (None, None)
        };
        self.last = BudgetChoice { nodes: selection.nodes.len(), splats: selection.splats, select_ms, changed };
        self.selected = Some(selection);
        Ok(Choice { cloud, key: self.chosen_key, grouping: None, spans })
    }
}

/// Which splats of `selection` gathered ([`gather`]: node after node) each of its nodes holds.
fn spans_of(hierarchy: &Hierarchy, selection: &Selection) -> NodeSpans {
    let mut at = 0u32;
    let spans = selection.nodes.iter().map(|&node| {
        let count = hierarchy.nodes[node as usize].count;
        at += count;
        (node, at - count..at)
    });
    NodeSpans(spans.collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn the_same_view_keeps_its_splats_and_a_new_one_names_new_ones() {
        let cloud = crate::scene::primitives::plane(40_000, 2.0, Vec3::ZERO, Vec3::new(0.3, 1.0, 0.2));
        let mut subset = BudgetSubset::new(Arc::new(Hierarchy::build(&cloud)), 7);
        subset.budget = 5_000;
        let camera = Camera::default_for(&cloud, 1.0);
        let first = subset.choose(&camera, (128, 128), Choosing::default()).unwrap();
        let chosen = first.cloud.expect("the first choice holds its splats");
        assert!(chosen.len() <= 5_000 && chosen.len() == subset.last.splats, "{}", chosen.len());
        let spans = first.spans.expect("a new choice names its nodes");
        assert_eq!(spans.0.len(), subset.last.nodes);
        for (node, splats) in &spans.0 {
            let node = subset.hierarchy.nodes[*node as usize];
            let held = &subset.hierarchy.splats.positions[node.first as usize..(node.first + node.count) as usize];
            assert_eq!(
                &chosen.positions[splats.start as usize..splats.end as usize],
                held,
                "a node's span holds its splats"
            );
        }
        let again = subset.choose(&camera, (128, 128), Choosing::default()).unwrap();
        assert!(again.cloud.is_none() && again.key == first.key, "the same view: the same splats, not gathered again");
        let close = Camera { distance: camera.distance * 0.3, ..camera };
        let moved = subset.choose(&close, (128, 128), Choosing::default()).unwrap();
        assert!(moved.cloud.is_some() && moved.key != first.key, "a closer view chooses other nodes");
    }
}
