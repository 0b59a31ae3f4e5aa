//! The loader pool: the chunks a selection lacks, fetched with at most
//! [`IN_FLIGHT`] requests at a time (Potree's default) and decoded on rayon
//! as they arrive.
//!
//! Chunks that lie close together in the file are merged into one request
//! (a gap under [`super::http::MIN_REQUEST`], up to [`MAX_MERGED`] in all),
//! as COPC readers do against object storage, where each request costs far
//! more than the bytes between two chunks. With `--disk-cache DIR`, chunks
//! are read from and written to DIR (one file per node and source, checked
//! on reading, see [`super::disk`]); unusable ones are fetched again, and
//! counted in one line.

use std::sync::Mutex;
use std::sync::mpsc;

use rayon::prelude::*;

use super::disk::{DiskCache, Miss};
use super::header::CopcHeader;
use super::held::MemoryNodes;
use super::hierarchy::CopcTree;
use super::source::ByteSource;
use crate::cloud::las_file::Columns;

/// Requests in flight at once.
pub const IN_FLIGHT: usize = 4;
/// Largest merged request.
const MAX_MERGED: u64 = 16 << 20;

/// What a loading step left to load: nodes, and the points they hold.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Left {
    pub nodes: usize,
    pub points: u64,
}

/// Turns a node's chunk into what the caller wants of it, or says why it cannot.
pub type ChunkDecoder<'a, T> = dyn Fn(u32, &[u8]) -> Result<T, String> + Sync + 'a;

/// Chunks read in one request: their nodes, from `start` to `end`.
struct Run {
    start: u64,
    end: u64,
    nodes: Vec<u32>,
}

/// Where the chunks go and come from.
pub struct Fetch<'a> {
    pub source: &'a dyn ByteSource,
    pub header: &'a CopcHeader,
    pub tree: &'a CopcTree,
    /// `--disk-cache DIR`, in the folder of this source's content.
    pub disk: Option<&'a DiskCache>,
    /// A file held whole: its nodes are gathered from memory, nothing read.
    pub memory: Option<&'a MemoryNodes>,
}

impl Fetch<'_> {
    /// The nodes' points, or why each failed, as they finish (any order).
    pub fn nodes(&self, nodes: &[u32], on_done: &(dyn Fn(u64) + Sync)) -> Vec<(u32, Result<Columns, String>)> {
        if let Some(memory) = self.memory {
            return nodes
                .par_iter()
                .map(|&n| {
                    let columns = memory.node(n);
                    on_done(columns.len() as u64);
                    (n, Ok(columns))
                })
                .collect();
        }
        let decode = |n: u32, bytes: &[u8]| {
            let node = &self.tree.nodes[n as usize];
            super::decode::decode(self.header, bytes, node.points, self.tree.cube(&node.key))
        };
        self.decoded(nodes, &decode, on_done)
    }

    /// The nodes' chunks, read from the disk cache or fetched (merged, at
    /// most [`IN_FLIGHT`] requests at a time), each decoded by `decode` as
    /// it arrives; or why each failed, as they finish (any order).
    pub fn decoded<T: Send>(
        &self,
        nodes: &[u32],
        decode: &ChunkDecoder<'_, T>,
        on_done: &(dyn Fn(u64) + Sync),
    ) -> Vec<(u32, Result<T, String>)> {
        let mut from_disk = Vec::new();
        let mut wanted = Vec::new();
        let mut unusable = 0;
        for &n in nodes {
            match self.disk_read(n) {
                Ok(bytes) => from_disk.push((n, bytes)),
                Err(miss) => {
                    unusable += usize::from(miss != Miss::Absent);
                    wanted.push(n);
                }
            }
        }
        if unusable > 0 {
            log::warn!(
                "{}: --disk-cache: {unusable} cached chunks were damaged or not plain files; removed and fetched again",
                self.source.name()
            );
        }
        let runs = Mutex::new(self.runs(wanted));
        let (sender, receiver) = mpsc::channel::<(u32, Result<Vec<u8>, String>)>();
        for (n, bytes) in from_disk {
            sender.send((n, Ok(bytes))).expect("the receiver lives");
        }
        std::thread::scope(|scope| {
            for _ in 0..IN_FLIGHT {
                let sender = sender.clone();
                let runs = &runs;
                scope.spawn(move || {
                    while let Some(run) = runs.lock().expect("no panics while held").pop() {
                        match self.source.read(run.start, run.end - run.start) {
                            Ok(bytes) => {
                                for &n in &run.nodes {
                                    let node = &self.tree.nodes[n as usize];
                                    let at = (node.offset - run.start) as usize;
                                    let chunk = bytes[at..at + node.byte_size as usize].to_vec();
                                    self.disk_write(n, &chunk);
                                    let _ = sender.send((n, Ok(chunk)));
                                }
                            }
                            Err(e) => {
                                for &n in &run.nodes {
                                    let _ = sender.send((n, Err(e.reason.clone())));
                                }
                            }
                        }
                    }
                });
            }
            drop(sender);
            receiver
                .into_iter()
                .par_bridge()
                .map(|(n, bytes)| {
                    let result = bytes.and_then(|b| decode(n, &b));
                    on_done(u64::from(self.tree.nodes[n as usize].points));
                    (n, result)
                })
                .collect()
        })
    }

    /// The wanted chunks in file order, nearby ones merged, largest runs first.
    fn runs(&self, mut nodes: Vec<u32>) -> Vec<Run> {
        let tree = self.tree;
        nodes.sort_by_key(|&n| tree.nodes[n as usize].offset);
        let mut runs: Vec<Run> = Vec::new();
        for n in nodes {
            let node = &tree.nodes[n as usize];
            let (start, end) = (node.offset, node.offset + node.byte_size);
            match runs.last_mut() {
                Some(run)
                    if start >= run.end
                        && start - run.end < super::http::MIN_REQUEST
                        && end - run.start <= MAX_MERGED =>
                {
                    run.end = end;
                    run.nodes.push(n);
                }
                _ => runs.push(Run { start, end, nodes: vec![n] }),
            }
        }
        // Popped from the back: the pool starts with the file's first chunks (the coarse levels).
        runs.reverse();
        runs
    }

    /// The node's name in the disk cache: its key.
    fn key_name(&self, n: u32) -> String {
        let key = self.tree.nodes[n as usize].key;
        format!("{}-{}-{}-{}", key.l, key.x, key.y, key.z)
    }

    fn disk_read(&self, n: u32) -> Result<Vec<u8>, Miss> {
        let Some(disk) = self.disk else { return Err(Miss::Absent) };
        let node = &self.tree.nodes[n as usize];
        disk.read(&self.key_name(n), node.offset, node.byte_size)
    }

    fn disk_write(&self, n: u32, bytes: &[u8]) {
        if let Some(disk) = self.disk {
            disk.keep(&self.key_name(n), self.tree.nodes[n as usize].offset, bytes);
        }
    }
}
