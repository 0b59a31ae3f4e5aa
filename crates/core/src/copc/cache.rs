//! Decoded nodes, kept while they fit: a least-recently-used cache bounded
//! in bytes (`--cache-mb`), as Potree keeps its loaded nodes. The nodes the
//! current frame draws are never evicted for one another: the frame needs
//! them all at once, so the cache may pass its bound by what one selection
//! holds, and falls back under it as soon as the view moves on.
//!
//! Beside a node's points the cache keeps what was made of them once, when
//! the node arrived: its normals and radii ([`super::node_estimates`]),
//! and its groups for the grouped modes ([`super::node_groups`]). They are
//! counted in its bytes and leave with it.

use std::collections::HashMap;
use std::sync::Arc;

use super::node_estimates::NodeEstimates;
use crate::cloud::las_file::Columns;
use crate::grouping::hash::HashOptions;

/// A node's hash groups, one per point, and the options they were made with.
pub type NodeLabels = (HashOptions, Arc<Vec<u8>>);

pub struct NodeCache {
    capacity: usize,
    used: usize,
    clock: u64,
    entries: HashMap<u32, Entry>,
}

struct Entry {
    columns: Arc<Columns>,
    estimates: Option<Arc<NodeEstimates>>,
    labels: Option<NodeLabels>,
    bytes: usize,
    last_used: u64,
}

impl NodeCache {
    pub fn new(capacity: usize) -> Self {
        Self { capacity, used: 0, clock: 0, entries: HashMap::new() }
    }

    /// The node's points, if kept; marks it used now.
    pub fn get(&mut self, node: u32) -> Option<Arc<Columns>> {
        self.clock += 1;
        let entry = self.entries.get_mut(&node)?;
        entry.last_used = self.clock;
        Some(entry.columns.clone())
    }

    /// The node's points, if kept, without marking it used (a neighbour's halo).
    pub fn peek(&self, node: u32) -> Option<&Arc<Columns>> {
        self.entries.get(&node).map(|e| &e.columns)
    }

    /// The node's normals and radii, if made.
    pub fn estimates(&self, node: u32) -> Option<Arc<NodeEstimates>> {
        self.entries.get(&node)?.estimates.clone()
    }

    /// Keeps the node's normals and radii beside its points (counted in its bytes).
    pub fn set_estimates(&mut self, node: u32, estimates: Arc<NodeEstimates>) {
        if let Some(entry) = self.entries.get_mut(&node) {
            let bytes = estimates.bytes();
            let old = entry.estimates.replace(estimates).map_or(0, |e| e.bytes());
            entry.bytes = entry.bytes + bytes - old;
            self.used = self.used + bytes - old;
        }
    }

    /// The node's groups, if made with `options`.
    pub fn labels(&self, node: u32, options: HashOptions) -> Option<Arc<Vec<u8>>> {
        let (made_with, labels) = self.entries.get(&node)?.labels.as_ref()?;
        (*made_with == options).then(|| Arc::clone(labels))
    }

    /// Keeps the node's groups beside its points (counted in its bytes), in place of any made otherwise.
    pub fn set_labels(&mut self, node: u32, labels: NodeLabels) {
        if let Some(entry) = self.entries.get_mut(&node) {
            let bytes = labels.1.len();
            let old = entry.labels.replace(labels).map_or(0, |(_, l)| l.len());
            entry.bytes = entry.bytes + bytes - old;
            self.used = self.used + bytes - old;
        }
    }

    pub fn contains(&self, node: u32) -> bool {
        self.entries.contains_key(&node)
    }

    /// Keeps the node's points, then evicts the least recently used nodes
    /// (not those in `keep`) until the cache fits its capacity.
    pub fn insert(&mut self, node: u32, columns: Arc<Columns>, keep: &dyn Fn(u32) -> bool) {
        self.clock += 1;
        let bytes = columns.bytes();
        if let Some(old) =
            self.entries.insert(node, Entry { columns, estimates: None, labels: None, bytes, last_used: self.clock })
        {
            self.used -= old.bytes;
        }
        self.used += bytes;
        self.evict(keep);
    }

    /// Evicts the least recently used nodes not in `keep` until the cache fits.
    pub fn evict(&mut self, keep: &dyn Fn(u32) -> bool) {
        if self.used <= self.capacity {
            return;
        }
        let mut order: Vec<(u64, u32)> =
            self.entries.iter().filter(|(n, _)| !keep(**n)).map(|(n, e)| (e.last_used, *n)).collect();
        order.sort_unstable();
        for (_, node) in order {
            if self.used <= self.capacity {
                break;
            }
            if let Some(e) = self.entries.remove(&node) {
                self.used -= e.bytes;
            }
        }
    }

    /// Bytes held, nodes held, and the bound.
    pub fn usage(&self) -> (usize, usize, usize) {
        (self.used, self.entries.len(), self.capacity)
    }
}
