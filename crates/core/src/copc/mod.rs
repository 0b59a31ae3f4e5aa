//! Streaming COPC files (Cloud Optimized Point Cloud 1.0: a LAZ 1.4 file
//! whose octree nodes are LAZ chunks, indexed by hierarchy pages) from disk
//! or over HTTP(S), node by node, under a point budget.
//!
//! [`source`] reads byte ranges (a file, or [`http`] range requests),
//! [`header`] the header and COPC info VLR, [`hierarchy`] the octree page by
//! page as the traversal reaches it, [`decode`] one node's chunk into the
//! columns a LAS file fills, [`load`] fetches and decodes the chunks a
//! selection lacks (at most four requests in flight), [`disk`] keeps the
//! chunks fetched on disk (`--disk-cache`), [`cache`] keeps
//! decoded nodes in an LRU bounded in bytes (with each node's normals and
//! radii, estimated once by [`node_estimates`] and drawn as the deepest
//! node drawn at their position estimated them ([`drawn_estimates`]), and its groups, labelled
//! once by [`node_groups`]), and [`stream`] puts them
//! together: select by projected spacing (additive refinement, the same
//! selection as the in-memory hierarchy's, [`crate::lod::select_in`]),
//! load, and build the selection into a [`crate::cloud::PointCloud`].
//! A point file opened under a point budget is held whole in [`memory`],
//! sorted into the octree a COPC file of it would hold ([`octree`]), and
//! streamed from there node by node the same way. [`layered`] draws several streamed files under one budget. [`write`] makes COPC files. [`redact`] masks a URL's credentials in
//! whatever is shown: every [`CopcError`] goes through it.

pub mod budget;
pub(crate) mod cache;
pub(crate) mod decode;
pub(crate) mod disk;
mod drawn_estimates;
mod facing;
pub mod header;
pub(crate) mod held;
pub mod hierarchy;
pub mod http;
pub mod layered;
pub(crate) mod load;
pub(crate) mod memory;
pub(crate) mod node_estimates;
pub(crate) mod node_groups;
pub mod octree;
pub mod redact;
mod region;
pub mod source;
pub mod stream;
mod stream_frame;
pub mod subset;
pub mod write;

pub use budget::StreamBudget;
pub use load::Left;
pub use memory::{drawn_by_nodes, header_points, open_nodes, window_draws_by_nodes};
pub use redact::shown;
pub use source::{is_streamed, is_url};
pub use stream::{CopcStream, StreamOptions, StreamStats, StreamedFrame};

/// A failure to stream a file: its path or URL and why, on one line, a
/// URL's credentials masked in both (an HTTP client's text may quote it).
#[derive(Debug, Clone, thiserror::Error)]
#[error("{name}: {reason}")]
pub struct CopcError {
    pub name: String,
    pub reason: String,
}

impl CopcError {
    pub fn new(name: &str, reason: impl Into<String>) -> Self {
        Self { name: redact::shown(name), reason: crate::cloud::one_line(&redact::shown(&reason.into())) }
    }
}
