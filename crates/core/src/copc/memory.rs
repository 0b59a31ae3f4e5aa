//! A LAS or LAZ file opened whole as a tree of nodes (Schütz's
//! PotreeConverter and Entwine prepare a file the same way before it is
//! drawn): its records are decoded into columns at once, then sorted into
//! the octree a COPC file of it would hold ([`super::octree`]). The stream
//! then draws it as it draws a COPC file: nodes selected by projected
//! spacing under the point budget, each node's normals, radii and groups
//! made once, when it is first drawn, with its halo, and its GPU copy kept
//! in the node pool. "Loading" a node gathers its points from the columns;
//! no byte is read, so a view's `bytes_read` is 0.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use glam::DVec3;

use super::budget::StreamBudget;
use super::header::CopcHeader;
use super::held::MemoryNodes;
use super::hierarchy::CopcTree;
use super::octree::{Cube, octree};
use super::source::{ByteSource, Counters, is_streamed};
use super::stream::{CopcStream, StreamOptions};
use super::{CopcError, write};
use crate::cloud::las_file;

/// What stands for a file held whole where a stream names its source:
/// its path and length. Nothing is read through it.
struct Held {
    name: String,
    /// The canonical path, length and modification time: a file rewritten
    /// in place is another file for the caches keyed by it.
    identity: String,
    len: u64,
    counters: Counters,
}

impl ByteSource for Held {
    fn name(&self) -> &str {
        &self.name
    }
    fn identity(&self) -> &str {
        &self.identity
    }
    fn len(&self) -> u64 {
        self.len
    }
    fn read(&self, _offset: u64, _len: u64) -> Result<Vec<u8>, CopcError> {
        Err(CopcError::new(&self.name, "the file is held in memory; nothing is read from it by range"))
    }
    fn counters(&self) -> &Counters {
        &self.counters
    }
}

impl CopcStream {
    /// Opens the LAS or LAZ file at `path` whole, as a tree of nodes.
    pub fn open_whole(path: &Path, options: StreamOptions) -> Result<Self, CopcError> {
        let name = path.display().to_string();
        let fail =
            |e: crate::cloud::CloudError| CopcError::new(&name, e.to_string().trim_start_matches(&format!("{name}: ")));
        if header_points(path).is_some_and(|n| n > u64::from(u32::MAX)) {
            return Err(CopcError::new(
                &name,
                "more than 4,294,967,295 points cannot be held whole; convert it to COPC (`pointblend convert`, PDAL or Untwine) to stream it",
            ));
        }
        let started = Instant::now();
        let decoded = las_file::read_columns(path).map_err(fail)?;
        let decode_s = started.elapsed().as_secs_f64();
        let columns = decoded.columns;
        let count = columns.len();
        if count == 0 {
            return Err(CopcError::new(&name, "the file has no points"));
        }
        let sorting = Instant::now();
        let position = |i: usize| DVec3::new(columns.x[i], columns.y[i], columns.z[i]);
        let cube = Cube::around(&position, count, decoded.header.transforms().x.scale);
        let (nodes, depth) = octree(&position, count, &cube);
        let sort_s = sorting.elapsed().as_secs_f64();
        log::info!(
            "{name}: {count} points decoded in {decode_s:.2} s, sorted into {} nodes ({} levels) in {sort_s:.2} s ({:.1} M points/s)",
            nodes.len(),
            depth + 1,
            count as f64 / sort_s.max(1e-9) / 1e6
        );
        let info = las::Vlr { data: write::info_data(&cube, (0, 0)), ..Default::default() };
        let info = las::copc::CopcInfoVlr::try_from(&info).map_err(|e| CopcError::new(&name, e.to_string()))?;
        let header = CopcHeader {
            las: with_bounds(&decoded.header, &cube),
            info,
            root_page: (0, 0),
            laz: None,
            fields: decoded.fields,
            warnings: decoded.warnings,
            file_len: decoded.file_len,
        };
        let tree = CopcTree::whole(&header, cube.centre, nodes.iter().map(|n| (n.key, n.points.len() as u32)));
        let memory = MemoryNodes::new(columns, nodes.into_iter().map(|n| n.points).collect());
        let identity = identity_of(path, header.file_len);
        let source = Box::new(Held { name, identity, len: header.file_len, counters: Counters::default() });
        Ok(Self::assemble(source, (header, tree), None, Some(Arc::new(memory)), options))
    }
}

/// What identifies the file at `path` of `len` bytes for caches: its
/// canonical path, length and modification time.
fn identity_of(path: &Path, len: u64) -> String {
    let canonical = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    let modified = std::fs::metadata(path).and_then(|m| m.modified()).ok();
    let nanos = modified.and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok()).map_or(0, |d| d.as_nanos());
    format!("held:{}:{len}:{nanos}", canonical.display())
}

/// The file's header with the bounds of its points (a header's own may be
/// stale): what the stream frames and centres on. The file's header when
/// it cannot be rebuilt.
fn with_bounds(header: &las::Header, cube: &Cube) -> las::Header {
    let rebuilt = || -> las::Result<las::Header> {
        let mut raw = header.clone().into_raw()?;
        (raw.min_x, raw.min_y, raw.min_z) = (cube.lo.x, cube.lo.y, cube.lo.z);
        (raw.max_x, raw.max_y, raw.max_z) = (cube.hi.x, cube.hi.y, cube.hi.z);
        let mut builder = las::Builder::new(raw)?;
        builder.vlrs = header.vlrs().clone();
        builder.evlrs = header.evlrs().clone();
        builder.into_header()
    };
    rebuilt().unwrap_or_else(|_| header.clone())
}

/// Whether `file` is drawn node by node under `budget`: a COPC file or a
/// URL always; a LAS or LAZ file when the budget is a number of points
/// below the points its header counts (under `all`, none, or a budget
/// that holds every point, it is drawn whole, as before).
pub fn drawn_by_nodes(file: &Path, budget: StreamBudget) -> bool {
    match budget {
        _ if is_streamed(file) => true,
        StreamBudget::Points(n) => header_points(file).is_some_and(|points| (n as u64) < points),
        _ => false,
    }
}

/// Whether the viewer draws `file` node by node under `budget`: as
/// [`drawn_by_nodes`], the default budget counting as its 1,000,000
/// points (a LAS/LAZ file of more is held as a tree of nodes).
pub fn window_draws_by_nodes(file: &Path, budget: StreamBudget) -> bool {
    let budget = match budget {
        StreamBudget::Default => StreamBudget::Points(super::budget::DEFAULT_BUDGET),
        other => other,
    };
    drawn_by_nodes(file, budget)
}

/// Opens a file [`drawn_by_nodes`]: streamed from its bytes (COPC, a URL),
/// or held whole.
pub fn open_nodes(file: &Path, options: StreamOptions) -> Result<CopcStream, CopcError> {
    if is_streamed(file) {
        CopcStream::open(&file.to_string_lossy(), options)
    } else {
        CopcStream::open_whole(file, options)
    }
}

/// The points a LAS or LAZ file's header counts; `None` for other files
/// and files whose header does not read.
pub fn header_points(file: &Path) -> Option<u64> {
    if !las_file::is_las(file) || is_streamed(file) {
        return None;
    }
    las_file::open(file).ok().map(|(reader, _)| reader.header().number_of_points())
}
