//! A streamed file's nodes, as a [`Subset`]: each frame selects the nodes
//! its view needs under the point budget, loads those the node cache lacks,
//! and gathers their points, only when the nodes drawn changed: a view that
//! draws the same nodes as the last one re-centres and estimates nothing.
//! `render`, `pick`, `bench` and the viewer all choose a streamed frame's
//! points through it.

use std::collections::HashSet;

use super::load::Left;
use super::{CopcError, CopcStream, StreamBudget};
use crate::cloud::LoadOptions;
use crate::frame::Camera;
use crate::frame::subset::{Choice, Choosing, Subset};
use crate::grouping::hash::HashOptions;
use crate::lod::Selection;

/// What the last frame of a stream drew, for the log and the statistics.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StreamChoice {
    /// Nodes the view selected, and those of them drawn (loaded).
    pub selected: usize,
    pub drawn: usize,
    pub points: usize,
    /// Nodes of the view loaded but not drawn yet: held back by a bound on
    /// the points one choice adds ([`StreamSubset::choose_loaded`]).
    pub held_back: usize,
    /// Load warnings, each a line.
    pub warnings: Vec<String>,
}

/// A stream and the budget its frames are chosen under.
pub struct StreamSubset {
    pub stream: CopcStream,
    pub budget: StreamBudget,
    /// How nodes are loaded (a progress bar, or none).
    pub load: LoadOptions,
    pub last: StreamChoice,
    /// The key of the nodes the last choice drew (none before the first), and the groups it gave them.
    shown: Option<(u64, Option<HashOptions>)>,
    /// The nodes the last choice drew.
    shown_nodes: HashSet<u32>,
}

impl StreamSubset {
    pub fn new(stream: CopcStream, budget: StreamBudget, load: LoadOptions) -> Self {
        let last = StreamChoice::default();
        StreamSubset { stream, budget, load, last, shown: None, shown_nodes: HashSet::new() }
    }

    /// One loading step of a view refined progressively: the view's nodes
    /// selected, and the first of those the cache lacks loaded, coarse
    /// first, until they hold `points` ([`CopcStream::load_up_to`]; on
    /// until some node of the view holds a point), then given their
    /// normals and radii where the file has none (each with a halo from the
    /// nodes loaded by then). Returns what remains to load (no node: the
    /// view is complete).
    pub fn load_step(
        &mut self,
        camera: &Camera,
        size: (u32, u32),
        choosing: Choosing,
        points: u64,
    ) -> Result<Left, CopcError> {
        let selection = self.select(camera, size, choosing)?;
        Ok(self.load_selected(&selection, points))
    }

    /// The view's nodes that are loaded, gathered as [`Subset::choose`]
    /// gathers them, loading nothing, and adding at most `adding` points of
    /// nodes the last choice did not draw: coarse first, and at least one
    /// node, so that what a window uploads for one frame is bounded
    /// (`last.held_back` counts the nodes left for the next choices). A
    /// node not drawn yet is drawn by its ancestors, which additive
    /// refinement selects with it (their radii stay as estimated where no
    /// finer node is drawn), so nothing is left uncovered.
    pub fn choose_loaded(
        &mut self,
        camera: &Camera,
        size: (u32, u32),
        choosing: Choosing,
        adding: u64,
    ) -> Result<Choice, CopcError> {
        let selection = self.select(camera, size, choosing)?;
        self.gather_selected(&selection, choosing, adding)
    }

    /// `selection` less its loaded nodes new since the last choice past
    /// the first `adding` points of them (coarse first, at least one node),
    /// and how many nodes that leaves out.
    fn within_adding(&self, selection: &Selection, adding: u64) -> (Selection, usize) {
        let loaded = self.stream.drawn(selection);
        let nodes = &self.stream.tree.nodes;
        let mut new: Vec<u32> = loaded.iter().copied().filter(|n| !self.shown_nodes.contains(n)).collect();
        // A node's parent is a level coarser: coarse first, no node comes before its parent.
        new.sort_by_key(|&n| (nodes[n as usize].key.l, nodes[n as usize].offset));
        let mut sum = 0u64;
        let taken = new
            .iter()
            .enumerate()
            .take_while(|&(i, &n)| {
                sum += u64::from(nodes[n as usize].points);
                i == 0 || sum <= adding
            })
            .count();
        let left_out: HashSet<u32> = new[taken..].iter().copied().collect();
        if left_out.is_empty() {
            return (selection.clone(), 0);
        }
        // The selection less what is left out (its nodes not loaded stay, to say why nothing is drawn).
        let kept: Vec<u32> = selection.nodes.iter().copied().filter(|n| !left_out.contains(n)).collect();
        let splats = kept.iter().map(|&n| nodes[n as usize].points as usize).sum();
        (Selection { nodes: kept, splats }, left_out.len())
    }

    /// The nodes the view selects under the budget.
    fn select(&mut self, camera: &Camera, size: (u32, u32), choosing: Choosing) -> Result<Selection, CopcError> {
        self.stream.check_fits(self.budget)?;
        Ok(self.stream.select(camera, size, self.budget.select_options(choosing)))
    }

    /// [`Self::load_step`] of nodes already selected.
    pub(super) fn load_selected(&mut self, selection: &Selection, points: u64) -> Left {
        let mut left = self.stream.load_up_to(selection, points);
        while left.nodes > 0 && self.stream.drawn(selection).is_empty() {
            left = self.stream.load_up_to(selection, points);
        }
        self.stream.estimate_loaded(selection, &self.load.estimate);
        left
    }

    /// [`Self::choose_loaded`] of nodes already selected.
    pub(super) fn gather_selected(
        &mut self,
        selection: &Selection,
        choosing: Choosing,
        adding: u64,
    ) -> Result<Choice, CopcError> {
        let (within, held_back) = self.within_adding(selection, adding);
        let drawn = self.stream.drawn(&within);
        let key = self.stream.key_of(&drawn);
        if self.shown == Some((key, choosing.groups)) {
            (self.last.selected, self.last.held_back) = (selection.nodes.len(), held_back);
            return Ok(Choice { cloud: None, key, grouping: None, spans: None });
        }
        let frame = self.stream.gather(&within, &self.load, choosing.groups)?;
        self.last = StreamChoice {
            selected: selection.nodes.len(),
            drawn: frame.drawn.len(),
            points: frame.cloud.len(),
            held_back,
            warnings: frame.report.warnings.clone(),
        };
        self.shown = Some((frame.hash, choosing.groups));
        self.shown_nodes = frame.drawn.iter().copied().collect();
        Ok(Choice { cloud: Some(frame.cloud), key: frame.hash, grouping: frame.grouping, spans: frame.spans })
    }
}

impl Subset for StreamSubset {
    type Error = CopcError;

    /// The view's nodes, selected and loaded; their points gathered only
    /// when they are not the nodes the last choice drew (or not in the
    /// groups it gave them), with their groups when `choosing` asks for
    /// them. Keyed by the source and the nodes drawn.
    fn choose(&mut self, camera: &Camera, size: (u32, u32), choosing: Choosing) -> Result<Choice, CopcError> {
        let selection = self.select(camera, size, choosing)?;
        self.load_selected(&selection, u64::MAX);
        self.gather_selected(&selection, choosing, u64::MAX)
    }
}
