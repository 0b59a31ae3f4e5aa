//! A streamed file's nodes, as a [`Subset`]: each frame selects the nodes
//! its view needs under the point budget, loads those the node cache lacks,
//! and gathers their points. `render`, `pick`, `bench` and the viewer all
//! choose a streamed frame's points through it.

use super::{CopcError, CopcStream, StreamBudget};
use crate::cloud::LoadOptions;
use crate::frame::Camera;
use crate::frame::subset::{Choice, Choosing, Subset};

/// What the last frame of a stream drew, for the log and the statistics.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StreamChoice {
    /// Nodes the view selected, and those of them drawn (loaded).
    pub selected: usize,
    pub drawn: usize,
    pub points: usize,
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
}

impl StreamSubset {
    pub fn new(stream: CopcStream, budget: StreamBudget, load: LoadOptions) -> Self {
        StreamSubset { stream, budget, load, last: StreamChoice::default() }
    }
}

impl Subset for StreamSubset {
    type Error = CopcError;

    /// Every choice holds its points (a new view is a new scene), keyed by the source and the nodes drawn.
    fn choose(&mut self, camera: &Camera, size: (u32, u32), choosing: Choosing) -> Result<Choice, CopcError> {
        let frame = self.stream.frame_under(camera, size, (self.budget, choosing), &self.load)?;
        self.last = StreamChoice {
            selected: frame.selection.nodes.len(),
            drawn: frame.drawn.len(),
            points: frame.cloud.len(),
            warnings: frame.report.warnings.clone(),
        };
        Ok(Choice { cloud: Some(frame.cloud), key: frame.hash })
    }
}
